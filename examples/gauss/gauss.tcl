# gauss — three overlapping Gaussians (thesis appendix D): an analytic field presented through
# the GaussTest interpolator, f(x) = Σ a·exp(−|x − c|²/ρ²), independent of the mesh that bounds
# it. The field is not linear inside the cells, so the exact method samples it with small steps.
# Low values are nearly transparent so the three peaks show through each other; black
# background. Images: out/gauss.0001.png exact, .0002 interpolateCoeff (node values only: coarse).

imagesize 400 400
background 0 0 0
output out/gauss.png
volume gauss.hmesh
colormap rainbow.cmap
alphamap cloud.amap
linedraw off
ortho_camera -0.9 0.9 -0.9 0.9 -10 10
vol_rotate 0 1 0 30
vol_rotate 1 0 0 20

method exact constEA 0.01 3
render_btf
method interpolateCoeff constEA 3
render_btf
