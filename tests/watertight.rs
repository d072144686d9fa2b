//! Exact for every ray and every mesh: degenerate views (rays within rounding of face planes),
//! non-convex and disconnected meshes, visibility cycles, mirrors — each against an independent
//! answer (the reference ray caster, an analytic box, an exactly turned copy of the mesh, or the
//! flipped unmirrored image).

#![allow(clippy::needless_range_loop)]

use vorang::Volume;
use vorang::accuracy::{scalar_maps, scalar_volume};
use vorang::framebuffer::Framebuffer;
use vorang::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
use vorang::mesh::generate::{SplitMix64, kuhn_box};
use vorang::reference::Options;
use vorang::render::{LineDraw, Method, Order, Settings, Stats, render};
use vorang::scene::{Affine, Camera, LookAt, Projector, TransformOp, View};

/// A smooth node field `s`, so that cells differ and the order along a ray matters.
fn with_field(nodes: Vec<[f64; 3]>, tets: Vec<[u32; 4]>) -> Volume {
    let s: Vec<f64> = nodes.iter().map(field_of).collect();
    scalar_volume(nodes, tets, s)
}

fn with_values(nodes: Vec<[f64; 3]>, tets: Vec<[u32; 4]>, s: Vec<f64>) -> Volume {
    scalar_volume(nodes, tets, s)
}

fn maps(vol: &Volume) -> Mapping {
    scalar_maps(vol)
}

fn homogeneous(vol: &Volume, eta: [f64; 3], chi: f64) -> Mapping {
    let c = format!(
        "# VoRANG Colormap 1.0\nCONSTANT @1\n@1\n{} {} {}\n",
        eta[0], eta[1], eta[2]
    );
    let a = format!("# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n{chi}\n");
    let c = parse_map::<dyn ColorShading>(c.as_bytes(), "c").unwrap().0;
    let a = parse_map::<dyn AlphaShading>(a.as_bytes(), "a").unwrap().0;
    Mapping::new(&c, &a, vol).unwrap().0
}

const METHODS: [&str; 5] = [
    "exact linear 0 1",
    "exact constEA 0.07 1",
    "interpolateCoeff linear 1",
    "interpolateColor 1",
    "test 0.3",
];

/// The methods whose result along a ray does not depend on where cell boundaries fall on it
/// (exact rules). A view turned by rounding is put back onto the degenerate one by the sub-pixel
/// grid, for every method; a view turned by 10⁻⁵° is not, and a ray grazing a face plane then
/// splits its stretch between the two cells at an ill-conditioned point, which only these are
/// indifferent to (step rules, `interpolateColor` and `test` see the split).
const SPLIT_FREE: [&str; 2] = ["exact linear 0 1", "interpolateCoeff linear 1"];

fn draw(vol: &Volume, m: &Mapping, view: &View, size: (usize, usize), method: &str) -> Framebuffer {
    draw_with(vol, m, view, size, method, Order::BackToFront).0
}

fn draw_with(
    vol: &Volume,
    m: &Mapping,
    view: &View,
    (width, height): (usize, usize),
    method: &str,
    order: Order,
) -> (Framebuffer, Stats) {
    let words: Vec<&str> = method.split_whitespace().collect();
    let s = Settings {
        width,
        height,
        method: Method::parse(&words).unwrap(),
        lines: LineDraw::Off,
        order,
        ..Settings::default()
    };
    render(vol, m, view, &s, None).unwrap()
}

/// Largest difference over all channels, with `b` read through `at(x, y)`.
fn worst(a: &Framebuffer, at: impl Fn(usize, usize) -> [f64; 4]) -> (f64, usize, usize) {
    let mut w = (0.0, 0, 0);
    for y in 0..a.height {
        for x in 0..a.width {
            let p = a.pixels[y * a.width + x];
            let q = at(x, y);
            for c in 0..4 {
                let d = (f64::from(p[c]) - q[c]).abs();
                if d > w.0 || d.is_nan() {
                    w = (d, x, y);
                }
            }
        }
    }
    w
}

fn pixel(fb: &Framebuffer, x: usize, y: usize) -> [f64; 4] {
    fb.pixels[y * fb.width + x].map(f64::from)
}

fn against_reference(vol: &Volume, m: &Mapping, view: &View, size: (usize, usize)) -> f64 {
    let (fb, _) = draw_with(vol, m, view, size, "exact linear 0 1", Order::BackToFront);
    let r = vorang::reference::render(vol, m, view, &Options::new(size.0, size.1));
    worst(&fb, |x, y| r[y * size.0 + x]).0
}

fn rotate(axis: [f64; 3], degrees: f64) -> TransformOp {
    TransformOp::Rotate { axis, degrees }
}

fn turned(ops: Vec<TransformOp>) -> View {
    View {
        transforms: ops,
        ..View::default()
    }
}

/// A 4×4×4 Kuhn box without jitter at 18×18: cube edges and diagonal faces run through rows
/// and columns of pixel centres.
fn structured() -> Volume {
    let (nodes, tets) = kuhn_box([4, 4, 4], [1.0; 3], 0.0, 1);
    with_field(nodes, tets)
}

#[test]
fn a_structured_mesh_turned_a_full_circle_renders_as_unturned() {
    let farbraum = Volume::load(std::path::Path::new("examples/farbraum/farbraum.hmesh"))
        .unwrap()
        .0;
    for (name, vol, size) in [
        ("kuhn box", structured(), (18, 18)),
        ("farbraum", farbraum, (32, 16)),
    ] {
        let m = if name == "farbraum" {
            homogeneous(&vol, [0.3, 0.6, 0.9], 1.5)
        } else {
            maps(&vol)
        };
        for method in SPLIT_FREE {
            let plain = draw(&vol, &m, &View::default(), size, method);
            let nearly = turned(vec![rotate([0.0, 1.0, 0.0], 1e-5)]);
            let fb = draw(&vol, &m, &nearly, size, method);
            let (d, x, y) = worst(&fb, |x, y| pixel(&plain, x, y));
            assert!(d <= 1e-6, "{name}, {method}, 1e-5°: {d:e} at ({x}, {y})");
        }
        let circles = [
            ("12 × 30° about y", vec![rotate([0.0, 1.0, 0.0], 30.0); 12]),
            ("4 × 90° about x", vec![rotate([1.0, 0.0, 0.0], 90.0); 4]),
            ("4 × 90° about z", vec![rotate([0.0, 0.0, 1.0], 90.0); 4]),
        ];
        for method in METHODS {
            let plain = draw(&vol, &m, &View::default(), size, method);
            for (what, ops) in &circles {
                let fb = draw(&vol, &m, &turned(ops.clone()), size, method);
                let (d, x, y) = worst(&fb, |x, y| pixel(&plain, x, y));
                assert!(d <= 1e-6, "{name}, {method}, {what}: {d:e} at ({x}, {y})");
            }
        }
    }
}

/// Turning by 90° about a coordinate axis, exactly, about the unit box's centre.
fn quarter(axis: usize, p: [f64; 3]) -> [f64; 3] {
    let c = p.map(|v| v - 0.5);
    let r = match axis {
        0 => [c[0], -c[2], c[1]],
        1 => [c[2], c[1], -c[0]],
        _ => [-c[1], c[0], c[2]],
    };
    r.map(|v| v + 0.5)
}

fn field_of(p: &[f64; 3]) -> f64 {
    (1.7 * p[0] + 0.3).sin() + (1.1 * p[1]).cos() * p[2] + 0.4 * p[2]
}

/// The mesh with its nodes turned exactly (a permutation of coordinates with signs) against the
/// mesh turned by the renderer's rotation matrix, which is off by rounding: every quarter and
/// half turn about each axis, every method.
#[test]
fn quarter_and_half_turns_equal_exactly_turned_meshes() {
    let (nodes, tets) = kuhn_box([3, 3, 3], [1.0; 3], 0.0, 1);
    let vol = with_field(nodes.clone(), tets.clone());
    let m = maps(&vol);
    for axis in 0..3 {
        for quarters in [1, 2] {
            let exact_nodes: Vec<[f64; 3]> = nodes
                .iter()
                .map(|&p| (0..quarters).fold(p, |p, _| quarter(axis, p)))
                .collect();
            // The field moves with the nodes: same values, same numbering.
            let values = nodes.iter().map(field_of).collect();
            let exact = with_values(exact_nodes, tets.clone(), values);
            let mut dir = [0.0; 3];
            dir[axis] = 1.0;
            let view = turned(vec![rotate(dir, 90.0 * quarters as f64)]);
            for method in METHODS {
                let want = draw(&exact, &m, &View::default(), (18, 18), method);
                let got = draw(&vol, &m, &view, (18, 18), method);
                let (d, x, y) = worst(&got, |x, y| pixel(&want, x, y));
                assert!(
                    d <= 1e-6,
                    "{method}, {}° about axis {axis}: {d:e} at ({x}, {y})",
                    90 * quarters
                );
            }
        }
    }
}

/// Length of the ray `o + t·d` (file coordinates) inside the box `[0, 1]³`.
fn slab(o: [f64; 3], d: [f64; 3]) -> f64 {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        if d[k] == 0.0 {
            if !(0.0..=1.0).contains(&o[k]) {
                return 0.0;
            }
            continue;
        }
        let (a, b) = ((0.0 - o[k]) / d[k], (1.0 - o[k]) / d[k]);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    (t1 - t0).max(0.0) * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// A homogeneous Kuhn box of 6n³ cells is one box: `I = θ + η/χ·(1 − θ)`, θ = e^(−χL), with L
/// the analytic length of each ray in the box — axis-aligned and 45° views, orthographic and
/// perspective, and an eye in the plane of diagonal faces.
#[test]
fn a_homogeneous_kuhn_box_equals_one_analytic_box() {
    let (nodes, tets) = kuhn_box([3, 3, 3], [1.0; 3], 0.0, 1);
    let vol = with_field(nodes, tets);
    let (eta, chi) = ([0.2, 0.5, 0.9], 1.7);
    let m = homogeneous(&vol, eta, chi);
    let persp = Some(Camera::Persp {
        fovy: 50.0,
        aspect: 1.0,
        near: 0.1,
        far: 20.0,
    });
    let eye = |e: [f64; 3]| LookAt {
        eye: e,
        reference: [0.0; 3],
        up: [0.0, 1.0, 0.0],
    };
    let views = [
        ("axis-aligned ortho", View::default()),
        ("45° ortho", turned(vec![rotate([0.0, 1.0, 0.0], 45.0)])),
        (
            "45°, 45° ortho",
            turned(vec![
                rotate([0.0, 1.0, 0.0], 45.0),
                rotate([1.0, 0.0, 0.0], 45.0),
            ]),
        ),
        (
            "axis-aligned perspective",
            View {
                look_at: eye([0.0, 0.0, 2.5]),
                camera: persp,
                ..View::default()
            },
        ),
        (
            "45° perspective",
            View {
                transforms: vec![rotate([0.0, 1.0, 0.0], 45.0)],
                look_at: eye([0.1, 0.2, 2.5]),
                camera: persp,
            },
        ),
        (
            // The Kuhn cubes' diagonal faces lie in the planes x = y (file coordinates, through
            // the box's centre): the eye is in one of them.
            "eye in a diagonal face plane",
            View {
                look_at: eye([1.6, 1.6, 2.2]),
                camera: persp,
                ..View::default()
            },
        ),
    ];
    let (w, h) = (21, 21);
    for (name, view) in views {
        let to_eye = view
            .view_matrix()
            .after(&view.model(vol.mesh.bbox().center()).unwrap());
        let from_eye: Affine = to_eye.inverse().unwrap();
        let proj = Projector::new(view.camera.as_ref(), vol.mesh.bbox().size(), w, h).unwrap();
        let expect = |x: usize, y: usize| -> [f64; 4] {
            let ray = proj.ray(x, y);
            let o = from_eye.apply(ray.origin);
            let d = from_eye.apply_vector(ray.dir);
            let theta = (-chi * slab(o, d)).exp();
            let i = eta.map(|e| theta + e / chi * (1.0 - theta));
            [i[0], i[1], i[2], 1.0 - theta]
        };
        for method in [
            "exact linear 0 1",
            "exact constEA 0 1",
            "interpolateCoeff constEA 1",
        ] {
            let fb = draw(&vol, &m, &view, (w, h), method);
            let (d, x, y) = worst(&fb, expect);
            assert!(d <= 1e-6, "{name}, {method}: {d:e} at ({x}, {y})");
        }
    }
}

/// Nodes and cells of several bodies in one mesh.
#[derive(Default)]
struct Bodies {
    nodes: Vec<[f64; 3]>,
    tets: Vec<[u32; 4]>,
}

impl Bodies {
    fn add(&mut self, nodes: &[[f64; 3]], tets: &[[u32; 4]]) {
        let base = self.nodes.len() as u32;
        self.nodes.extend_from_slice(nodes);
        self.tets.extend(tets.iter().map(|t| t.map(|n| n + base)));
    }

    fn add_box(&mut self, n: usize, origin: [f64; 3], size: f64) {
        let (nodes, tets) = kuhn_box([n; 3], [size; 3], 0.0, 1);
        let nodes: Vec<[f64; 3]> = nodes
            .iter()
            .map(|p| [0, 1, 2].map(|k| p[k] + origin[k]))
            .collect();
        self.add(&nodes, &tets);
    }

    /// A triangular prism from triangle `a` to triangle `b` (corresponding corners), as 3 tets.
    fn add_prism(&mut self, a: [[f64; 3]; 3], b: [[f64; 3]; 3]) {
        let nodes = [a[0], a[1], a[2], b[0], b[1], b[2]];
        self.add(&nodes, &[[0, 1, 2, 3], [1, 2, 3, 4], [2, 3, 4, 5]]);
    }

    fn volume(self) -> Volume {
        with_field(self.nodes, self.tets)
    }
}

fn ortho(l: f64, r: f64, b: f64, t: f64) -> Option<Camera> {
    Some(Camera::Ortho {
        left: l,
        right: r,
        bottom: b,
        top: t,
        front: -1000.0,
        back: 1000.0,
    })
}

/// Several bodies, strongly anisotropic cells: a prism whose front lies over a small box but
/// which reaches 100 units back (its centroid far behind the box); one isolated tet in front of
/// a few connected ones; a body inside a cavity-like gap.
#[test]
fn disjoint_bodies_and_anisotropic_cells_follow_the_rays() {
    let mut scene = Bodies::default();
    scene.add_box(2, [0.0, 0.0, 0.0], 1.0);
    // Front over the box at z = 2, then sheared 5 units sideways per unit of depth: it never
    // meets the box, and its centroid lies ~33 units behind it.
    scene.add_prism(
        [[0.2, 0.2, 2.0], [0.8, 0.3, 2.0], [0.4, 0.8, 2.0]],
        [
            [500.2, 0.2, -100.0],
            [500.8, 0.3, -100.0],
            [500.4, 0.8, -100.0],
        ],
    );
    // An isolated tet in front of the box's right half.
    scene.add(
        &[
            [0.6, 0.1, 1.4],
            [1.0, 0.2, 1.3],
            [0.7, 0.9, 1.5],
            [0.8, 0.5, 1.9],
        ],
        &[[0, 1, 2, 3]],
    );
    // A flat body behind the box.
    scene.add_prism(
        [[-0.2, -0.2, -1.0], [1.2, -0.1, -1.0], [0.5, 1.3, -1.0]],
        [[-0.2, -0.2, -1.3], [1.2, -0.1, -1.3], [0.5, 1.3, -1.3]],
    );
    let vol = scene.volume();
    let m = maps(&vol);
    for view in [
        View {
            camera: ortho(-0.3, 1.3, -0.3, 1.3),
            ..View::default()
        },
        View {
            transforms: vec![rotate([1.0, 0.4, 0.0], 12.0)],
            camera: ortho(-0.3, 1.3, -0.3, 1.3),
            ..View::default()
        },
    ] {
        let (_, stats) = draw_with(
            &vol,
            &m,
            &view,
            (24, 24),
            "exact linear 0 1",
            Order::BackToFront,
        );
        assert!(stats.per_pixel && !stats.convex);
        assert_eq!(stats.overlap_pixels, 0, "valid bodies do not overlap");
        let d = against_reference(&vol, &m, &view, (24, 24));
        assert!(d <= 1e-6, "{d:e}");
    }
}

/// Three long tets interlocked like a triangle of sticks, each over the next at one end and
/// under it at the other: no back-to-front order of the cells exists.
#[test]
fn a_visibility_cycle_is_resolved_per_pixel() {
    let mut scene = Bodies::default();
    let corner = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / 3.0;
        [a.cos(), a.sin()]
    };
    for k in 0..3 {
        let (p, q) = (corner(k), corner(k + 1));
        // From beyond p (high) to beyond q (low), a thin edge across at each end.
        let dir = [q[0] - p[0], q[1] - p[1]];
        let side = [-dir[1] * 0.12, dir[0] * 0.12];
        let s = [p[0] - 0.25 * dir[0], p[1] - 0.25 * dir[1]];
        let e = [q[0] + 0.25 * dir[0], q[1] + 0.25 * dir[1]];
        scene.add(
            &[
                [s[0] + side[0], s[1] + side[1], 0.5],
                [s[0] - side[0], s[1] - side[1], 0.5],
                [e[0], e[1], -0.5 + 0.1],
                [e[0], e[1], -0.5 - 0.1],
            ],
            &[[0, 1, 2, 3]],
        );
    }
    let vol = scene.volume();
    let m = maps(&vol);
    let view = View {
        camera: ortho(-1.5, 1.5, -1.5, 1.5),
        ..View::default()
    };
    let (_, stats) = draw_with(
        &vol,
        &m,
        &view,
        (30, 30),
        "exact linear 0 1",
        Order::BackToFront,
    );
    assert!(stats.per_pixel);
    assert!(stats.most_runs >= 2, "the sticks overlap on screen");
    let d = against_reference(&vol, &m, &view, (30, 30));
    assert!(d <= 1e-6, "{d:e}");
    // Both compositing orders give the same image.
    let a = draw_with(
        &vol,
        &m,
        &view,
        (30, 30),
        "interpolateCoeff linear 1",
        Order::BackToFront,
    )
    .0;
    let b = draw_with(
        &vol,
        &m,
        &view,
        (30, 30),
        "interpolateCoeff linear 1",
        Order::FrontToBack,
    )
    .0;
    assert!(worst(&a, |x, y| pixel(&b, x, y)).0 <= 1e-6);
}

/// Excluded regions as real meshes have them: a jittered box with 3 % of its cells removed, and
/// the eye inside a box.
#[test]
fn meshes_with_holes_and_an_eye_inside_match_the_reference() {
    let (nodes, mut tets) = kuhn_box([4, 4, 4], [1.0; 3], 0.12, 5);
    let mut rng = SplitMix64(17);
    tets.retain(|_| rng.next_f64() > 0.03);
    let vol = with_field(nodes, tets);
    let m = maps(&vol);
    for view in [
        turned(vec![rotate([0.3, 1.0, 0.1], 37.0)]),
        View {
            transforms: vec![rotate([1.0, 0.0, 0.2], -28.0)],
            look_at: LookAt {
                eye: [0.3, 0.2, 2.6],
                reference: [0.0; 3],
                up: [0.0, 1.0, 0.0],
            },
            camera: Some(Camera::Persp {
                fovy: 40.0,
                aspect: 1.0,
                near: 0.2,
                far: 9.0,
            }),
        },
    ] {
        let d = against_reference(&vol, &m, &view, (24, 24));
        assert!(d <= 1e-6, "{d:e}");
    }
    // The eye inside a (convex) box.
    let (nodes, tets) = kuhn_box([3, 3, 3], [1.0; 3], 0.1, 8);
    let vol = with_field(nodes, tets);
    let m = maps(&vol);
    let view = View {
        look_at: LookAt {
            eye: [0.1, -0.05, 0.15],
            reference: [-0.3, 0.1, -1.0],
            up: [0.0, 1.0, 0.0],
        },
        camera: Some(Camera::Persp {
            fovy: 70.0,
            aspect: 1.0,
            near: 0.05,
            far: 9.0,
        }),
        ..View::default()
    };
    let d = against_reference(&vol, &m, &view, (24, 24));
    assert!(d <= 1e-6, "{d:e}");
}

/// `vol_scale −1 1 1` is the image flipped left–right, `1 −1 1` upside down; `−1 −1 −1` is a
/// half turn about y (a proper rotation) flipped upside down. Every method, both orders.
#[test]
fn mirrored_volumes_give_mirror_images() {
    let (nodes, tets) = kuhn_box([3, 3, 3], [1.0; 3], 0.12, 4);
    let vol = with_field(nodes, tets);
    let m = maps(&vol);
    let base = vec![rotate([0.2, 1.0, 0.3], 23.0)];
    let with = |extra: TransformOp| {
        let mut ops = base.clone();
        ops.push(extra);
        turned(ops)
    };
    let (w, h) = (20, 20);
    for method in METHODS {
        for order in [Order::BackToFront, Order::FrontToBack] {
            let plain = draw_with(&vol, &m, &turned(base.clone()), (w, h), method, order).0;
            let half = draw_with(
                &vol,
                &m,
                &with(rotate([0.0, 1.0, 0.0], 180.0)),
                (w, h),
                method,
                order,
            )
            .0;
            let cases = [
                ("-1 1 1", [-1.0, 1.0, 1.0], &plain, true, false),
                ("1 -1 1", [1.0, -1.0, 1.0], &plain, false, true),
                ("-1 -1 -1", [-1.0, -1.0, -1.0], &half, false, true),
            ];
            for (name, s, source, flip_x, flip_y) in cases {
                let fb = draw_with(
                    &vol,
                    &m,
                    &with(TransformOp::Scale(s)),
                    (w, h),
                    method,
                    order,
                )
                .0;
                let (d, x, y) = worst(&fb, |x, y| {
                    let sx = if flip_x { w - 1 - x } else { x };
                    let sy = if flip_y { h - 1 - y } else { y };
                    pixel(source, sx, sy)
                });
                assert!(
                    d <= 1e-6,
                    "{method} {order:?}, vol_scale {name}: {d:e} at ({x}, {y})"
                );
            }
        }
    }
}

/// Random rigid turns — arbitrary ones against the reference, and quarter turns built from
/// several steps (30° × 3, 45° × 2) against the exactly turned mesh — of random structured and
/// jittered meshes.
#[test]
fn random_turns_of_random_meshes_match_independent_answers() {
    let mut rng = SplitMix64(2026);
    for case in 0..8 {
        let jitter = if case % 2 == 0 { 0.0 } else { 0.12 };
        let n = 2 + case % 3;
        let (nodes, tets) = kuhn_box([n, n, n], [1.0; 3], jitter, 40 + case as u64);
        let vol = with_field(nodes.clone(), tets.clone());
        let m = maps(&vol);
        if case % 4 < 2 {
            let a = (case / 4 + case) % 3;
            let b = (a + 1 + case % 2) % 3;
            let unit = |k: usize| {
                let mut v = [0.0; 3];
                v[k] = 1.0;
                v
            };
            let mut ops = vec![rotate(unit(a), 30.0); 3];
            ops.extend(vec![rotate(unit(b), 45.0); 2]);
            let turned_nodes = nodes.iter().map(|&p| quarter(b, quarter(a, p))).collect();
            let values = nodes.iter().map(field_of).collect();
            let exact = with_values(turned_nodes, tets, values);
            for method in METHODS {
                let want = draw(&exact, &m, &View::default(), (16, 16), method);
                let got = draw(&vol, &m, &turned(ops.clone()), (16, 16), method);
                let (d, x, y) = worst(&got, |x, y| pixel(&want, x, y));
                assert!(d <= 1e-6, "case {case}, {method}: {d:e} at ({x}, {y})");
            }
        } else {
            let axis = [
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
            ];
            let view = turned(vec![rotate(axis, 360.0 * rng.next_f64())]);
            let d = against_reference(&vol, &m, &view, (16, 16));
            assert!(d <= 1e-6, "case {case}: {d:e}");
        }
    }
}

/// A ring of `n` triangular prisms around `centre` in the plane spanned by unit vectors `u`, `v`
/// (radius 1, cross-section a small triangle in the plane of the radius and `u × v`).
fn add_ring(scene: &mut Bodies, centre: [f64; 3], u: [f64; 3], v: [f64; 3], n: usize) {
    let w = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let section = |k: usize| -> [[f64; 3]; 3] {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let r = [0, 1, 2].map(|i| a.cos() * u[i] + a.sin() * v[i]);
        let at = |dr: f64, dw: f64| [0, 1, 2].map(|i| centre[i] + (1.0 + dr) * r[i] + dw * w[i]);
        [at(-0.12, -0.1), at(0.12, -0.1), at(0.0, 0.12)]
    };
    for k in 0..n {
        scene.add_prism(section(k), section(k + 1));
    }
}

/// Two interlocked rings, and a comb of slabs (a connected mesh with deep notches): rays leave
/// and re-enter them several times.
#[test]
fn interlocked_rings_and_a_comb_match_the_reference() {
    let mut rings = Bodies::default();
    add_ring(&mut rings, [0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 16);
    add_ring(
        &mut rings,
        [1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        16,
    );
    let rings = rings.volume();
    let (nodes, tets) = kuhn_box([7, 1, 3], [1.4, 0.3, 0.9], 0.0, 1);
    // Teeth: remove the upper two layers of every other column.
    let tets: Vec<[u32; 4]> = tets
        .into_iter()
        .filter(|t| {
            let c = [0, 1, 2].map(|k| t.iter().map(|&n| nodes[n as usize][k]).sum::<f64>() / 4.0);
            let column = (c[0] / 0.2) as usize;
            !(column % 2 == 1 && c[2] > 0.3)
        })
        .collect();
    let comb = with_field(nodes, tets);
    for (name, vol) in [("rings", rings), ("comb", comb)] {
        let m = maps(&vol);
        for view in [
            turned(vec![rotate([1.0, 0.3, 0.0], 25.0)]),
            turned(vec![
                rotate([0.0, 1.0, 0.0], 90.0),
                rotate([1.0, 0.0, 0.0], 20.0),
            ]),
        ] {
            let (_, stats) = draw_with(
                &vol,
                &m,
                &view,
                (24, 24),
                "exact linear 0 1",
                Order::BackToFront,
            );
            assert!(stats.per_pixel && stats.most_runs >= 2, "{name}");
            assert_eq!(stats.overlap_pixels, 0, "{name}");
            let d = against_reference(&vol, &m, &view, (24, 24));
            assert!(d <= 1e-6, "{name}: {d:e}");
        }
    }
}

/// A ring of prisms whose cross-sections are all tilted the same way about their radius (a
/// screw ring): seen along its axis, each prism is in front of the next across their shared
/// face, all the way round — a true visibility cycle among face-adjacent cells, which the sort
/// has to break.
fn screw_ring(tilt_degrees: f64, n: usize) -> Volume {
    let mut ring = Bodies::default();
    let tilt = tilt_degrees.to_radians();
    let section = |k: usize| -> [[f64; 3]; 3] {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let r = [a.cos(), a.sin(), 0.0];
        let t = [-a.sin(), a.cos(), 0.0];
        let w = [0, 1, 2].map(|i| tilt.cos() * [0.0, 0.0, 1.0][i] + tilt.sin() * t[i]);
        let at = |dr: f64, dw: f64| [0, 1, 2].map(|i| (1.0 + dr) * r[i] + dw * w[i]);
        [at(-0.15, -0.12), at(0.15, -0.12), at(0.0, 0.15)]
    };
    // Consecutive prisms share their cross-section's nodes: one connected mesh.
    let mut nodes = Vec::new();
    for k in 0..n {
        nodes.extend(section(k));
    }
    let mut tets = Vec::new();
    for k in 0..n {
        let a = 3 * k as u32;
        let b = 3 * ((k + 1) % n) as u32;
        tets.extend([
            [a, a + 1, a + 2, b],
            [a + 1, a + 2, b, b + 1],
            [a + 2, b, b + 1, b + 2],
        ]);
    }
    ring.add(&nodes, &tets);
    ring.volume()
}

#[test]
fn a_cycle_among_face_adjacent_cells_is_broken_and_settled_per_pixel() {
    let vol = screw_ring(-40.0, 12);
    let m = maps(&vol);
    let view = View::default();
    let (_, stats) = draw_with(
        &vol,
        &m,
        &view,
        (28, 28),
        "exact linear 0 1",
        Order::BackToFront,
    );
    assert!(
        stats.cycle_cells > 0,
        "the screw ring must hold a visibility cycle"
    );
    assert!(stats.per_pixel);
    let d = against_reference(&vol, &m, &view, (28, 28));
    assert!(d <= 1e-6, "{d:e}");
}

/// On a non-convex mesh every method composites the same image in both orders (the runs are
/// settled by depth whatever order the cells arrive in).
#[test]
fn non_convex_meshes_give_one_image_in_both_orders_with_every_method() {
    let (nodes, mut tets) = kuhn_box([4, 4, 4], [1.0; 3], 0.12, 6);
    let mut rng = SplitMix64(23);
    tets.retain(|_| rng.next_f64() > 0.05);
    let vol = with_field(nodes, tets);
    let m = maps(&vol);
    let view = turned(vec![rotate([0.4, 1.0, 0.2], 31.0)]);
    for method in METHODS {
        let (a, sa) = draw_with(&vol, &m, &view, (20, 20), method, Order::BackToFront);
        let (b, _) = draw_with(&vol, &m, &view, (20, 20), method, Order::FrontToBack);
        assert!(sa.per_pixel);
        let (d, x, y) = worst(&a, |x, y| pixel(&b, x, y));
        assert!(d <= 1e-6, "{method}: {d:e} at ({x}, {y})");
    }
}
