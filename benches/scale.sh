#!/usr/bin/env bash
# How VoRANG scales with threads (docs/performance.md, "Threads"): load, first frame, later
# frames and their stages (sort, bin, draw, from VORANG_TIMING) for 1, 2, 4, … threads up to the
# machine's cores, on generated jittered boxes, for `exact linear 0` and `interpolateColor`.
# usage: benches/scale.sh [VORANG]          (default: target/release/vorang)
#   SIZES="1000000:1024 8000000:2048"        cells:image size pairs
#   THREADS="1 2 4 8 16"                     (default: powers of two up to nproc, and nproc)
#   FRAMES=4                                  frames after the first (median reported)
#   METHODS="exact interpolateColor"
#   HOLES=0.03                                remove this fraction of the cells (a non-convex
#                                             mesh, sorted by MPVONC and ordered per pixel)
# Prints a Markdown table; speed-up is the 1-thread frame time over this one's. The machine is
# whatever runs it: say which, and measure when nothing else runs.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
vorang=$(realpath "${1:-$repo/target/release/vorang}")
sizes=${SIZES:-"1000000:1024 8000000:2048"}
frames=${FRAMES:-4}
methods=${METHODS:-"exact interpolateColor"}
cores=$(nproc)
if [ -z "${THREADS:-}" ]; then
  THREADS=""
  t=1
  while [ "$t" -lt "$cores" ]; do THREADS="$THREADS $t"; t=$((t * 2)); done
  THREADS="$THREADS $cores"
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$repo/benches/viewer/box.cmap" "$repo/benches/viewer/box.amap" "$work/"
median() { sort -n | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]; else print "-"}'; }

echo "| cells | image | method | threads | load s | first frame s | frame s | sort ms | bin ms | draw ms | speed-up |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for size in $sizes; do
  cells=${size%%:*} pixels=${size##*:}
  mesh="$work/box$cells.bin"
  "$vorang" generate "$mesh" --tets "$cells" --binary --holes "${HOLES:-0}" >/dev/null 2>&1
  for method in $methods; do
    case $method in
      exact) command="exact linear 0 1" ;;
      *) command="$method 1" ;;
    esac
    renders=$(printf 'render_btf; %.0s' $(seq $((frames + 1))))
    cat >"$work/run.tcl" <<EOF
imagesize $pixels $pixels
puts "load [lindex [time {volume $mesh}] 0] us"
colormap $work/box.cmap
alphamap $work/box.amap
linedraw off
vol_rotate 1 1 0 30
method $command
output $work/frame.pfm
$renders
EOF
    one=""
    for threads in $THREADS; do
      out=$(cd "$work" && RAYON_NUM_THREADS=$threads VORANG_TIMING=1 "$vorang" run.tcl 2>&1)
      load=$(grep -oE '^load [0-9]+ us' <<<"$out" | awk '{printf "%.3f", $2 / 1e6}')
      totals=$(grep -oE '[0-9.]+ s ' <<<"$out" | awk '{print $1}')
      first=$(head -1 <<<"$totals")
      frame=$(tail -n +2 <<<"$totals" | median)
      stage() { grep -oE "$1 [0-9.]+ ms" <<<"$out" | tail -n +2 | awk '{print $2}' | median; }
      [ -z "$one" ] && one=$frame
      speedup=$(awk -v a="$one" -v b="$frame" 'BEGIN {printf "%.2f", a / b}')
      echo "| $cells | ${pixels}² | $method | $threads | $load | $first | $frame | $(stage sort) | $(stage bin) | $(stage draw) | $speedup |"
    done
  done
done
