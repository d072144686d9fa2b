//! The examples of `docs/guide.md` are real: its HyperMesh, colormap and alphamap blocks are
//! written to files and its Tcl block renders them, so the guide cannot drift from the program.

use std::path::Path;

use vorang::script::{Collect, Runner};

/// The fenced blocks of `text`: (info string, body).
fn blocks(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if let Some(info) = line.strip_prefix("```") {
            let mut body = String::new();
            for l in lines.by_ref() {
                if l.starts_with("```") {
                    break;
                }
                body.push_str(l);
                body.push('\n');
            }
            out.push((info.trim().to_string(), body));
        }
    }
    out
}

#[test]
fn the_guide_s_examples_load_and_render() {
    let guide =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/guide.md"))
            .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let mut files = 0;
    let mut script = None;
    for (info, body) in blocks(&guide) {
        let mut words = info.split_whitespace();
        match (words.next(), words.next()) {
            (Some("hypermesh" | "colormap" | "alphamap"), Some(name)) => {
                std::fs::write(tmp.path().join(name), body).unwrap();
                files += 1;
            }
            (Some("tcl"), _) => script = Some(body),
            _ => {}
        }
    }
    assert_eq!(files, 3, "the guide's example files");
    let script = script.expect("the guide's Tcl example");
    let path = tmp.path().join("guide.tcl");
    std::fs::write(&path, format!("imagesize 48 40\n{script}")).unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    runner
        .run_file(&path)
        .unwrap_or_else(|e| panic!("{e}\n{}", e.trace));
    let written = runner.session().written.clone();
    assert_eq!(written.len(), 4, "{written:?}");
    for w in &written {
        let img = image::open(w).unwrap().to_rgb8();
        // Something was drawn: not every pixel is the white background.
        assert!(
            img.pixels().any(|p| p.0 != [255, 255, 255]),
            "{}",
            w.display()
        );
    }
}
