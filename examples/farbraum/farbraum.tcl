# farbraum — the transparent colour cuboid (thesis 7.1, fig. 6.1).
#
# Two unit cubes, 12 nodes, 12 tetrahedra; every node carries an RGB colour (red along x, green
# along y, blue along z) that is used directly as emission (IDENTITY), with a constant
# absorption about halfway between transparent and opaque. The cuboid is rendered with every
# approximation method and integration rule:
#   exact samples every 0.05, interpolateCoeff integrates each cell in one piece, so with the
#   thesis's rules used here the two differ (frame 2, interpolateCoeff trapez, by up to 44/255
#   from frame 1, exact trapez); only with the linear rule would both be exact (the data are
#   linear and χ is constant);
#   weightedConstEA stresses the colour at the front a little too much;
#   interpolateColor (Gouraud projected tetrahedra) is far more transparent and shows edges;
#   test draws the cell walls.
# Images: out/farbraum.0001.png … (in this folder).

imagesize 500 300
output out/farbraum.png
volume farbraum.hmesh
colormap identity.cmap
alphamap half.amap
linedraw off
ortho_camera -1.25 1.25 -0.75 0.75 -10 10
vol_rotate 0 1 0 -30
vol_rotate 1 0 0 25
vol_scale 0.85 0.85 0.85

foreach rule {trapez constEA weightedConstEA} {
    method exact $rule 0.05 1
    render_btf
    method interpolateCoeff $rule 1
    render_btf
}
method interpolateColor 1
render_btf
linedraw on
method test 0.3
render_btf
