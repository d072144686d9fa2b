#!/usr/bin/env bash
# A distributed frame's time against its compositing time (docs/distributed.md, "Scaling").
# usage: benches/distributed.sh VORANG [NP...]
# VORANG must be built with --features mpi (cargo build --release --features mpi). Generates the
# 150k and 1M jittered boxes (vorang generate; cached in $DIST_DIR, default /tmp/vorang-dist),
# renders each at 512² and 1024² (exact linear 0, no grid lines, three views per run) in one
# process and with `mpirun -np N` for each NP (default 2), and prints per run the median frame
# time and, for the ranks, rank 0's median compositing time (the runs' all-to-all, the owners'
# settling, the gather: the `composite` part of the VORANG_TIMING line). Each rank gets
# RAYON_NUM_THREADS threads (default: the cores divided by the ranks, at least 1), so that the
# ranks share the machine as the one process does. The machine may be shared with others:
# compare numbers of one run only.
set -euo pipefail
vorang=$(realpath "$1")
shift
nps=("${@:-2}")
dir=${DIST_DIR:-/tmp/vorang-dist}
mkdir -p "$dir"
cd "$dir"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cores=$(nproc)
for tets in 150000 1000000; do
  [ -f "box$tets.hm" ] || "$vorang" generate "box$tets.hm" --tets "$tets" --binary >/dev/null 2>&1
done
printf '# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 1 0.2\n1 1 0 0.5\n1 0 0 0.8\n' > c.map
printf '# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.5 0.2\n4 0.5\n1 0.8\n' > a.map
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
for tets in 150000 1000000; do
  for size in 512 1024; do
    cat > "bench$tets-$size.tcl" <<EOF
volume box$tets.hm
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
EOF
    s="bench$tets-$size.tcl"
    one=$(VORANG_TIMING=1 "$vorang" "$s" 2>&1 | grep -oE '[0-9.]+ s ' | awk '{print $1}' | median)
    echo "$tets cells ${size}²: one process ($cores threads) ${one} s"
    for np in "${nps[@]}"; do
      threads=$(( cores / np > 0 ? cores / np : 1 ))
      out=$(RAYON_NUM_THREADS=$threads VORANG_TIMING=1 mpirun -np "$np" --oversubscribe --bind-to none \
        -x RAYON_NUM_THREADS -x VORANG_TIMING "$vorang" "$s" 2>&1)
      frame=$(grep -oE '[0-9.]+ s ' <<<"$out" | awk '{print $1}' | median)
      comp=$(grep -oE 'composite [0-9.]+ ms' <<<"$out" | awk '{print $2}' | median)
      echo "$tets cells ${size}²: -np $np ($threads threads each) frame ${frame} s, composite ${comp} ms"
    done
  done
done
