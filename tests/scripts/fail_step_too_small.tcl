# expect: fail_step_too_small.tcl:6: a step of 1e-20 would cut a ray
volume ../data/two_tets_nodes.hmesh
imagesize 4 4
method exact linear 1e-20 1
output $::tmp/tiny.png
render_btf
