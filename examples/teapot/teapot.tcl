# teapot (appendix D.2): a solid teapot on a hot plate, the steady temperature inside it
# (teapot.hmesh, made by generate.py: Gmsh body of revolution, spout, handle; P1 heat FEM).
# The mesh is not convex (the handle's hole, the creases where spout and handle meet the pot),
# so this scene needs a correct ordering for non-convex meshes. The view is from the side and
# a little above, through the handle's hole.
# Images: out/teapot.0001.png exact (linear integration: 5e-8 from the reference ray caster
# at 32×32, which intersects every ray with every cell and needs no ordering), .0002 turned
# by 60° about the vertical.

imagesize 256 256
background 0.08 0.08 0.1
output out/teapot.png
volume teapot.hmesh
colormap thermal.cmap
alphamap thermal.amap
linedraw off
# Decimetres, centred: z up, the spout towards +x, the handle towards −x.
look_at 0.6 -3 1.4  0 0 0  0 0 1
ortho_camera -1.8 1.8 -1.8 1.8 -10 10

method exact linear 0 1
render_btf
vol_rotate 0 0 1 60
render_btf
