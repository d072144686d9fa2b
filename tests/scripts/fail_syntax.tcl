# expect: fail_syntax.tcl:3: missing close-brace
set a 1
if {$a} {
    set b 2
