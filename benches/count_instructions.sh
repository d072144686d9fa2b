#!/usr/bin/env bash
# Instructions executed for one frame, per build: a measure that does not drift with the machine's
# load (docs/performance.md, "How to measure"). Time is what counts, but on
# a shared VM a 5 % change hides in the noise of frame times; the instruction count of the same
# frame is exact to the last digit, so two builds can be told apart — though fewer instructions
# need not mean less time (see that section).
#
# usage: benches/count_instructions.sh VORANG [VORANG...]
#   METHOD   the method line (default "exact linear 0 1"; e.g. "interpolateColor 1")
#   TETS     tetrahedra of the jittered box (default 150000), SIZE image side (default 512)
#   WORK     where the mesh, maps, script and outputs go (default: a new temporary directory)
# Needs valgrind (`apt-get install valgrind`); each build takes a couple of minutes under it.
# Prints, per build: instructions, conditional branches and cachegrind's modelled mispredictions
# (its simple predictor, not the processor's), and the frame's image checksum (same bits or not).
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,14p' "$0"; exit 2; }
command -v valgrind >/dev/null || { echo "valgrind is needed: apt-get install valgrind" >&2; exit 1; }
method=${METHOD:-exact linear 0 1}
tets=${TETS:-150000}
size=${SIZE:-512}
work=${WORK:-$(mktemp -d)}
mkdir -p "$work"
first=$1
mesh="$work/box$tets.bin"
[ -f "$mesh" ] || "$first" generate "$mesh" --tets "$tets" --binary >/dev/null
# The maps of benches/render.rs: five breakpoints, colour and absorption on the same knots.
cat >"$work/bench.cmap" <<'MAP'
# VoRANG Colormap 1.0
SIMPLE_EMITTER @1
@1
0 0 1 0.45
0 1 0 0.55
1 1 0 0.65
1 0 0 0.75
1 1 1 0.85
MAP
cat >"$work/bench.amap" <<'MAP'
# VoRANG Alphamap 1.0
SIMPLE_ABSORBER @1
@1
0.2 0.45
3 0.55
0.5 0.65
6 0.75
1 0.85
MAP
i=0
for bin in "$@"; do
  i=$((i + 1))
  cat >"$work/frame$i.tcl" <<TCL
imagesize $size $size
volume $mesh
colormap $work/bench.cmap
alphamap $work/bench.amap
linedraw off
output $work/frame$i.pfm
vol_rotate 1 1 0 30
method $method
render_btf
TCL
  RAYON_NUM_THREADS=1 valgrind --tool=cachegrind --cache-sim=no --branch-sim=yes \
    --cachegrind-out-file="$work/cachegrind$i.out" "$bin" "$work/frame$i.tcl" \
    >/dev/null 2>"$work/valgrind$i.log"
  ir=$(grep -oE 'I +refs: +[0-9,]+' "$work/valgrind$i.log" | grep -oE '[0-9,]+$')
  bc=$(grep -oE 'Branches: +[0-9,]+' "$work/valgrind$i.log" | grep -oE '[0-9,]+$')
  bm=$(grep -oE 'Mispredicts: +[0-9,]+' "$work/valgrind$i.log" | grep -oE '[0-9,]+$')
  sum=$(cksum <"$work/frame$i.0001.pfm" 2>/dev/null || cksum <"$work/frame$i.pfm")
  echo "$bin: instructions $ir, branches $bc, mispredicted (model) $bm, image cksum ${sum%% *}"
done
echo "per-line counts: cg_annotate --auto=yes $work/cachegrind1.out"
