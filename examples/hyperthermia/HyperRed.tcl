# HyperRed (thesis 7.3, fig. 6.4 below; appendix D.2): the simulated temperature of a regional
# hyperthermia treatment of the pelvis, red at body temperature to yellow in the heated tumour,
# with two unwanted hot spots in the groin in front of it. The absorption grows (piecewise)
# linearly with the temperature, the emission with the absorption.
# hyperthermia.hmesh is made by generate.py (a Gmsh body model, Pennes bioheat FEM).
# Images: out/HyperRed.0001.png exact (linear integration, cut at the map's breakpoints: 3e-8
# from the reference ray caster at 32×32), .0002 interpolateCoeff as in the thesis: one
# integral per cell of values mapped at its vertices, which the steep map turns into visible
# cell facets around the hot regions (the thesis's artefact; up to 0.08 of 0.9 off).

imagesize 256 256
background 0 0 0
output out/HyperRed.png
volume hyperthermia.hmesh
colormap red.cmap
alphamap heat.amap
linedraw off
# Metres, centred: x across the body, y back to front, z from the thighs up to the spine.
look_at -0.5 1 0.3  0 0 0  0 0 1
ortho_camera -0.21 0.21 -0.21 0.21 -10 10

method exact linear 0 1
render_btf
method interpolateCoeff constEA 1
render_btf
