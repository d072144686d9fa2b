# HyperGreen (thesis 7.3, fig. 6.4 above; appendix D.2): the same temperature with a colour
# scale from blue (the skin, cooled by the water bolus) over green (body temperature) and
# yellow to red (the heated tumour, 43.5 °C); the two weaker maxima in the groin, which a
# treatment plan tries to avoid, show in yellow in front of it.

imagesize 256 256
background 0 0 0
output out/HyperGreen.png
volume hyperthermia.hmesh
colormap green.cmap
alphamap heat.amap
linedraw off
look_at -0.5 1 0.3  0 0 0  0 0 1
ortho_camera -0.21 0.21 -0.21 0.21 -10 10

method exact linear 0 1
render_btf
