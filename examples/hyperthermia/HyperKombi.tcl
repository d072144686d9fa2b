# HyperKombi (appendix D.2): the hyperthermia data set with two mapping methods at once,
# switched by the material (CategoryField): the bone is a grey-blue CONST_CELL block, muscle,
# fat and tumour show the temperature as a red SIMPLE_EMITTER around it. The front view from
# a little above shows the pelvic ring with the spine and both femurs; the tumour glows inside
# the ring, behind the pubis, the two hot spots in the groin in front of the femurs.
# exact linear 0: exact up to floating point (3e-8 from the reference ray caster at 32×32);
# interpolateCoeff would be faster but is off by up to 0.08 (of 0.75) in places.
# Image: out/HyperKombi.0001.png.

imagesize 256 256
background 0 0 0
output out/HyperKombi.png
volume hyperthermia.hmesh
colormap kombi.cmap
alphamap kombi.amap
linedraw off
look_at -0.5 1 0.3  0 0 0  0 0 1
ortho_camera -0.21 0.21 -0.21 0.21 -10 10

method exact linear 0 1
render_btf
