# expect: fail_missing_map.tcl:3: no_such.map
volume ../data/two_tets_nodes.hmesh
colormap no_such.map
