//! Complex fields mapped through their real part, imaginary part or modulus:
//! rendered with `exact` and compared with an independent computation in this file (the ray's
//! interval in each cell from its barycentric coordinates, the tables interpolated here, the
//! transport equation integrated by Runge–Kutta, or its closed form for constant cells).

#![allow(clippy::needless_range_loop)]

use vorang::Volume;
use vorang::hypermesh::read_bytes;
use vorang::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
use vorang::render::{LineDraw, Method, Settings, render};
use vorang::scene::View;

const NODES: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
];
/// Two cells sharing the face (2 3 4): seen along z, rays with x + y < 1 cross both.
const TETS: [[usize; 4]; 2] = [[0, 1, 2, 3], [1, 2, 3, 4]];
/// Node values (re, im); the edge from node 4 to node 5 passes through 0 (a kink of |z|).
const Z: [[f64; 2]; 5] = [
    [1.0, 0.0],
    [-2.0, 1.0],
    [0.5, -2.0],
    [3.0, 3.0],
    [-1.0, -1.0],
];

/// The two cells with the node values `Z` as a Linear complex field 0 "z", a real Linear
/// field 1 (the real parts as doubles) and cell values `cells` as a Constant complex field 2.
fn volume(cells: [[f64; 2]; 2]) -> Volume {
    let mut t = String::from(
        "# HyperMesh 3D ASCII 0.7\nnNodes = 5\nnTetrahedra = 2\nNodes { float[3] Coordinates } = @1\nTetrahedra { int[4] Nodes } = @2\nNodeData { complex } = @3\nNodeData { double } = @4\nTetrahedronData { complex } = @5\nField \"z\" { complex } = Linear(@3)\nField { double } = Linear(@4)\nField { complex } = Constant(@5)\n@1\n",
    );
    for p in NODES {
        t += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    t += "@2\n";
    for c in TETS {
        t += &format!("{} {} {} {}\n", c[0] + 1, c[1] + 1, c[2] + 1, c[3] + 1);
    }
    t += "@3\n";
    for z in Z {
        t += &format!("{} {}\n", z[0], z[1]);
    }
    t += "@4\n";
    for z in Z {
        t += &format!("{}\n", z[0]);
    }
    t += "@5\n";
    for z in cells {
        t += &format!("{} {}\n", z[0], z[1]);
    }
    Volume::from_file(read_bytes(t.as_bytes(), "two.hmesh").unwrap()).unwrap()
}

/// Colour rows (r g b value) and absorption rows (a value), shared by every test.
const COLOR: [[f64; 4]; 4] = [
    [1.0, 0.0, 0.0, -2.0],
    [0.0, 1.0, 0.0, 0.5],
    [0.0, 0.0, 1.0, 3.0],
    [0.5, 0.5, 0.0, 4.0],
];
const ALPHA: [[f64; 2]; 3] = [[0.2, -2.0], [2.0, 1.0], [0.5, 4.5]];

fn maps(field: &str) -> (String, String) {
    let mut c = format!("# VoRANG Colormap 1.0\nDataField {field}\nSIMPLE_EMITTER @1\n@1\n");
    for r in COLOR {
        c += &format!("{} {} {} {}\n", r[0], r[1], r[2], r[3]);
    }
    let mut a = format!("# VoRANG Alphamap 1.0\nDataField {field}\nSIMPLE_ABSORBER @1\n@1\n");
    for r in ALPHA {
        a += &format!("{} {}\n", r[0], r[1]);
    }
    (c, a)
}

fn bind(vol: &Volume, color: &str, alpha: &str) -> Result<Mapping, String> {
    let c = parse_map::<dyn ColorShading>(color.as_bytes(), "c.map")
        .map_err(|e| e.to_string())?
        .0;
    let a = parse_map::<dyn AlphaShading>(alpha.as_bytes(), "a.map")
        .map_err(|e| e.to_string())?
        .0;
    Mapping::new(&c, &a, vol)
        .map(|(m, _)| m)
        .map_err(|e| e.to_string())
}

/// A table with rows (values…, x), x increasing: linear in between, clamped outside.
fn table<const N: usize>(rows: &[[f64; N]], x: f64) -> [f64; N] {
    let k = N - 1;
    if x <= rows[0][k] {
        return rows[0];
    }
    for w in rows.windows(2) {
        if x <= w[1][k] {
            let t = (x - w[0][k]) / (w[1][k] - w[0][k]);
            return std::array::from_fn(|c| w[0][c] + t * (w[1][c] - w[0][c]));
        }
    }
    rows[rows.len() - 1]
}

/// Barycentric coordinates of `p` in cell `c` (Cramer's rule).
fn barycentric(c: usize, p: [f64; 3]) -> [f64; 4] {
    let n = TETS[c].map(|i| NODES[i]);
    let e: [[f64; 3]; 3] = std::array::from_fn(|k| std::array::from_fn(|d| n[k + 1][d] - n[0][d]));
    let q: [f64; 3] = std::array::from_fn(|d| p[d] - n[0][d]);
    let det = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0])
    };
    let d = det(e[0], e[1], e[2]);
    let l1 = det(q, e[1], e[2]) / d;
    let l2 = det(e[0], q, e[2]) / d;
    let l3 = det(e[0], e[1], q) / d;
    [1.0 - l1 - l2 - l3, l1, l2, l3]
}

/// The z interval of the line through (x, y) parallel to z inside cell `c`, if any.
fn interval(c: usize, x: f64, y: f64) -> Option<(f64, f64)> {
    let (l0, l1) = (barycentric(c, [x, y, 0.0]), barycentric(c, [x, y, 1.0]));
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..4 {
        let (a, b) = (l0[i], l1[i] - l0[i]); // λ_i(z) = a + b·z ≥ 0
        if b > 0.0 {
            lo = lo.max(-a / b);
        } else if b < 0.0 {
            hi = hi.min(-a / b);
        } else if a < 0.0 {
            return None;
        }
    }
    (hi > lo + 1e-12).then_some((lo, hi))
}

/// (R, G, B, alpha) of the ray through (x, y) over a white background, brightness 1: along
/// the ray towards the eye (+z) dI/dz = η − χ·I, by classical Runge–Kutta with `steps` steps
/// per cell; `scalar(cell, z)` is the mapped part at height z.
fn reference(x: f64, y: f64, steps: usize, scalar: &dyn Fn(usize, [f64; 3]) -> f64) -> [f64; 4] {
    let mut cells: Vec<(usize, f64, f64)> = (0..2)
        .filter_map(|c| interval(c, x, y).map(|(a, b)| (c, a, b)))
        .collect();
    cells.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut state = [1.0, 1.0, 1.0, 0.0]; // I (RGB), optical depth τ
    for (c, z0, z1) in cells {
        let deriv = |z: f64, s: &[f64; 4]| -> [f64; 4] {
            let v = scalar(c, [x, y, z]);
            let eta = table(&COLOR, v);
            let chi = table(&ALPHA, v)[0];
            [
                eta[0] - chi * s[0],
                eta[1] - chi * s[1],
                eta[2] - chi * s[2],
                chi,
            ]
        };
        let h = (z1 - z0) / steps as f64;
        for k in 0..steps {
            let z = z0 + k as f64 * h;
            let add = |s: &[f64; 4], d: &[f64; 4], f: f64| -> [f64; 4] {
                std::array::from_fn(|i| s[i] + f * d[i])
            };
            let k1 = deriv(z, &state);
            let k2 = deriv(z + h / 2.0, &add(&state, &k1, h / 2.0));
            let k3 = deriv(z + h / 2.0, &add(&state, &k2, h / 2.0));
            let k4 = deriv(z + h, &add(&state, &k3, h));
            state = std::array::from_fn(|i| {
                state[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
        }
    }
    [state[0], state[1], state[2], 1.0 - (-state[3]).exp()]
}

/// The complex Linear field at a point of cell `c`, from the node values.
fn z_at(c: usize, p: [f64; 3]) -> [f64; 2] {
    let l = barycentric(c, p);
    let mut z = [0.0; 2];
    for (i, &n) in TETS[c].iter().enumerate() {
        z[0] += l[i] * Z[n][0];
        z[1] += l[i] * Z[n][1];
    }
    z
}

const SIZE: usize = 12;

fn render_exact(vol: &Volume, m: &Mapping) -> Vec<[f32; 4]> {
    let words = ["exact", "linear", "0", "1"];
    let settings = Settings {
        width: SIZE,
        height: SIZE,
        method: Method::parse(&words).unwrap(),
        lines: LineDraw::Off,
        ..Settings::default()
    };
    render(vol, m, &View::default(), &settings, None)
        .unwrap()
        .0
        .pixels
}

/// Pixel (i, j)'s ray in file coordinates: the default camera frames the unit box's x, y
/// extent; j counts from the top.
fn ray(i: usize, j: usize) -> (f64, f64) {
    let s = SIZE as f64;
    ((i as f64 + 0.5) / s, 1.0 - (j as f64 + 0.5) / s)
}

fn compare(pixels: &[[f32; 4]], tol: f64, truth: impl Fn(f64, f64) -> [f64; 4]) -> f64 {
    let mut worst = 0.0f64;
    let mut drawn = 0;
    for j in 0..SIZE {
        for i in 0..SIZE {
            let (x, y) = ray(i, j);
            let want = truth(x, y);
            let got = pixels[j * SIZE + i];
            for k in 0..4 {
                let d = (f64::from(got[k]) - want[k]).abs();
                worst = worst.max(d);
                assert!(
                    d < tol,
                    "pixel ({i}, {j}) channel {k}: {} vs {}",
                    got[k],
                    want[k]
                );
            }
            drawn += usize::from(want[3] > 0.0);
        }
    }
    assert!(drawn > SIZE * SIZE / 2, "the mesh covers the image");
    worst
}

#[test]
fn real_and_imaginary_parts_render_exactly_like_a_real_field() {
    let vol = volume([[0.0, 0.0]; 2]);
    for (sel, part) in [("re(0)", 0), ("im(\"z\")", 1)] {
        let (c, a) = maps(sel);
        let pixels = render_exact(&vol, &bind(&vol, &c, &a).unwrap());
        let worst = compare(&pixels, 2e-6, |x, y| {
            reference(x, y, 4000, &|c, p| z_at(c, p)[part])
        });
        eprintln!("{sel}: largest difference {worst:.2e}");
    }
    // The real part is the same image as the real field 1 that holds it.
    let (c, a) = maps("re(0)");
    let (c1, a1) = maps("1");
    assert_eq!(
        render_exact(&vol, &bind(&vol, &c, &a).unwrap()),
        render_exact(&vol, &bind(&vol, &c1, &a1).unwrap())
    );
}

#[test]
fn the_modulus_renders_to_the_independent_integral() {
    let vol = volume([[0.0, 0.0]; 2]);
    let (c, a) = maps("abs(0)");
    let pixels = render_exact(&vol, &bind(&vol, &c, &a).unwrap());
    let worst = compare(&pixels, 1e-5, |x, y| {
        reference(x, y, 4000, &|c, p| {
            let z = z_at(c, p);
            z[0].hypot(z[1])
        })
    });
    eprintln!("abs(0): largest difference {worst:.2e}");
}

#[test]
fn the_modulus_of_a_constant_field_has_the_closed_form() {
    // |3 + 4i| = 5 in the first cell, |0.6 − 0.8i| = 1 in the second.
    let vol = volume([[3.0, 4.0], [0.6, -0.8]]);
    let (c, a) = maps("abs(2)");
    let pixels = render_exact(&vol, &bind(&vol, &c, &a).unwrap());
    let modulus = [5.0, 1.0];
    compare(&pixels, 2e-6, |x, y| {
        let mut cells: Vec<(usize, f64, f64)> = (0..2)
            .filter_map(|c| interval(c, x, y).map(|(lo, hi)| (c, lo, hi)))
            .collect();
        cells.sort_by(|a, b| a.1.total_cmp(&b.1));
        // Far to near: I ← I·θ + η/χ·(1 − θ), θ = exp(−χ·L).
        let (mut i, mut tau) = ([1.0; 3], 0.0f64);
        for (c, lo, hi) in cells {
            let eta = table(&COLOR, modulus[c]);
            let chi = table(&ALPHA, modulus[c])[0];
            let theta = (-chi * (hi - lo)).exp();
            for k in 0..3 {
                i[k] = i[k] * theta + eta[k] / chi * (1.0 - theta);
            }
            tau += chi * (hi - lo);
        }
        [i[0], i[1], i[2], 1.0 - (-tau).exp()]
    });
}

#[test]
fn a_complex_field_without_a_part_names_the_three_choices() {
    let vol = volume([[0.0, 0.0]; 2]);
    let (c, a) = maps("abs(0)");
    let e = bind(&vol, &c.replace("DataField abs(0)", "DataField 0"), &a).unwrap_err();
    assert_eq!(
        e,
        "c.map:3: SIMPLE_EMITTER: field 0 \"z\" { complex } = Linear is complex: name the part to map, its real part re(0), imaginary part im(0) or modulus abs(0)"
    );
    // By name, and on a method line.
    let e = bind(
        &vol,
        &c,
        &a.replace("SIMPLE_ABSORBER @1", "SIMPLE_ABSORBER field:\"z\" @1"),
    )
    .unwrap_err();
    assert!(
        e.starts_with("a.map:3: SIMPLE_ABSORBER: field 0 \"z\"")
            && e.contains("re(\"z\"), imaginary part im(\"z\") or modulus abs(\"z\")"),
        "{e}"
    );
    // A part of a real field.
    let e = bind(&vol, &c.replace("abs(0)", "abs(1)"), &a).unwrap_err();
    assert_eq!(
        e,
        "c.map:3: SIMPLE_EMITTER: abs(1): field 1 { double } = Linear is not complex, so it has no modulus; write 1 alone"
    );
    // A complex category needs a part too.
    let e = bind(
        &vol,
        &c,
        &a.replace("DataField abs(0)", "DataField abs(0)\nCategoryField 2"),
    )
    .unwrap_err();
    assert!(
        e.starts_with("a.map:3: CategoryField: field 2 { complex } = Constant is complex"),
        "{e}"
    );
    assert!(
        bind(
            &vol,
            &c,
            &a.replace("DataField abs(0)", "DataField abs(0)\nCategoryField re(2)")
        )
        .is_ok()
    );
}

#[test]
fn info_shows_each_part_and_suggests_the_modulus() {
    let vol = volume([[3.0, 4.0], [0.6, -0.8]]);
    let text = vorang::info::describe_volume(&vol, "ASCII 0.7");
    // Field 2 is constant per cell: exact ranges. Field 0: the nodes' values (and centres).
    assert!(
        text.contains("range re [0.6, 3] im [-0.8, 4] abs [1, 5]"),
        "{text}"
    );
    assert!(
        text.contains("range re [-2, 3] im [-2, 3] abs [0.279508, 4.24264]"),
        "{text}"
    );
    assert!(
        text.contains("try   colormap preset viridis 1 5 abs(2); alphamap ramp 1 5"),
        "{text}"
    );
    // The suggested line works as it is.
    let line = text
        .lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix("try   colormap preset viridis 1 5 abs(2)")
        })
        .unwrap();
    assert!(line.contains("abs(2)"));
    let c = vorang::mapping::preset_colormap("viridis", 1.0, 5.0, Some("abs(2)")).unwrap();
    let a = vorang::mapping::ramp_alphamap(1.0, 5.0, 2.0, Some("abs(2)")).unwrap();
    Mapping::new(&c, &a, &vol).unwrap();
}

#[test]
fn the_legend_of_a_constant_colour_spans_the_part_s_range() {
    let vol = volume([[3.0, 4.0], [0.6, -0.8]]);
    let c = parse_map::<dyn ColorShading>(
        b"# VoRANG Colormap 1.0\nDataField abs(2)\nCONSTANT @1\n@1\n1 0 0\n",
        "c.map",
    )
    .unwrap()
    .0;
    let scale = vorang::legend::ColorScale::of_map(&c, &vol).unwrap();
    assert_eq!((scale.lo, scale.hi), (1.0, 5.0));
}

#[test]
fn lighting_refuses_a_part_of_a_complex_field() {
    // LIT_EMITTER shades by the field's gradient, which a part of a complex field lacks.
    let vol = volume([[0.0, 0.0]; 2]);
    let (_, a) = maps("abs(0)");
    let lit = "# VoRANG Colormap 1.0\nDataField im(0)\nLIT_EMITTER @1\n@1\n0.2 1 0.5 16\n1 1 1 0\n";
    assert_eq!(
        bind(&vol, lit, &a).unwrap_err(),
        "c.map:3: LIT_EMITTER: im(0): lighting needs the gradient of a real field, which the imaginary part of a complex field does not provide"
    );
    assert!(bind(&vol, &lit.replace("im(0)", "1"), &a).is_ok());
}
