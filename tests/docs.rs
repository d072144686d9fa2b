//! `docs/commands.md` is generated from the program's tables (`vorang_tcl::script::reference`): this
//! test fails when a command, method or interpolator changes and the document was not
//! regenerated. `VORANG_BLESS=1 cargo test --test docs` rewrites it.

use std::path::Path;

#[test]
fn the_command_reference_is_current() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/commands.md");
    let want = vorang_tcl::script::reference::markdown();
    if std::env::var_os("VORANG_BLESS").is_some() {
        std::fs::write(&path, &want).unwrap();
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/commands.md is out of date: run `VORANG_BLESS=1 cargo test --test docs`"
    );
    // Every command is in it, under its own heading.
    for c in vorang_tcl::script::COMMANDS {
        assert!(have.contains(&format!("### `{}", c.name)), "{}", c.name);
    }
}
