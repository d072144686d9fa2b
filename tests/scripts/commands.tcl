# Every VoRANG command: the happy path and its errors.
expect_error {imagesize 10} {wrong # args: should be "imagesize width height"}
expect_error {imagesize 0 10} {*at least 1 × 1*}
expect_error {imagesize ten 10} {*expected a whole number*"width"*"ten"*}
imagesize 32 24
expect_error {output img.xyz} {*unknown image format 'xyz'*}
output $::tmp/commands/img.png
expect_error {set_nr -1} {*whole number*}
set_nr 5
expect_error {background no_such_image.png} {*no_such_image.png*}
background clear
background 0 0 0.2
expect_error {background 0 -1 0} {*must be ≥ 0*}
expect_error {background 0 1} {wrong # args: should be "background file|clear|none|r g b"}
background clear

# Rendering needs a volume.
expect_error {render_btf} {*no volume loaded*}
expect_error {data ../data/two_tets_fields.dat} {*no volume loaded*}
expect_error {volume ../data/does_not_exist.hmesh} {*does_not_exist.hmesh*}
assert {[volume ../data/two_tets_data.hmesh] eq "5 nodes, 2 tetrahedra, 8 fields"}
# A failed volume leaves the previous one in place.
expect_error {volume ../bad/degenerate.hmesh} {*degenerate*}
assert {[file tail [render_btf]] eq "img.0005.png"}
assert {[file exists $::tmp/commands/img.0005.png]}

expect_error {data + ../data/two_tets_nodes.hmesh} {*holds a grid*}
expect_error {data - ../data/two_tets_fields.dat} {wrong # args*}
assert {[data + ../data/two_tets_fields.dat] eq "10 fields"}
assert {[data ../data/two_tets_fields.dat] eq "2 fields"}

expect_error {save_volume $::tmp/x.hmesh json} {*unknown option 'json'*}
save_volume $::tmp/saved.hmesh binary small
assert {[file size $::tmp/saved.hmesh] > 0}
expect_error {save_subset $::tmp/sub.hmesh 0} {*must be a Constant*}
save_subset $::tmp/sub.hmesh 1
volume $::tmp/sub.hmesh

expect_error {addlight 1 1 1 0 0 0} {*direction must not be zero*}
assert {[addlight 1 1 1 0 0 1] == 1}
assert {[addlight 0.5 0.5 0.5 1 0 0] == 2}
expect_error {removelight 3} {*no light 3*}
removelight 1

volume ../data/two_tets_data.hmesh
expect_error {colormap ../bad/maps/color_not_increasing.map} {*color_not_increasing.map:8:*increase strictly*}
expect_error {colormap ../bad/maps/color_identity_scalar.map} {*IDENTITY needs a float\[3\] field*}
expect_error {alphamap ../bad/maps/color_title.map} {*expected the title line '# VoRANG Alphamap 1.0'*}
expect_error {linedraw sometimes} {wrong # args*}
expect_error {linedraw 0 {1 2}} {*must be a scalar Constant*}
linedraw 2 {0 7}
linedraw off
linedraw on

expect_error {persp_camera 40 1 0 10} {*near must be > 0*}
expect_error {persp_camera 40 1 5 1} {*far must be greater than near*}
persp_camera 40 1 0.1 20
expect_error {ortho_camera -1 1 -1 1 2 1} {*front < back*}
ortho_camera -1 1 -1 1 -5 5
expect_error {vol_rotate 1 0 0} {wrong # args: should be "vol_rotate x y z degrees"}
expect_error {vol_rotate 0 0 0 10} {*axis must not be zero*}
expect_error {vol_rotate 1 0 0 lots} {*expected a number for "degrees" but got "lots"*}
vol_rotate 1 0 0 30
expect_error {vol_scale 1 0 1} {*flatten*}
vol_scale 1 2 1
vol_translate 0.1 0 0
look_at 0 0 3 0 0 0 0 1 0

expect_error {method} {*expected a method*}
expect_error {method splat 1} {*unknown method 'splat'*}
expect_error {method exact constEA 0.1} {*should be "method exact integration step brightness"*}
expect_error {method exact simpson 0.1 1} {*unknown integration 'simpson'*trapez, constEA, weightedConstEA*}
method exact weightedConstEA 0.05 1
render_ftb
method interpolateCoeff trapez 2
render_btf remote
method interpolateColor 1
render_btf
method test 0.5
expect_error {render_btf sideways} {*expected online or remote*}
render_ftb
assert {[file exists $::tmp/commands/img.0009.png]}

assert {[string match "*render_btf*" [help]]}
assert {[string match "*exact integration step brightness*" [help method]]}
assert {[string match "*LIT_EMITTER*" [help addlight]]}
expect_error {help nope} {*no VoRANG command 'nope'*}
