//! Black-box tests of HyperMesh reading and writing on hand-written files (`tests/data`).

#![allow(clippy::needless_range_loop)]

use std::path::{Path, PathBuf};

use vorang::Volume;
use vorang::field::Interpolator;
use vorang::hypermesh::{self, Encoding, Layout, ScalarType, Values, WriteOptions};
use vorang::mesh::barycentric;

fn data_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn load(name: &str) -> Volume {
    let (vol, _) = Volume::load(&data_path(name)).unwrap_or_else(|e| panic!("{e}"));
    vol
}

fn sorted_cells(vol: &Volume) -> Vec<[u32; 4]> {
    vol.mesh
        .tets()
        .iter()
        .map(|t| {
            let mut t = *t;
            t.sort_unstable();
            t
        })
        .collect()
}

#[test]
fn every_coding_gives_the_same_mesh() {
    let reference = load("two_tets_nodes.hmesh");
    assert_eq!(sorted_cells(&reference), vec![[0, 1, 2, 3], [1, 2, 3, 4]]);
    assert_eq!(reference.mesh.neighbor(0, 0), Some(1));
    assert_eq!(reference.mesh.neighbor(1, 3), Some(0));
    assert_eq!(reference.mesh.boundary_face_count(), 6);
    for name in [
        "two_tets_edges.hmesh",
        "two_tets_triangles.hmesh",
        "two_tets_all_codings.hmesh",
    ] {
        let v = load(name);
        assert_eq!(v.mesh.nodes(), reference.mesh.nodes(), "{name}");
        assert_eq!(v.mesh.tets(), reference.mesh.tets(), "{name}");
        assert_eq!(v.mesh.neighbors(), reference.mesh.neighbors(), "{name}");
    }
    let edges = load("two_tets_edges.hmesh");
    assert_eq!(edges.coord_type, ScalarType::Float);
    assert_eq!(
        edges.edges.as_ref().unwrap()[8],
        [4, 3],
        "edge directions are kept"
    );
    let mut first = edges.triangles.as_ref().unwrap()[0];
    first.sort_unstable();
    assert_eq!(first, [1, 2, 3]);
}

#[test]
fn negative_cells_are_reoriented_with_one_warning_and_keep_their_data() {
    let file = hypermesh::read_file(&data_path("two_tets_negative.hmesh")).unwrap();
    assert_eq!(file.warnings.len(), 1);
    assert!(
        file.warnings[0].message.contains("2 of 2 tetrahedra"),
        "{}",
        file.warnings[0]
    );
    let vol = Volume::from_file(file).unwrap();
    assert_eq!(vol.mesh.reoriented(), 2);
    let f = vol.field(0).unwrap();
    let mut v = [0.0];
    f.eval(&vol.support(), 1, &[0.25; 4], [0.0; 3], &mut v);
    assert_eq!(v[0], 20.0);
    let mut nodes = vol.mesh.tets()[1];
    nodes.sort_unstable();
    assert_eq!(nodes, [1, 2, 3, 4]);
}

#[test]
fn every_type_is_read_exactly() {
    let vol = load("two_tets_data.hmesh");
    let raw = &vol.data.raw;
    assert_eq!(raw.len(), 16);
    assert_eq!(raw[0].values, Values::U8(vec![0, 255, 7, 12, 3]));
    assert_eq!(raw[1].values, Values::I16(vec![-32768, 32767, 0, -1, 5]));
    assert_eq!(raw[2].ty.to_string(), "int[2]");
    assert_eq!(raw[2].value(2, 0), 2147483647.0);
    assert_eq!(raw[2].value(2, 1), -2147483648.0);
    assert_eq!(raw[3].ty.scalar, ScalarType::Long);
    assert_eq!(raw[4].denominator.as_deref(), Some("Color"));
    assert_eq!(
        raw[4].values,
        Values::F32(vec![
            1., 0., 0., 0., 1., 0., 0., 0., 1., 0.5, 0.5, 0., 0.25, 0.5, 0.1
        ])
    );
    assert_eq!(raw[5].value(4, 0), 39.5);
    assert_eq!((raw[6].value(1, 0), raw[6].imag(1, 0)), (2.0, -0.5));
    assert_eq!((raw[7].value(3, 1), raw[7].imag(3, 1)), (15.0, 16.0));
    assert_eq!(raw[10].denominator.as_deref(), Some("ClassId"));
    assert_eq!(raw[12].values, Values::U8(vec![0, 7]));
    assert_eq!(raw[15].elements(), 2);
    let mats = vol.data.materials.as_ref().unwrap();
    assert_eq!(mats.get(7).unwrap().name, "Bone");
    assert_eq!(mats.get(7).unwrap().prop("rho"), Some(1900.0));
    assert_eq!(vol.data.fields.len(), 8);
    let names: Vec<_> = vol.data.fields.iter().map(|f| f.interpolator).collect();
    assert_eq!(
        names,
        [
            Interpolator::Linear,
            Interpolator::Linear,
            Interpolator::Constant,
            Interpolator::GaussTest,
            Interpolator::EdgeElem,
            Interpolator::EdgeElemSar,
            Interpolator::HigherOrder,
            Interpolator::Linear
        ]
    );
    assert!(vol.field(2).unwrap().is_byte_constant(&vol.data.raw));
    assert!(!vol.field(0).unwrap().is_byte_constant(&vol.data.raw));
}

/// Evaluates field `n` at the point `p` of cell `cell`.
fn eval_at(vol: &Volume, n: usize, cell: usize, p: [f64; 3]) -> Vec<f64> {
    let (l, _) = barycentric(&vol.mesh.corners(cell), p).unwrap();
    let f = vol.field(n).unwrap();
    let mut out = vec![0.0; f.components()];
    f.eval(&vol.support(), cell, &l, p, &mut out);
    out
}

#[test]
fn linear_constant_and_gauss_fields_have_their_analytic_values() {
    let vol = load("two_tets_data.hmesh");
    // Linear: f = 36.5 + 0.5x + 1.75y + 4.5z on cell 0 (values at the unit corners).
    let p = [0.2, 0.1, 0.3];
    let t = eval_at(&vol, 0, 0, p)[0];
    assert!(
        (t - (36.5 + 0.5 * 0.2 + 1.75 * 0.1 + 4.5 * 0.3)).abs() < 1e-12,
        "{t}"
    );
    let g = vol
        .field(0)
        .unwrap()
        .gradient(&vol.support(), 0, 0)
        .unwrap();
    for (a, b) in g.iter().zip([0.5, 1.75, 4.5]) {
        assert!((a - b).abs() < 1e-12);
    }
    // Vector linear: at node 2 the colour is (1,0,0)… at the centroid of cell 0 the mean.
    let c = eval_at(&vol, 1, 0, [0.25; 3]);
    assert!(
        (c[0] - 0.375).abs() < 1e-7 && (c[1] - 0.375).abs() < 1e-7 && (c[2] - 0.25).abs() < 1e-7,
        "{c:?}"
    );
    assert_eq!(eval_at(&vol, 2, 1, [0.5; 3]), vec![7.0]);
    // GaussTest: 2·exp(−|x|²/1) − exp(−|x−(1,1,1)|²/0.25)
    let p = [0.1, 0.2, 0.3];
    let d0: f64 = p.iter().map(|v| v * v).sum();
    let d1: f64 = p.iter().map(|v| (v - 1.0) * (v - 1.0)).sum();
    let expect = 2.0 * (-d0).exp() - (-d1 / 0.25).exp();
    assert!((eval_at(&vol, 3, 0, p)[0] - expect).abs() < 1e-14);
    // Complex linear fields give (re, im) pairs.
    let z = eval_at(&vol, 7, 0, [0.0, 0.0, 0.0]);
    assert_eq!(z, vec![1.0, 0.5]);
}

#[test]
fn edge_elements_have_the_edge_values_as_tangential_integrals() {
    // For Whitney 1-forms, E·(b − a) on the edge a → b equals that edge's value, everywhere on
    // the edge; the tangential component of the other edges' functions vanishes there.
    let vol = load("two_tets_data.hmesh");
    let nodes = vol.mesh.nodes();
    let edges = vol.edges.as_ref().unwrap();
    let values = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
    for (e, &[a, b]) in edges.iter().enumerate() {
        let (pa, pb) = (nodes[a as usize], nodes[b as usize]);
        let cell = (0..2)
            .find(|&c| vol.mesh.tets()[c].contains(&a) && vol.mesh.tets()[c].contains(&b))
            .unwrap();
        for s in [0.1, 0.5, 0.8] {
            let p = [0, 1, 2].map(|k| pa[k] + s * (pb[k] - pa[k]));
            let field = eval_at(&vol, 4, cell, p);
            let t: f64 = (0..3).map(|k| field[k] * (pb[k] - pa[k])).sum();
            assert!((t - values[e]).abs() < 1e-12, "edge {e}: {t}");
        }
    }
}

#[test]
fn sar_is_half_sigma_e_squared_over_rho() {
    let vol = load("two_tets_data.hmesh");
    // Complex edge values (re, im) of @ec; rebuild E = E(re) + i E(im) by evaluating EdgeElem on
    // real-only copies is overkill: check the ratio between two materials instead, and the
    // formula directly at a point by recomputing the Whitney sum.
    let p = [0.7, 0.6, 0.5];
    let cell = 1; // Bone: sigma 2.5, rho 1900
    let (l, g) = barycentric(&vol.mesh.corners(cell), p).unwrap();
    let tet = vol.mesh.tets()[cell];
    let edges = vol.edges.as_ref().unwrap();
    let ec = &vol.data.raw[9];
    let (mut re, mut im) = ([0.0; 3], [0.0; 3]);
    for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        let (a, b) = (tet[i], tet[j]);
        let (e, sign) = edges
            .iter()
            .enumerate()
            .find_map(|(k, &[f, t])| match (f == a && t == b, f == b && t == a) {
                (true, _) => Some((k, 1.0)),
                (_, true) => Some((k, -1.0)),
                _ => None,
            })
            .unwrap();
        for d in 0..3 {
            let w = l[i] * g[j][d] - l[j] * g[i][d];
            re[d] += sign * ec.value(e, 0) * w;
            im[d] += sign * ec.imag(e, 0) * w;
        }
    }
    let e2: f64 = (0..3).map(|d| re[d] * re[d] + im[d] * im[d]).sum();
    let sar = eval_at(&vol, 5, cell, p)[0];
    assert!(
        (sar - 0.5 * 2.5 * e2 / 1900.0).abs() < 1e-12 * e2.max(1.0),
        "{sar}"
    );
}

#[test]
fn higher_order_interpolates_nodes_midpoints_and_bubble() {
    let vol = load("two_tets_data.hmesh");
    let d = [36.5, 37.0, 38.25, 41.0, 39.5];
    let ed = [0.5, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5];
    let nodes = vol.mesh.nodes();
    for cell in 0..2 {
        let tet = vol.mesh.tets()[cell];
        for &n in &tet {
            let v = eval_at(&vol, 6, cell, nodes[n as usize])[0];
            assert!((v - d[n as usize]).abs() < 1e-12);
        }
        for (e, &[a, b]) in vol.edges.as_ref().unwrap().iter().enumerate() {
            if tet.contains(&a) && tet.contains(&b) {
                let m = [0, 1, 2].map(|k| 0.5 * (nodes[a as usize][k] + nodes[b as usize][k]));
                let v = eval_at(&vol, 6, cell, m)[0];
                assert!((v - ed[e]).abs() < 1e-12, "edge {e}: {v}");
            }
        }
    }
    // Centroid of cell 1: −Σv/8 + Σv_e/4 + b with b = −3.
    let tet = vol.mesh.tets()[1];
    let c = [0, 1, 2].map(|k| tet.iter().map(|&n| nodes[n as usize][k]).sum::<f64>() / 4.0);
    let sum_v: f64 = tet.iter().map(|&n| d[n as usize]).sum();
    let sum_e: f64 = [3, 4, 5, 6, 7, 8].iter().map(|&e| ed[e]).sum();
    let v = eval_at(&vol, 6, 1, c)[0];
    assert!(
        (v - (-sum_v / 8.0 + sum_e / 4.0 - 3.0)).abs() < 1e-12,
        "{v}"
    );
}

/// Everything that must survive a write → read round trip.
fn assert_same_volume(a: &Volume, b: &Volume, what: &str) {
    assert_eq!(a.mesh.nodes(), b.mesh.nodes(), "{what}: nodes");
    assert_eq!(a.mesh.tets(), b.mesh.tets(), "{what}: tets");
    assert_eq!(a.mesh.neighbors(), b.mesh.neighbors(), "{what}: adjacency");
    assert_eq!(a.coord_type, b.coord_type, "{what}: coordinate type");
    assert_eq!(a.data.materials, b.data.materials, "{what}: materials");
    assert_eq!(a.data.raw, b.data.raw, "{what}: raw data");
    assert_eq!(a.data.fields.len(), b.data.fields.len(), "{what}: fields");
    for (f, g) in a.data.fields.iter().zip(&b.data.fields) {
        assert_eq!(
            (&f.name, f.ty, &f.denominator, f.interpolator, &f.sources),
            (&g.name, g.ty, &g.denominator, g.interpolator, &g.sources),
            "{what}: field"
        );
    }
    if a.edges.is_some() && b.edges.is_some() {
        assert_eq!(a.edges, b.edges, "{what}: edges");
    }
}

const VARIANTS: [(Encoding, Layout); 4] = [
    (Encoding::Ascii, Layout::Full),
    (Encoding::Ascii, Layout::Small),
    (Encoding::Binary, Layout::Full),
    (Encoding::Binary, Layout::Small),
];

fn round_trip(vol: &Volume, encoding: Encoding, layout: Layout) -> Volume {
    let mut bytes = Vec::new();
    hypermesh::write_volume(vol, &mut bytes, WriteOptions { encoding, layout }).unwrap();
    let file = hypermesh::read_bytes(&bytes, "round-trip").unwrap_or_else(|e| {
        panic!(
            "{e}\n{}",
            String::from_utf8_lossy(&bytes[..bytes.len().min(3000)])
        )
    });
    Volume::from_file(file).unwrap()
}

#[test]
fn write_then_read_gives_back_the_same_volume_in_all_four_variants() {
    for name in [
        "two_tets_data.hmesh",
        "two_tets_triangles.hmesh",
        "two_tets_edges.hmesh",
        "two_tets_negative.hmesh",
    ] {
        let vol = load(name);
        for (enc, layout) in VARIANTS {
            let back = round_trip(&vol, enc, layout);
            assert_same_volume(&vol, &back, &format!("{name} {enc:?} {layout:?}"));
            // And again: a written file reads back to itself.
            let again = round_trip(&back, enc, layout);
            assert_same_volume(&back, &again, &format!("{name} {enc:?} {layout:?} twice"));
        }
    }
}

#[test]
fn full_layout_keeps_the_file_triangles_first() {
    let vol = load("two_tets_triangles.hmesh");
    let back = round_trip(&vol, Encoding::Ascii, Layout::Full);
    assert_eq!(back.triangles, vol.triangles);
    let nodes_only = load("two_tets_nodes.hmesh");
    let back = round_trip(&nodes_only, Encoding::Ascii, Layout::Full);
    assert_eq!(back.triangles.unwrap().len(), 7);
}

#[test]
fn data_replaces_and_data_plus_appends_fields() {
    let mut vol = load("two_tets_data.hmesh");
    let file = hypermesh::read_file(&data_path("two_tets_fields.dat")).unwrap();
    assert!(file.geometry.is_none());
    let mut appended = vol.clone();
    appended.attach_data(file.clone(), true).unwrap();
    assert_eq!(appended.data.fields.len(), 10);
    let mut v = [0.0];
    let f = appended.field(8).unwrap();
    f.eval(&appended.support(), 1, &[0.25; 4], [0.0; 3], &mut v);
    assert!((v[0] - 3.5).abs() < 1e-12);
    vol.attach_data(file, false).unwrap();
    assert_eq!(vol.data.fields.len(), 2);
    assert_eq!(vol.field(0).unwrap().name.as_deref(), Some("pressure"));
    assert!(vol.data.materials.is_some(), "materials stay with the grid");
}

#[test]
fn data_with_wrong_counts_changes_nothing() {
    let vol = load("two_tets_nodes.hmesh");
    let text = "# HyperMesh 3D ASCII 0.7\nnNodes = 6\nNodeData { float } = @1\nField { float } = Linear(@1)\n@1\n1\n2\n3\n4\n5\n6\n";
    let file = hypermesh::read_bytes(text.as_bytes(), "six.dat").unwrap();
    let mut v = vol.clone();
    let e = v.attach_data(file, true).unwrap_err();
    assert_eq!((e.file.as_str(), e.line), ("six.dat", 2), "{e}");
    assert!(
        e.message.contains("nNodes = 6") && e.message.contains("5 nodes"),
        "{e}"
    );
    assert_eq!(v, vol);
}

#[test]
fn save_subset_keeps_the_masked_cells_with_their_data() {
    let mut vol = load("two_tets_data.hmesh");
    let file = hypermesh::read_file(&data_path("two_tets_fields.dat")).unwrap();
    vol.attach_data(file, true).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sub/subset.hmesh");
    hypermesh::save_subset(&vol, &out, 9, Encoding::Ascii).unwrap();
    let (sub, _) = Volume::load(&out).unwrap();
    assert_eq!(sub.mesh.tet_count(), 1);
    assert_eq!(sub.mesh.node_count(), 4);
    assert_eq!(sub.edges.as_ref().unwrap().len(), 6);
    assert_eq!(sub.data.raw[0].values, Values::U8(vec![0, 255, 7, 12]));
    assert_eq!(sub.data.raw[12].values, Values::U8(vec![0]));
    // The fields still evaluate the same inside the kept cell.
    for n in [0, 4, 5, 6] {
        let p = [0.1, 0.2, 0.3];
        assert_eq!(eval_at(&sub, n, 0, p), eval_at(&vol, n, 0, p), "field {n}");
    }
    // A mask that is not Constant, or zero everywhere, is refused.
    assert!(hypermesh::save_subset(&vol, &out, 0, Encoding::Ascii).is_err());
}

/// Reads every prefix of a file: none may panic, and every prefix that cuts data must fail.
fn truncations(bytes: &[u8], must_fail_below: usize) {
    for len in 0..bytes.len() {
        let r = hypermesh::read_bytes(&bytes[..len], "cut").and_then(Volume::from_file);
        if len < must_fail_below {
            assert!(r.is_err(), "prefix of {len} bytes read without error");
        }
    }
}

#[test]
fn every_truncation_of_an_ascii_and_a_binary_file_fails_cleanly() {
    let text = std::fs::read(data_path("two_tets_data.hmesh")).unwrap();
    let last_row = text[..text.len() - 1]
        .iter()
        .rposition(|&b| b == b'\n')
        .unwrap();
    truncations(&text, last_row + 1);
    let vol = load("two_tets_data.hmesh");
    for layout in [Layout::Full, Layout::Small] {
        let mut bin = Vec::new();
        hypermesh::write_volume(
            &vol,
            &mut bin,
            WriteOptions {
                encoding: Encoding::Binary,
                layout,
            },
        )
        .unwrap();
        // The final newline after the last block is optional.
        truncations(&bin, bin.len() - 1);
    }
}

#[test]
fn binary_errors_point_at_the_block() {
    let vol = load("two_tets_nodes.hmesh");
    let mut bin = Vec::new();
    hypermesh::write_volume(
        &vol,
        &mut bin,
        WriteOptions {
            encoding: Encoding::Binary,
            layout: Layout::Small,
        },
    )
    .unwrap();
    let text = String::from_utf8_lossy(&bin).into_owned();
    let marker_line = |m: &str| text.lines().position(|l| l == m).unwrap() + 1;

    // Truncated block → the block's marker line.
    let cut = &bin[..bin.len() - 5];
    let e = hypermesh::read_bytes(cut, "b").unwrap_err();
    assert_eq!(e.line, marker_line("@2"), "{e}");
    assert!(e.message.contains("truncated"), "{e}");

    // An absurd count fails at once, before allocating.
    let huge = String::from_utf8_lossy(&bin).replace("nNodes = 5", "nNodes = 2000000000");
    let e = hypermesh::read_bytes(huge.as_bytes(), "b").unwrap_err();
    assert!(e.message.contains("truncated"), "{e}");

    // A NaN coordinate.
    let at = bin.windows(4).position(|w| w == b"\n@1\n").unwrap() + 4;
    let mut nan = bin.clone();
    nan[at..at + 8].copy_from_slice(&f64::NAN.to_be_bytes());
    let e = hypermesh::read_bytes(&nan, "b").unwrap_err();
    assert!(
        e.message.contains("non-finite") && e.message.contains("element 1"),
        "{e}"
    );

    // A node index out of range in binary names the element and block.
    let at = bin.windows(4).position(|w| w == b"\n@2\n").unwrap() + 4;
    let mut bad = bin.clone();
    bad[at..at + 4].copy_from_slice(&9i32.to_be_bytes());
    let e = hypermesh::read_bytes(&bad, "b")
        .and_then(Volume::from_file)
        .unwrap_err();
    assert_eq!(e.line, marker_line("@2"));
    assert!(
        e.message.contains("tetrahedron 1 of block @2") && e.message.contains("out of range"),
        "{e}"
    );
}
