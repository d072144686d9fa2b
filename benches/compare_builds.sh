#!/usr/bin/env bash
# Side-by-side frame times of two builds of vorang on the same scripts (docs/performance.md).
# usage: benches/compare_builds.sh OLD_VORANG NEW_VORANG SCRIPT...
# Runs each script with the old and the new binary alternately, ROUNDS times (default 2), and
# prints the median of the per-frame times the program reports ("… 1.234 s …") and their ratio.
# The machine is shared: only a ratio measured in one such run holds, and a few rounds more
# (ROUNDS=10) steady the medians. Every thread the machine has is used, as in the targets of
# docs/performance.md; for one thread each, paired, see pair_builds.sh.
set -euo pipefail
old=$1 new=$2
shift 2
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
times() { "$1" "$2" 2>&1 | grep -oE '[0-9.]+ s ' | awk '{print $1}'; }
for s in "$@"; do
  o=() n=()
  for _ in $(seq "${ROUNDS:-2}"); do
    o+=($(times "$old" "$s"))
    n+=($(times "$new" "$s"))
  done
  mo=$(printf '%s\n' "${o[@]}" | median)
  mn=$(printf '%s\n' "${n[@]}" | median)
  echo "$s old $mo new $mn (${#o[@]} and ${#n[@]} frames) ratio $(awk -v a="$mn" -v b="$mo" 'BEGIN {printf "%.3f", a / b}')"
done
