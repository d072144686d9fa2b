# inclusion: your own data — a Gmsh geometry with two physical groups (matrix, inclusion) and a
# steady temperature solved with scikit-fem, read from a .vtu file (generate.py makes it). The
# maps pick their fields by name: DataField "temperature", CategoryField "material".
imagesize 320 200
output out/inclusion.png
volume inclusion.vtu
colormap temperature.cmap
alphamap material.amap
linedraw off
ortho_camera -1.3 1.3 -0.8125 0.8125 -10 10
vol_rotate 1 0 0 -25
vol_rotate 0 1 0 20
method exact linear 0 1.5
render_btf
