# Assertions for the script tests (sourced by the test runner before each script).
proc assert {cond {what ""}} {
    if {![uplevel 1 [list expr $cond]]} {
        error "assertion failed: $cond $what"
    }
}
# Runs `script`, which must fail with a message matching the glob `pattern`.
proc expect_error {script pattern} {
    if {![catch {uplevel 1 $script} msg]} {
        error "expected an error from: $script"
    }
    if {![string match $pattern $msg]} {
        error "error '$msg' does not match '$pattern'"
    }
}
