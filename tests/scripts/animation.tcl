# An animation is a loop: 36 frames, each rotated by 10 degrees, numbered from set_nr on.
volume ../data/two_tets_nodes.hmesh
imagesize 16 16
linedraw off
method interpolateCoeff constEA 1
output $::tmp/anim/frame.tiff
for {set i 0} {$i < 36} {incr i} {
    vol_rotate 0 1 0 10
    render_btf
}
for {set i 1} {$i <= 36} {incr i} {
    assert {[file exists [format "%s/anim/frame.%04d.tiff" $::tmp $i]]} "frame $i"
}
assert {![file exists $::tmp/anim/frame.0037.tiff]}
set_nr 100
render_btf
assert {[file exists $::tmp/anim/frame.0100.tiff]}
