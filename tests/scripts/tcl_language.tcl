# Real Tcl: float math, procs, lists, format, source of another script (relative to this one).
assert {[expr {sin(0.5)*2.0}] == 2*sin(0.5)}
assert {[expr {7/2.0}] == 3.5}
assert {[format %.3f [expr {sqrt(2)}]] eq "1.414"}
proc square {x} { return [expr {$x * $x}] }
assert {[square 1.5] == 2.25}
set l {}
foreach v {1 2 3} { lappend l [expr {$v * 10}] }
assert {$l eq {10 20 30}}
source lib_sourced.tcl
assert {$sourced_value == 42}
