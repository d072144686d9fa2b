# propEA — emission coupled to absorption (thesis 7.2, fig. 6.3).
#
# A scalar rises from left to right through a red cuboid and the absorption grows with it.
# First image: constant red emission — the more opaque right half gets darker, because less of
# its light reaches the eye. Second image: ABSORPTION_WEIGHTED makes the emission grow with the
# absorption, and the brightness stays even while the opacity changes.
# Images: out/propEA.0001.png (constant emission), out/propEA.0002.png (coupled).

imagesize 500 300
output out/propEA.png
volume propEA.hmesh
alphamap rising.amap
linedraw off
ortho_camera -1.25 1.25 -0.75 0.75 -10 10
vol_rotate 0 1 0 -25
vol_rotate 1 0 0 20
vol_scale 0.85 0.85 0.85
method exact constEA 0.02 1

colormap red.cmap
render_btf
colormap red_weighted.cmap
render_btf
