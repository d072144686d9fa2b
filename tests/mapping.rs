//! Colour and alpha mapping: every method, category switching, field overrides, binding errors,
//! and the breakpoint/linearity reports checked against brute-force sampling.

#![allow(clippy::needless_range_loop)]

use std::path::Path;

use vorang::Volume;
use vorang::field::Interpolator;
use vorang::hypermesh::{DataType, ElementKind, RawData, ScalarType, Values};
use vorang::mapping::{AlphaMap, AlphaShading, ColorMap, ColorShading, Mapping, Shape, parse_map};
use vorang::mesh::TetMesh;
use vorang::mesh::generate::SplitMix64;

fn color(text: &str) -> ColorMap {
    parse_map::<dyn ColorShading>(text.as_bytes(), "c.map")
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

fn alpha(text: &str) -> AlphaMap {
    parse_map::<dyn AlphaShading>(text.as_bytes(), "a.map")
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// One tetrahedron with: field 0 scalar Linear (node values s), field 1 scalar Linear (t),
/// field 2 float[4] Linear (barycentric coordinates), field 3 float[3] Linear (colours),
/// field 4 byte Constant (the given value), field 5 scalar Constant (cat).
fn tet_volume(s: [f32; 4], t: [f32; 4], byte: u8, cat: f32) -> Volume {
    let nodes = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mesh = TetMesh::new(nodes, vec![[0, 1, 2, 3]]).unwrap();
    let mut vol = Volume::from_mesh("tet", mesh);
    let mut add = |kind, ty: DataType, values, interp| {
        let r = vol
            .add_raw(RawData {
                kind,
                ty,
                denominator: None,
                values,
            })
            .unwrap();
        vol.add_field(None, ty, interp, &[r]).unwrap();
    };
    let f = ScalarType::Float;
    add(
        ElementKind::Node,
        DataType::scalar(f),
        Values::F32(s.to_vec()),
        Interpolator::Linear,
    );
    add(
        ElementKind::Node,
        DataType::scalar(f),
        Values::F32(t.to_vec()),
        Interpolator::Linear,
    );
    let bary: Vec<f32> = (0..4)
        .flat_map(|i| (0..4).map(move |j| if i == j { 1.0 } else { 0.0 }))
        .collect();
    add(
        ElementKind::Node,
        DataType::array(f, 4),
        Values::F32(bary),
        Interpolator::Linear,
    );
    let rgb = vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.5, 0.5, 0.5];
    add(
        ElementKind::Node,
        DataType::array(f, 3),
        Values::F32(rgb),
        Interpolator::Linear,
    );
    add(
        ElementKind::Tetrahedron,
        DataType::scalar(ScalarType::Byte),
        Values::U8(vec![byte]),
        Interpolator::Constant,
    );
    add(
        ElementKind::Tetrahedron,
        DataType::scalar(f),
        Values::F32(vec![cat]),
        Interpolator::Constant,
    );
    vol
}

/// Barycentric coordinates of `p` in the unit corner tetrahedron.
fn lambda(p: [f64; 3]) -> [f64; 4] {
    [1.0 - p[0] - p[1] - p[2], p[0], p[1], p[2]]
}

/// (η, χ) at point `p` of the single cell.
fn at(m: &Mapping, vol: &Volume, p: [f64; 3]) -> ([f64; 3], f64) {
    let mut buf = vec![0.0; m.width()];
    m.sample_fields(vol, 0, &lambda(p), p, &mut buf);
    m.eval(&buf, 0, p)
}

fn bind(c: &ColorMap, a: &AlphaMap, vol: &Volume) -> Mapping {
    Mapping::new(c, a, vol).unwrap_or_else(|e| panic!("{e}")).0
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn defaults_are_constant_red_and_absorption_two() {
    let vol = tet_volume([0.0; 4], [0.0; 4], 0, 0.0);
    let m = bind(&ColorMap::default_map(), &AlphaMap::default_map(), &vol);
    assert_eq!(m.width(), 0, "the defaults read no field");
    assert_eq!(at(&m, &vol, [0.1, 0.2, 0.3]), ([1.0, 0.0, 0.0], 2.0));
    // They need no field at all.
    let empty = Volume::from_mesh(
        "empty",
        TetMesh::new(vol.mesh.nodes().to_vec(), vol.mesh.tets().to_vec()).unwrap(),
    );
    assert!(Mapping::new(&ColorMap::default_map(), &AlphaMap::default_map(), &empty).is_ok());
}

#[test]
fn tables_interpolate_between_rows_and_clamp_outside() {
    // s = 10·x along the x axis (node 1 has 10).
    let vol = tet_volume([0.0, 10.0, 0.0, 0.0], [0.0; 4], 0, 0.0);
    let c = color("# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n1 0 0 2\n0 1 0 4\n0 0 4 8\n");
    let a = alpha("# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.5 3\n2.5 5\n");
    let m = bind(&c, &a, &vol);
    for (x, eta, chi) in [
        (0.0, [1.0, 0.0, 0.0], 0.5), // below the first row: clamped
        (0.2, [1.0, 0.0, 0.0], 0.5), // s = 2: first row
        (0.3, [0.5, 0.5, 0.0], 0.5), // s = 3: midway; absorber's first row
        (0.4, [0.0, 1.0, 0.0], 1.5), // s = 4
        (0.6, [0.0, 0.5, 2.0], 2.5), // s = 6; absorber clamped above 5
        (0.9, [0.0, 0.0, 4.0], 2.5), // s = 9: above the last row
    ] {
        let (e, k) = at(&m, &vol, [x, 0.0, 0.0]);
        assert!(
            e.iter().zip(eta).all(|(a, b)| close(*a, b)) && close(k, chi),
            "x={x}: {e:?} {k}"
        );
    }
}

#[test]
fn absorption_weighted_is_the_table_times_chi_with_separate_fields() {
    // Colour table on field 1 (t), absorption on field 0 (s): different DataFields.
    let vol = tet_volume([0.0, 4.0, 0.0, 0.0], [0.0, 0.0, 2.0, 0.0], 0, 0.0);
    let c =
        color("# VoRANG Colormap 1.0\nDataField 1\nABSORPTION_WEIGHTED @1\n@1\n1 0 0 0\n1 1 0 2\n");
    let a = alpha("# VoRANG Alphamap 1.0\nDataField 0\nSIMPLE_ABSORBER @1\n@1\n0 0\n8 4\n");
    let m = bind(&c, &a, &vol);
    assert_eq!(m.fields().len(), 2);
    let p = [0.25, 0.5, 0.0]; // s = 1, t = 1
    let (e, k) = at(&m, &vol, p);
    assert!(close(k, 2.0));
    assert!(close(e[0], 2.0) && close(e[1], 1.0) && e[2] == 0.0, "{e:?}");
}

#[test]
fn constant_and_identity() {
    let vol = tet_volume([0.0; 4], [0.0; 4], 0, 0.0);
    let c = color("# VoRANG Colormap 1.0\nDataField 3\nIDENTITY\n");
    let a = alpha("# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n0.75\n");
    let m = bind(&c, &a, &vol);
    let (e, k) = at(&m, &vol, [0.25, 0.25, 0.25]);
    // Colours (1,0,0), (0,1,0), (0,0,1), (0.5,0.5,0.5) at weights ¼ each.
    assert!(e.iter().all(|v| close(*v, 0.375)), "{e:?}");
    assert_eq!(k, 0.75);
}

#[test]
fn const_cell_looks_up_bytes_and_warns_once_about_missing_values() {
    let table_c = "# VoRANG Colormap 1.0\nDataField 4\nCONST_CELL @1\n@1\n0 3 1.8 0\n25 0 0 5\n";
    let table_a = "# VoRANG Alphamap 1.0\nDataField 4\nCONST_CELL @1\n@1\n1.0 0\n5 5\n";
    let vol = tet_volume([0.0; 4], [0.0; 4], 5, 0.0);
    let (m, w) = Mapping::new(&color(table_c), &alpha(table_a), &vol).unwrap();
    assert!(w.is_empty());
    assert_eq!(at(&m, &vol, [0.1; 3]), ([25.0, 0.0, 0.0], 5.0));
    let missing = tet_volume([0.0; 4], [0.0; 4], 9, 0.0);
    let (m, w) = Mapping::new(&color(table_c), &alpha(table_a), &missing).unwrap();
    assert_eq!(w.len(), 2, "one warning per map: {w:?}");
    assert!(w[0].message.contains("value 9"), "{}", w[0]);
    assert_eq!(at(&m, &missing, [0.1; 3]), ([0.0; 3], 0.0));
}

#[test]
fn every_bary_shading_scheme() {
    let vol = tet_volume([0.0; 4], [0.0; 4], 0, 0.0);
    let p = [0.1, 0.2, 0.3];
    let [v1, v2, v3, _] = lambda(p);
    let expect = [
        v1,
        v1 * v2,
        v1 * v2 * (v1 - v2).abs(),
        v1 * v2 * v3,
        v1 * v1 * v2 * v3,
    ];
    for k in 1..=5 {
        let a = alpha(&format!(
            "# VoRANG Alphamap 1.0\nDataField 2\nBARY_SHADING @1\n@1\n{k} 150\n"
        ));
        let m = bind(&ColorMap::default_map(), &a, &vol);
        let (_, chi) = at(&m, &vol, p);
        assert!(close(chi, 150.0 * expect[k - 1]), "scheme {k}: {chi}");
    }
}

#[test]
fn categories_pick_the_first_matching_line_and_miss_to_zero() {
    let c = "# VoRANG Colormap 1.0\nCategoryField 5\nCONSTANT from:0 to:5 @a\nCONSTANT from:3 to:8 @b\nCONSTANT from:20 @c\n@a\n1 0 0\n@b\n0 1 0\n@c\n0 0 1\n";
    let a = "# VoRANG Alphamap 1.0\nCategoryField 5\nCONSTANT to:4 @1\nSIMPLE_ABSORBER field:0 @2\n@1\n7\n@2\n1 0\n3 10\n";
    for (cat, eta, chi) in [
        (-1.0, [0.0; 3], 7.0), // no colour line holds −1; alpha's open 'to:4' does
        (0.0, [1.0, 0.0, 0.0], 7.0), // from is inclusive
        (4.0, [1.0, 0.0, 0.0], 2.0), // overlap [3,5): the first line wins; alpha falls through
        (5.0, [0.0, 1.0, 0.0], 2.0), // to is exclusive
        (8.0, [0.0; 3], 2.0),  // gap [8, 20)
        (25.0, [0.0, 0.0, 1.0], 2.0),
    ] {
        // s = 5 at the sample point → the overriding absorber (field 0) gives 2.
        let vol = tet_volume([5.0; 4], [0.0; 4], 0, cat as f32);
        let m = bind(&color(c), &alpha(a), &vol);
        let (e, k) = at(&m, &vol, [0.2; 3]);
        assert_eq!(e, eta, "category {cat}");
        assert!(close(k, chi), "category {cat}: {k}");
    }
}

#[test]
fn field_overrides_read_another_field() {
    let vol = tet_volume([1.0; 4], [3.0; 4], 0, 0.0);
    let c = "# VoRANG Colormap 1.0\nDataField 0\nSIMPLE_EMITTER field:1 @1\n@1\n0 0 0 0\n1 1 1 4\n";
    let m = bind(&color(c), &AlphaMap::default_map(), &vol);
    assert_eq!(m.fields(), &[1]);
    assert!(close(at(&m, &vol, [0.1; 3]).0[0], 0.75));
    let g = "# VoRANG Colormap 1.0\nDataField 1\nSIMPLE_EMITTER field:global @1\n@1\n0 0 0 0\n1 1 1 4\n";
    let m = bind(&color(g), &AlphaMap::default_map(), &vol);
    assert_eq!(m.fields(), &[1]);
}

#[test]
fn binding_errors_name_the_map_line() {
    let vol = tet_volume([0.0; 4], [0.0; 4], 0, 0.0);
    let cases: [(&str, bool, usize, &str); 7] = [
        (
            "# VoRANG Colormap 1.0\nDataField 9\nSIMPLE_EMITTER @1\n@1\n1 1 1 0\n",
            true,
            2,
            "DataField 9",
        ),
        (
            "# VoRANG Colormap 1.0\nCategoryField 3\nCONSTANT @1\n@1\n1 1 1\n",
            true,
            2,
            "must be scalar",
        ),
        (
            "# VoRANG Colormap 1.0\nDataField 0\n\nIDENTITY\n",
            true,
            4,
            "needs a float[3] field",
        ),
        (
            "# VoRANG Colormap 1.0\nCONST_CELL field:0 @1\n@1\n1 1 1 0\n",
            true,
            2,
            "byte Constant",
        ),
        (
            "# VoRANG Colormap 1.0\nSIMPLE_EMITTER field:12 @1\n@1\n1 1 1 0\n",
            true,
            2,
            "field: 12",
        ),
        (
            "# VoRANG Alphamap 1.0\nDataField 3\nBARY_SHADING @1\n@1\n3 1\n",
            false,
            3,
            "float[4]",
        ),
        (
            "# VoRANG Alphamap 1.0\nDataField 2\nSIMPLE_ABSORBER @1\n@1\n1 0\n",
            false,
            3,
            "scalar",
        ),
    ];
    for (text, is_color, line, fragment) in cases {
        let e = if is_color {
            Mapping::new(&color(text), &AlphaMap::default_map(), &vol).unwrap_err()
        } else {
            Mapping::new(&ColorMap::default_map(), &alpha(text), &vol).unwrap_err()
        };
        assert_eq!(e.line, line, "{e}");
        assert!(e.message.contains(fragment), "{e}");
    }
}

/// Brute force: on every piece between the reported cuts, η and χ must be polynomials of the
/// reported degree (checked by finite differences on many samples), and the cuts must be real
/// (the shape changes across each).
#[test]
fn breakpoints_and_shapes_match_brute_force_sampling() {
    let maps: Vec<(ColorMap, AlphaMap)> = vec![
        (
            color(
                "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 0 0\n1 0.5 0 0.3\n2 2 1 0.5\n0 1 3 0.9\n",
            ),
            alpha("# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0 0.1\n4 0.4\n1 0.6\n"),
        ),
        (
            color(
                "# VoRANG Colormap 1.0\nDataField 1\nABSORPTION_WEIGHTED @1\n@1\n1 0 0 0.2\n0 1 0 0.7\n",
            ),
            alpha("# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0 0\n5 0.5\n2 1\n"),
        ),
        (
            color(
                "# VoRANG Colormap 1.0\nCategoryField 1\nSIMPLE_EMITTER from:0.4 @1\nCONSTANT @2\n@1\n0 0 0 0\n3 3 3 1\n@2\n0.5 0.5 0.5\n",
            ),
            alpha("# VoRANG Alphamap 1.0\nDataField 2\nBARY_SHADING @1\n@1\n1 3\n"),
        ),
        (
            ColorMap::default_map(),
            alpha("# VoRANG Alphamap 1.0\nDataField 2\nBARY_SHADING @1\n@1\n3 10\n"),
        ),
    ];
    let mut rng = SplitMix64(42);
    let mut checked_pieces = 0;
    for (c, a) in &maps {
        for _ in 0..200 {
            let s: [f32; 4] = std::array::from_fn(|_| rng.next_f64() as f32);
            let t: [f32; 4] = std::array::from_fn(|_| rng.next_f64() as f32);
            let vol = tet_volume(s, t, 0, 0.0);
            let m = bind(c, a, &vol);
            // A random chord of the tetrahedron.
            let rand_point = |rng: &mut SplitMix64| {
                let w: [f64; 4] = std::array::from_fn(|_| rng.next_f64());
                let sum: f64 = w.iter().sum();
                [w[1] / sum, w[2] / sum, w[3] / sum]
            };
            let (p0, p1) = (rand_point(&mut rng), rand_point(&mut rng));
            let point = |u: f64| [0, 1, 2].map(|k| p0[k] + u * (p1[k] - p0[k]));
            let values = |u: f64| {
                let mut b = vec![0.0; m.width()];
                m.sample_fields(&vol, 0, &lambda(point(u)), point(u), &mut b);
                b
            };
            let mut cuts = Vec::new();
            m.cuts(&values(0.0), &values(1.0), &mut cuts);
            cuts.retain(|&t| t > 0.0 && t < 1.0);
            cuts.sort_by(f64::total_cmp);
            let mut ends = vec![0.0];
            ends.extend(&cuts);
            ends.push(1.0);
            for w in ends.windows(2) {
                let (u0, u1) = (w[0], w[1]);
                if u1 - u0 < 1e-6 {
                    continue;
                }
                let mid = values(0.5 * (u0 + u1));
                let (eta_shape, chi_shape) = m.piece_shapes(&mid);
                let lines = m.lines_at(&mid);
                let n = 24;
                let samples: Vec<([f64; 3], f64)> = (0..=n)
                    .map(|i| {
                        let u = u0 + (u1 - u0) * i as f64 / n as f64;
                        m.eval_on(lines, &values(u), 0, point(u))
                    })
                    .collect();
                let chi: Vec<f64> = samples.iter().map(|s| s.1).collect();
                assert_polynomial(&chi, chi_shape, "χ");
                for k in 0..3 {
                    let eta: Vec<f64> = samples.iter().map(|s| s.0[k]).collect();
                    assert_polynomial(&eta, eta_shape, "η");
                }
                checked_pieces += 1;
            }
        }
    }
    assert!(checked_pieces > 800, "{checked_pieces}");
}

/// Equally spaced samples of a polynomial of degree d have vanishing (d+1)-th differences.
fn assert_polynomial(v: &[f64], shape: Shape, what: &str) {
    let degree = match shape {
        Shape::Constant => 0,
        Shape::Linear => 1,
        Shape::Quadratic => 2,
        Shape::Nonlinear => return,
    };
    let scale = v.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let mut d = v.to_vec();
    for _ in 0..=degree {
        d = d.windows(2).map(|w| w[1] - w[0]).collect();
    }
    let worst = d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(
        worst <= 1e-9 * scale,
        "{what} is not of degree {degree} on a piece: residual {worst}, samples {v:?}"
    );
}

#[test]
fn a_missing_cut_would_be_caught() {
    // The checker itself: a SIMPLE_EMITTER piece that spans a breakpoint is not linear.
    let v: Vec<f64> = (0..=24).map(|i| (i as f64 / 24.0 - 0.5).abs()).collect();
    let r = std::panic::catch_unwind(|| assert_polynomial(&v, Shape::Linear, "test"));
    assert!(r.is_err());
}

#[test]
fn every_bad_map_file_fails_at_the_stated_line() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad/maps");
    let (vol, _) =
        Volume::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/two_tets_data.hmesh"))
            .unwrap();
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    let mut failures = Vec::new();
    let mut checked = 0;
    for path in entries {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&path).unwrap();
        let expect = text
            .lines()
            .nth(1)
            .and_then(|l| l.strip_prefix("# expect: line "))
            .unwrap_or_else(|| panic!("{name}: no expectation"));
        let (line, fragment) = expect.split_once(": ").unwrap();
        let line: usize = line.parse().unwrap();
        let file = path.display().to_string();
        let result = if name.starts_with("color") {
            parse_map::<dyn ColorShading>(text.as_bytes(), &file)
                .and_then(|(c, _)| Mapping::new(&c, &AlphaMap::default_map(), &vol))
                .map(|_| ())
        } else {
            parse_map::<dyn AlphaShading>(text.as_bytes(), &file)
                .and_then(|(a, _)| Mapping::new(&ColorMap::default_map(), &a, &vol))
                .map(|_| ())
        };
        match result {
            Ok(()) => failures.push(format!("{name}: accepted")),
            Err(e) if e.line != line || !e.message.contains(fragment) || e.file != file => failures
                .push(format!(
                    "{name}: expected line {line} '{fragment}', got {e}"
                )),
            Err(_) => {}
        }
        checked += 1;
    }
    assert!(checked >= 20, "{checked}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// IDENTITY of a vector field with negative components: the emission is
/// clamped to 0 and each render warns once, with the count; a field without negative values
/// gives no warning.
#[test]
fn identity_clamps_negative_emission_with_one_warning_per_render() {
    let tmp = tempfile::tempdir().unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/two_tets_data.hmesh");
    let run = |field: usize| {
        let map = tmp.path().join(format!("c{field}.map"));
        std::fs::write(
            &map,
            format!("# VoRANG Colormap 1.0\nDataField {field}\nIDENTITY\n"),
        )
        .unwrap();
        let script = tmp.path().join(format!("s{field}.tcl"));
        std::fs::write(
            &script,
            format!(
                "imagesize 16 16\nvolume {{{}}}\ncolormap {{{}}}\nlinedraw off\nmethod exact linear 0 1\noutput {{{}}}\nrender_btf\nrender_btf\n",
                data.display(),
                map.display(),
                tmp.path().join(format!("i{field}.pfm")).display()
            ),
        )
        .unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
            .arg(&script)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    // Field 4 ("E", EdgeElem) has negative components; field 1 ("colour") lies in [0, 1].
    let negative = run(4);
    let warnings: Vec<&str> = negative
        .lines()
        .filter(|l| l.contains("IDENTITY clamped"))
        .collect();
    assert_eq!(warnings.len(), 2, "{negative}");
    assert!(
        warnings[0].contains("negative components to 0"),
        "{negative}"
    );
    assert!(!run(1).contains("IDENTITY clamped"));
}
