#!/usr/bin/env bash
# The GPU backend against the CPU: ms per frame for 1M cells at 1024², `exact linear 0` (and
# interpolateColor on the CPU, which the GPU does not render yet), both orders. Builds the
# release binary with the gpu feature. On a machine without a GPU the Vulkan device is lavapipe
# (software): its numbers only show that the path works, not how fast a GPU is.
#
#   benches/gpu.sh [tetrahedra (default 1000000)] [size (default 1024)]
set -euo pipefail
cd "$(dirname "$0")/.."
tets="${1:-1000000}"
size="${2:-1024}"
cargo build --release --features gpu --bin vorang >/dev/null
bin="$PWD/target/release/vorang"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
"$bin" generate --tets "$tets" --binary "$dir/box.hm" >/dev/null
for backend in cpu gpu; do
    for method in "exact linear 0 1" "interpolateColor 1"; do
        if [ "$backend" = gpu ] && [ "$method" = "interpolateColor 1" ]; then
            continue
        fi
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
puts "$backend  [format %-20s {$method}]  first frame [expr {\$t1 - \$t0}] ms, next [expr {\$t2 - \$t1}] ms"
TCL
        (cd "$dir" && XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}" "$bin" frame.tcl 2>&1 | grep -E "^(cpu|gpu) ") || true
    done
done
