//! The renderer against analytic answers and the independent reference ray caster.

#![allow(clippy::needless_range_loop)]

use vorang::Volume;
use vorang::field::Interpolator;
use vorang::framebuffer::Framebuffer;
use vorang::hypermesh::{DataType, ElementKind, RawData, ScalarType, Values};
use vorang::integrate::RULES;
use vorang::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
use vorang::mesh::TetMesh;
use vorang::mesh::generate::{SplitMix64, kuhn_box};
use vorang::reference::Options;
use vorang::render::cell::EyeCell;
use vorang::render::footprint::footprint;
use vorang::render::project::ProjClass;
use vorang::render::{LineDraw, Method, Order, Settings, render};
use vorang::scene::{Camera, LookAt, Projector, TransformOp, View};
use vorang::sort::{self, SortInput};

fn mapping(vol: &Volume, color: &str, alpha: &str) -> Mapping {
    let c = parse_map::<dyn ColorShading>(color.as_bytes(), "c.map")
        .unwrap()
        .0;
    let a = parse_map::<dyn AlphaShading>(alpha.as_bytes(), "a.map")
        .unwrap()
        .0;
    Mapping::new(&c, &a, vol).unwrap().0
}

fn constant_maps(vol: &Volume, eta: [f64; 3], chi: f64) -> Mapping {
    mapping(
        vol,
        &format!(
            "# VoRANG Colormap 1.0\nCONSTANT @1\n@1\n{} {} {}\n",
            eta[0], eta[1], eta[2]
        ),
        &format!("# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n{chi}\n"),
    )
}

/// A box of `n³` Kuhn cubes with one smooth scalar node field.
fn box_volume(n: usize, size: [f64; 3], jitter: f64, seed: u64) -> Volume {
    let (nodes, tets) = kuhn_box([n, n, n], size, jitter, seed);
    let values: Vec<f64> = nodes
        .iter()
        .map(|p| (1.3 * p[0] + 0.4).sin() * (2.1 * p[1]).cos() + p[2] * p[2])
        .collect();
    let mesh = TetMesh::new(nodes, tets).unwrap();
    let mut vol = Volume::from_mesh("box", mesh);
    vol.add_node_field(Some("s"), values).unwrap();
    vol
}

fn settings(w: usize, h: usize, method: &str) -> Settings {
    let words: Vec<&str> = method.split_whitespace().collect();
    Settings {
        width: w,
        height: h,
        method: Method::parse(&words).unwrap(),
        lines: LineDraw::Off,
        ..Settings::default()
    }
}

fn max_diff(a: &Framebuffer, b: &[[f64; 4]]) -> f64 {
    a.pixels
        .iter()
        .zip(b)
        .flat_map(|(p, q)| (0..4).map(move |k| (f64::from(p[k]) - q[k]).abs()))
        .fold(0.0, f64::max)
}

fn max_diff_fb(a: &Framebuffer, b: &Framebuffer) -> f64 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..4).map(move |k| (p[k] - q[k]).abs() as f64))
        .fold(0.0, f64::max)
}

/// Every method × rule on a homogeneous slab: the opacity is 1 − e^{−χl} and the intensity
/// I0·e^{−χl} + B·η/χ·(1 − e^{−χl}) where the rule is exact for constant coefficients.
#[test]
fn a_homogeneous_slab_matches_the_analytic_answer() {
    // A 1 × 1 × 0.4 slab seen along z with the default camera: every ray crosses 0.4.
    let (nodes, tets) = kuhn_box([3, 3, 2], [1.0, 1.0, 0.4], 0.1, 3);
    let vol = Volume::from_mesh("slab", TetMesh::new(nodes, tets).unwrap());
    let (eta, chi, l, b) = ([0.3, 0.6, 0.9], 2.5, 0.4, 1.5);
    let m = constant_maps(&vol, eta, chi);
    let theta = (-chi * l).exp();
    let expect: [f64; 4] = [0, 1, 2, 3].map(|c| {
        if c < 3 {
            theta + b * eta[c] / chi * (1.0 - theta)
        } else {
            1.0 - theta
        }
    });
    let view = View::default();
    for rule in RULES {
        for method in [
            format!("exact {} 0.01 {b}", rule.name),
            format!("exact {} 0 {b}", rule.name),
            format!("interpolateCoeff {} {b}", rule.name),
        ] {
            let (fb, _) = render(&vol, &m, &view, &settings(16, 16, &method), None).unwrap();
            for p in &fb.pixels {
                assert!(
                    (f64::from(p[3]) - expect[3]).abs() < 1e-6,
                    "{method}: alpha {} vs {}",
                    p[3],
                    expect[3]
                );
                // trapez is exact only in the limit of short pieces.
                let tol = if rule.name == "trapez" && !method.contains("0.01") {
                    0.05
                } else if rule.name == "trapez" {
                    2e-5
                } else {
                    1e-6
                };
                for c in 0..3 {
                    assert!(
                        (f64::from(p[c]) - expect[c]).abs() < tol,
                        "{method}: channel {c}: {} vs {}",
                        p[c],
                        expect[c]
                    );
                }
            }
        }
    }
    // interpolateColor: exact at the thick points only, more transparent elsewhere (thesis 7.1);
    // never more opaque than the truth.
    let (fb, _) = render(
        &vol,
        &m,
        &view,
        &settings(16, 16, &format!("interpolateColor {b}")),
        None,
    )
    .unwrap();
    for p in &fb.pixels {
        assert!(f64::from(p[3]) <= expect[3] + 1e-6 && p[3] > 0.0);
    }
}

/// With constant coefficients interpolateCoeff integrates one segment per cell, exactly as
/// `exact` with a step longer than any cell does.
#[test]
fn interpolate_coeff_equals_exact_with_one_piece_per_cell_for_constant_maps() {
    let vol = box_volume(3, [1.0; 3], 0.1, 4);
    let m = constant_maps(&vol, [0.4, 0.2, 0.9], 3.0);
    let view = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 2.0, 0.5],
            degrees: 40.0,
        }],
        ..View::default()
    };
    for rule in RULES {
        let a = render(
            &vol,
            &m,
            &view,
            &settings(24, 24, &format!("exact {} 100 1", rule.name)),
            None,
        )
        .unwrap()
        .0;
        let b = render(
            &vol,
            &m,
            &view,
            &settings(24, 24, &format!("interpolateCoeff {} 1", rule.name)),
            None,
        )
        .unwrap()
        .0;
        assert!(max_diff_fb(&a, &b) < 1e-6, "{}", rule.name);
    }
}

const PL_COLOR: &str = "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0.1 0 0.2 -1\n1 0.5 0 -0.2\n0.2 1 0.4 0.3\n0.5 0.3 1 0.8\n1 1 1 1.4\n";
const PL_ALPHA: &str =
    "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.5 -1\n4 -0.3\n1 0.2\n6 0.9\n2 1.5\n";

fn views() -> Vec<(&'static str, View)> {
    vec![
        (
            "ortho rotated",
            View {
                transforms: vec![
                    TransformOp::Rotate {
                        axis: [0.3, 1.0, 0.2],
                        degrees: 33.0,
                    },
                    TransformOp::Rotate {
                        axis: [1.0, 0.0, 0.0],
                        degrees: -20.0,
                    },
                ],
                camera: Some(Camera::Ortho {
                    left: -0.9,
                    right: 0.9,
                    bottom: -0.9,
                    top: 0.9,
                    front: -5.0,
                    back: 5.0,
                }),
                ..View::default()
            },
        ),
        (
            "perspective rotated",
            View {
                transforms: vec![TransformOp::Rotate {
                    axis: [1.0, 1.0, 0.0],
                    degrees: 25.0,
                }],
                look_at: LookAt {
                    eye: [0.4, 0.3, 2.5],
                    reference: [0.0, 0.0, 0.0],
                    up: [0.0, 1.0, 0.0],
                },
                camera: Some(Camera::Persp {
                    fovy: 40.0,
                    aspect: 1.0,
                    near: 0.5,
                    far: 10.0,
                }),
            },
        ),
    ]
}

fn rms_diff(a: &Framebuffer, b: &[[f64; 4]]) -> f64 {
    let d: Vec<f64> = a
        .pixels
        .iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |k| f64::from(p[k]) - q[k]))
        .collect();
    (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt()
}

/// exact constEA converges to the reference at second order: the error falls by about 4 per
/// halving of the step (RMS over the image; steps small enough for every cell to be cut into
/// several pieces, where `ceil(length/step)` pieces halve with the step).
#[test]
fn exact_const_ea_converges_to_the_reference_at_second_order() {
    let vol = box_volume(3, [1.0; 3], 0.12, 7);
    let m = mapping(&vol, PL_COLOR, PL_ALPHA);
    for (name, view) in views() {
        let (w, h) = (20, 20);
        let reference = vorang::reference::render(&vol, &m, &view, &Options::new(w, h));
        let mut errors = Vec::new();
        for step in [0.02, 0.01, 0.005, 0.0025] {
            let (fb, _) = render(
                &vol,
                &m,
                &view,
                &settings(w, h, &format!("exact constEA {step} 1")),
                None,
            )
            .unwrap();
            errors.push(rms_diff(&fb, &reference));
        }
        let ratios: Vec<f64> = errors.windows(2).map(|e| e[0] / e[1]).collect();
        eprintln!("{name}: RMS errors {errors:?} ratios {ratios:?}");
        assert!(
            errors[3] > 1e-7,
            "{name}: the error reached f32 precision, the test measures nothing: {errors:?}"
        );
        for r in &ratios {
            assert!(
                (3.2..5.0).contains(r),
                "{name}: error ratios {ratios:?} (errors {errors:?})"
            );
        }
    }
}

#[test]
fn back_to_front_equals_front_to_back() {
    let vol = box_volume(3, [1.0; 3], 0.1, 2);
    let m = mapping(&vol, PL_COLOR, PL_ALPHA);
    for (_, view) in views() {
        for method in [
            "exact constEA 0.05 1",
            "interpolateCoeff weightedConstEA 2",
            "interpolateColor 1",
            "test 0.4",
        ] {
            let mut s = settings(24, 24, method);
            s.lines = LineDraw::All;
            let a = render(&vol, &m, &view, &s, None).unwrap().0;
            s.order = Order::FrontToBack;
            let b = render(&vol, &m, &view, &s, None).unwrap().0;
            assert!(
                max_diff_fb(&a, &b) < 2e-6,
                "{method}: {}",
                max_diff_fb(&a, &b)
            );
        }
    }
}

#[test]
fn tiles_and_threads_do_not_change_a_single_bit() {
    let vol = box_volume(4, [1.0; 3], 0.1, 5);
    let m = mapping(&vol, PL_COLOR, PL_ALPHA);
    let (_, view) = &views()[1];
    let mut s = settings(70, 50, "exact constEA 0.03 1");
    s.lines = LineDraw::All;
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let reference = one.install(|| render(&vol, &m, view, &s, None).unwrap().0);
    for (threads, tile) in [(2, 32), (3, 8), (4, 64), (2, 1), (1, 13)] {
        s.tile = tile;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let fb = pool.install(|| render(&vol, &m, view, &s, None).unwrap().0);
        assert!(fb == reference, "{threads} threads, tiles of {tile}");
    }
}

/// One tetrahedron seen along −z with the default camera, for each projection class.
fn class_cases() -> Vec<(ProjClass, [[f64; 3]; 4])> {
    let base = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    vec![
        (
            ProjClass::OneA,
            [base[0], base[1], base[2], [0.3, 0.3, 0.8]],
        ),
        (
            ProjClass::OneB,
            [base[0], base[1], base[2], [0.3, 0.3, -0.8]],
        ),
        (
            ProjClass::Two,
            [
                [0.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [1.0, 0.0, 0.7],
                [0.0, 1.0, 0.7],
            ],
        ),
        (
            ProjClass::ThreeA,
            [base[0], base[1], base[2], [0.5, 0.0, 0.9]],
        ),
        (
            ProjClass::ThreeB,
            [base[0], base[1], base[2], [0.5, 0.0, -0.9]],
        ),
        (
            ProjClass::Four,
            [base[0], base[1], base[2], [0.0, 0.0, 0.9]],
        ),
    ]
}

fn single_tet(p: [[f64; 3]; 4]) -> Volume {
    let mesh = TetMesh::new(p.to_vec(), vec![[0, 1, 2, 3]]).unwrap();
    let mut vol = Volume::from_mesh("tet", mesh);
    let values: Vec<f64> = p
        .iter()
        .map(|q| -0.8 + 1.3 * q[0] + 0.9 * q[1] + 0.6 * q[2])
        .collect();
    let r = vol
        .add_raw(RawData {
            kind: ElementKind::Node,
            ty: DataType::scalar(ScalarType::Double),
            denominator: None,
            values: Values::F64(values),
        })
        .unwrap();
    vol.add_field(
        None,
        DataType::scalar(ScalarType::Double),
        Interpolator::Linear,
        &[r],
    )
    .unwrap();
    vol
}

#[test]
fn every_projection_class_is_produced_and_rendered_correctly() {
    let camera = Camera::Ortho {
        left: -0.2,
        right: 1.2,
        bottom: -0.2,
        top: 1.2,
        front: -5.0,
        back: 5.0,
    };
    for (class, p) in class_cases() {
        let vol = single_tet(p);
        // The class as the renderer sees it (default view: eye space = centred file space).
        let view = View {
            camera: Some(camera),
            ..View::default()
        };
        let c = vol.mesh.bbox().center();
        let eye = vol.mesh.tets()[0].map(|n| {
            let q = vol.mesh.nodes()[n as usize];
            [q[0] - c[0], q[1] - c[1], q[2] - c[2]]
        });
        let proj = Projector::new(Some(&camera), [1.0; 3], 40, 40).unwrap();
        let screen = eye.map(|q| proj.screen(q));
        let fp = footprint(vol.mesh.tets()[0], &eye, &screen, &proj).unwrap();
        assert_eq!(fp.projection.unwrap().class, class);
        // Rendered exactly: against the reference, with the piecewise-linear maps.
        let m = mapping(&vol, PL_COLOR, PL_ALPHA);
        let reference = vorang::reference::render(&vol, &m, &view, &Options::new(40, 40));
        let (fb, _) = render(
            &vol,
            &m,
            &view,
            &settings(40, 40, "exact constEA 0.002 1"),
            None,
        )
        .unwrap();
        let e = max_diff(&fb, &reference);
        assert!(e < 2e-4, "class {}: exact differs by {e}", class.name());
        // interpolateColor: where a pixel centre meets the thick point exactly, θ there is the
        // cell's true transparency along that ray; everywhere it lies between that and 1.
        let m = constant_maps(&vol, [0.5, 0.5, 0.5], 3.0);
        let (fb, _) = render(
            &vol,
            &m,
            &view,
            &settings(40, 40, "interpolateColor 1"),
            None,
        )
        .unwrap();
        let reference = vorang::reference::render(&vol, &m, &view, &Options::new(40, 40));
        for (p, q) in fb.pixels.iter().zip(&reference) {
            assert!(
                f64::from(p[3]) <= q[3] + 1e-6,
                "class {}: Gouraud opacity above the truth",
                class.name()
            );
        }
        assert!(
            fb.pixels.iter().any(|p| p[3] > 0.0),
            "class {} drew nothing",
            class.name()
        );
    }
}

#[test]
fn many_small_cells_render_like_one_box_no_cracks_no_double_counting() {
    let (eta, chi) = ([0.7, 0.3, 0.1], 1.7);
    let (n1, t1) = kuhn_box([1, 1, 1], [1.0; 3], 0.0, 0);
    let one = Volume::from_mesh("one", TetMesh::new(n1, t1).unwrap());
    let (n2, t2) = kuhn_box([6, 6, 6], [1.0; 3], 0.0, 0);
    let many = Volume::from_mesh("many", TetMesh::new(n2, t2).unwrap());
    let (m1, m2) = (
        constant_maps(&one, eta, chi),
        constant_maps(&many, eta, chi),
    );
    let mut views = vec![View::default()];
    views.extend(self::views().into_iter().map(|v| v.1));
    views.push(View {
        transforms: vec![TransformOp::Rotate {
            axis: [0.0, 0.0, 1.0],
            degrees: 90.0,
        }],
        ..View::default()
    });
    for view in &views {
        // Odd and even sizes put pixel centres exactly on cell faces seen edge-on.
        for size in [9, 12, 31] {
            let s = settings(size, size, "exact constEA 0 1");
            let a = render(&one, &m1, view, &s, None).unwrap().0;
            let b = render(&many, &m2, view, &s, None).unwrap().0;
            assert!(
                max_diff_fb(&a, &b) < 1e-6,
                "{size}×{size}: {}",
                max_diff_fb(&a, &b)
            );
        }
    }
}

/// The sort must put, on every ray, the cells it crosses in order of depth.
#[test]
fn mpvo_orders_random_meshes_along_every_ray() {
    let mut rng = SplitMix64(99);
    for trial in 0..6 {
        let (nodes, tets) = kuhn_box([4, 3, 3], [1.0, 0.8, 0.9], 0.14, 100 + trial);
        let mesh = TetMesh::new(nodes, tets).unwrap();
        let r = vorang::scene::Affine::rotation(
            [
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
            ],
            360.0 * rng.next_f64(),
        )
        .unwrap();
        let perspective = trial % 2 == 1;
        let eye_nodes: Vec<[f64; 3]> = mesh
            .nodes()
            .iter()
            .map(|&p| {
                let q = r.apply([p[0] - 0.5, p[1] - 0.4, p[2] - 0.45]);
                [q[0], q[1], q[2] - if perspective { 3.0 } else { 0.0 }]
            })
            .collect();
        let screen: Vec<[f64; 2]> = eye_nodes
            .iter()
            .map(|p| {
                if perspective {
                    [p[0] / -p[2], -p[1] / -p[2]]
                } else {
                    [p[0], -p[1]]
                }
            })
            .collect();
        let order = (sort::choose(true).sort)(&SortInput {
            mesh: &mesh,
            eye_nodes: &eye_nodes,
            screen: &screen,
            perspective,
            mirrored: false,
        });
        assert_eq!(order.cycle_cells, 0);
        let mut pos = vec![0; mesh.tet_count()];
        for (i, &c) in order.back_to_front.iter().enumerate() {
            pos[c as usize] = i;
        }
        let cells: Vec<EyeCell> = mesh
            .tets()
            .iter()
            .map(|t| EyeCell::new(&t.map(|n| eye_nodes[n as usize])).unwrap())
            .collect();
        for _ in 0..400 {
            let (x, y) = (rng.next_f64() * 1.4 - 0.7, rng.next_f64() * 1.4 - 0.7);
            let ray = if perspective {
                vorang::scene::Ray {
                    origin: [0.0; 3],
                    dir: [x / 3.0, y / 3.0, -1.0],
                }
            } else {
                vorang::scene::Ray {
                    origin: [x, y, 0.0],
                    dir: [0.0, 0.0, -1.0],
                }
            };
            let mut hits: Vec<(f64, usize)> = cells
                .iter()
                .enumerate()
                .filter_map(|(c, e)| {
                    e.interval(&ray)
                        .filter(|i| i.far - i.near > 1e-9)
                        .map(|i| (i.near, c))
                })
                .collect();
            hits.sort_by(|a, b| b.0.total_cmp(&a.0));
            for w in hits.windows(2) {
                assert!(
                    pos[w[0].1] < pos[w[1].1],
                    "trial {trial}: cell {} (depth {}) drawn after {} (depth {})",
                    w[0].1,
                    w[0].0,
                    w[1].1,
                    w[1].0
                );
            }
        }
    }
}

#[test]
fn lines_are_black_opaque_and_hidden_by_the_volume_in_front() {
    let (nodes, tets) = kuhn_box([1, 1, 1], [1.0; 3], 0.0, 0);
    let vol = Volume::from_mesh("cube", TetMesh::new(nodes, tets).unwrap());
    let m = constant_maps(&vol, [0.0; 3], 50.0);
    let mut s = settings(41, 41, "exact constEA 0 1");
    s.lines = LineDraw::All;
    let (fb, _) = render(&vol, &m, &View::default(), &s, None).unwrap();
    // The outline of the cube (seen along z) is a line at the very front: black, opaque.
    let corner = fb.get(0, 0);
    assert_eq!(corner, [0.0, 0.0, 0.0, 1.0]);
    // A black absorbing volume in front of every line: the image is black everywhere the cube
    // is, and the lines are there (alpha 1) too.
    assert!(fb.pixels.iter().all(|p| p[0] < 1e-6 && p[3] > 0.99));
    // A less absorbing volume without lines is nowhere fully opaque; with lines, the line
    // pixels are.
    let m5 = constant_maps(&vol, [0.0; 3], 5.0);
    s.lines = LineDraw::Off;
    let (fb2, _) = render(&vol, &m5, &View::default(), &s, None).unwrap();
    assert!(fb2.pixels.iter().all(|p| p[3] < 1.0));
    s.lines = LineDraw::All;
    let (fb3, _) = render(&vol, &m5, &View::default(), &s, None).unwrap();
    assert!(fb3.pixels.iter().filter(|p| p[3] == 1.0).count() > 40);
    // A transparent emitting volume over a line: the line is attenuated, not hidden.
    let m = constant_maps(&vol, [1.0, 0.0, 0.0], 0.5);
    s.lines = LineDraw::All;
    let (fb, _) = render(&vol, &m, &View::default(), &s, None).unwrap();
    let (fb_off, _) = render(
        &vol,
        &m,
        &View::default(),
        &settings(41, 41, "exact constEA 0 1"),
        None,
    )
    .unwrap();
    let centre = (20, 20);
    // The diagonal through the centre of the front face is a line at depth 0: nothing in front.
    let _ = (fb.get(centre.0, centre.1), fb_off.get(centre.0, centre.1));
    let mut darker = 0;
    for (p, q) in fb.pixels.iter().zip(&fb_off.pixels) {
        assert!(p[0] <= q[0] + 1e-6, "a line never adds light");
        if p[1] < q[1] - 1e-3 {
            darker += 1;
        }
    }
    assert!(
        darker > 20,
        "lines remove the background behind them: {darker} pixels"
    );
}

#[test]
fn bad_render_requests_are_refused() {
    let vol = box_volume(1, [1.0; 3], 0.0, 0);
    let m = constant_maps(&vol, [1.0; 3], 1.0);
    let view = View::default();
    assert!(
        render(
            &vol,
            &m,
            &view,
            &Settings {
                width: 0,
                ..settings(4, 4, "test 0.5")
            },
            None
        )
        .is_err()
    );
    assert!(
        render(
            &vol,
            &m,
            &view,
            &Settings {
                width: 1 << 20,
                height: 1 << 20,
                ..settings(4, 4, "test 0.5")
            },
            None
        )
        .is_err()
    );
    let bad_cam = View {
        camera: Some(Camera::Persp {
            fovy: 30.0,
            aspect: 1.0,
            near: 0.0,
            far: 1.0,
        }),
        ..View::default()
    };
    assert!(render(&vol, &m, &bad_cam, &settings(4, 4, "test 0.5"), None).is_err());
    let flat = View {
        transforms: vec![TransformOp::Scale([1.0, 0.0, 1.0])],
        ..View::default()
    };
    assert!(render(&vol, &m, &flat, &settings(4, 4, "test 0.5"), None).is_err());
}

/// The merged 1D transfer function (the renderer's fast path) against the general mapping path,
/// which a category field with a single all-covering line forces: same images up to rounding,
/// for every method that maps per sample, both compositing orders and both projections.
#[test]
fn the_transfer_fast_path_agrees_with_the_general_mapping() {
    let vol = box_volume(6, [1.0, 1.2, 0.9], 0.1, 3);
    let table = "0 0 1 -0.5\n0 1 0 0\n1 1 0 0.5\n1 0 0 1\n1 1 1 1.5\n";
    let absorber = "SIMPLE_ABSORBER @2\n@2\n0.5 -0.4\n4 0.1\n1 0.7\n6 1.2\n";
    let maps = [
        (
            format!("SIMPLE_EMITTER @1\n@1\n{table}"),
            absorber.to_string(),
        ),
        (
            format!("ABSORPTION_WEIGHTED @1\n@1\n{table}"),
            absorber.to_string(),
        ),
        (
            "CONSTANT @1\n@1\n0.3 0.6 0.9\n".to_string(),
            absorber.to_string(),
        ),
        (
            format!("SIMPLE_EMITTER @1\n@1\n{table}"),
            "CONSTANT @2\n@2\n2.5\n".to_string(),
        ),
    ];
    let views = [
        View {
            transforms: vec![TransformOp::Rotate {
                axis: [1.0, 2.0, 0.5],
                degrees: 35.0,
            }],
            ..View::default()
        },
        View {
            camera: Some(Camera::Persp {
                fovy: 50.0,
                aspect: 1.0,
                near: 0.1,
                far: 10.0,
            }),
            look_at: LookAt {
                eye: [0.4, 0.3, 1.8],
                reference: [0.0; 3],
                up: [0.0, 1.0, 0.0],
            },
            ..View::default()
        },
    ];
    let methods = [
        "exact linear 0 1",
        "exact linear 0.07 1",
        "exact constEA 0.03 1",
        "exact trapez 0 1",
        "interpolateCoeff linear 1",
        "interpolateColor 1",
    ];
    for (color, alpha) in &maps {
        let fast = mapping(
            &vol,
            &format!("# VoRANG Colormap 1.0\n{color}"),
            &format!("# VoRANG Alphamap 1.0\n{alpha}"),
        );
        assert!(fast.transfer(&vol).is_some(), "{color} / {alpha}");
        let general = mapping(
            &vol,
            &format!("# VoRANG Colormap 1.0\nCategoryField 0\n{color}"),
            &format!("# VoRANG Alphamap 1.0\nCategoryField 0\n{alpha}"),
        );
        assert!(general.transfer(&vol).is_none());
        for view in &views {
            for method in methods {
                for order in [Order::BackToFront, Order::FrontToBack] {
                    let s = Settings {
                        order,
                        ..settings(48, 48, method)
                    };
                    let a = render(&vol, &fast, view, &s, None).unwrap().0;
                    let b = render(&vol, &general, view, &s, None).unwrap().0;
                    let d = max_diff_fb(&a, &b);
                    assert!(
                        a.max_channel() > 0.01,
                        "{method}: an empty image tests nothing"
                    );
                    // The framebuffer holds f32: one rounding step of values up to ~2.
                    assert!(d <= 1e-6, "{method} {order:?} {color}: differs by {d}");
                }
            }
        }
    }
}

/// `test` draws every face a ray crosses once. Counted by brute force over all cells: the cells
/// the ray passes through for a length, plus the exit from the (convex) mesh. The colour cuboid
/// is a regular grid, so in its thesis view many pixel centres fall exactly on projected edges,
/// where a ray only touches cells (an interval of rounding size) and must draw nothing there.
#[test]
fn test_method_draws_each_crossed_face_once() {
    let (vol, _) = Volume::load(std::path::Path::new("examples/farbraum/farbraum.hmesh")).unwrap();
    let m = constant_maps(&vol, [1.0; 3], 1.0);
    let view = View {
        transforms: vec![
            TransformOp::Rotate {
                axis: [0.0, 1.0, 0.0],
                degrees: -30.0,
            },
            TransformOp::Rotate {
                axis: [1.0, 0.0, 0.0],
                degrees: 25.0,
            },
            TransformOp::Scale([0.85; 3]),
        ],
        camera: Some(Camera::Ortho {
            left: -1.25,
            right: 1.25,
            bottom: -0.75,
            top: 0.75,
            front: -10.0,
            back: 10.0,
        }),
        ..View::default()
    };
    let touched = assert_faces_once(&vol, &m, &view, (500, 300));
    assert!(
        touched > 0,
        "the view must have rays that only touch a cell"
    );
}

/// `test` on a mesh with holes (non-convex: per-pixel runs, cells in no order along a ray):
/// still every crossed face once, whichever cell of a face comes first.
#[test]
fn test_method_draws_each_crossed_face_once_with_holes() {
    let vol = vorang::volume::jittered_box_with_holes(1500, 0.1, 11, 0.25);
    let m = constant_maps(&vol, [1.0; 3], 1.0);
    for degrees in [0.0, 33.0, 90.0] {
        let view = View {
            transforms: vec![TransformOp::Rotate {
                axis: [1.0, 0.6, 0.2],
                degrees,
            }],
            ..View::default()
        };
        assert_faces_once(&vol, &m, &view, (160, 120));
    }
}

/// Renders `test 0.3` in both orders and checks every pixel's opacity against the faces its
/// ray crosses, counted by brute force over all cells: the cells it passes through for a
/// length, in stretches of cells that meet end to end, each stretch one face more than cells.
/// Returns how many ray–cell pairs only touched (an interval of rounding size).
fn assert_faces_once(vol: &Volume, m: &Mapping, view: &View, (w, h): (usize, usize)) -> usize {
    let images = [Order::BackToFront, Order::FrontToBack].map(|order| {
        let s = Settings {
            order,
            ..settings(w, h, "test 0.3")
        };
        render(vol, m, view, &s, None).unwrap().0
    });
    let bbox = vol.mesh.bbox();
    let to_eye = view
        .view_matrix()
        .after(&view.model(bbox.center()).unwrap());
    let projector = Projector::new(view.camera.as_ref(), bbox.size(), w, h).unwrap();
    let cells: Vec<(EyeCell, f64)> = (0..vol.mesh.tet_count())
        .map(|c| {
            let eye = vol.mesh.corners(c).map(|p| to_eye.apply(p));
            let depth = eye.map(|p| -p[2]);
            let extent = depth.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
                - depth.iter().cloned().fold(f64::INFINITY, f64::min);
            (EyeCell::new(&eye).unwrap(), extent)
        })
        .collect();
    let mut touched = 0;
    let mut crossed: Vec<(f64, f64)> = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let ray = projector.ray(x, y);
            crossed.clear();
            for (cell, extent) in &cells {
                match cell.interval(&ray) {
                    // Longer than rounding (the renderer's threshold, far below a pixel).
                    Some(iv) if iv.far - iv.near > 1e-9 * extent => crossed.push((iv.near, iv.far)),
                    Some(_) => touched += 1,
                    None => {}
                }
            }
            crossed.sort_by(|a, b| a.0.total_cmp(&b.0));
            let stretches = crossed
                .windows(2)
                .filter(|p| p[1].0 > p[0].1 + 1e-9 * (1.0 + p[0].1.abs()))
                .count()
                + usize::from(!crossed.is_empty());
            let faces = (crossed.len() + stretches) as i32;
            let want = 1.0 - 0.7f64.powi(faces);
            for fb in &images {
                let got = f64::from(fb.pixels[y * w + x][3]);
                assert!(
                    (got - want).abs() < 1e-6,
                    "pixel ({x}, {y}): opacity {got}, {faces} faces crossed give {want}"
                );
            }
        }
    }
    touched
}

/// The SIMD span kernels (`render::span`) against the scalar per-pixel path on the same frames:
/// cells inside one table piece, cells cut at knots, thick cells that fall back to the scalar
/// rule, mirrored and perspective views, both orders. Both paths integrate the same segments exactly, so the
/// float images agree to their last bits; and most segments really went through the lanes.
#[test]
fn span_kernels_agree_with_the_scalar_path() {
    let vol = box_volume(7, [1.0, 1.3, 0.8], 0.15, 11);
    let table = "0 0 1 -0.5\n0 1 0 0\n1 1 0 0.5\n1 0 0 1\n1 1 1 1.5\n";
    let maps = [
        format!("SIMPLE_EMITTER @1\n@1\n{table}"),
        format!("ABSORPTION_WEIGHTED @1\n@1\n{table}"),
    ];
    let alphas = [
        "SIMPLE_ABSORBER @2\n@2\n0.5 -0.4\n4 0.1\n1 0.7\n6 1.2\n",
        // Thick: many cells above the lanes' optical-depth bound.
        "SIMPLE_ABSORBER @2\n@2\n3 -0.4\n40 0.1\n9 0.7\n60 1.2\n",
        "CONSTANT @2\n@2\n2.5\n",
    ];
    let views = [
        View {
            transforms: vec![TransformOp::Rotate {
                axis: [1.0, 2.0, 0.5],
                degrees: 35.0,
            }],
            ..View::default()
        },
        View {
            transforms: vec![
                TransformOp::Scale([-1.0, 1.0, 1.0]),
                TransformOp::Rotate {
                    axis: [0.3, -1.0, 0.2],
                    degrees: 70.0,
                },
            ],
            ..View::default()
        },
        View {
            camera: Some(Camera::Persp {
                fovy: 50.0,
                aspect: 1.0,
                near: 0.1,
                far: 10.0,
            }),
            look_at: LookAt {
                eye: [0.4, 0.3, 1.8],
                reference: [0.0; 3],
                up: [0.0, 1.0, 0.0],
            },
            transforms: vec![TransformOp::Rotate {
                axis: [0.2, 1.0, 0.1],
                degrees: 25.0,
            }],
        },
    ];
    for color in &maps {
        for alpha in alphas {
            let m = mapping(
                &vol,
                &format!("# VoRANG Colormap 1.0\n{color}"),
                &format!("# VoRANG Alphamap 1.0\n{alpha}"),
            );
            for view in &views {
                for method in [
                    "exact linear 0 1",
                    "exact linear 0.2 1.5",
                    "interpolateCoeff linear 1",
                    "interpolateColor 1.5",
                ] {
                    for order in [Order::BackToFront, Order::FrontToBack] {
                        let s = Settings {
                            order,
                            ..settings(64, 64, method)
                        };
                        let scalar = Settings {
                            span_kernels: false,
                            ..s.clone()
                        };
                        let (a, sa) = render(&vol, &m, view, &s, None).unwrap();
                        let (b, sb) = render(&vol, &m, view, &scalar, None).unwrap();
                        assert!(
                            a.max_channel() > 0.01,
                            "{method}: an empty image tests nothing"
                        );
                        assert_eq!(sb.lane_fragments, 0);
                        assert_eq!(sa.fragments, sb.fragments);
                        // Weighted emission with a varying absorption is quadratic along
                        // the ray: not for the lanes; thick cells neither. The coarse test mesh
                        // has many cells above the lanes' depth bound with the first map.
                        let quadratic = color.contains("WEIGHTED") && !alpha.contains("CONSTANT");
                        let gouraud = method.starts_with("interpolateColor");
                        let share = if gouraud {
                            // Every cell nothing clips, whatever the maps.
                            0.9
                        } else if quadratic || alpha.contains("40") {
                            0.0
                        } else if alpha.contains("CONSTANT") {
                            0.5
                        } else {
                            0.2
                        };
                        assert!(
                            sa.lane_fragments as f64 >= share * sa.fragments as f64,
                            "{method}: {} of {} in lanes",
                            sa.lane_fragments,
                            sa.fragments
                        );
                        let d = max_diff_fb(&a, &b);
                        assert!(d <= 2e-7, "{method} {order:?} {color} {alpha}: {d}");
                        // Screen-space shading in lanes is the same arithmetic, lane by lane.
                        assert!(!gouraud || d == 0.0, "{method} {order:?}: {d}");
                    }
                }
            }
        }
    }
}

/// A render whose cancel flag is set (here by its progress callback after the first tile, as the
/// Python package does on Ctrl-C) skips the tiles not yet started and returns an error, not a
/// partial image.
#[test]
fn a_cancelled_render_stops_early_and_returns_no_image() {
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    let vol = box_volume(6, [1.0, 1.0, 1.0], 0.1, 5);
    let m = constant_maps(&vol, [1.0; 3], 1.0);
    let s = Settings {
        tile: 8,
        ..settings(64, 64, "exact linear 0 1")
    };
    let cancel = AtomicBool::new(false);
    let finished = AtomicUsize::new(0);
    let progress = |_: usize, _: usize| {
        finished.fetch_add(1, Ordering::Relaxed);
        cancel.store(true, Ordering::Relaxed);
    };
    let r = vorang::render::render_cancellable(
        &vol,
        &m,
        &View::default(),
        &s,
        Some(&progress),
        &cancel,
    );
    match r {
        Err(e) => assert!(e.to_string().contains(vorang::render::CANCELLED), "{e}"),
        Ok(_) => panic!("a cancelled render returned an image"),
    }
    // 64 tiles; only those already running when the flag was set finish.
    let n = finished.load(Ordering::Relaxed);
    assert!(
        n >= 1 && n <= rayon::current_num_threads() + 1,
        "{n} tiles finished"
    );
    // Without the flag the same render completes.
    assert!(render(&vol, &m, &View::default(), &s, None).is_ok());
}

/// A byte material number per cell (a Constant field named "material"); returns its number.
fn add_material(vol: &mut Volume, material: Vec<u8>) -> usize {
    let r = vol
        .add_raw(RawData {
            kind: ElementKind::Tetrahedron,
            ty: DataType::scalar(ScalarType::Byte),
            denominator: None,
            values: Values::U8(material),
        })
        .unwrap();
    vol.add_field(
        Some("material"),
        DataType::scalar(ScalarType::Byte),
        Interpolator::Constant,
        &[r],
    )
    .unwrap()
}

/// A map switched by a per-cell category (a material number, CONST_CELL-style): each cell's
/// lines are fixed, so its pair of lines becomes a merged transfer function and the cell takes
/// the fast path (SIMD kernels for a convex mesh) — checked against the reference ray caster,
/// which evaluates the maps sample by sample. A CONST_CELL line (no merged form) keeps the
/// general path for its cells in the same image.
#[test]
fn per_cell_categories_take_the_fast_path_and_agree_with_the_reference() {
    let mut vol = box_volume(4, [1.0, 1.2, 0.9], 0.1, 5);
    let cells = vol.mesh.tet_count();
    let m = add_material(&mut vol, (0..cells).map(|c| 1 + (c % 3) as u8).collect());
    let color = format!(
        "# VoRANG Colormap 1.0\nDataField 0\nCategoryField {m}\n\
         SIMPLE_EMITTER from:1 to:2 @1\nSIMPLE_EMITTER from:2 to:3 @2\nCONST_CELL field:{m} from:3 @3\n\
         @1\n0 0 1 -0.5\n1 1 0 0.5\n1 0 0 1.5\n@2\n0.2 0.9 0.2 -0.5\n0.9 0.2 0.9 1.5\n@3\n0.5 0.5 0.5 3\n"
    );
    let alpha = format!(
        "# VoRANG Alphamap 1.0\nDataField 0\nCategoryField {m}\n\
         SIMPLE_ABSORBER from:1 to:3 @1\nCONSTANT from:3 @2\n@1\n0.5 -0.4\n4 0.7\n@2\n1.5\n"
    );
    let map = mapping(&vol, &color, &alpha);
    assert!(map.transfer(&vol).is_none());
    assert!(map.category_transfers(&vol).is_some());
    let view = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 2.0, 0.5],
            degrees: 35.0,
        }],
        ..View::default()
    };
    let s = settings(20, 20, "exact linear 0 1");
    let (fb, stats) = render(&vol, &map, &view, &s, None).unwrap();
    assert!(stats.lane_fragments > 0, "{stats:?}");
    assert!(stats.lane_fragments < stats.fragments, "{stats:?}");
    let reference = vorang::reference::render(&vol, &map, &view, &Options::new(20, 20));
    let d = max_diff(&fb, &reference);
    assert!(fb.max_channel() > 0.01);
    assert!(d < 1e-6, "differs from the reference by {d}");
    // The same pixels with the kernels off (the per-pixel transfer path).
    let off = Settings {
        span_kernels: false,
        ..s
    };
    let (slow, _) = render(&vol, &map, &view, &off, None).unwrap();
    assert!(max_diff_fb(&fb, &slow) <= 1e-6);
}

/// The same category map through the fast path (a Constant material field) and the general one
/// (the same material numbers as a Linear field, which could vary inside a cell and so gets no
/// merged transfer functions): every method gives the same image.
#[test]
fn per_cell_categories_give_every_method_the_image_of_the_general_path() {
    let mut vol = box_volume(4, [1.0, 1.2, 0.9], 0.1, 9);
    let cells = vol.mesh.tet_count();
    let nodes = vol.mesh.node_count();
    // Material 1 everywhere, once per cell and once per node.
    let per_cell = add_material(&mut vol, vec![1; cells]);
    let per_node = vol.add_node_field(Some("m"), vec![1.0; nodes]).unwrap();
    let maps = |cat: usize| {
        mapping(
            &vol,
            &format!(
                "# VoRANG Colormap 1.0\nDataField 0\nCategoryField {cat}\nCONSTANT from:-1 to:0.5 @2\n\
                 SIMPLE_EMITTER from:0.5 to:2 @1\n@1\n0 0 1 -0.5\n1 1 0 0.5\n1 0 0 1.5\n@2\n1 1 1\n"
            ),
            &format!(
                "# VoRANG Alphamap 1.0\nDataField 0\nCategoryField {cat}\n\
                 SIMPLE_ABSORBER from:0.5 to:2 @1\n@1\n0.5 -0.4\n4 0.7\n"
            ),
        )
    };
    let (fast, general) = (maps(per_cell), maps(per_node));
    assert!(fast.category_transfers(&vol).is_some());
    assert!(general.category_transfers(&vol).is_none());
    let view = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 2.0, 0.5],
            degrees: 35.0,
        }],
        ..View::default()
    };
    for method in [
        "exact linear 0 1",
        "exact constEA 0.03 1",
        "interpolateCoeff linear 1",
        "interpolateColor 1",
    ] {
        let s = settings(32, 32, method);
        let a = render(&vol, &fast, &view, &s, None).unwrap().0;
        let b = render(&vol, &general, &view, &s, None).unwrap().0;
        assert!(a.max_channel() > 0.01, "{method}");
        let d = max_diff_fb(&a, &b);
        assert!(d <= 1e-6, "{method}: differs by {d}");
    }
}

/// A non-convex mesh (a box with cavities and tunnels) is ordered per pixel; its cells still go
/// through the SIMD kernels, each pixel's result chained into that pixel's runs — against the
/// reference ray caster, both compositing orders, and with the kernels off.
#[test]
fn per_pixel_order_takes_the_kernels_and_agrees_with_the_reference() {
    let vol = vorang::volume::jittered_box_with_holes(1500, 0.1, 11, 0.25);
    let map = mapping(
        &vol,
        "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 1 0.2\n1 1 0 0.5\n1 0 0 0.8\n",
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.5 0.2\n4 0.5\n1 0.8\n",
    );
    let view = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 0.6, 0.2],
            degrees: 33.0,
        }],
        ..View::default()
    };
    let reference = vorang::reference::render(&vol, &map, &view, &Options::new(24, 24));
    for order in [Order::BackToFront, Order::FrontToBack] {
        let s = Settings {
            order,
            ..settings(24, 24, "exact linear 0 1")
        };
        let (fb, stats) = render(&vol, &map, &view, &s, None).unwrap();
        assert!(stats.per_pixel && !stats.convex, "{stats:?}");
        // Cells whose field crosses more table pieces than the kernel takes (or runs both ways
        // through them) keep the scalar path; most of the rest go through the kernel.
        assert!(stats.lane_fragments > 0, "{stats:?}");
        let d = max_diff(&fb, &reference);
        assert!(fb.max_channel() > 0.01);
        assert!(d < 1e-6, "{order:?}: differs from the reference by {d}");
        let off = Settings {
            span_kernels: false,
            ..s
        };
        let (slow, slow_stats) = render(&vol, &map, &view, &off, None).unwrap();
        assert_eq!(slow_stats.lane_fragments, 0);
        assert!(max_diff_fb(&fb, &slow) <= 1e-6);
    }
}
