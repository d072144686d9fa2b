# expect: fail_command_in_loop.tcl:7: vol_rotate: expected a number for "degrees" but got "x"
volume ../data/two_tets_nodes.hmesh
foreach angle {10 20 x 40} {
    # a comment line inside the loop body

    if {$angle > 0} {
        vol_rotate 0 1 0 $angle
    }
}
