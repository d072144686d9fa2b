# farbraumOpaq — the colour cuboid made nearly opaque (thesis 6.3.2, 7.1, fig. 6.2).
#
# With high absorption and one integration step per cell, the trapezoid rule darkens the cell
# borders: there Δs → 0 while the opacity stays high, so the emission vanishes. constEA does
# not show this; trapez with small steps converges to the same image. interpolateColor cannot
# reach this opacity at all and overstresses edges. The brightness factor 10 makes up for the
# emission an opaque medium lets out (about η/χ); interpolateColor composites η itself, so it
# keeps 1. The largest channel value printed after each render shows trapez's overshoot.
# Images: out/opaq.0001.png trapez one step per cell, .0002 constEA, .0003 trapez step 0.01,
# .0004 interpolateColor.

imagesize 500 300
output out/opaq.png
volume ../farbraum/farbraum.hmesh
colormap ../farbraum/identity.cmap
alphamap opaque.amap
linedraw off
ortho_camera -1.25 1.25 -0.75 0.75 -10 10
vol_rotate 0 1 0 -30
vol_rotate 1 0 0 25
vol_scale 0.85 0.85 0.85

method exact trapez 100 10
render_btf
method exact constEA 100 10
render_btf
method exact trapez 0.01 10
render_btf
method interpolateColor 1
render_btf
