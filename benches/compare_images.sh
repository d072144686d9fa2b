#!/usr/bin/env bash
# Renders every example script with two builds of vorang and compares the images bit for bit
# (a restructuring must not change one bit). Each build runs on its own copy of examples/ with
# every `output NAME.EXT` turned into `output NAME.pfm` (float RGB, no 8-bit rounding).
# usage: benches/compare_images.sh OLD_VORANG NEW_VORANG
# Prints one line per differing frame and a summary; exits 1 if any frame differs or is missing.
set -euo pipefail
old=$(realpath "$1") new=$(realpath "$2")
repo="$(cd "$(dirname "$0")/.." && pwd)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for which in old new; do
  cp -r "$repo/examples" "$work/$which"
  find "$work/$which" -name '*.tcl' -exec sed -i -E 's/^( *output +[^ ]+)\.[A-Za-z0-9]+ *$/\1.pfm/' {} +
done
for script in "$work"/old/*/*.tcl; do
  rel=${script#"$work/old/"}
  (cd "$(dirname "$script")" && "$old" "$(basename "$script")" > /dev/null 2>&1) || echo "old build failed on $rel"
  (cd "$(dirname "$work/new/$rel")" && "$new" "$(basename "$rel")" > /dev/null 2>&1) || echo "new build failed on $rel"
done
same=0 differ=0
while IFS= read -r f; do
  rel=${f#"$work/old/"}
  if cmp -s "$f" "$work/new/$rel"; then same=$((same + 1)); else echo "differs: $rel"; differ=$((differ + 1)); fi
done < <(find "$work/old" -name '*.pfm' | sort)
extra=$(find "$work/new" -name '*.pfm' | wc -l)
echo "$same frames identical, $differ differ ($extra written by the new build)"
[ "$differ" -eq 0 ] && [ "$extra" -eq "$same" ]
