//! Rows parsed on every core ([`crate::formats::lines`]) must read exactly as token by token:
//! the same mesh, or the same first error at the same line. Token by token is the reference:
//! files written by Gmsh, and generated 2.2 and 4.1 files spoilt at random rows, are read both
//! ways and compared.

use super::read;
use crate::formats::lines::TOKENS_ONLY;
use crate::mesh::generate::{SplitMix64, kuhn_box};

fn both_ways(text: &[u8], what: &str) -> bool {
    let fast = read(text, "t.msh");
    TOKENS_ONLY.with(|t| t.set(true));
    let tokens = read(text, "t.msh");
    TOKENS_ONLY.with(|t| t.set(false));
    assert_eq!(fast, tokens, "{what}");
    tokens.is_ok()
}

/// A jittered box as a 4.1 (two element blocks) or 2.2 ASCII file, as lines.
fn box_lines(cubes: usize, v4: bool) -> Vec<String> {
    let (nodes, tets) = kuhn_box([cubes, cubes, cubes + 1], [1.0; 3], 0.1, 3);
    let (n, m) = (nodes.len(), tets.len());
    let mut l = vec!["$MeshFormat".to_string()];
    l.push(if v4 { "4.1 0 8" } else { "2.2 0 8" }.into());
    l.extend(["$EndMeshFormat".into(), "$Nodes".into()]);
    let xyz = |p: &[f64; 3]| format!("{} {} {}", p[0], p[1], p[2]);
    if v4 {
        l.push(format!("1 {n} 1 {n}"));
        l.push(format!("3 1 0 {n}"));
        l.extend((1..=n).map(|t| t.to_string()));
        l.extend(nodes.iter().map(xyz));
    } else {
        l.push(n.to_string());
        l.extend(
            nodes
                .iter()
                .enumerate()
                .map(|(i, p)| format!("{} {}", i + 1, xyz(p))),
        );
    }
    l.extend(["$EndNodes".into(), "$Elements".into()]);
    let tet = |t: &[u32; 4]| format!("{} {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1, t[3] + 1);
    if v4 {
        let half = m / 2;
        l.push(format!("2 {m} 1 {m}"));
        for (b, range) in [(1, 0..half), (2, half..m)] {
            l.push(format!("3 {b} 4 {}", range.len()));
            l.extend(range.map(|i| format!("{} {}", i + 1, tet(&tets[i]))));
        }
    } else {
        l.push(m.to_string());
        l.extend((0..m).map(|i| format!("{} 4 2 {} 1 {}", i + 1, 1 + i % 2, tet(&tets[i]))));
    }
    l.push("$EndElements".into());
    l
}

fn spoil(lines: &mut Vec<String>, kind: u64, rng: &mut SplitMix64) -> Vec<u8> {
    let at = 6 + (rng.next_u64() as usize) % (lines.len() - 7);
    let section = |s: &str| s.starts_with('$');
    match kind {
        1 if !section(&lines[at]) => lines[at] = lines[at].replacen(' ', " x ", 1),
        2 if !section(&lines[at]) => {
            let cut = lines[at].rfind(' ').unwrap_or(0);
            lines[at].truncate(cut);
        }
        3 => lines[at].push_str(" 7"),
        4 => lines.insert(at, String::new()),
        5 if !section(&lines[at]) => lines[at] = lines[at].replacen(' ', " +", 1),
        6 if !section(&lines[at]) => {
            // A node tag or element node that is not defined, or a repeated node tag.
            let last = lines[at].rfind(' ').map_or(0, |i| i + 1);
            lines[at].replace_range(last.., "99999999");
        }
        7 => lines[at] = lines[at].replace(' ', "  \t"),
        8 if !section(&lines[at]) => lines[at] = lines[at].replacen('1', "-1", 1),
        _ => {}
    }
    let eol = if kind == 9 { "\r\n" } else { "\n" };
    let mut text = lines.join(eol).into_bytes();
    if kind != 10 {
        text.extend_from_slice(eol.as_bytes());
    }
    if kind == 11 {
        let cut = 100 + (rng.next_u64() as usize) % (text.len() - 100);
        text.truncate(cut);
    }
    text
}

#[test]
fn rows_on_every_core_read_as_tokens() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/formats");
    for f in [
        "gmsh_41_ascii.msh",
        "gmsh_22_ascii.msh",
        "cube_41_entities.msh",
        "gmsh_hex27.msh",
    ] {
        let text = std::fs::read(dir.join(f)).unwrap();
        assert!(both_ways(&text, f), "{f} reads");
    }
    let mut rng = SplitMix64(7);
    let mut failed = 0;
    for case in 0..48u64 {
        // 5–12 cubes a side: blocks of up to 10k rows, several pieces each.
        let cubes = 5 + (rng.next_u64() % 8) as usize;
        let mut lines = box_lines(cubes, case % 2 == 0);
        let text = spoil(&mut lines, (case / 2) % 12, &mut rng);
        failed += usize::from(!both_ways(&text, &format!("case {case}")));
    }
    assert!(
        failed >= 14,
        "only {failed} of 48 spoilt files failed to read"
    );
}
