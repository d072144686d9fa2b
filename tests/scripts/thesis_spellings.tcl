# The thesis's spellings: the short method names interpolCoeff and
# interpolColor, and value lists with commas, `linedraw field {0, 7}`. Each renders the same
# image as the long form.
proc bytes {f} {
    set h [open $f rb]
    set d [read $h]
    close $h
    return $d
}
proc render_as {name} {
    output $::tmp/$name.pfm
    return [bytes [render_btf]]
}
volume ../../examples/selfMade/selfMade.hmesh
colormap ../../examples/selfMade/glow.cmap
alphamap ../../examples/selfMade/ramp.amap
imagesize 24 20
linedraw off
method interpolateCoeff linear 1.5
set long [render_as coeff_long]
method interpolCoeff linear 1.5
assert {[render_as coeff_short] eq $long} "interpolCoeff"
method interpolateColor 2
set long [render_as color_long]
method interpolColor 2
assert {[render_as color_short] eq $long} "interpolColor"
expect_error {method interpolColor} {*wrong # args*}

volume ../data/two_tets_data.hmesh
linedraw 2 {0 7}
set spaces [render_as lines_spaces]
linedraw 2 {0, 7}
assert {[render_as lines_commas] eq $spaces} "{0, 7}"
linedraw 2 {0,7}
assert {[render_as lines_tight] eq $spaces} "{0,7}"
expect_error {linedraw 2 {0, x}} {*expected numbers*}
