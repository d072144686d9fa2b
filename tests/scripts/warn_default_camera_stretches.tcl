# The default camera puts the grid's x/y extent on the whole image (thesis A.1): a cube in a
# 2:1 image is stretched by 2, which one hint points out (once per session), naming view_all.
# expect: render_btf: the default camera stretches the volume by 2.000
volume ../data/formats/cube.hmesh
imagesize 32 16
linedraw off
output $::tmp/s.pfm
render_btf
render_btf
view_all
render_btf
