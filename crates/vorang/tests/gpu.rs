//! The GPU backend against its Rust twins (bit for bit) and against the CPU renderer (within
//! 1e-12 per channel): needs a Vulkan adapter with 64-bit floats (lavapipe will do). Without one
//! the tests say so and pass, unless `VORANG_GPU_TESTS=required` (CI installs lavapipe).
#![cfg(feature = "gpu")]

use std::sync::{Arc, OnceLock};

use vorang::accuracy;
use vorang::gpu::twin::{self, Buffers, Corner};
use vorang::gpu::{Gpu, frame};
use vorang::mesh::generate::SplitMix64;
use vorang::render::{Method, Order, Settings, render};
use vorang::scene::{TransformOp, View};
use vorang::volume::Volume;

fn gpu() -> Option<&'static Gpu> {
    static GPU: OnceLock<Result<Gpu, String>> = OnceLock::new();
    match GPU.get_or_init(Gpu::open) {
        Ok(g) => Some(g),
        Err(e) => {
            if std::env::var("VORANG_GPU_TESTS").as_deref() == Ok("required") {
                panic!("VORANG_GPU_TESTS=required but no GPU: {e}");
            }
            eprintln!("skipping the GPU test: {e}");
            None
        }
    }
}

fn bits_equal(a: &[f64], b: &[f64]) -> Option<usize> {
    assert_eq!(a.len(), b.len());
    (0..a.len()).find(|&i| a[i].to_bits() != b[i].to_bits() && !(a[i].is_nan() && b[i].is_nan()))
}

/// Coordinates on the sub-pixel grid, sometimes on pixel centres and half-pixels (ties).
fn grid_point(rng: &mut SplitMix64, tie: bool) -> [f64; 2] {
    let mut c = || {
        let v = 40.0 * rng.next_f64();
        if tie {
            (2.0 * v).round() / 2.0
        } else {
            vorang::scene::snap(v)
        }
    };
    [c(), c()]
}

#[test]
fn predicates_are_their_twins_bit_for_bit() {
    let Some(g) = gpu() else { return };
    let mut rng = SplitMix64(7);
    let mut input = Vec::new();
    for i in 0..20_000 {
        let (a, b) = (
            grid_point(&mut rng, i % 3 == 0),
            grid_point(&mut rng, i % 3 == 0),
        );
        // Points on the line through a and b, and near it.
        let t = (8.0 * rng.next_f64()).round() / 4.0;
        let mut c = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        if i % 2 == 0 {
            c = grid_point(&mut rng, i % 5 == 0);
        }
        input.extend([a[0], a[1], b[0], b[1], c[0], c[1]]);
    }
    let out = g.run_probe("orient_probe", &input, 6, 2).unwrap();
    let mut zeros = 0;
    for (i, q) in input.chunks(6).enumerate() {
        let (a, b, c) = ([q[0], q[1]], [q[2], q[3]], [q[4], q[5]]);
        let o = twin::orient(a, b, c, g.exact_fma());
        assert_eq!(out[2 * i], f64::from(o), "orient {q:?}");
        assert_eq!(out[2 * i + 1] != 0.0, twin::inside(a, b, c, g.exact_fma()));
        // The twin is the CPU's exact predicate.
        assert_eq!(
            o,
            i32::from(vorang::predicates::orient_sign(a, b, c)),
            "{q:?}"
        );
        zeros += usize::from(o == 0);
    }
    assert!(zeros > 1000, "{zeros} collinear cases");
}

#[test]
fn faces_and_exits_are_their_twins_bit_for_bit() {
    let Some(g) = gpu() else { return };
    let fma = g.exact_fma();
    let mut rng = SplitMix64(11);
    let mut input = Vec::new();
    let mut cases = Vec::new();
    for i in 0..6000 {
        let mut k = [0u32, 1, 2].map(|j| Corner {
            p: grid_point(&mut rng, false),
            z: 0.5 + 5.0 * rng.next_f64(),
            v: rng.next_f64() * 4.0 - 1.0,
            id: (j * 7 + i) % 5 + 3 * j,
        });
        if i % 4 == 0 {
            // A sliver: the third corner within rounding of the first two's line.
            let t = rng.next_f64();
            let (a, b) = (k[0].p, k[1].p);
            k[2].p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]) + 1e-9];
        }
        let p = [
            (40.0 * rng.next_f64()).floor() + 0.5,
            (40.0 * rng.next_f64()).floor() + 0.5,
        ];
        let persp = i % 2 == 1;
        for c in &k {
            input.extend([c.p[0], c.p[1], c.z, c.v, f64::from(c.id)]);
        }
        input.extend([p[0], p[1], f64::from(u8::from(persp))]);
        cases.push((k, p, persp));
    }
    let out = g.run_probe("face_probe", &input, 18, 2).unwrap();
    let want: Vec<f64> = cases
        .iter()
        .flat_map(|(k, p, persp)| twin::face_hit(*k, *p, *persp, fma))
        .collect();
    assert_eq!(bits_equal(&out, &want), None);

    let mut input = Vec::new();
    let mut cells = Vec::new();
    for i in 0..6000 {
        let s: [[f64; 2]; 4] = std::array::from_fn(|_| grid_point(&mut rng, i % 2 == 0));
        let p = [
            (40.0 * rng.next_f64()).floor() + 0.5,
            (40.0 * rng.next_f64()).floor() + 0.5,
        ];
        let sign = if i % 3 == 0 { 1 } else { -1 };
        for q in &s {
            input.extend(q);
        }
        input.extend([f64::from(sign), p[0], p[1]]);
        cells.push((s, sign, p));
    }
    let out = g.run_probe("exit_probe", &input, 11, 1).unwrap();
    for (i, (s, sign, p)) in cells.iter().enumerate() {
        assert_eq!(
            out[i],
            twin::exit_face(s, *sign, *p, fma) as f64,
            "{s:?} {p:?}"
        );
    }
}

#[test]
fn the_linear_rule_is_its_twin_and_the_cpu_rule() {
    let Some(g) = gpu() else { return };
    let mut rng = SplitMix64(5);
    let mut input = Vec::new();
    let mut cases = Vec::new();
    for i in 0..8000 {
        let mut chi = || match rng.next_u64() % 6 {
            0 => 0.0,
            _ => 10f64.powf(rng.next_f64() * 5.0 - 3.0),
        };
        let (cf, cn) = (chi(), chi());
        let l = 10f64.powf(rng.next_f64() * 3.0 - 2.0);
        let e: [f64; 9] = std::array::from_fn(|_| rng.next_f64());
        let quadratic = i % 3 == 0;
        input.extend(e);
        input.extend([f64::from(u8::from(quadratic)), cf, cn, l]);
        cases.push((e, quadratic, cf, cn, l));
    }
    let out = g.run_probe("segment_probe", &input, 13, 4).unwrap();
    let mut worst = 0.0f64;
    for (i, (e, quadratic, cf, cn, l)) in cases.iter().enumerate() {
        let (far, near, mid) = ([e[0], e[1], e[2]], [e[3], e[4], e[5]], [e[6], e[7], e[8]]);
        let (b, theta) = twin::segment(far, near, mid, *quadratic, *cf, *cn, *l);
        let got = &out[4 * i..4 * i + 4];
        assert_eq!(
            bits_equal(got, &[b[0], b[1], b[2], theta]),
            None,
            "{:?}",
            cases[i]
        );
        let seg = vorang::integrate::Segment {
            eta: [far, near],
            chi: [*cf, *cn],
            ds: *l,
            eta_mid: quadratic.then_some(mid),
        };
        let (cb, ct) = vorang::integrate::linear::rule(&seg);
        for k in 0..3 {
            worst = worst.max((cb[k] - b[k]).abs() / cb[k].abs().max(1e-300).max(1e-3));
        }
        worst = worst.max((ct - theta).abs());
    }
    // The CPU's rule is held to 1e-12 of quadrature (integrate::linear's tests); the series
    // with thick segments cut stays well within that of it.
    eprintln!("series rule vs the CPU's linear rule: worst difference {worst:e}");
    assert!(worst < 1e-12, "{worst:e}");
}

/// interpolateColor's θ^f of a clipped interval (`pow_frac`, with `soft_ln` and `soft_exp`):
/// the twin's bits, and within a few units in the last place of the CPU's `powf` (times
/// `1 + |f·ln θ|`).
#[test]
fn pow_frac_is_its_twin_and_the_cpu_powf() {
    let Some(g) = gpu() else { return };
    let mut rng = SplitMix64(17);
    let mut input = Vec::new();
    let mut cases = Vec::new();
    for i in 0..8000 {
        let theta = match i % 8 {
            0 => 0.0,
            1 => 1.0,
            2 => -rng.next_f64(),
            3 => 1.0 + rng.next_f64() * 1e-15,
            4 => 10f64.powf(-rng.next_f64() * 300.0),
            _ => rng.next_f64(),
        };
        let f = if i % 5 == 0 { 1.0 } else { rng.next_f64() };
        input.extend([theta, f]);
        cases.push((theta, f));
    }
    let out = g.run_probe("pow_probe", &input, 2, 1).unwrap();
    let mut worst = 0.0f64;
    for (i, &(theta, f)) in cases.iter().enumerate() {
        let t = twin::color::pow_frac(theta, f);
        assert_eq!(bits_equal(&out[i..i + 1], &[t]), None, "{theta:e}^{f}");
        let cpu = theta.max(0.0).powf(f);
        let rel = if cpu == 0.0 {
            t.abs()
        } else {
            (t - cpu).abs() / cpu
        };
        // ln θ is off by a few units in its last place, which e^{f·ln θ} scales by |f·ln θ|.
        let y = if theta > 0.0 {
            (f * theta.ln()).abs()
        } else {
            0.0
        };
        worst = worst.max(rel / (1.0 + y));
    }
    eprintln!("pow_frac vs powf: worst relative difference / (1 + |f·ln θ|) {worst:e}");
    assert!(worst < 1e-15, "{worst:e}");
}

fn settings(size: usize, order: Order, brightness: f64) -> Settings {
    with_method(size, order, &format!("exact linear 0 {brightness}"))
}

/// The methods the GPU renders.
const METHODS: [&str; 3] = [
    "exact linear 0 1",
    "interpolateCoeff linear 1.5",
    "interpolateColor 1.5",
];

fn with_method(size: usize, order: Order, method: &str) -> Settings {
    let words: Vec<&str> = method.split_whitespace().collect();
    Settings {
        width: size,
        height: size,
        method: Method::parse(&words).unwrap(),
        order,
        lines: vorang::render::LineDraw::Off,
        ..Settings::default()
    }
}

/// Renders with the CPU and the GPU; checks the GPU's bits against the twin march and the CPU
/// image within `tol` per channel; returns the largest difference.
fn compare(
    g: &Gpu,
    vol: &Arc<Volume>,
    mapping: &vorang::mapping::Mapping,
    view: &View,
    s: &Settings,
    what: &str,
) -> f64 {
    let (cpu, _) = render(vol, mapping, view, s, None).unwrap();
    let (gpu, _) = g.render(vol, mapping, view, s).unwrap();
    // The twin: the same march on the CPU.
    let data = frame::prepare(vol, mapping, view, s, g.exact_fma()).unwrap();
    let image = g.march(vol, &data).unwrap();
    let mut cells = Vec::new();
    for (t, nb) in vol.mesh.tets().iter().zip(vol.mesh.neighbors()) {
        cells.push(*t);
        cells.push(*nb);
    }
    let b = Buffers {
        mesh: &cells,
        nodes: &data.nodes,
        lists: &data.lists,
        lines: data.lines.as_deref().unwrap_or(&[]),
        consts: &data.consts,
    };
    let mut twin_image = Vec::new();
    for y in 0..s.height as u32 {
        for x in 0..s.width as u32 {
            twin_image.extend(b.pixel(x, y));
        }
    }
    if let Some(i) = bits_equal(&image, &twin_image) {
        panic!(
            "{what}: pixel {} differs from its twin: {:?} vs {:?}",
            i / 5,
            &image[i / 5 * 5..i / 5 * 5 + 5],
            &twin_image[i / 5 * 5..i / 5 * 5 + 5]
        );
    }
    let mut worst = (0.0f64, 0);
    let mut over = 0;
    for (i, (a, b)) in cpu.pixels.iter().zip(&gpu.pixels).enumerate() {
        for k in 0..4 {
            let d = (f64::from(a[k]) - f64::from(b[k])).abs();
            over += usize::from(d > 1e-12);
            if d > worst.0 {
                worst = (d, i);
            }
        }
    }
    if over > 0 {
        eprintln!("{what}: {over} channels differ by more than 1e-12");
    }
    let i = worst.1;
    assert!(
        worst.0 <= 1e-12,
        "{what}: GPU vs CPU {:e} at pixel ({}, {}): {:?} vs {:?}",
        worst.0,
        i % s.width,
        i / s.width,
        cpu.pixels[i],
        gpu.pixels[i]
    );
    worst.0
}

#[test]
fn accuracy_scenes_match_the_cpu() {
    let Some(g) = gpu() else { return };
    let mut n = 0;
    for scene in accuracy::scenes() {
        if frame::check_mapping(&scene.mapping, &scene.volume).is_err() {
            eprintln!("{}: maps not on the GPU yet", scene.name);
            continue;
        }
        let views = accuracy::views(&scene);
        let vol = Arc::new(scene.volume.clone());
        for (name, view) in views {
            for order in [Order::BackToFront, Order::FrontToBack] {
                for method in METHODS {
                    let s = with_method(64, order, method);
                    let what = format!("{} {name} {order:?} {method}", scene.name);
                    let d = compare(g, &vol, &scene.mapping, &view, &s, &what);
                    eprintln!("{what}: largest difference {d:e}");
                    n += 1;
                }
            }
        }
    }
    assert!(n >= 24, "{n} renders");
}

#[test]
fn mirrored_and_axis_aligned_views_match_the_cpu() {
    let Some(g) = gpu() else { return };
    let (nodes, tets) = vorang::mesh::generate::kuhn_box([3, 2, 2], [1.0, 0.8, 0.6], 0.0, 0);
    let values = nodes.iter().map(|p| p[0] + 0.5 * p[1] - p[2]).collect();
    let vol = Arc::new(accuracy::scalar_volume(nodes, tets, values));
    let mapping = accuracy::scalar_maps(&vol);
    let views = [
        ("axis", vec![]),
        (
            "axis rotated 90",
            vec![TransformOp::Rotate {
                axis: [0.0, 1.0, 0.0],
                degrees: 90.0,
            }],
        ),
        ("mirrored", vec![TransformOp::Scale([-1.0, 1.0, 1.0])]),
        (
            "mirrored and turned",
            vec![
                TransformOp::Scale([1.0, -1.3, 1.0]),
                TransformOp::Rotate {
                    axis: [1.0, 0.4, 0.2],
                    degrees: 33.0,
                },
            ],
        ),
    ];
    for (name, transforms) in views {
        let view = View {
            transforms,
            ..View::default()
        };
        for order in [Order::BackToFront, Order::FrontToBack] {
            for method in METHODS {
                let s = with_method(96, order, method);
                let d = compare(g, &vol, &mapping, &view, &s, name);
                eprintln!("{name} {order:?} {method}: largest difference {d:e}");
            }
        }
    }
}

/// The steps of a time series on the GPU: steps with the same points and cells share the mesh,
/// and with it the cells uploaded to the device; every step is the CPU's image.
#[test]
fn time_steps_sharing_a_mesh_match_the_cpu() {
    let Some(g) = gpu() else { return };
    let flow =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/series/flow.pvd");
    let series = vorang::formats::collection::Series::read(&flow).unwrap();
    let (mut step, _) = series.load_step(0, None).unwrap();
    let view = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 1.0, 0.0],
            degrees: 30.0,
        }],
        ..View::default()
    };
    for k in [0, 1, 2, 0] {
        let (next, _) = series.load_step(k, Some(&step)).unwrap();
        assert!(next.shares_mesh(&step));
        step = next;
        let mapping = accuracy::scalar_maps(&step.volume);
        let s = settings(48, Order::BackToFront, 1.0);
        let d = compare(
            g,
            &step.volume,
            &mapping,
            &view,
            &s,
            &format!("flow step {k}"),
        );
        eprintln!("flow step {k}: largest difference {d:e}");
    }
}

/// Meshes built of pieces (the scenes of the CPU's watertight tests, tests/watertight.rs).
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
        let (nodes, tets) = vorang::mesh::generate::kuhn_box([n; 3], [size; 3], 0.0, 1);
        let nodes: Vec<[f64; 3]> = nodes
            .iter()
            .map(|p| [0, 1, 2].map(|k| p[k] + origin[k]))
            .collect();
        self.add(&nodes, &tets);
    }

    /// A triangular prism from triangle `a` to triangle `b`, as 3 tets.
    fn add_prism(&mut self, a: [[f64; 3]; 3], b: [[f64; 3]; 3]) {
        let nodes = [a[0], a[1], a[2], b[0], b[1], b[2]];
        self.add(&nodes, &[[0, 1, 2, 3], [1, 2, 3, 4], [2, 3, 4, 5]]);
    }

    /// A ring of `n` prisms about `centre` in the plane of `u` and `v`; `tilt` turns the
    /// cross-sections about their radius (a screw ring: a visibility cycle among face-adjacent
    /// cells). Consecutive prisms share their nodes.
    fn add_ring(&mut self, centre: [f64; 3], u: [f64; 3], v: [f64; 3], n: usize, tilt: f64) {
        let w = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let tilt = tilt.to_radians();
        let mut nodes = Vec::new();
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            let r = [0, 1, 2].map(|i| a.cos() * u[i] + a.sin() * v[i]);
            let t = [0, 1, 2].map(|i| -a.sin() * u[i] + a.cos() * v[i]);
            let s = [0, 1, 2].map(|i| tilt.cos() * w[i] + tilt.sin() * t[i]);
            let at =
                |dr: f64, dw: f64| [0, 1, 2].map(|i| centre[i] + (1.0 + dr) * r[i] + dw * s[i]);
            nodes.extend([at(-0.14, -0.11), at(0.14, -0.11), at(0.0, 0.13)]);
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
        self.add(&nodes, &tets);
    }

    fn volume(self) -> Volume {
        with_field(self.nodes, self.tets)
    }
}

fn with_field(nodes: Vec<[f64; 3]>, tets: Vec<[u32; 4]>) -> Volume {
    let s = nodes
        .iter()
        .map(|p| (1.7 * p[0] + 0.3).sin() + (1.1 * p[1]).cos() * p[2] + 0.4 * p[2])
        .collect();
    accuracy::scalar_volume(nodes, tets, s)
}

/// A Kuhn box without the cells whose centroid `keep` refuses.
fn carved(n: [usize; 3], jitter: f64, seed: u64, mut keep: impl FnMut([f64; 3]) -> bool) -> Volume {
    let (nodes, tets) = vorang::mesh::generate::kuhn_box(n, [1.0; 3], jitter, seed);
    let tets = tets
        .into_iter()
        .filter(|t| {
            keep([0, 1, 2].map(|k| t.iter().map(|&i| nodes[i as usize][k]).sum::<f64>() / 4.0))
        })
        .collect();
    with_field(nodes, tets)
}

/// The non-convex scenes: holes, a cavity, disjoint and anisotropic bodies, a visibility cycle,
/// interlocked rings, a screw ring (a cycle among face-adjacent cells) and a comb.
fn non_convex_scenes() -> Vec<(&'static str, Volume)> {
    let mut rng = SplitMix64(17);
    let holes = carved([4, 4, 4], 0.12, 5, |_| rng.next_f64() > 0.03);
    let inner = |c: [f64; 3]| c.iter().all(|&v| (0.3..0.7).contains(&v));
    let cavity = carved([5, 5, 5], 0.1, 3, |c| !inner(c));
    let comb = carved([7, 1, 3], 0.0, 1, |c| {
        !((c[0] / (1.0 / 7.0)) as usize % 2 == 1 && c[2] > 0.4)
    });
    let mut bodies = Bodies::default();
    bodies.add_box(2, [0.0, 0.0, 0.0], 1.0);
    bodies.add_prism(
        [[0.2, 0.2, 2.0], [0.8, 0.3, 2.0], [0.4, 0.8, 2.0]],
        [[5.2, 0.2, -1.0], [5.8, 0.3, -1.0], [5.4, 0.8, -1.0]],
    );
    bodies.add(
        &[
            [0.6, 0.1, 1.4],
            [1.0, 0.2, 1.3],
            [0.7, 0.9, 1.5],
            [0.8, 0.5, 1.9],
        ],
        &[[0, 1, 2, 3]],
    );
    bodies.add_prism(
        [[-0.2, -0.2, -1.0], [1.2, -0.1, -1.0], [0.5, 1.3, -1.0]],
        [[-0.2, -0.2, -1.3], [1.2, -0.1, -1.3], [0.5, 1.3, -1.3]],
    );
    let mut sticks = Bodies::default();
    let corner = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / 3.0;
        [a.cos(), a.sin()]
    };
    for k in 0..3 {
        let (p, q) = (corner(k), corner(k + 1));
        let dir = [q[0] - p[0], q[1] - p[1]];
        let side = [-dir[1] * 0.12, dir[0] * 0.12];
        let s = [p[0] - 0.25 * dir[0], p[1] - 0.25 * dir[1]];
        let e = [q[0] + 0.25 * dir[0], q[1] + 0.25 * dir[1]];
        sticks.add(
            &[
                [s[0] + side[0], s[1] + side[1], 0.5],
                [s[0] - side[0], s[1] - side[1], 0.5],
                [e[0], e[1], -0.4],
                [e[0], e[1], -0.6],
            ],
            &[[0, 1, 2, 3]],
        );
    }
    let mut rings = Bodies::default();
    rings.add_ring([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 16, 0.0);
    rings.add_ring([1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], 16, 0.0);
    let mut screw = Bodies::default();
    screw.add_ring([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 12, -40.0);
    vec![
        ("holes", holes),
        ("cavity", cavity),
        ("comb", comb),
        ("bodies", bodies.volume()),
        ("sticks", sticks.volume()),
        ("rings", rings.volume()),
        ("screw ring", screw.volume()),
    ]
}

/// Every non-convex scene in the accuracy report's views (orthographic and perspective) and
/// along the axes, both orders, both methods: every channel within 1e-12 of the CPU's.
#[test]
fn non_convex_meshes_and_cavities_match_the_cpu() {
    let Some(g) = gpu() else { return };
    for (name, volume) in non_convex_scenes() {
        let mapping = accuracy::scalar_maps(&volume);
        let scene = accuracy::Scene {
            name,
            what: "",
            volume,
            mapping,
        };
        let mut views = accuracy::views(&scene);
        views.push(("axis", View::default()));
        views.push((
            "axis turned 90",
            View {
                transforms: vec![TransformOp::Rotate {
                    axis: [0.0, 1.0, 0.0],
                    degrees: 90.0,
                }],
                ..View::default()
            },
        ));
        let vol = Arc::new(scene.volume.clone());
        assert!(!vol.mesh.is_convex(), "{name}");
        for (view_name, view) in views {
            for order in [Order::BackToFront, Order::FrontToBack] {
                for method in METHODS {
                    let s = with_method(64, order, method);
                    let what = format!("{name} {view_name} {order:?} {method}");
                    let d = compare(g, &vol, &scene.mapping, &view, &s, &what);
                    eprintln!("{what}: largest difference {d:e}");
                }
            }
        }
    }
}

fn inside_view(eye: [f64; 3], reference: [f64; 3], fovy: f64, near: f64) -> View {
    View {
        look_at: vorang::scene::LookAt {
            eye,
            reference,
            up: [0.0, 1.0, 0.0],
        },
        camera: Some(vorang::scene::Camera::Persp {
            fovy,
            aspect: 1.0,
            near,
            far: 9.0,
        }),
        ..View::default()
    }
}

/// The eye inside the volume, inside a cavity, and a near plane cutting the volume: the rays
/// start in the cells that reach in front of the near plane, as the CPU's do.
#[test]
fn the_eye_inside_the_volume_matches_the_cpu() {
    let Some(g) = gpu() else { return };
    let (nodes, tets) = vorang::mesh::generate::kuhn_box([3, 3, 3], [1.0; 3], 0.1, 8);
    let convex = with_field(nodes, tets);
    let mut rng = SplitMix64(17);
    let holes = carved([4, 4, 4], 0.12, 5, |_| rng.next_f64() > 0.03);
    let inner = |c: [f64; 3]| c.iter().all(|&v| (0.3..0.7).contains(&v));
    let cavity = carved([5, 5, 5], 0.1, 3, |c| !inner(c));
    let scenes = [
        (
            "convex, eye inside",
            convex.clone(),
            inside_view([0.1, -0.05, 0.15], [-0.3, 0.1, -1.0], 70.0, 0.05),
        ),
        (
            "convex, near plane through it",
            convex,
            inside_view([0.2, 0.3, 0.9], [0.0; 3], 50.0, 0.6),
        ),
        (
            "holes, eye inside",
            holes,
            inside_view([0.05, 0.1, -0.1], [1.0, 0.6, -0.4], 80.0, 0.02),
        ),
        (
            "cavity, eye in it",
            cavity,
            inside_view([0.02, -0.03, 0.01], [0.3, 0.2, -1.0], 90.0, 0.01),
        ),
    ];
    for (name, volume, view) in scenes {
        let mapping = accuracy::scalar_maps(&volume);
        let vol = Arc::new(volume);
        // The rays that start at the near plane or behind it in a cell reaching in front of it.
        let s = with_method(64, Order::BackToFront, METHODS[0]);
        let data = frame::prepare(&vol, &mapping, &view, &s, g.exact_fma()).unwrap();
        let near = data.lists[64 * 64 + 1..]
            .iter()
            .filter(|&&c| c & twin::NEAR_ENTRY != 0)
            .count();
        eprintln!("{name}: {near} entries into near-clipped cells");
        assert!(near > 0, "{name}: no ray starts in a near-clipped cell");
        for order in [Order::BackToFront, Order::FrontToBack] {
            for method in METHODS {
                let s = with_method(64, order, method);
                let what = format!("{name} {order:?} {method}");
                let d = compare(g, &vol, &mapping, &view, &s, &what);
                eprintln!("{what}: largest difference {d:e}");
            }
        }
    }
}

/// What the GPU does not render is refused with the method's name (no adapter needed).
#[test]
fn methods_not_on_the_gpu_are_named() {
    for (method, named) in [
        ("test 0.3", "method test"),
        ("exact constEA 0 1", "method exact constEA"),
        ("exact linear 0.1 1", "method exact linear 0.1"),
        (
            "interpolateCoeff constEA 1",
            "method interpolateCoeff constEA",
        ),
    ] {
        let words: Vec<&str> = method.split_whitespace().collect();
        let e = frame::check_method(&Method::parse(&words).unwrap()).unwrap_err();
        assert!(e.starts_with(named) && e.contains("backend cpu"), "{e}");
    }
    for method in METHODS {
        let words: Vec<&str> = method.split_whitespace().collect();
        assert!(frame::check_method(&Method::parse(&words).unwrap()).is_ok());
    }
}

/// A mesh larger than one buffer binding holds is split across the march's mesh bindings (its
/// own device here, with the bindings made small), and renders the CPU's image; one that needs
/// more bindings than the march has is refused with a message.
#[test]
fn a_mesh_split_across_bindings_matches_the_cpu() {
    if gpu().is_none() {
        return;
    }
    let g = Gpu::open().unwrap();
    let (nodes, tets) = vorang::mesh::generate::kuhn_box([6, 5, 4], [1.0, 0.8, 0.7], 0.1, 2);
    let vol = Arc::new(with_field(nodes, tets));
    let mapping = accuracy::scalar_maps(&vol);
    let view = accuracy::views(&accuracy::Scene {
        name: "split",
        what: "",
        volume: (*vol).clone(),
        mapping: mapping.clone(),
    })
    .remove(0)
    .1;
    // 720 cells, 1440 rows of 16 bytes: 400 rows a binding make four parts.
    g.limit_mesh_bindings(400 * 16);
    for method in METHODS {
        let s = with_method(64, Order::FrontToBack, method);
        let d = compare(&g, &vol, &mapping, &view, &s, &format!("split {method}"));
        eprintln!("mesh in 4 bindings, {method}: largest difference {d:e}");
    }
    g.limit_mesh_bindings(300 * 16);
    let s = with_method(64, Order::FrontToBack, METHODS[0]);
    let e = g.render(&vol, &mapping, &view, &s).unwrap_err().to_string();
    assert!(e.contains("720 cells") && e.contains("backend cpu"), "{e}");
}

/// The device's memory per cell: 32 bytes of cells, the nodes' share (per node 7 numbers, 10
/// for interpolateCoeff) on a generated box, the shape of the benchmark's meshes, and for
/// interpolateColor one word per cell, its fan (gpu::color).
#[test]
fn gpu_memory_per_cell_stays_within_50_bytes() {
    let (nodes, tets) = vorang::mesh::generate::kuhn_box([20, 20, 20], [1.0; 3], 0.1, 1);
    let vol = Arc::new(with_field(nodes, tets));
    let mapping = accuracy::scalar_maps(&vol);
    for method in METHODS {
        let s = with_method(64, Order::FrontToBack, method);
        let data = frame::prepare(&vol, &mapping, &View::default(), &s, false).unwrap();
        let cells = vol.mesh.tet_count() as f64;
        // The pixels' entries and offsets are per pixel; what follows them is per cell.
        let pixels = s.width * s.height;
        let per_cell_words = data.lists.len() - (pixels + 1) - data.entries;
        let per_cell =
            (32.0 * cells + 8.0 * data.nodes.len() as f64 + 4.0 * per_cell_words as f64) / cells;
        eprintln!("{method}: {per_cell:.1} bytes per cell on the GPU");
        assert!(per_cell <= 50.0, "{method}: {per_cell} bytes per cell");
    }
}

/// Grid lines (every edge: the rays end at the nearest line) and a coloured background, with a
/// non-convex mesh, both projections, both orders.
#[test]
fn grid_lines_and_backgrounds_match_the_cpu() {
    let Some(g) = gpu() else { return };
    let mut rng = SplitMix64(29);
    let volume = carved([3, 3, 3], 0.1, 9, |_| rng.next_f64() > 0.1);
    let mapping = accuracy::scalar_maps(&volume);
    let scene = accuracy::Scene {
        name: "lines",
        what: "",
        volume,
        mapping,
    };
    let vol = Arc::new(scene.volume.clone());
    for (view_name, view) in accuracy::views(&scene) {
        for order in [Order::BackToFront, Order::FrontToBack] {
            for method in METHODS {
                for background in [
                    vorang::framebuffer::Background::Color([0.2, 0.1, 0.4]),
                    vorang::framebuffer::Background::None,
                ] {
                    let s = Settings {
                        lines: vorang::render::LineDraw::All,
                        background,
                        ..with_method(64, order, method)
                    };
                    let what = format!("lines {view_name} {order:?} {method}");
                    let d = compare(g, &vol, &scene.mapping, &view, &s, &what);
                    eprintln!("{what}: largest difference {d:e}");
                }
            }
        }
    }
}

/// A volume without fields under CONSTANT maps (what `vorang generate` writes): η and χ the
/// same everywhere, mapped at the nodes as the CPU maps them.
#[test]
fn constant_maps_without_a_field_match_the_cpu() {
    use vorang::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
    let Some(g) = gpu() else { return };
    let (nodes, tets) = vorang::mesh::generate::kuhn_box([4, 3, 3], [1.0, 0.8, 0.7], 0.1, 4);
    let mesh = vorang::mesh::TetMesh::new(nodes, tets).unwrap();
    let vol = Arc::new(Volume::from_mesh("box", mesh));
    let c = "# VoRANG Colormap 1.0\nCONSTANT @1\n@1\n0.9 0.5 0.2\n";
    let a = "# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n1.3\n";
    let c = parse_map::<dyn ColorShading>(c.as_bytes(), "c").unwrap().0;
    let a = parse_map::<dyn AlphaShading>(a.as_bytes(), "a").unwrap().0;
    let mapping = Mapping::new(&c, &a, &vol).unwrap().0;
    let view = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 1.0, 0.0],
            degrees: 30.0,
        }],
        ..View::default()
    };
    for order in [Order::BackToFront, Order::FrontToBack] {
        for method in METHODS {
            let s = with_method(64, order, method);
            let d = compare(g, &vol, &mapping, &view, &s, &format!("constant {method}"));
            eprintln!("constant maps {order:?} {method}: largest difference {d:e}");
        }
    }
}

/// Maps of `knots` knots evenly spaced in `[lo, hi]` (`colors`: SIMPLE_EMITTER or
/// ABSORPTION_WEIGHTED; SIMPLE_ABSORBER), as `vorang.plot` makes from a sampled colormap.
fn many_knot_maps(
    vol: &Volume,
    colors: &str,
    knots: usize,
    [lo, hi]: [f64; 2],
) -> vorang::mapping::Mapping {
    use vorang::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
    let mut c = format!("# VoRANG Colormap 1.0\n{colors} @1\n@1\n");
    let mut a = String::from("# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n");
    for i in 0..knots {
        let t = i as f64 / (knots - 1) as f64;
        let s = lo + (hi - lo) * t;
        c += &format!("{t} {} 0.5 {s}\n", 1.0 - t);
        a += &format!("{} {s}\n", 0.5 + 3.0 * t * t);
    }
    let c = parse_map::<dyn ColorShading>(c.as_bytes(), "c").unwrap().0;
    let a = parse_map::<dyn AlphaShading>(a.as_bytes(), "a").unwrap().0;
    Mapping::new(&c, &a, vol).unwrap().0
}

/// The twin's bisections count the knots as the CPU's table does (`Transfer1D::piece`, and
/// `knots_between` from the knots below its upper end), on and between knots.
#[test]
fn knot_lookups_are_the_cpus() {
    let vol = carved([2, 2, 2], 0.0, 1, |_| true);
    for knots in [2, 3, 64, 257] {
        let mapping = many_knot_maps(&vol, "SIMPLE_EMITTER", knots, [-0.5, 1.5]);
        let transfer = mapping.transfer(&vol).unwrap();
        let mut consts = vec![0.0; twin::slot::TABLE];
        consts[twin::slot::KNOTS] = transfer.knot_count() as f64;
        consts.extend(transfer.flat());
        let b = Buffers {
            mesh: &[],
            nodes: &[],
            lists: &[],
            lines: &[],
            consts: &consts,
        };
        let knot = |i: usize| consts[twin::slot::TABLE + i];
        let mut rng = SplitMix64(3);
        for i in 0..4000 {
            let s = match i % 4 {
                0 => knot(i / 4 % knots),
                1 => f64::from_bits(knot(i / 4 % knots).to_bits() + 1),
                _ => 2.5 * rng.next_f64() - 0.75,
            };
            assert_eq!(b.piece_of(s), transfer.piece(s), "{knots} knots, {s}");
            let between = transfer.knots_between(-0.6, s).len();
            if s > -0.6 {
                assert_eq!(b.knots_below(s) - b.piece_of(-0.6), between, "{s}");
            }
        }
        assert_eq!(b.piece_of(f64::NAN), transfer.piece(f64::NAN));
    }
}

/// Maps of 70 to 256 knots on a jittered, holed box: many knots cut each cell's interval.
/// The march is its twin bit for bit and the CPU's image in every method and order (with a
/// count over every knot per lookup, lavapipe's limit on a shader's loop iterations cut these
/// marches short, docs/gpu.md).
#[test]
fn many_knot_maps_match_the_cpu() {
    let Some(g) = gpu() else { return };
    let mut rng = SplitMix64(41);
    let volume = carved([5, 5, 5], 0.1, 13, |_| rng.next_f64() > 0.05);
    let scene = accuracy::Scene {
        name: "many knots",
        what: "",
        mapping: accuracy::scalar_maps(&volume),
        volume,
    };
    let vol = Arc::new(scene.volume.clone());
    let (view_name, view) = accuracy::views(&scene).swap_remove(0);
    for colors in ["SIMPLE_EMITTER", "ABSORPTION_WEIGHTED"] {
        for knots in [70, 97, 128, 256] {
            let mapping = many_knot_maps(&vol, colors, knots, [-0.5, 1.5]);
            for order in [Order::BackToFront, Order::FrontToBack] {
                for method in METHODS {
                    let s = with_method(48, order, method);
                    let what = format!("{colors} {knots} knots {view_name} {order:?} {method}");
                    let d = compare(g, &vol, &mapping, &view, &s, &what);
                    eprintln!("{what}: largest difference {d:e}");
                }
            }
        }
    }
}

/// Past the driver's loop limit (thousands of knots crossed along a ray on lavapipe) the march
/// marks the pixels it could not finish, is its twin everywhere else, and the frame takes the
/// marked pixels from the twin: still the CPU's image.
#[test]
fn marches_the_driver_cuts_short_are_redone_by_the_twin() {
    let Some(g) = gpu() else { return };
    let mut rng = SplitMix64(43);
    let vol = Arc::new(carved([5, 5, 5], 0.1, 13, |_| rng.next_f64() > 0.05));
    let mapping = many_knot_maps(&vol, "ABSORPTION_WEIGHTED", 4096, [-0.5, 1.5]);
    let view = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 0.3, 0.0],
            degrees: 35.0,
        }],
        ..View::default()
    };
    let s = settings(48, Order::BackToFront, 1.0);
    let data = frame::prepare(&vol, &mapping, &view, &s, g.exact_fma()).unwrap();
    let image = g.march(&vol, &data).unwrap();
    let cells: Vec<[u32; 4]> = vol
        .mesh
        .tets()
        .iter()
        .zip(vol.mesh.neighbors())
        .flat_map(|(t, nb)| [*t, *nb])
        .collect();
    let b = Buffers {
        mesh: &cells,
        nodes: &data.nodes,
        lists: &data.lists,
        lines: &[],
        consts: &data.consts,
    };
    let mut cut = 0;
    for p in 0..s.width * s.height {
        let got = &image[5 * p..5 * p + 5];
        if got[4] == twin::LOOPS_CUT {
            cut += 1;
            continue;
        }
        let want = b.pixel((p % s.width) as u32, (p / s.width) as u32);
        assert_eq!(
            bits_equal(got, &want),
            None,
            "pixel {p}: {got:?} vs {want:?}"
        );
    }
    eprintln!("{}: {cut} pixels cut short", g.name());
    if g.name().contains("llvmpipe") {
        assert!(cut > 0, "the scene reaches lavapipe's loop limit");
    }
    let (cpu, _) = render(&vol, &mapping, &view, &s, None).unwrap();
    let (gpu, _) = g.render(&vol, &mapping, &view, &s).unwrap();
    for (a, b) in cpu.pixels.iter().zip(&gpu.pixels) {
        for k in 0..4 {
            assert!(
                (f64::from(a[k]) - f64::from(b[k])).abs() <= 1e-12,
                "{a:?} vs {b:?}"
            );
        }
    }
}
