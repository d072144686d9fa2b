# expect: fail_set_nr_overflow.tcl:2: set_nr: 4294967295 is too large
set_nr 4294967295
