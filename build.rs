//! Links the Tcl 8.6 library (DESIGN §3a: the script language is real Tcl), found with
//! pkg-config. On Debian/Ubuntu: `apt-get install tcl-dev`; on macOS: `brew install tcl-tk`.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    for name in ["tcl", "tcl8.6", "tcl86"] {
        if pkg_config::Config::new()
            .atleast_version("8.6")
            .probe(name)
            .is_ok()
        {
            return;
        }
    }
    // pkg-config knows no Tcl: try the usual library name and let the linker report it.
    println!(
        "cargo:warning=pkg-config found no Tcl 8.6; trying -ltcl8.6 (install the Tcl development package, e.g. 'apt-get install tcl-dev')"
    );
    println!("cargo:rustc-link-lib=tcl8.6");
}
