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

/// The box as a binary file (4.1 with two element blocks, or 2.2 with two tags per element),
/// in either byte order.
fn box_binary(cubes: usize, v4: bool, big_endian: bool) -> Vec<u8> {
    let (nodes, tets) = kuhn_box([cubes, cubes, cubes + 1], [1.0; 3], 0.1, 3);
    let (n, m) = (nodes.len() as u64, tets.len() as u64);
    let mut b = Vec::new();
    let w4 = |b: &mut Vec<u8>, v: u32| {
        b.extend(if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        })
    };
    let w8 = |b: &mut Vec<u8>, v: u64| {
        b.extend(if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        })
    };
    let version = if v4 { "4.1" } else { "2.2" };
    b.extend(format!("$MeshFormat\n{version} 1 8\n").bytes());
    w4(&mut b, 1);
    b.extend(b"\n$EndMeshFormat\n$Nodes\n");
    if v4 {
        for v in [1, n, 1, n] {
            w8(&mut b, v);
        }
        for v in [3, 1, 0] {
            w4(&mut b, v);
        }
        w8(&mut b, n);
        (1..=n).for_each(|t| w8(&mut b, t));
        nodes.iter().flatten().for_each(|x| w8(&mut b, x.to_bits()));
    } else {
        b.extend(format!("{n}\n").bytes());
        for (i, p) in nodes.iter().enumerate() {
            w4(&mut b, i as u32 + 1);
            p.iter().for_each(|x| w8(&mut b, x.to_bits()));
        }
    }
    b.extend(b"\n$EndNodes\n$Elements\n");
    if v4 {
        for v in [2, m, 1, m] {
            w8(&mut b, v);
        }
        let half = tets.len() / 2;
        for (block, range) in [(1, 0..half), (2, half..tets.len())] {
            for v in [3, block, 4] {
                w4(&mut b, v);
            }
            w8(&mut b, range.len() as u64);
            for i in range {
                w8(&mut b, i as u64 + 1);
                tets[i].iter().for_each(|&k| w8(&mut b, u64::from(k) + 1));
            }
        }
    } else {
        b.extend(format!("{m}\n").bytes());
        for v in [4, m as u32, 2] {
            w4(&mut b, v);
        }
        for (i, t) in tets.iter().enumerate() {
            for v in [i as u32 + 1, 1 + i as u32 % 2, 1] {
                w4(&mut b, v);
            }
            t.iter().for_each(|&k| w4(&mut b, k + 1));
        }
    }
    b.extend(b"\n$EndElements\n");
    b
}

/// Binary sections are read in bulk and decoded on every core: the same nodes, cells and
/// physical groups as the ASCII file, in both byte orders.
#[test]
fn binary_files_read_as_ascii_ones() {
    for v4 in [true, false] {
        let ascii = box_lines(9, v4).join("\n") + "\n";
        let want = read(ascii.as_bytes(), "a.msh").unwrap();
        for big in [false, true] {
            let got = read(&box_binary(9, v4, big), "b.msh").unwrap();
            let case = format!("v4 {v4}, big-endian {big}");
            assert!(got.nodes == want.nodes, "{case}: nodes");
            assert!(got.cells == want.cells, "{case}: cells");
            // Lines in binary data count stray newline bytes: only the values must agree.
            let arrays = |d: &super::MeshDescription| {
                let a = d.cell_arrays.iter();
                a.map(|a| (a.name.clone(), a.values.clone()))
                    .collect::<Vec<_>>()
            };
            assert!(arrays(&got) == arrays(&want), "{case}: cell arrays");
            assert_eq!(want.cell_arrays.len(), usize::from(!v4), "{case}");
        }
    }
}

/// Node tags become node indices on every core: a mixed 2.2 file whose tags are not the node
/// numbers, with elements Gmsh and VTK number alike (the tetrahedron), one node pair apart (the
/// 10-node tetrahedron) and all apart (the 20-node hexahedron), between them a triangle that
/// names an unknown node (kept as node 0: it is skipped later). A volume element naming an
/// unknown tag is refused at its own line, the first of two such.
#[test]
fn node_tags_become_indices_in_every_element() {
    // Node k (0-based) has tag 200 − 3k: no tag is its index.
    let tag = |k: usize| 200 - 3 * k;
    let mut l = vec!["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$Nodes", "20"]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>();
    l.extend((0..20).map(|k| format!("{} {k} {} 0.5", tag(k), k % 3)));
    l.extend(["$EndNodes".into(), "$Elements".into(), "4".into()]);
    let row = |n: usize, ty: usize, nodes: &[usize]| {
        let tags: Vec<String> = nodes.iter().map(|&k| tag(k).to_string()).collect();
        format!("{n} {ty} 2 1 1 {}", tags.join(" "))
    };
    let (tet, tet10, hex20) = ([3, 1, 4, 0], [9, 8, 7, 6, 5, 4, 3, 2, 1, 0], (0..20).rev());
    let hex20: Vec<usize> = hex20.collect();
    l.push(row(1, 4, &tet));
    l.push(row(2, 2, &[2, 5]).replace(" 185", " 185 999"));
    l.push(row(3, 11, &tet10));
    l.push(row(4, 17, &hex20));
    l.push("$EndElements".into());
    let text = l.join("\n") + "\n";
    let d = read(text.as_bytes(), "t.msh").unwrap();
    let cells = &d.cells;
    assert_eq!(cells.types, [10, 5, 24, 25]);
    assert_eq!(cells.nodes(0), [3, 1, 4, 0]);
    assert_eq!(
        cells.nodes(1),
        [2, 5, 0],
        "the unknown tag 999 becomes node 0"
    );
    assert_eq!(
        cells.nodes(2),
        [9, 8, 7, 6, 5, 4, 3, 2, 0, 1],
        "VTK's last two swapped"
    );
    // VTK's node i is Gmsh's node ORDER[i] (edges by first corner in Gmsh, around in VTK).
    const ORDER: [usize; 20] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15,
    ];
    let want: Vec<u32> = ORDER.iter().map(|&g| hex20[g] as u32).collect();
    assert_eq!(cells.nodes(3), want);

    // Two tetrahedra with unknown tags: the first one (element 3, line 31) is reported.
    let mut bad = l.clone();
    bad[30] = row(3, 4, &[1, 2, 3, 4]).replace(" 191", " 998");
    bad[31] = row(4, 4, &[1, 2, 3, 4]).replace(" 194", " 997");
    let e = read((bad.join("\n") + "\n").as_bytes(), "t.msh").unwrap_err();
    assert_eq!(e.line, 31, "{e}");
    assert!(
        e.to_string()
            .contains("element 3 refers to node tag 998, which $Nodes does not define"),
        "{e}"
    );
}
