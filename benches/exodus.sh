#!/bin/sh
# Loading a 1M-tetrahedron Exodus II file against the same mesh as BINARY HyperMesh
# (docs/formats.md, "Speed and memory"): `vorang generate --tets 1000000 --binary` writes the
# box, `vorang convert` a .vtu of it, benches/exodus_write.py the same mesh and field as
# Exodus II in MOOSE/libMesh's layout (netCDF-4, netCDF-4 with deflate, CDF-2). Each file is
# loaded RUNS times, interleaved (`vorang -e 'volume F'` under /usr/bin/time); the medians
# of wall time, CPU time (user + sys) and peak RSS are printed, with each file's ratio to
# HyperMesh.
#
#   cargo build --release
#   PY=/tmp/vexo/bin/python sh benches/exodus.sh      # a python with netCDF4, meshio, numpy
#
# Environment: VORANG (default target/release/vorang), PY (python3), RUNS (7), DIR (a new
# temporary folder; the files are kept there).
set -eu
VORANG=${VORANG:-target/release/vorang}
PY=${PY:-python3}
RUNS=${RUNS:-7}
DIR=${DIR:-$(mktemp -d)}
HERE=$(dirname "$0")

if [ ! -f "$DIR/box1m.bin" ]; then
    "$VORANG" generate "$DIR/box1m.bin" --tets 1000000 --binary >/dev/null
    "$VORANG" convert "$DIR/box1m.bin" "$DIR/box1m.vtu" >/dev/null
    "$PY" "$HERE/exodus_write.py" "$DIR/box1m.vtu" "$DIR/box1m"
fi
FILES="box1m.bin box1m.vtu box1m.exo box1m_zlib.exo box1m.e"
: >"$DIR/times.txt"
for r in $(seq "$RUNS"); do
    for f in $FILES; do
        /usr/bin/time -f "$f %e %U %S %M" -a -o "$DIR/times.txt" \
            "$VORANG" -e "volume {$DIR/$f}" >/dev/null
    done
done
echo "median of $RUNS runs (files in $DIR)"
printf '%-16s %10s %8s %8s %10s %8s %8s\n' file size wall cpu "peak RSS" "cpu/bin" "RSS/bin"
median() { sort -n | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
for f in $FILES; do
    wall=$(awk -v f="$f" '$1 == f { print $2 }' "$DIR/times.txt" | median)
    cpu=$(awk -v f="$f" '$1 == f { print $3 + $4 }' "$DIR/times.txt" | median)
    rss=$(awk -v f="$f" '$1 == f { print $5 / 1024 }' "$DIR/times.txt" | median)
    size=$(wc -c <"$DIR/$f")
    if [ "$f" = box1m.bin ]; then bcpu=$cpu; brss=$rss; fi
    awk -v f="$f" -v s="$size" -v w="$wall" -v c="$cpu" -v m="$rss" -v bc="$bcpu" -v bm="$brss" \
        'BEGIN { printf "%-16s %8.1f MB %7.2fs %7.2fs %7.1f MiB %7.2fx %7.2fx\n", f, s / 1e6, w, c, m, c / bc, m / bm }'
done
