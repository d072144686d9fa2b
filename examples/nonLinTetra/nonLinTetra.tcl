# nonLinTetra — a non-linear distribution inside one cell (thesis 7.4, fig. 6.5).
#
# The field is the quadruple of barycentric coordinates (b0, b1, b2, b3) of a single
# tetrahedron; BARY_SHADING scheme 3 maps it to s = b0·b1·|b0 − b1| (a quantity that matters for
# higher-order FEM), with emission and absorption both proportional to s. Only the exact method
# with small steps shows this structure; interpolateCoeff, which maps at the nodes only (where
# s = 0), shows nothing.
# Images: out/nonLinTetra.0001.png exact, .0002 interpolateCoeff.

imagesize 400 400
output out/nonLinTetra.png
volume nonLinTetra.hmesh
colormap weighted.cmap
alphamap bary3.amap
linedraw on
ortho_camera -0.7 0.7 -0.7 0.7 -10 10
vol_rotate 1 0 0 -60
vol_rotate 0 0 1 20

method exact constEA 0.004 1
render_btf
method interpolateCoeff constEA 1
render_btf
