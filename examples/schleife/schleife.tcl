# schleife — an animation loop (thesis appendix D): nonLinTetra spinning about an axis that does
# not pass through its centre.
#
# vol_rotate always turns the cell about its own (carried) bounding-box centre; moving that
# centre along a circle with vol_translate at the same time turns the whole motion into a
# rotation about an off-centre axis. 24 numbered frames: out/schleife.0001.png … 0024.

imagesize 200 200
output out/schleife.png
volume ../nonLinTetra/nonLinTetra.hmesh
colormap ../nonLinTetra/weighted.cmap
alphamap ../nonLinTetra/bary3.amap
linedraw on
ortho_camera -1.3 1.3 -1.3 1.3 -10 10
vol_rotate 1 0 0 -60
method exact constEA 0.01 1

set frames 24
set radius 0.35
set pi [expr {acos(-1)}]
for {set k 0} {$k < $frames} {incr k} {
    # The centre moves from angle k to angle k+1 on a circle about the y axis …
    set a0 [expr {2 * $pi * $k / $frames}]
    set a1 [expr {2 * $pi * ($k + 1) / $frames}]
    vol_translate [expr {$radius * (cos($a1) - cos($a0))}] 0 [expr {$radius * (sin($a0) - sin($a1))}]
    # … while the cell turns by the same angle about its own centre.
    vol_rotate 0 1 0 [expr {360.0 / $frames}]
    render_btf
}
