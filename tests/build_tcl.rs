//! The build's Tcl version check: Tcl 8.6 is used, Tcl 9 (whose C API
//! differs) and older versions are refused with a message that says what to install.

#[path = "../crates/vorang-tcl/build/tcl_check.rs"]
mod tcl_check;

use tcl_check::refusal;

#[test]
fn tcl_8_6_is_used_and_tcl_9_refused_with_what_to_install() {
    assert_eq!(refusal("8.6.13"), None);
    assert_eq!(refusal("8.6"), None);
    let nine = refusal("9.0.1").expect("Tcl 9 is refused");
    assert!(
        nine.contains("needs Tcl 8.6") && nine.contains("9.0.1"),
        "{nine}"
    );
    assert!(
        nine.contains("tcl-tk@8") && nine.contains("PKG_CONFIG_PATH"),
        "{nine}"
    );
    assert!(refusal("8.5.19").is_some());
}
