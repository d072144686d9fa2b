# selfMade — artefacts of the integration rules (thesis 6.3.2).
#
# A slab: absorption-free on the left (but emitting), a bump, and increasingly opaque to the
# right. Integrated once per cell (interpolateCoeff):
#   trapez darkens the opaque cells towards their borders;
#   constEA is exact where emission and absorption are proportional and handles the
#   absorption-free part with the correct limit (the thesis's 1e-7 hack gave black there);
#   weightedConstEA over-weights the front emission;
# and, for comparison, exact constEA with small steps. A black background shows the glow of the
# absorption-free part.
# Images: out/selfMade.0001.png trapez, .0002 constEA, .0003 weightedConstEA, .0004 exact.

imagesize 500 250
background 0 0 0
output out/selfMade.png
volume selfMade.hmesh
colormap glow.cmap
alphamap ramp.amap
linedraw off
ortho_camera -1.2 1.2 -0.6 0.6 -10 10
vol_rotate 1 0 0 15
vol_rotate 0 1 0 -10

foreach rule {trapez constEA weightedConstEA} {
    method interpolateCoeff $rule 1
    render_btf
}
method exact constEA 0.01 1
render_btf
