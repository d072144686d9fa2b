# lighting: LIT_EMITTER (docs/lighting.md) on the temperature of the inclusion example. Frame 1
# uses the default light (white, at the camera); frame 2 a warm key light from the upper left
# and a weak blue fill light from the right.
imagesize 320 200
output out/lit.png
volume ../inclusion/inclusion.vtu
colormap lit.cmap
alphamap ../inclusion/material.amap
linedraw off
background 0 0 0
ortho_camera -1.3 1.3 -0.8125 0.8125 -10 10
vol_rotate 1 0 0 -25
vol_rotate 0 1 0 20
method exact linear 0 1.5
render_btf
addlight 1 0.85 0.7  -1 1 1
addlight 0.2 0.3 0.6  1 0 0.3
render_btf
