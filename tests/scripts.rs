//! Script tests written in Tcl (`tests/scripts/*.tcl`), run by this one test.
//!
//! - `lib_*.tcl` are helpers (assertions, sourced files).
//! - `fail_*.tcl` must fail; their first line says where and how:
//!   `# expect: FILE:LINE: part of the message`.
//! - every other script must run without error; `$::tmp` is a fresh temporary folder.

use std::path::Path;

use vorang_tcl::script::{Collect, Runner};

#[test]
fn tcl_script_tests() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts");
    let mut scripts: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "tcl"))
        .filter(|p| !p.file_name().unwrap().to_string_lossy().starts_with("lib_"))
        .collect();
    scripts.sort();
    let mut failures = Vec::new();
    for path in &scripts {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let tmp = tempfile::tempdir().unwrap();
        let mut runner = Runner::new(Box::new(Collect::default()));
        let setup = format!("set ::tmp {{{}}}", tmp.path().display());
        runner.run_string(&setup, "setup").unwrap();
        runner.run_file(&dir.join("lib_helpers.tcl")).unwrap();
        let result = runner.run_file(path);
        if name.starts_with("fail_") {
            let first = std::fs::read_to_string(path)
                .unwrap()
                .lines()
                .next()
                .unwrap_or("")
                .to_string();
            let expect = first
                .strip_prefix("# expect: ")
                .unwrap_or_else(|| panic!("{name}: no '# expect:' line"));
            let mut parts = expect.splitn(3, ':');
            let (file, line, fragment) = (
                parts.next().unwrap(),
                parts.next().unwrap(),
                parts.next().unwrap_or("").trim(),
            );
            match result {
                Ok(()) => failures.push(format!("{name}: ran without error")),
                Err(e) => {
                    if !e.file.ends_with(file)
                        || e.line.to_string() != line
                        || !e.message.contains(fragment)
                    {
                        failures.push(format!("{name}: expected {expect}\n    got {e}"));
                    }
                }
            }
        } else if let Err(e) = result {
            failures.push(format!("{name}: {e}\n{}", e.trace));
        }
    }
    assert!(scripts.len() >= 8, "{} scripts", scripts.len());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
