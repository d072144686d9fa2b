//! Which Tcl versions VoRANG's bindings speak (used by `build.rs`, tested in
//! `tests/build_tcl.rs`).

/// Why a Tcl of this version (as pkg-config reports it) cannot be used, or `None` if it can.
pub fn refusal(version: &str) -> Option<String> {
    let mut parts = version.split('.').map(|p| p.parse::<u32>().unwrap_or(0));
    let (major, minor) = (parts.next().unwrap_or(0), parts.next().unwrap_or(0));
    if major == 8 && minor >= 6 {
        return None;
    }
    if major >= 9 {
        return Some(format!(
            "VoRANG needs Tcl 8.6, but pkg-config found Tcl {version} (Tcl 9 changed the C API). \
             Install Tcl 8.6 beside it and point pkg-config at it: on macOS \
             `brew install tcl-tk@8` and `export PKG_CONFIG_PATH=\"$(brew --prefix tcl-tk@8)/lib/pkgconfig\"`; \
             on Linux the tcl8.6-dev package"
        ));
    }
    Some(format!(
        "VoRANG needs Tcl 8.6, but pkg-config found Tcl {version}: install the Tcl 8.6 development files"
    ))
}
