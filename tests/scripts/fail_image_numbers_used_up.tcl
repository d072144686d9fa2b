# expect: fail_image_numbers_used_up.tcl:7: the image numbers are used up
volume ../data/two_tets_nodes.hmesh
imagesize 4 4
output $::tmp/last.png
set_nr 4294967294
render_btf
render_btf
