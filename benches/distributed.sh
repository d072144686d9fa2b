#!/usr/bin/env bash
# A distributed frame rank by rank (docs/distributed.md, "Scaling").
# usage: benches/distributed.sh VORANG [NP...]
# VORANG must be built with --features mpi (cargo build --release --features mpi). For each
# mesh and image size of $CASES (default "1000000:1024"; e.g. "1000000:1024 8000000:2048") it
# generates the jittered box (vorang generate; cached in $DIST_DIR, default /tmp/vorang-dist),
# cuts it into 12 pieces (vorang convert --pieces 12: every rank count 1 … 4 reads whole
# pieces), and renders three views (exact linear 0, no grid lines) in one process and with
# `mpirun -np N` for each NP (default 1 2 3 4). Per run, medians over the frames: the frame
# time; each rank's render time (its cells into runs: setup, sort, binning, drawing); the
# ray segments (pixel–cell pairs) and runs per pixel of all ranks together; the bytes each
# rank sends to the others; rank 0's compositing time (all-to-all, settling, gather) and its
# share of the frame — the VORANG_TIMING lines of rank 0. Each rank gets RAYON_NUM_THREADS
# threads (default: the cores divided by the ranks, at least 1), so that the ranks share the
# machine as the one process does. The machine may be shared with others: compare numbers of
# one run only.
set -euo pipefail
vorang=$(realpath "$1")
shift
nps=("${@:-1 2 3 4}")
# shellcheck disable=SC2206
nps=(${nps[*]})
dir=${DIST_DIR:-/tmp/vorang-dist}
mkdir -p "$dir"
cd "$dir"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cores=$(nproc)
printf '# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 1 0.2\n1 1 0 0.5\n1 0 0 0.8\n' > c.map
printf '# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.5 0.2\n4 0.5\n1 0.8\n' > a.map
median() { sort -n | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]; else print "-"}'; }
# The medians of one run's timing lines ($1: the output, $2: ranks, $3: pixels).
summary() {
  local out=$1 np=$2 pixels=$3
  local frame comp renders="" sent="" segs runs share
  frame=$(grep -oE '^.* [0-9.]+ s ' <<<"$out" | grep -oE '[0-9.]+ s $' | awk '{print $1}' | median)
  comp=$(grep -oE '; composite [0-9.]+ ms \(runs' <<<"$out" | awk '{print $3}' | median)
  for r in $(seq 0 $((np - 1))); do
    renders+="$(grep -oE "; rank $r: render [0-9.]+ ms" <<<"$out" | awk '{print $5}' | median) "
    sent+="$(grep -oE "; rank $r: [^;]* bytes sent" <<<"$out" | grep -oE '[0-9]+ bytes' | awk '{printf "%.1f\n", $1 / 1e6}' | median) "
  done
  segs=$(grep -oE 'draw [0-9.]+ ms; [0-9]+ ray segments' <<<"$out" | awk -v p="$pixels" '{printf "%.1f\n", $4 / p}' | median)
  runs=$(awk -v p="$pixels" '/; rank 0: render/ {n = 0; s = $0; while (match(s, /[0-9]+ runs,/)) {n += substr(s, RSTART, RLENGTH - 6); s = substr(s, RSTART + RLENGTH)} printf "%.2f\n", n / p}' <<<"$out" | median)
  share=$(awk -v c="$comp" -v f="$frame" 'BEGIN {if (f > 0 && c != "-") printf "%.0f %%", c / 10 / f; else print "-"}')
  echo "| $np | $frame s | ${renders% } ms | $segs | $runs | ${sent% } MB | $comp ms ($share) |"
}
for case in ${CASES:-1000000:1024}; do
  tets=${case%%:*}
  size=${case##*:}
  [ -f "box$tets.hm" ] || "$vorang" generate "box$tets.hm" --tets "$tets" --binary >/dev/null 2>&1
  [ -f "box$tets.pvtu" ] || "$vorang" convert "box$tets.hm" "box$tets.pvtu" --pieces 12 >/dev/null 2>&1
  for input in "box$tets.hm" "box$tets.pvtu"; do
    cat > "bench-$input-$size.tcl" <<EOT
volume $input
imagesize $size $size
colormap c.map
alphamap a.map
method exact linear 0 1
linedraw off
output bench.pfm
render_btf
vol_rotate 1 0.6 0.2 33
render_btf
vol_rotate 0.2 1 0 71
render_btf
EOT
  done
  pixels=$((size * size))
  one=$(VORANG_TIMING=1 "$vorang" "bench-box$tets.hm-$size.tcl" 2>&1 | grep -oE ' [0-9.]+ s ' | awk '{print $1}' | median)
  echo "$tets cells, ${size}², one process ($cores threads, the HyperMesh file): frame $one s"
  echo "| ranks | frame | render per rank | ray segments per pixel | runs per pixel | sent per rank | compositing (share of the frame) |"
  echo "|---|---|---|---|---|---|---|"
  for np in "${nps[@]}"; do
    threads=$(( cores / np > 0 ? cores / np : 1 ))
    out=$(RAYON_NUM_THREADS=$threads VORANG_TIMING=1 mpirun -np "$np" --oversubscribe --bind-to none \
      -x RAYON_NUM_THREADS -x VORANG_TIMING "$vorang" "bench-box$tets.pvtu-$size.tcl" 2>&1)
    summary "$out" "$np" "$pixels"
  done
done
