#!/usr/bin/env bash
# The GPU backend against the CPU: ms per frame, ray segments per second and the upload of the
# cells, for 1M cells at 1024² and 27M at 2048² (`vorang generate`), `exact linear 0`,
# `interpolateCoeff linear` and `interpolateColor` on both.
# Builds the release binary with the gpu feature. On a machine without a GPU the Vulkan device
# is lavapipe (software, on the CPU): its numbers only show that the path works, not how fast a
# GPU is — run it there with a small mesh.
#
#   benches/gpu.sh                      # 1000000 at 1024², then 27000000 at 2048²
#   benches/gpu.sh TETS SIZE [TETS SIZE …]
set -euo pipefail
cd "$(dirname "$0")/.."
cases=("$@")
if [ ${#cases[@]} -eq 0 ]; then
    cases=(1000000 1024 27000000 2048)
fi
cargo build --release --features gpu --bin vorang >/dev/null
bin="$PWD/target/release/vorang"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
for ((i = 0; i + 1 < ${#cases[@]}; i += 2)); do
    tets="${cases[i]}"
    size="${cases[i + 1]}"
    "$bin" generate --tets "$tets" --binary "$dir/box.hm" >/dev/null
    echo "== $tets tetrahedra at ${size}²"
    for backend in cpu gpu; do
        for method in "exact linear 0 1" "interpolateCoeff linear 1" "interpolateColor 1"; do
            cat >"$dir/frame.tcl" <<TCL
backend $backend
volume box.hm
imagesize $size $size
linedraw off
view_all
vol_rotate 1 1 0 30
method $method
output frame.pfm
set t0 [clock milliseconds]
render_ftb
set t1 [clock milliseconds]
render_ftb
set t2 [clock milliseconds]
puts "$backend  [format %-26s {$method}]  first frame [expr {\$t1 - \$t0}] ms (with the upload), next [expr {\$t2 - \$t1}] ms"
TCL
            # The timing lines (VORANG_TIMING) give the segments per second and the upload.
            (cd "$dir" && VORANG_TIMING=1 "$bin" frame.tcl 2>&1 |
                grep -E "^(cpu|gpu) |ray segments" | sed -e 's/^ */    /') || true
        done
    done
done
