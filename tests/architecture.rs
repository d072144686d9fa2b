//! The floor plan holds (docs/architecture.md): no module imports another that imports it back
//! (directly or through others), no product source file has more than 1,000 lines and no
//! function more than 200. Read from the sources, so a change that breaks the plan fails here.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_FILE_LINES: usize = 1000;
const MAX_FN_LINES: usize = 200;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The product source roots: each crate's `src/` (tests, benches and fuzz targets aside).
fn roots() -> Vec<PathBuf> {
    [
        "crates/vorang/src",
        "crates/vorang-tcl/src",
        "crates/vorang-mpi/src",
        "src",
        "python/src",
    ]
    .iter()
    .map(|r| repo().join(r))
    .collect()
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a file below its crate's `src/`: `render/span/avx2.rs` → render, span,
/// avx2; `render/mod.rs` → render; `lib.rs` → (empty).
fn module_of(root: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(root).unwrap().with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

/// The source without comments, string literals and `#[cfg(test)]` modules (tests may import
/// anything).
fn code_of(text: &str) -> String {
    let mut out = String::new();
    let mut in_tests = false;
    for line in text.lines() {
        let t = line.trim_start();
        if t.starts_with("#[cfg(test)]") {
            in_tests = true;
        }
        if in_tests {
            continue;
        }
        if t.starts_with("//") {
            continue;
        }
        let mut s = String::new();
        let mut in_str = false;
        let mut prev = ' ';
        for c in line.chars() {
            if c == '"' && prev != '\\' {
                in_str = !in_str;
            } else if !in_str {
                s.push(c);
            }
            prev = c;
        }
        out.push_str(&s);
        out.push('\n');
    }
    out
}

/// The module paths a file's code names: `crate::a::b`, `super::c`, and the items of `use`
/// groups (`use crate::a::{b, c::d}`), resolved against the file's module.
fn references(module: &[String], code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let bytes: Vec<char> = code.chars().collect();
    let text: String = bytes.iter().collect();
    for (start, _) in text
        .match_indices("crate::")
        .chain(text.match_indices("super::"))
    {
        if start > 0 {
            let before = bytes[start - 1];
            if before.is_alphanumeric() || before == '_' || before == ':' {
                continue;
            }
        }
        let rest = &text[start..];
        let (mut base, rest) = if let Some(r) = rest.strip_prefix("crate::") {
            (Vec::new(), r)
        } else {
            let mut base = module.to_vec();
            let mut r = rest;
            while let Some(next) = r.strip_prefix("super::") {
                base.pop();
                r = next;
            }
            (base, r)
        };
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let mut path = base.clone();
                path.extend(
                    item.trim()
                        .split("::")
                        .take_while(|s| {
                            !s.is_empty() && s.chars().all(|c| c.is_alphanumeric() || c == '_')
                        })
                        .map(str::to_string),
                );
                out.push(path);
            }
            continue;
        }
        base.extend(
            rest.split("::")
                .map(|s| {
                    s.chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect::<String>()
                })
                .take_while(|s| !s.is_empty()),
        );
        out.push(base);
    }
    out
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let mut problems = Vec::new();
    for root in roots() {
        let mut files = Vec::new();
        rust_files(&root, &mut files);
        let modules: BTreeSet<Vec<String>> = files.iter().map(|f| module_of(&root, f)).collect();
        // Edges between sibling modules: a file of `a/x…` naming `a/y…` makes x depend on y.
        let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
        for file in &files {
            let from = module_of(&root, file);
            let code = code_of(&std::fs::read_to_string(file).unwrap());
            for mut to in references(&from, &code) {
                // Only the part of the path that names modules.
                while !to.is_empty() && !modules.contains(&to) {
                    to.pop();
                }
                let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
                if common < from.len() && common < to.len() {
                    edges
                        .entry(from[..=common].to_vec())
                        .or_default()
                        .insert(to[..=common].to_vec());
                }
            }
        }
        // A cycle is an edge a → b with a path b → a.
        for (a, targets) in &edges {
            for b in targets {
                let mut seen = BTreeSet::new();
                let mut stack = vec![b.clone()];
                while let Some(m) = stack.pop() {
                    if &m == a {
                        problems.push(format!(
                            "{}: {} imports {}, which imports it back",
                            root.strip_prefix(repo()).unwrap().display(),
                            a.join("::"),
                            b.join("::")
                        ));
                        break;
                    }
                    if seen.insert(m.clone())
                        && let Some(next) = edges.get(&m)
                    {
                        stack.extend(next.iter().cloned());
                    }
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The functions of a file and their lengths in lines, from `fn` to the matching brace.
fn function_lengths(text: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let t = line.trim_start();
        let Some(at) = t.find("fn ") else { continue };
        let head = &t[..at];
        if !(head.is_empty()
            || head.ends_with("pub ")
            || head.ends_with("pub(crate) ")
            || head.ends_with("unsafe ")
            || head.ends_with("const ")
            || head.ends_with("extern \"C\" "))
            || t.starts_with("//")
        {
            continue;
        }
        let name: String = t[at + 3..]
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        // From the first `{` after the signature to the brace that closes it.
        let mut depth = 0i64;
        let mut opened = false;
        let mut end = None;
        'scan: for (j, l) in lines.iter().enumerate().skip(i) {
            for c in l.chars() {
                match c {
                    '{' => {
                        depth += 1;
                        opened = true;
                    }
                    '}' => depth -= 1,
                    ';' if !opened => break 'scan,
                    _ => {}
                }
                if opened && depth == 0 {
                    end = Some(j);
                    break 'scan;
                }
            }
        }
        if let Some(end) = end {
            out.push((name, i + 1, end - i + 1));
        }
    }
    out
}

#[test]
fn files_and_functions_stay_short() {
    let mut problems = Vec::new();
    for root in roots() {
        let mut files = Vec::new();
        rust_files(&root, &mut files);
        for file in files {
            let text = std::fs::read_to_string(&file).unwrap();
            let name = file.strip_prefix(repo()).unwrap().display().to_string();
            let n = text.lines().count();
            if n > MAX_FILE_LINES {
                problems.push(format!("{name}: {n} lines (at most {MAX_FILE_LINES})"));
            }
            for (f, line, len) in function_lengths(&text) {
                if len > MAX_FN_LINES {
                    problems.push(format!(
                        "{name}:{line}: fn {f} has {len} lines (at most {MAX_FN_LINES})"
                    ));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_checks_find_what_they_look_for() {
    // A function of 3 lines, found with its length.
    let f = function_lengths("pub fn a() {\n    1;\n}\nfn b();\n");
    assert_eq!(f, vec![("a".to_string(), 1, 3)]);
    // `use super::{x, y::z}` from a/b names a/x and a/y/z.
    let r = references(&["a".into(), "b".into()], "use super::{x, y::z};");
    assert_eq!(
        r,
        vec![
            vec!["a".to_string(), "x".into()],
            vec!["a".into(), "y".into(), "z".into()]
        ]
    );
}
