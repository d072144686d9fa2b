//! `LIT_EMITTER` and the lights against hand-computed answers:
//! a slab whose Linear field rises along x, lit along and across its gradient, so that the
//! emission is one constant per cell and the pixel follows the closed form of a homogeneous
//! slab, I = I0·θ + η/χ·(1 − θ) with θ = e^{−χl}.

use vorang::Volume;
use vorang::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
use vorang::mesh::TetMesh;
use vorang::mesh::generate::kuhn_box;
use vorang::reference::Options;
use vorang::render::{LineDraw, Method, Settings, render};
use vorang::scene::{Light, LookAt, TransformOp, View};
use vorang_tcl::script::{Collect, Runner};

/// A 1 × 1 × 0.4 slab (seen along z by the default camera, every ray crosses 0.4) with the
/// field `f(x) = field(p)` on its nodes.
fn slab(field: impl Fn([f64; 3]) -> f64) -> Volume {
    let (nodes, tets) = kuhn_box([3, 3, 2], [1.0, 1.0, 0.4], 0.1, 7);
    let values: Vec<f64> = nodes.iter().map(|&p| field(p)).collect();
    let mut vol = Volume::from_mesh("slab", TetMesh::new(nodes, tets).unwrap());
    vol.add_node_field(Some("f"), values).unwrap();
    vol
}

const CHI: f64 = 2.5;
const COLOR: [f64; 3] = [0.2, 0.4, 0.8];
const PHONG: [f64; 4] = [0.1, 0.6, 0.3, 4.0];

/// LIT_EMITTER with a table that is `COLOR` everywhere, constant absorption `CHI`.
fn lit_mapping(vol: &Volume) -> Mapping {
    let [r, g, b] = COLOR;
    let [ka, kd, ks, n] = PHONG;
    let color = format!(
        "# VoRANG Colormap 1.0\nLIT_EMITTER @1\n@1\n{ka} {kd} {ks} {n}\n{r} {g} {b} -100\n{r} {g} {b} 100\n"
    );
    let alpha = format!("# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n{CHI}\n");
    let c = parse_map::<dyn ColorShading>(color.as_bytes(), "c.map")
        .unwrap()
        .0;
    let a = parse_map::<dyn AlphaShading>(alpha.as_bytes(), "a.map")
        .unwrap()
        .0;
    Mapping::new(&c, &a, vol).unwrap().0
}

fn settings(method: &str, lights: Vec<Light>) -> Settings {
    let words: Vec<&str> = method.split_whitespace().collect();
    Settings {
        width: 12,
        height: 12,
        method: Method::parse(&words).unwrap(),
        lines: LineDraw::Off,
        lights,
        ..Settings::default()
    }
}

/// The slab's pixel for emission `eta` on the white background (B = 1, l = 0.4).
fn slab_pixel(eta: [f64; 3]) -> [f64; 3] {
    let theta = (-CHI * 0.4).exp();
    eta.map(|e| theta + e / CHI * (1.0 - theta))
}

/// Renders with every exact way (closed form, fixed steps, interpolateCoeff) and the reference
/// ray caster, and checks every covered pixel against `want`.
fn check(vol: &Volume, view: &View, lights: Vec<Light>, want: [f64; 3]) {
    let m = lit_mapping(vol);
    for method in [
        "exact linear 0 1",
        "exact linear 0.05 1",
        "exact constEA 0.05 1",
        "interpolateCoeff linear 1",
    ] {
        let (fb, _) = render(vol, &m, view, &settings(method, lights.clone()), None).unwrap();
        for (i, p) in fb.pixels.iter().enumerate() {
            for c in 0..3 {
                assert!(
                    (f64::from(p[c]) - want[c]).abs() < 1e-6,
                    "{method}: pixel {i} channel {c}: {} vs {}",
                    p[c],
                    want[c]
                );
            }
        }
    }
    let mut opts = Options::new(6, 6);
    opts.lights = lights;
    for p in vorang::reference::render(vol, &m, view, &opts) {
        for c in 0..3 {
            assert!(
                (p[c] - want[c]).abs() < 1e-9,
                "reference channel {c}: {} vs {}",
                p[c],
                want[c]
            );
        }
    }
}

fn light(color: [f64; 3], direction: [f64; 3]) -> Light {
    Light { color, direction }
}

#[test]
fn lit_along_the_falling_gradient() {
    // f rises along +x, so n = −x̂; a light from −x: n·l = 1. The viewer is at +z, so
    // h = (−1, 0, 1)/√2 and n·h = 1/√2. Light colour (1, 0.5, 0.25).
    let vol = slab(|p| 3.0 * p[0] + 1.0);
    let [ka, kd, ks, n] = PHONG;
    let lc = [1.0, 0.5, 0.25];
    let per_light = kd + ks * 0.5f64.sqrt().powf(n);
    let eta = [0, 1, 2].map(|c| COLOR[c] * (ka + lc[c] * per_light));
    let lights = vec![light(lc, [-2.0, 0.0, 0.0])];
    check(&vol, &View::default(), lights, slab_pixel(eta));
}

#[test]
fn lit_across_the_gradient_or_from_behind_only_the_ambient_term_remains() {
    let vol = slab(|p| 3.0 * p[0] + 1.0);
    let ambient = slab_pixel(COLOR.map(|c| c * PHONG[0]));
    // Across: n·l = 0 and n·h = 0 (h lies in the y–z plane).
    check(
        &vol,
        &View::default(),
        vec![light([1.0; 3], [0.0, 1.0, 0.0])],
        ambient,
    );
    // From the side the values rise towards: n·l = −1, n·h = −1/√2.
    check(
        &vol,
        &View::default(),
        vec![light([1.0; 3], [1.0, 0.0, 0.0])],
        ambient,
    );
    // A constant field has no gradient: ambient only, whatever the lights.
    let flat = slab(|_| 0.5);
    check(
        &flat,
        &View::default(),
        vec![light([1.0; 3], [0.0, 0.0, 1.0])],
        ambient,
    );
}

#[test]
fn lights_add_up() {
    // Two lights: one along the normal (n·l = 1, n·h = 1/√2), one across (nothing).
    let vol = slab(|p| 1.0 - 2.0 * p[1]);
    // f falls along +y: n = +ŷ.
    let [ka, kd, ks, n] = PHONG;
    let along = kd + ks * 0.5f64.sqrt().powf(n);
    let eta = [0, 1, 2].map(|c| COLOR[c] * (ka + [0.5, 1.0, 0.0][c] * along));
    let lights = vec![
        light([0.5, 1.0, 0.0], [0.0, 5.0, 0.0]),
        light([1.0, 1.0, 1.0], [1.0, 0.0, 0.0]),
    ];
    check(&vol, &View::default(), lights, slab_pixel(eta));
}

#[test]
fn the_default_light_is_at_the_camera() {
    // f falls towards the viewer (+z): n = +ẑ. The default light shines from the camera (the
    // eye of the default look_at sits on the axis, the light comes from +z), the viewer is
    // there too: n·l = 1, h = ẑ, n·h = 1.
    let vol = slab(|p| -p[2]);
    let [ka, kd, ks, _] = PHONG;
    let eta = COLOR.map(|c| c * (ka + kd + ks));
    check(&vol, &View::default(), Vec::new(), slab_pixel(eta));
}

#[test]
fn the_default_light_follows_the_eye() {
    // The eye moved to (0, 0, 5), looking at the volume's centre: the light comes from the
    // eye, along +z, as before.
    let vol = slab(|p| -p[2]);
    let [ka, kd, ks, _] = PHONG;
    let view = View {
        look_at: LookAt {
            eye: [0.0, 0.0, 5.0],
            reference: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
        },
        ..View::default()
    };
    check(
        &vol,
        &view,
        Vec::new(),
        slab_pixel(COLOR.map(|c| c * (ka + kd + ks))),
    );
}

#[test]
fn a_mirrored_volume_turns_its_normals_with_it() {
    // f rises along +x in the file; vol_scale −1 1 1 mirrors x, so in the world f rises along
    // −x and n = +x̂: the light from −x is behind the surface now (ambient only), the light
    // from +x faces it.
    let vol = slab(|p| 3.0 * p[0] + 1.0);
    let view = View {
        transforms: vec![TransformOp::Scale([-1.0, 1.0, 1.0])],
        ..View::default()
    };
    let [ka, kd, ks, n] = PHONG;
    check(
        &vol,
        &view,
        vec![light([1.0; 3], [-1.0, 0.0, 0.0])],
        slab_pixel(COLOR.map(|c| c * ka)),
    );
    let lit = ka + kd + ks * 0.5f64.sqrt().powf(n);
    check(
        &vol,
        &view,
        vec![light([1.0; 3], [1.0, 0.0, 0.0])],
        slab_pixel(COLOR.map(|c| c * lit)),
    );
}

#[test]
fn a_stretched_volume_keeps_normals_normal_to_the_level_sets() {
    // f = x + y in the file; vol_scale 2 1 1 stretches x, so the world field is x/2 + y with
    // gradient (1/2, 1): n = −(1, 2)/√5. A light from −(1, 2) direction: n·l = 1; h = (l + ẑ)/|…|.
    let vol = slab(|p| p[0] + p[1]);
    let view = View {
        transforms: vec![TransformOp::Scale([2.0, 1.0, 1.0])],
        ..View::default()
    };
    let s5 = 5f64.sqrt();
    let l = [-1.0 / s5, -2.0 / s5, 0.0];
    let hl = [l[0], l[1], 1.0];
    let hn = (hl[0] * hl[0] + hl[1] * hl[1] + 1.0).sqrt();
    let n_dot_h = (l[0] * hl[0] + l[1] * hl[1]) / hn;
    let [ka, kd, ks, sh] = PHONG;
    let f = ka + kd + ks * n_dot_h.powf(sh);
    // The stretched slab is 2 wide: the default camera's window is the untransformed box, so
    // every pixel is still covered.
    check(
        &vol,
        &view,
        vec![light([1.0; 3], [-1.0, -2.0, 0.0])],
        slab_pixel(COLOR.map(|c| c * f)),
    );
}

#[test]
fn a_varying_table_is_exact_per_cell_against_the_reference() {
    // A colour ramp over a Linear field, lit from a skew direction: the closed-form rule and
    // the reference ray caster (adaptive quadrature) agree.
    let vol = slab(|p| (1.3 * p[0] + 0.4).sin() * (2.1 * p[1]).cos() + p[2]);
    let c = parse_map::<dyn ColorShading>(
        "# VoRANG Colormap 1.0\nLIT_EMITTER @1\n@1\n0.2 0.7 0.4 8\n0 0 1 -1\n1 1 0 0.5\n1 0 0 1.5\n"
            .as_bytes(),
        "c.map",
    )
    .unwrap()
    .0;
    let a = parse_map::<dyn AlphaShading>(
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.5 -1\n4 1.5\n".as_bytes(),
        "a.map",
    )
    .unwrap()
    .0;
    let m = Mapping::new(&c, &a, &vol).unwrap().0;
    let lights = vec![
        light([1.0, 0.9, 0.8], [0.3, -0.5, 0.8]),
        light([0.2, 0.2, 0.5], [-1.0, 0.2, 0.1]),
    ];
    let view = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 1.0, 0.0],
            degrees: 25.0,
        }],
        ..View::default()
    };
    let s = Settings {
        width: 10,
        height: 10,
        ..settings("exact linear 0 1", lights.clone())
    };
    let (fb, _) = render(&vol, &m, &view, &s, None).unwrap();
    let mut opts = Options::new(10, 10);
    opts.lights = lights;
    let reference = vorang::reference::render(&vol, &m, &view, &opts);
    let mut worst: f64 = 0.0;
    for (p, q) in fb.pixels.iter().zip(&reference) {
        for c in 0..4 {
            worst = worst.max((f64::from(p[c]) - q[c]).abs());
        }
    }
    assert!(worst < 1e-6, "largest difference {worst}");
    // And the lights matter: unlit (ambient 1, no lights' terms) differs.
    let (unlit, _) = render(
        &vol,
        &m,
        &view,
        &settings("exact linear 0 1", vec![light([0.0; 3], [0.0, 0.0, 1.0])]),
        None,
    )
    .unwrap();
    assert_ne!(unlit.pixels, fb.pixels);
}

#[test]
fn the_block_needs_the_lighting_row_and_a_table() {
    let parse = |text: &str| {
        parse_map::<dyn ColorShading>(text.as_bytes(), "c.map")
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    let e = parse("# VoRANG Colormap 1.0\nLIT_EMITTER @1\n@1\n0.1 0.5 0.5 8\n").unwrap_err();
    assert!(e.contains("c.map:3") && e.contains("r g b value"), "{e}");
    let e =
        parse("# VoRANG Colormap 1.0\nLIT_EMITTER @1\n@1\n0.1 -0.5 0.5 8\n1 1 1 0\n").unwrap_err();
    assert!(e.contains("c.map:4") && e.contains("≥ 0"), "{e}");
    let e = parse("# VoRANG Colormap 1.0\nLIT_EMITTER @1\n@1\n0.1 0.5 0.5\n1 1 1 0\n").unwrap_err();
    assert!(e.contains("c.map:4"), "{e}");
    parse("# VoRANG Colormap 1.0\nLIT_EMITTER @1\n@1\n0.1 0.5 0.5 8\n1 1 1 0\n").unwrap();
}

#[test]
fn addlight_numbers_lights_and_removelight_takes_them_away() {
    let mut r = Runner::new(Box::new(Collect::default()));
    assert_eq!(r.run_string("addlight 1 1 1 0 0 1", "t").unwrap(), "1");
    assert_eq!(r.run_string("addlight 1 0 0 1 0 0", "t").unwrap(), "2");
    r.run_string("removelight 1", "t").unwrap();
    let lights = r.session().settings().lights.clone();
    assert_eq!(lights, vec![light([1.0, 0.0, 0.0], [1.0, 0.0, 0.0])]);
    let e = r.run_string("removelight 2", "t").unwrap_err().to_string();
    assert!(e.contains("no light 2"), "{e}");
    let e = r
        .run_string("addlight 1 1 1 0 0 0", "t")
        .unwrap_err()
        .to_string();
    assert!(e.contains("direction"), "{e}");
    r.run_string("removelight 1", "t").unwrap();
    assert!(r.session().settings().lights.is_empty());
}
