//! Every file in `tests/bad/` must fail with an error on the line its second line states:
//! `# expect: line N: <part of the message>`. Dropping a new file there adds a case.

use std::path::Path;

use vorang::{Error, Volume};

fn expectation(text: &str) -> Option<(usize, String)> {
    let line = text.lines().nth(1)?;
    let rest = line.strip_prefix("# expect: line ")?;
    let (n, msg) = rest.split_once(": ")?;
    Some((n.parse().ok()?, msg.to_string()))
}

#[test]
fn every_bad_hypermesh_file_fails_at_the_stated_line() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad");
    let mut checked = 0;
    let mut failures = Vec::new();
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "hmesh"))
    {
        let text = std::fs::read_to_string(&path).unwrap();
        let (line, fragment) = if text.is_empty() {
            (1, "empty file".to_string())
        } else {
            expectation(&text)
                .unwrap_or_else(|| panic!("{}: no '# expect: line N: …' on line 2", path.display()))
        };
        let result = Volume::load(&path);
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        match result {
            Ok(_) => failures.push(format!("{name}: read without error")),
            Err(Error::Parse(e)) => {
                let shown = e.to_string();
                if e.line != line
                    || !e.message.contains(&fragment)
                    || !shown.starts_with(&format!("{}:{line}: ", path.display()))
                {
                    failures.push(format!(
                        "{name}: expected line {line} '{fragment}', got: {shown}"
                    ));
                }
            }
            Err(other) => failures.push(format!("{name}: not a located error: {other}")),
        }
        checked += 1;
    }
    assert!(checked >= 40, "only {checked} bad files found");
    assert!(
        failures.is_empty(),
        "{} of {checked} bad files misbehaved:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
