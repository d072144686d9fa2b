//! Script tests written in Tcl (`tests/scripts/*.tcl`), run by this one test.
//!
//! - `lib_*.tcl` are helpers (assertions, sourced files).
//! - `fail_*.tcl` must fail; their first line says where and how:
//!   `# expect: FILE:LINE: part of the message`.
//! - `warn_*.tcl` must run without error and warn: each `# expect: text` line names a warning
//!   that must appear among those the script gave, in that order.
//! - every other script must run without error; `$::tmp` is a fresh temporary folder.

use std::cell::RefCell;
use std::path::Path;
use std::rc::Rc;

use vorang_tcl::script::{Reporter, Runner};

/// The script's warnings, readable after the run.
#[derive(Clone, Default)]
struct Warnings(Rc<RefCell<Vec<String>>>);

impl Reporter for Warnings {
    fn info(&mut self, _text: &str) {}
    fn warn(&mut self, text: &str) {
        self.0.borrow_mut().push(text.to_string());
    }
}

/// Whether every expected text appears in some warning, in order.
fn warned_in_order(expected: &[String], warnings: &[String]) -> bool {
    let mut rest = warnings.iter();
    expected
        .iter()
        .all(|e| rest.any(|w| w.contains(e.as_str())))
}

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
        let warnings = Warnings::default();
        let mut runner = Runner::new(Box::new(warnings.clone()));
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
        } else if name.starts_with("warn_") {
            let expected: Vec<String> = std::fs::read_to_string(path)
                .unwrap()
                .lines()
                .filter_map(|l| l.strip_prefix("# expect: "))
                .map(str::to_string)
                .collect();
            let got = warnings.0.borrow().clone();
            if expected.is_empty() {
                failures.push(format!("{name}: no '# expect:' line"));
            } else if !warned_in_order(&expected, &got) {
                failures.push(format!("{name}: expected {expected:?}\n    got {got:?}"));
            }
        }
    }
    assert!(scripts.len() >= 8, "{} scripts", scripts.len());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
