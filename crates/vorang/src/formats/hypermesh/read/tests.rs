//! ASCII blocks read in parallel batches straight from the reader's buffer must read exactly as
//! line by line: the same volume, or the same first error at the same line. A reader whose
//! buffer holds one byte never has a whole line in it, so it reads every line by itself; it is
//! the reference the batched readers (the whole text as one buffer, and buffers of every size
//! between) are held to, on valid files and on files spoilt at random rows.

use std::io::BufReader;

use super::read;
use crate::mesh::generate::{SplitMix64, kuhn_box};

/// A small-layout ASCII file of a jittered box: nodes, tetrahedra and a node field, as lines.
fn box_lines(cubes: usize) -> Vec<String> {
    let (nodes, tets) = kuhn_box([cubes, cubes, cubes + 1], [1.0; 3], 0.1, 3);
    let mut l = vec![
        "# HyperMesh 3D ASCII 0.7".to_string(),
        format!("nNodes = {}", nodes.len()),
        format!("nTetrahedra = {}", tets.len()),
        "Nodes { double[3] Coordinates } = @1".into(),
        "Tetrahedra { int[4] Nodes } = @2".into(),
        "NodeData { float } = @3".into(),
        "Field \"t\" { float } = Linear(@3)".into(),
        "@1".into(),
    ];
    l.extend(nodes.iter().map(|p| format!("{} {} {}", p[0], p[1], p[2])));
    l.push("@2".into());
    l.extend(
        tets.iter()
            .map(|t| format!("{} {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1, t[3] + 1)),
    );
    l.push("@3".into());
    l.extend(nodes.iter().map(|p| format!("{}", p[0] + 2.0 * p[2])));
    l
}

/// Spoils the file in one of several ways at a random line (kind 0 leaves it whole).
fn spoil(lines: &mut Vec<String>, kind: u64, rng: &mut SplitMix64) -> Vec<u8> {
    let at = 8 + (rng.next_u64() as usize) % (lines.len() - 8);
    let marker = |s: &str| s.starts_with('@');
    match kind {
        1 if !marker(&lines[at]) => lines[at] = lines[at].replacen(' ', " x ", 1),
        2 if !marker(&lines[at]) => {
            let cut = lines[at].rfind(' ').unwrap_or(0);
            lines[at].truncate(cut);
        }
        3 => lines[at].push_str(" 7"),
        4 => lines.insert(at, "  # a comment".into()),
        5 => lines.insert(at, String::new()),
        6 => {
            // An extra row just before the next marker (or at the end).
            let end = (at..lines.len())
                .find(|&i| marker(&lines[i]))
                .unwrap_or(lines.len());
            lines.insert(end, lines[end - 1].clone());
        }
        7 => {
            lines.remove(at);
        }
        8 => lines.insert(at, "@3".into()),
        9 => lines[at] = "1e999 2 3 4".into(),
        _ => {}
    }
    let eol = if kind == 10 { "\r\n" } else { "\n" };
    let mut text = lines.join(eol).into_bytes();
    text.extend_from_slice(eol.as_bytes());
    if kind == 11 {
        // Cut at a random byte: the last line may lack its end.
        let cut = 200 + (rng.next_u64() as usize) % (text.len() - 200);
        text.truncate(cut);
    }
    text
}

#[test]
fn batches_read_as_line_by_line() {
    let mut rng = SplitMix64(11);
    let mut errors = 0;
    for case in 0..36u64 {
        // 6–14 cubes a side: up to 19k rows, blocks of several pieces and batches.
        let cubes = 6 + (rng.next_u64() % 9) as usize;
        let mut lines = box_lines(cubes);
        let text = spoil(&mut lines, case % 12, &mut rng);
        let name = "box.hmesh";
        let one_by_one = read(BufReader::with_capacity(1, &text[..]), name, None);
        let whole = read(&text[..], name, Some(text.len() as u64));
        let cap = 16 + (rng.next_u64() as usize) % 300_000;
        let buffered = read(BufReader::with_capacity(cap, &text[..]), name, None);
        assert_eq!(whole, one_by_one, "case {case}: whole text");
        assert_eq!(buffered, one_by_one, "case {case}: buffer of {cap} bytes");
        errors += usize::from(one_by_one.is_err());
    }
    // The spoiling must mostly spoil (a comment, a blank line or a CR do not).
    assert!(errors >= 18, "{errors} of 36 cases failed to read");
}
