# expect: fail_wrong_args.tcl:5: wrong # args: should be "look_at ex ey ez rx ry rz ux uy uz"
set eye {0 0 5}


look_at {*}$eye 0 0 0
