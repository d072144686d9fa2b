//! Links the Tcl 8.6 library (docs/architecture.md: the script language is real Tcl), found with
//! pkg-config. On Debian/Ubuntu: `apt-get install tcl-dev`; on macOS: `brew install tcl-tk@8`.
//!
//! Tcl 9 changed its C API (`Tcl_Size` lengths, removed functions), which VoRANG's bindings do not
//! speak: a Tcl 9 found by pkg-config is refused with a clear message ([`tcl_check::refusal`])
//! instead of a program that fails to link or misbehaves.

#[path = "build/tcl_check.rs"]
mod tcl_check;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=build/tcl_check.rs");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    let mut refused = None;
    for name in ["tcl", "tcl8.6", "tcl86"] {
        let Ok(lib) = pkg_config::Config::new().cargo_metadata(false).probe(name) else {
            continue;
        };
        match tcl_check::refusal(&lib.version) {
            None => {
                // A usable Tcl: now emit its link flags.
                pkg_config::Config::new()
                    .probe(name)
                    .expect("probed just before");
                return;
            }
            Some(why) => refused = Some(why),
        }
    }
    if let Some(why) = refused {
        panic!("{why}");
    }
    // pkg-config knows no Tcl: try the usual library name and let the linker report it.
    println!(
        "cargo:warning=pkg-config found no Tcl 8.6; trying -ltcl8.6 (install the Tcl development package, e.g. 'apt-get install tcl-dev')"
    );
    println!("cargo:rustc-link-lib=tcl8.6");
}
