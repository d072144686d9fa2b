//! Cells beyond tetrahedra, in files the tools users use wrote (VTK, dolfinx-style, meshio):
//! Lagrange cells (VTK 71–74) of every degree, VTK's quadratic hexahedra, wedges and pyramids
//! (25–27, as Lagrange cells), voxels (11) and polyhedra (42, both XML
//! layouts and legacy `.vtk`). A degree-2 file whose field is linear renders bit for bit like
//! the degree-1 file (so a wrong node order cannot pass); nodes of every degree sit where VTK
//! puts them; polyhedra split conformingly and render like the same cubes as hexahedra;
//! volumes round-trip through `vorang convert`; bad face streams and node counts give
//! `file:line: message`.
//!
//! The data files in `tests/data/formats/` are made by `tests/data/formats/generate.py cells`.

use std::path::{Path, PathBuf};

use vorang::Volume;
use vorang::field::Interpolator;
use vorang::formats::lagrange::Shape;
use vorang::formats::{self, build};
use vorang::framebuffer::read_pfm;
use vorang::mesh::tet_volume;
use vorang_tcl::script::{Collect, Runner};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/formats")
        .join(name)
}

const COLORMAP: &str = "# VoRANG Colormap 1.0
DataField \"f\"
SIMPLE_EMITTER @1
@1
1 0.2 0   0.5
0 0.5 1   2.25
";

const ALPHAMAP: &str = "# VoRANG Alphamap 1.0
DataField \"f\"
SIMPLE_ABSORBER @1
@1
0.3 0.5
2.5 2.25
";

const VIEWS: [&str; 3] = [
    "",
    "vol_rotate 0 1 0 35\nvol_rotate 1 0 0 20",
    "vol_rotate 1 2 3 70",
];

/// Renders `file` (exact method, closed-form integration) with the maps of field `f` and
/// returns the RGB floats of the PFM image.
fn render(file: &Path, view: &str) -> Vec<f32> {
    let tmp = tempfile::tempdir().unwrap();
    let (cmap, amap) = (tmp.path().join("c.map"), tmp.path().join("a.map"));
    std::fs::write(&cmap, COLORMAP).unwrap();
    std::fs::write(&amap, ALPHAMAP).unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "imagesize 40 32\noutput {{{}}}\nvolume {{{}}}\ncolormap {{{}}}\nalphamap {{{}}}\nlinedraw off\nmethod exact linear 0 1\n{view}\nrender_btf\n",
        tmp.path().join("img.pfm").display(),
        file.display(),
        cmap.display(),
        amap.display()
    );
    runner
        .run_string(&script, "test")
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let bytes = std::fs::read(&runner.session().written()[0]).unwrap();
    let (_, _, rgb) = read_pfm(&bytes).unwrap();
    rgb.into_iter().flatten().collect()
}

fn largest_difference(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

/// Renders both files in every view: bit for bit equal (`tolerance` 0) or within it.
fn assert_renders_alike(a: &Path, b: &Path, tolerance: f32) {
    for view in VIEWS {
        let (x, y) = (render(a, view), render(b, view));
        assert!(
            x.iter().any(|&v| v < 0.9),
            "{}: the volume is visible",
            a.display()
        );
        let d = largest_difference(&x, &y);
        assert!(
            d <= tolerance,
            "{} and {} differ by {d} in view '{view}'",
            a.display(),
            b.display()
        );
    }
}

fn load(name: &str) -> (Volume, Vec<vorang::error::Warning>) {
    Volume::load(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn volume_of(vol: &Volume) -> f64 {
    (0..vol.mesh.tet_count())
        .map(|t| {
            let c = vol.mesh.corners(t);
            tet_volume(c[0], c[1], c[2], c[3])
        })
        .sum()
}

#[test]
fn dolfinx_style_lagrange_tetrahedra_load_as_tetrahedra() {
    // Type 71 of degree 1 is the tetrahedron itself: the same mesh as the cube's.
    let (p1, _) = load("lagrange_p1.vtu");
    let (cube, _) = load("cube.hmesh");
    assert_eq!(p1.mesh.nodes(), cube.mesh.nodes());
    assert_eq!(p1.mesh.tets(), cube.mesh.tets());
    // Degree 2: the same tetrahedra; the linear `f` stays Linear, `q` is a P2 field.
    let (p2, warnings) = load("lagrange_p2.vtu");
    assert!(
        warnings.iter().all(|w| !w.message.contains("skipped")),
        "{warnings:?}"
    );
    assert_eq!(p2.mesh.tets(), p1.mesh.tets());
    assert_eq!(p2.field(0).unwrap().interpolator, Interpolator::Linear);
    let q = p2.field(1).unwrap();
    assert_eq!(q.interpolator, Interpolator::HigherOrder);
    for cell in [0, 17, 47] {
        let c = p2.mesh.corners(cell);
        for l in [[0.1, 0.2, 0.3, 0.4], [0.25; 4], [0.7, 0.1, 0.1, 0.1]] {
            let p: [f64; 3] = [0, 1, 2].map(|d| (0..4).map(|i| l[i] * c[i][d]).sum());
            let mut out = [0.0];
            q.eval(&p2.support(), cell, &l, p, &mut out);
            let want = p[0] * p[0] + p[1] * p[2];
            assert!((out[0] - want).abs() < 1e-12, "{} vs {want}", out[0]);
        }
    }
    assert!(p2.field(2).unwrap().is_byte_constant(&p2.data.raw));
}

#[test]
fn a_p2_file_with_a_linear_field_renders_exactly_like_the_p1_file() {
    assert_renders_alike(&data("lagrange_p1.vtu"), &data("lagrange_p2.vtu"), 0.0);
    assert_renders_alike(
        &data("lagrange_hex_p1.vtu"),
        &data("lagrange_hex_p2.vtu"),
        0.0,
    );
    // A wrong node order does not pass: with the mid-edge nodes of edges (1,2) and (0,2)
    // exchanged, `f` is no longer linear on the cells and the image changes.
    let bytes = std::fs::read(data("lagrange_p2.vtu")).unwrap();
    let mut desc = formats::read_description(&bytes, "swapped.vtu").unwrap();
    for i in 0..desc.cells.len() {
        let a = desc.cells.offsets[i];
        desc.cells.connectivity.swap(a + 5, a + 6);
    }
    let (swapped, _) = build::volume(desc).unwrap();
    assert_eq!(
        swapped.field(0).unwrap().interpolator,
        Interpolator::HigherOrder
    );
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("swapped.vtu");
    formats::save_volume(&swapped, &out, Default::default()).unwrap();
    let d = largest_difference(
        &render(&out, VIEWS[2]),
        &render(&data("lagrange_p1.vtu"), VIEWS[2]),
    );
    assert!(d > 1e-3, "a wrong node order renders alike ({d})");
}

/// VTK's quadratic hexahedra, wedges and pyramid (serendipity cells, types 25–27) are the
/// Lagrange cells through their face and cell centres: the same curved cells written as
/// Lagrange cells (72–74) whose centres VTK's own serendipity interpolation placed and filled
/// (`generate.py serendipity`) render alike, bit for bit. Read by their corners only, they
/// would not.
#[test]
fn serendipity_cells_render_like_the_lagrange_cells_vtk_fills() {
    assert_renders_alike(
        &data("serendipity.vtu"),
        &data("serendipity_lagrange.vtu"),
        0.0,
    );
    let (vol, warnings) = load("serendipity.vtu");
    assert!(
        !warnings.iter().any(|w| w.message.contains("skipped")),
        "{warnings:?}"
    );
    assert_eq!(
        vol.field(0).unwrap().interpolator,
        Interpolator::HigherOrder
    );
    // The faces two cells share have one centre: as many points as the Lagrange file.
    let (lagrange, _) = load("serendipity_lagrange.vtu");
    assert_eq!(vol.mesh.node_count(), lagrange.mesh.node_count());
    // The corners only: another image.
    let bytes = std::fs::read(data("serendipity.vtu")).unwrap();
    let mut desc = formats::read_description(&bytes, "corners.vtu").unwrap();
    let mut corners = formats::Cells::default();
    for i in 0..desc.cells.len() {
        let (ty, n) = match desc.cells.types[i] {
            25 => (12, 8),
            26 => (13, 6),
            _ => (14, 5),
        };
        let nodes: Vec<u64> = desc.cells.nodes(i)[..n]
            .iter()
            .map(|&v| u64::from(v))
            .collect();
        corners.push(ty, &nodes);
    }
    desc.cells = corners;
    let (linear, _) = build::volume(desc).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("corners.vtu");
    formats::save_volume(&linear, &out, Default::default()).unwrap();
    let d = largest_difference(
        &render(&out, VIEWS[1]),
        &render(&data("serendipity.vtu"), VIEWS[1]),
    );
    assert!(d > 1e-3, "the corners alone render alike ({d})");
}

/// Gmsh's second-order hexahedra and prisms (20 and 27 nodes, 15 and 18: Gmsh's own node
/// order, curved cells, a field from a Gmsh view) render as the same cells in VTK's order,
/// where `generate.py serendipity` found each node by its place.
#[test]
fn gmsh_second_order_hexahedra_and_prisms_are_vtks_cells() {
    for name in ["gmsh_hex20", "gmsh_hex27", "gmsh_prism15", "gmsh_prism18"] {
        let (vol, warnings) = load(&format!("{name}.msh"));
        assert!(
            !warnings
                .iter()
                .any(|w| w.message.contains("quadratic hexahedron")
                    || w.message.contains("quadratic wedge")),
            "{name}: {warnings:?}"
        );
        assert!(vol.mesh.tet_count() > 0);
        let (msh, vtu) = (
            render(&data(&format!("{name}.msh")), VIEWS[1]),
            render(&data(&format!("{name}.vtu")), VIEWS[1]),
        );
        assert!(
            msh.iter().any(|&v| v < 0.9),
            "{name}: the volume is visible"
        );
        assert_eq!(largest_difference(&msh, &vtu), 0.0, "{name}");
    }
}

#[test]
fn hexahedra_voxels_and_lagrange_hexahedra_are_the_same_volume() {
    let (hex, _) = load("hexahedra_bar.vtu");
    for name in [
        "voxels.vtu",
        "lagrange_hex_p1.vtu",
        "lagrange_hex_p2.vtu",
        "lagrange_hex_p2_vtk8.vtu",
    ] {
        let (vol, warnings) = load(name);
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        assert_eq!(vol.mesh.tets(), hex.mesh.tets(), "{name}");
        assert_eq!(
            &vol.mesh.nodes()[..18],
            hex.mesh.nodes(),
            "{name}: the corners"
        );
        assert_eq!(vol.field(0).unwrap().interpolator, Interpolator::Linear);
        assert!(vol.mesh.is_convex(), "{name}: split conformingly");
    }
    assert_renders_alike(&data("hexahedra_bar.vtu"), &data("voxels.vtu"), 0.0);
    assert_renders_alike(
        &data("hexahedra_bar.vtu"),
        &data("lagrange_hex_p2_vtk8.vtu"),
        0.0,
    );
}

/// The affine map `generate.py` places the reference cell of the `n`-th cell of
/// `lagrange_orders.vtu` with.
fn placed(n: usize, [r, s, t]: [f64; 3]) -> [f64; 3] {
    [
        3.0 * n as f64 + 2.0 * r + 0.5 * s,
        1.5 * s - 0.25 * t,
        1.25 * t + 0.125 * r,
    ]
}

#[test]
fn lagrange_nodes_sit_where_vtk_puts_them() {
    let bytes = std::fs::read(data("lagrange_orders.vtu")).unwrap();
    let desc = formats::read_description(&bytes, "lagrange_orders.vtu").unwrap();
    assert_eq!(desc.cells.len(), 13);
    for c in 0..desc.cells.len() {
        let shape = Shape::of(desc.cells.types[c]).unwrap();
        let conn = desc.cells.nodes(c);
        let p = shape.degree(conn.len()).unwrap();
        let mut checked = 0;
        for k in 0..=p {
            for j in 0..=p {
                for i in 0..=p {
                    let inside = match shape {
                        Shape::Tetrahedron => i + j + k <= p,
                        Shape::Wedge => i + j <= p,
                        _ => true,
                    };
                    if !inside {
                        continue;
                    }
                    let mut at = shape.index(p, [i, j, k]);
                    if conn.len() == 21 && at >= 15 {
                        at += 2; // the 21-node wedge's triangle centres come first
                    }
                    let want = placed(c, [i, j, k].map(|x| x as f64 / p as f64));
                    let got = desc.nodes[conn[at] as usize];
                    let err = (0..3).map(|d| (got[d] - want[d]).abs()).fold(0.0, f64::max);
                    assert!(
                        err < 1e-12,
                        "cell {c} {shape:?} p={p} ({i},{j},{k}): {got:?} vs {want:?}"
                    );
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, shape.nodes(p), "cell {c}");
    }
    // Every cell is filled once: the tetrahedra's volume is the cells' (tetrahedron 1/6,
    // hexahedron 1, wedge 1/2 times the map's determinant), whatever the degree.
    let (vol, warnings) = build::volume(desc).unwrap();
    let det = 2.0 * (1.5 * 1.25) - 0.5 * (0.25 * 0.125);
    let want = det * (4.0 / 6.0 + 4.0 + 5.0 / 2.0);
    assert!(
        (volume_of(&vol) - want).abs() < 1e-9,
        "{} vs {want}",
        volume_of(&vol)
    );
    let subdivided: Vec<_> = warnings
        .iter()
        .filter(|w| w.message.contains("subdivided"))
        .collect();
    assert_eq!(subdivided.len(), 1, "{warnings:?}");
    assert!(
        subdivided[0]
            .message
            .starts_with("6 Lagrange cells of degree 3 or more")
    );
}

#[test]
fn subdivided_cells_render_like_their_linear_cells() {
    // The same cells of degree 1 (their corners): the linear field is the same, so the
    // images agree up to rounding.
    let bytes = std::fs::read(data("lagrange_orders.vtu")).unwrap();
    let high = formats::read_description(&bytes, "orders.vtu").unwrap();
    let mut low = high.clone();
    low.cells = Default::default();
    for c in 0..high.cells.len() {
        let shape = Shape::of(high.cells.types[c]).unwrap();
        let conn = high.cells.nodes(c);
        let p = shape.degree(conn.len()).unwrap();
        let corners: Vec<u64> = (0..shape.vertices())
            .map(|v| u64::from(conn[shape.index(p, shape.corner(p, v))]))
            .collect();
        low.cells.push(shape.linear(), &corners);
    }
    let tmp = tempfile::tempdir().unwrap();
    let files = [("high.vtu", high), ("low.vtu", low)].map(|(name, desc)| {
        let (vol, _) = build::volume(desc).unwrap();
        let path = tmp.path().join(name);
        formats::save_volume(&vol, &path, Default::default()).unwrap();
        path
    });
    assert_renders_alike(&files[0], &files[1], 2e-6);
}

#[test]
fn polyhedra_split_conformingly_and_render_like_the_same_hexahedra() {
    let (reference, _) = load("polyhedra.vtu");
    // 18 corners, 4 cell centres, 20 distinct quadrilaterals (4 shared): each shared face's
    // centre is one point; every face a fan of 4 tetrahedra.
    assert_eq!(reference.mesh.node_count(), 18 + 4 + 20);
    assert_eq!(reference.mesh.tet_count(), 4 * 6 * 4);
    assert!(reference.mesh.is_convex(), "no inner boundary: conforming");
    assert!((volume_of(&reference) - 4.0).abs() < 1e-12);
    for name in [
        "polyhedra_ascii.vtu",
        "polyhedra_old.vtu",
        "polyhedra_meshio.vtu",
        "polyhedra.vtk",
    ] {
        let (vol, warnings) = load(name);
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        assert_eq!(vol.mesh.nodes(), reference.mesh.nodes(), "{name}");
        assert_eq!(vol.mesh.tets(), reference.mesh.tets(), "{name}");
        assert_eq!(vol.data.raw, reference.data.raw, "{name}");
    }
    // The added points carry the mean of `f`, which is linear: the same field as the
    // hexahedra's, on other tetrahedra.
    assert_renders_alike(&data("hexahedra_bar.vtu"), &data("polyhedra.vtu"), 2e-6);
}

#[test]
fn polyhedra_with_pentagons_and_triangles_share_their_faces() {
    let (vol, warnings) = load("polyhedra_prisms.vtu");
    assert!(warnings.is_empty(), "{warnings:?}");
    // Outer faces only: 5 + 10 × 4 (bottom pentagon and sides, as fans) + 4 of the
    // pyramid's triangles + 3 of the tetrahedron's.
    assert_eq!(vol.mesh.boundary_face_count(), 5 + 40 + 4 + 3);
    let area = 2.5 * (72.0f64).to_radians().sin();
    let tet = {
        let c = vol.mesh.corners(vol.mesh.tet_count() - 1);
        tet_volume(c[0], c[1], c[2], c[3])
    };
    let want = 2.0 * area + area / 3.0 + tet;
    assert!(
        (volume_of(&vol) - want).abs() < 1e-12,
        "{} vs {want}",
        volume_of(&vol)
    );
}

#[test]
fn new_cells_round_trip_through_convert() {
    let tmp = tempfile::tempdir().unwrap();
    for (name, ext) in [
        ("lagrange_p2.vtu", "vtu"),
        ("lagrange_p2.vtu", "hmesh"),
        ("lagrange_orders.vtu", "vtu"),
        ("voxels.vtu", "vtu"),
        ("polyhedra.vtu", "vtu"),
        ("polyhedra_prisms.vtu", "hmesh"),
    ] {
        let out = tmp.path().join(format!("out.{ext}"));
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
            .arg("convert")
            .arg(data(name))
            .arg(&out)
            .output()
            .unwrap();
        assert!(status.status.success(), "{name}: {status:?}");
        let (a, _) = load(name);
        let (b, _) = Volume::load(&out).unwrap();
        assert_eq!(b.mesh.nodes(), a.mesh.nodes(), "{name} → {ext}");
        assert_eq!(b.mesh.tets(), a.mesh.tets(), "{name} → {ext}");
        assert_eq!(b.data.raw, a.data.raw, "{name} → {ext}");
        assert_eq!(b.data.fields.len(), a.data.fields.len());
        for (f, g) in b.data.fields.iter().zip(&a.data.fields) {
            assert_eq!((&f.name, f.interpolator), (&g.name, g.interpolator));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Bad input

/// Loads `bytes` as a file named `name`: must fail (no panic) with `file:line: message`;
/// returns the line and the message.
fn must_fail(bytes: &[u8], name: &str) -> (usize, String) {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    match Volume::load(&path) {
        Ok(_) => panic!("{name}: loaded a bad file"),
        Err(e) => {
            let msg = e.to_string();
            let prefix = format!("{}:", path.display());
            assert!(msg.starts_with(&prefix), "{name}: {msg}");
            let rest = &msg[prefix.len()..];
            let line = rest.split(':').next().unwrap();
            let line = line
                .parse::<usize>()
                .unwrap_or_else(|_| panic!("{name}: no line in {msg}"));
            (line, msg)
        }
    }
}

fn replace_once(bytes: &[u8], from: &str, to: &str) -> Vec<u8> {
    let k = bytes
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap_or_else(|| panic!("'{from}' not found"));
    [&bytes[..k], to.as_bytes(), &bytes[k + from.len()..]].concat()
}

/// The 1-based line of the first occurrence of `text`.
fn line_of(bytes: &[u8], text: &str) -> usize {
    let k = bytes
        .windows(text.len())
        .position(|w| w == text.as_bytes())
        .unwrap();
    1 + bytes[..k].iter().filter(|&&b| b == b'\n').count()
}

#[test]
fn bad_face_streams_name_the_file_and_the_line() {
    let new = std::fs::read(data("polyhedra_ascii.vtu")).unwrap();
    let old = std::fs::read(data("polyhedra_old.vtu")).unwrap();
    let at = |bytes: &[u8], name: &str| line_of(bytes, &format!("Name=\"{name}\""));
    let cases: Vec<(&str, Vec<u8>, usize, &str)> = vec![
        (
            "a face point out of range",
            replace_once(&new, "13 12 15 16 4 7", "13 12 15 99 4 7"),
            at(&new, "face_connectivity"),
            "refers to point 99",
        ),
        (
            "a face beyond the face offsets",
            replace_once(&new, "18 19 20 21 22 23\n", "18 19 20 21 22 24\n"),
            // ASCII values that run out are reported where they end.
            line_of(&new, "76 80 84 88 92 96") + 1,
            "but 25 are needed",
        ),
        (
            "face offsets going back",
            replace_once(&new, "4 8 12 16 20 24\n", "4 8 2 16 20 24\n"),
            at(&new, "face_offsets"),
            "before the previous entry's end",
        ),
        (
            "a polyhedron without faces",
            replace_once(&new, "6 12 18 24", "6 12 12 24"),
            at(&new, "polyhedron_offsets"),
            "cell 3 is a polyhedron, but no faces are listed for it",
        ),
        (
            "a negative face",
            replace_once(&new, "0 1 2 3 4 5\n", "0 1 2 3 4 -5\n"),
            at(&new, "polyhedron_to_faces"),
            "face -5",
        ),
        (
            "a face stream that ends elsewhere than its offset says",
            replace_once(&old, "31 62 93 124", "31 61 93 124"),
            at(&old, "faces"),
            "the face stream of cell 2",
        ),
        (
            "a face count beyond the stream",
            replace_once(&old, ">6 4 13 12", ">9 4 13 12"),
            at(&old, "faces"),
            "the face stream of cell 1",
        ),
        (
            "a face point out of range (old layout)",
            replace_once(&old, ">6 4 13 12", ">6 4 13 77"),
            at(&old, "faces"),
            "refers to point 77",
        ),
        (
            "a polyhedron marked as having no faces",
            replace_once(&old, "31 62 93 124", "31 -1 93 124"),
            at(&old, "faceoffsets"),
            "cell 2 is a polyhedron, but its offset is −1",
        ),
        (
            "no face arrays",
            replace_once(&old, "Name=\"faceoffsets\"", "Name=\"other\""),
            line_of(&old, "<Piece"),
            "has no face arrays",
        ),
        (
            "a face point that is not the cell's",
            replace_once(&old, "3 4 6 7 12 13 15 16", "3 4 6 7 12 13 15 17"),
            at(&old, "connectivity"),
            "cell 1 is a polyhedron, but its face 1 uses point 16, which is not among the cell's points",
        ),
    ];
    for (what, bytes, line, fragment) in cases {
        let (got, msg) = must_fail(&bytes, "bad.vtu");
        assert!(msg.contains(fragment), "{what}: {msg}");
        assert_eq!(got, line, "{what}: {msg}");
    }
    let legacy = std::fs::read(data("polyhedra.vtk")).unwrap();
    let (_, msg) = must_fail(&replace_once(&legacy, "6 4 13 12", "6 4 13 99"), "bad.vtk");
    assert!(msg.contains("cell 1: a face refers to point 99"), "{msg}");
    let (_, msg) = must_fail(&replace_once(&legacy, "6 4 13 12", "7 4 13 12"), "bad.vtk");
    assert!(msg.contains("cell 1:"), "{msg}");
}

#[test]
fn bad_lagrange_node_counts_name_the_file_and_the_line() {
    let p2 = std::fs::read(data("lagrange_p2.vtu")).unwrap();
    let bad = replace_once(&p2, "10 20 30", "11 20 30");
    let (line, msg) = must_fail(&bad, "bad.vtu");
    assert_eq!(line, line_of(&p2, "Name=\"offsets\""), "{msg}");
    assert!(
        msg.contains("cell 1 is a Lagrange tetrahedron (type 71) and needs the node count of a degree (for degrees 1, 2, 3: 4, 10, 20, …), but its offsets give it 11"),
        "{msg}"
    );
    // The same count in a description built directly (as Python's blocks are).
    let mut desc = formats::read_description(&p2, "p2.vtu").unwrap();
    desc.cells.types[3] = vorang::formats::cell_type::LAGRANGE_HEXAHEDRON;
    let e = build::volume(desc).unwrap_err();
    assert!(
        e.message
            .contains("cell 4 is a Lagrange hexahedron and needs"),
        "{e}"
    );
}

#[test]
fn truncated_new_cell_files_fail_cleanly() {
    for name in [
        "polyhedra.vtu",
        "polyhedra_old.vtu",
        "polyhedra.vtk",
        "lagrange_p2.vtu",
        "lagrange_orders.vtu",
    ] {
        let bytes = std::fs::read(data(name)).unwrap();
        let step = (bytes.len() / 200).max(1);
        let mut cut = 0;
        while cut < bytes.len() {
            // Never a panic: a volume or an error.
            let _ = formats::volume_from_bytes(&bytes[..cut], name);
            cut += step;
        }
    }
}

#[test]
fn every_number_of_the_cell_arrays_changed_fails_cleanly_or_loads() {
    // Each number of the <Cells> section (connectivity, offsets, types, both face layouts)
    // replaced by values a damaged or hostile file might hold: a volume or a located error,
    // never a panic.
    for name in ["polyhedra_ascii.vtu", "polyhedra_old.vtu", "polyhedra.vtk"] {
        let bytes = std::fs::read(data(name)).unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        let start = text.find("<Cells>").or_else(|| text.find("CELLS")).unwrap();
        let end = text.find("</Cells>").unwrap_or(text.len());
        let mut at = start;
        let mut tried = 0;
        while at < end {
            let rest = &text[at..end];
            let Some(k) = rest.find(|c: char| c.is_ascii_digit()) else {
                break;
            };
            let begin = at + k;
            let len = text[begin..]
                .find(|c: char| !c.is_ascii_digit())
                .unwrap_or(0);
            let inside_tag = text[..begin].rfind('<') > text[..begin].rfind('>');
            if !inside_tag {
                for v in ["-1", "0", "1", "7", "99", "4294967296"] {
                    let changed = [&text[..begin], v, &text[begin + len..]].concat();
                    match formats::volume_from_bytes(changed.as_bytes(), name) {
                        Ok(_) => {}
                        Err(e) => assert!(e.line >= 1 && e.file == name, "{e}"),
                    }
                    tried += 1;
                }
            }
            at = begin + len.max(1);
        }
        assert!(tried > 100, "{name}: {tried}");
    }
}

#[test]
fn added_points_of_a_float_file_are_floats_and_round_trip() {
    // Found by fuzzing: a polyhedron's centre, the mean of `float` coordinates, is rounded to
    // a `float` too, so that the volume stays a `float` one and reads back from its `.vtu`.
    let bytes = std::fs::read(data("polyhedra_prisms.vtu")).unwrap();
    let mut desc = formats::read_description(&bytes, "prisms.vtu").unwrap();
    for p in desc.nodes.iter_mut() {
        *p = p.map(|c| f64::from(c as f32));
    }
    desc.float_coordinates = true;
    let (vol, _) = build::volume(desc).unwrap();
    assert!(
        vol.mesh
            .nodes()
            .iter()
            .flatten()
            .all(|&c| f64::from(c as f32) == c)
    );
    let mut out = Vec::new();
    formats::vtu::write(&vol, &mut out).unwrap();
    let again = formats::vtu::read(&out, "again.vtu").unwrap();
    let (again, _) = build::volume(again).unwrap();
    assert_eq!(again.mesh.nodes(), vol.mesh.nodes());
    assert_eq!(again.mesh.tets(), vol.mesh.tets());
}

#[test]
fn pieces_and_time_steps_of_polyhedra_and_lagrange_cells() {
    use vorang::formats::collection::Series;
    // Two parts of two polyhedral cubes each, merged: the shared quadrilaterals are one face
    // (the parts' points merged by coordinates, the faces mapped), so the split is conforming
    // across the parts; the second time step shares the first's mesh.
    let series = Series::read(&data("polyhedra_parts.pvd")).unwrap();
    let (first, warnings) = series.load_step(0, None).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let (single, _) = load("polyhedra.vtu");
    let vol = &first.volume;
    assert_eq!(vol.mesh.node_count(), single.mesh.node_count());
    assert_eq!(vol.mesh.tet_count(), single.mesh.tet_count());
    assert!(vol.mesh.is_convex(), "no inner boundary between the parts");
    assert!((volume_of(vol) - 4.0).abs() < 1e-12);
    let (second, _) = series.load_step(1, Some(&first)).unwrap();
    assert!(first.shares_mesh(&second));
    assert_eq!(second.volume.data.raw, first.volume.data.raw);
    // A P2 file twice: the second step shares the mesh and still has its P2 field.
    let tmp = tempfile::tempdir().unwrap();
    let pvd = tmp.path().join("p2.pvd");
    let file = data("lagrange_p2.vtu");
    std::fs::write(
        &pvd,
        format!(
            "<VTKFile type=\"Collection\" version=\"0.1\"><Collection>\n<DataSet timestep=\"0\" file=\"{0}\"/>\n<DataSet timestep=\"1\" file=\"{0}\"/>\n</Collection></VTKFile>\n",
            file.display()
        ),
    )
    .unwrap();
    let series = Series::read(&pvd).unwrap();
    let (a, _) = series.load_step(0, None).unwrap();
    let (b, _) = series.load_step(1, Some(&a)).unwrap();
    assert!(a.shares_mesh(&b));
    let (p2, _) = load("lagrange_p2.vtu");
    assert_eq!(b.volume.data.raw, p2.data.raw);
    let kinds = |v: &Volume| -> Vec<Interpolator> {
        v.data.fields.iter().map(|f| f.interpolator).collect()
    };
    assert_eq!(kinds(&b.volume), kinds(&p2));
    assert_eq!(kinds(&p2)[1], Interpolator::HigherOrder);
}
