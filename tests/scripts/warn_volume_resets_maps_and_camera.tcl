# `volume` starts a new scene (thesis A.1): maps and camera set before it are reset, with a
# warning that names them.
# expect: volume: a new volume resets the colormap, camera and vol_* transforms set before it to the defaults
volume ../data/formats/cube.hmesh
colormap preset viridis 0 1
ortho_camera -1 1 -1 1 -10 10
vol_rotate 0 1 0 30
volume ../data/formats/cube.hmesh
