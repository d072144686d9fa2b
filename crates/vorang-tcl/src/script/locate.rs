//! Finding the file and line of a failing command.
//!
//! A failing VoRANG command asks Tcl where it was called from (`info frame -1`, exact inside
//! procedures and loop bodies since Tcl 8.5). For errors Tcl raises itself, its `errorInfo`
//! trace is walked from the innermost command outwards: each `("for" body line N)` adds N − 1
//! lines to the body's first line, until an anchor — `(file "x.tcl" line N)` or a procedure whose
//! body's first line was recorded when it was defined.

use crate::tcl::{Interp, TclError};

/// `(file, line)` of the command that called the running command; the file is empty for
/// commands evaluated from a string.
pub fn caller(interp: &Interp) -> (String, usize) {
    let Ok(frame) = interp.eval("info frame -1") else {
        return (String::new(), 0);
    };
    let Ok(words) = interp.split_list(&frame) else {
        return (String::new(), 0);
    };
    let get = |key: &str| {
        words
            .chunks(2)
            .find(|kv| kv[0] == key)
            .and_then(|kv| kv.get(1).cloned())
    };
    let line = get("line").and_then(|l| l.parse().ok()).unwrap_or(0);
    (get("file").unwrap_or_default(), line)
}

/// The file and line of the failure described by `e`. `label` names a script evaluated from a
/// string; `proc_start(name)` gives the file and first body line of a procedure.
pub fn from_trace(
    e: &TclError,
    label: &str,
    proc_start: impl Fn(&str) -> Option<(String, usize)>,
) -> (String, usize) {
    let mut extra = 0usize;
    for line in e.info.lines() {
        let l = line.trim();
        let Some(inner) = l.strip_prefix('(').and_then(|r| r.strip_suffix(')')) else {
            continue;
        };
        let Some(n) = inner
            .rsplit_once(" line ")
            .and_then(|(_, n)| n.trim().parse::<usize>().ok())
        else {
            continue;
        };
        if let Some(rest) = inner.strip_prefix("file \"") {
            let file = rest.rsplit_once("\" line ").map_or(rest, |(f, _)| f);
            return (file.to_string(), n + extra);
        }
        if let Some(rest) = inner.strip_prefix("procedure \"") {
            let name = rest.split('"').next().unwrap_or("");
            let tail = name.rsplit("::").next().unwrap_or(name);
            match proc_start(tail) {
                Some((file, start)) => return (file, start + n - 1 + extra),
                // A procedure defined from a string: report where it was called instead.
                None => extra = 0,
            }
            continue;
        }
        // ("for" body line N), ("if" then script line N), ("eval" body line N) …: a script
        // that starts on the line of the command holding it.
        extra += n - 1;
    }
    // No file anchor: a string evaluated at top level; Tcl's error line counts within it.
    (label.to_string(), e.line.max(1) + extra)
}

/// A path as short as possible: relative to the current folder when it lies inside it.
pub fn display_path(path: &str) -> String {
    let p = std::path::Path::new(path);
    if p.is_absolute()
        && let Ok(cwd) = std::env::current_dir()
        && let Ok(rel) = p.strip_prefix(&cwd)
    {
        return rel.display().to_string();
    }
    path.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(info: &str, line: usize) -> TclError {
        TclError {
            message: String::new(),
            info: info.into(),
            line,
        }
    }

    #[test]
    fn traces_through_loop_bodies_to_the_file() {
        let e = err(
            "invalid command name \"bogus\"\n    while executing\n\"bogus $i\"\n    (\"if\" then script line 2)\n    invoked from within\n\"if {$i} {\"\n    (\"for\" body line 3)\n    invoked from within\n\"for {set i 0} {$i < 3} {incr i} {\"\n    (file \"x.tcl\" line 10)\n    invoked from within\n\"source x.tcl\"",
            1,
        );
        assert_eq!(from_trace(&e, "-e", |_| None), ("x.tcl".into(), 10 + 2 + 1));
    }

    #[test]
    fn procedures_use_their_recorded_body() {
        let e = err(
            "boom\n    while executing\n\"bogus $n\"\n    (procedure \"foo\" line 4)\n    invoked from within\n\"foo 3\"\n    (file \"t.tcl\" line 16)",
            1,
        );
        assert_eq!(
            from_trace(&e, "-e", |n| (n == "foo")
                .then(|| ("t.tcl".to_string(), 11))),
            ("t.tcl".into(), 14)
        );
        // Unknown procedure: the call site.
        assert_eq!(from_trace(&e, "-e", |_| None), ("t.tcl".into(), 16));
    }

    #[test]
    fn strings_fall_back_to_the_error_line() {
        let e = err("boom\n    while executing\n\"bogus\"", 3);
        assert_eq!(from_trace(&e, "-e", |_| None), ("-e".into(), 3));
    }
}
