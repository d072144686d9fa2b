# expect: fail_in_proc.tcl:9: invalid command name "vol_rotat"
volume ../data/two_tets_nodes.hmesh
imagesize 8 8
output $::tmp/fail/x.png

proc spin {n} {
    for {set i 0} {$i < $n} {incr i} {
        if {$i == 1} {
            vol_rotat 0 1 0 10
        }
    }
}
spin 3
