#!/usr/bin/env bash
# Paired frame times of two builds (docs/performance.md, "How to measure").
# usage: benches/pair_builds.sh OLD_VORANG NEW_VORANG SCRIPT [PAIRS]
# Starts both builds at the same moment, one thread each, pinned to CPUs 0 and 1 (swapped every
# pair), sums each run's per-frame draw times (VORANG_TIMING=1) and prints the median ratio
# new/old over the pairs with its range. On a shared machine both runs of a pair see the same
# load, so the ratio holds where lone timings drift; a build against itself gives the noise.
set -euo pipefail
old=$1 new=$2 script=$3 pairs=${4:-6}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
drawsum() { grep -oE 'draw [0-9.]+' "$1" | awk '{s += $2} END {print s}'; }
for i in $(seq "$pairs"); do
  if [ $((i % 2)) = 0 ]; then co=0 cn=1; else co=1 cn=0; fi
  RAYON_NUM_THREADS=1 VORANG_TIMING=1 taskset -c $co "$old" "$script" > "$tmp/old" 2>&1 &
  po=$!
  RAYON_NUM_THREADS=1 VORANG_TIMING=1 taskset -c $cn "$new" "$script" > "$tmp/new" 2>&1 &
  pn=$!
  wait $po $pn
  echo "$(drawsum "$tmp/old") $(drawsum "$tmp/new")" | awk '{printf "%.4f %s %s\n", $2 / $1, $1, $2}' >> "$tmp/ratios"
done
sort -n "$tmp/ratios" | awk '{r[NR] = $1; a += $2; b += $3}
  END {printf "new/old median %.4f (min %.4f, max %.4f, %d pairs); draw sums old %.0f ms, new %.0f ms\n",
       r[int((NR + 1) / 2)], r[1], r[NR], NR, a, b}'
