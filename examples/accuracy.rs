//! Writes the accuracy report: every method × rule (and steps for `exact`) against the
//! reference ray caster on the scenes of `vorang::accuracy`, with render times.
//!
//! ```sh
//! cargo run --release --example accuracy > docs/accuracy.md
//! ```

use std::time::Instant;

use vorang::Volume;
use vorang::accuracy::{scalar_maps, scalar_volume, scenes, views};
use vorang::framebuffer::Framebuffer;
use vorang::mapping::Mapping;
use vorang::mesh::generate::{SplitMix64, kuhn_box};
use vorang::reference::{self, Options};
use vorang::render::{LineDraw, Method, Settings, render};
use vorang::scene::{TransformOp, View};

const SIZE: usize = 64;

const METHODS: &[&str] = &[
    "exact linear 0 1",
    "exact linear 0.05 1",
    "exact constEA 0.1 1",
    "exact constEA 0.02 1",
    "exact constEA 0.005 1",
    "exact weightedConstEA 0.02 1",
    "exact trapez 0.02 1",
    "exact trapez 0.005 1",
    "interpolateCoeff linear 1",
    "interpolateCoeff constEA 1",
    "interpolateCoeff weightedConstEA 1",
    "interpolateCoeff trapez 1",
    "interpolateColor 1",
];

fn main() {
    let threads = rayon::current_num_threads();
    println!("# Accuracy of the approximation methods\n");
    println!(
        "Every method and integration rule rendered at {SIZE}×{SIZE} and compared, pixel by pixel and channel by"
    );
    println!(
        "channel (R, G, B, alpha), with the independent reference ray caster (`crates/vorang/src/reference.rs`: f64, every ray"
    );
    println!(
        "against every cell, adaptive Gauss–Legendre quadrature of the optical model to 1e-13). Images are f32, so"
    );
    println!(
        "errors around 6e-8 are rounding. Times are the median of 3 renders on {threads} threads, without grid lines.\n"
    );
    println!("Reproduce: `cargo run --release --example accuracy > docs/accuracy.md`\n");
    println!("Reading the tables:\n");
    println!(
        "- `exact linear 0` cuts every cell's ray interval where the maps change slope and integrates each piece in"
    );
    println!(
        "  closed form: its error is f32 rounding on every scene, also with emission ∝ absorption (quadratic η)"
    );
    println!("  and with maps switching by category along the ray.");
    println!(
        "- `exact` with the thesis's rules converges as the step shrinks (second order for constEA and trapez);"
    );
    println!(
        "  weightedConstEA converges to a biased image (it over-weights the near end by design)."
    );
    println!(
        "- `interpolateCoeff` maps only at the nodes, so it is exact only where the maps are linear across a cell"
    );
    println!(
        "  (the colour cuboid, with the `linear` rule); elsewhere it blurs the transfer functions' features."
    );
    println!(
        "- `interpolateColor` composites η itself (thesis 2.1.1.2): with emission far above 1, as when emission is"
    );
    println!(
        "  weighted by a large absorption, it is far off; its Gouraud transparency is always too transparent.\n"
    );
    println!("Scenes (`crates/vorang/src/accuracy.rs`):\n");
    let all = scenes();
    for s in &all {
        println!(
            "- **{}** ({} cells): {}",
            s.name,
            s.volume.mesh.tet_count(),
            s.what
        );
    }
    println!();
    for scene in &all {
        for (view_name, view) in views(scene) {
            println!("## {} — {view_name}\n", scene.name);
            println!("| method | max error | RMS error | time |");
            println!("|---|---:|---:|---:|");
            let reference = reference::render(
                &scene.volume,
                &scene.mapping,
                &view,
                &Options::new(SIZE, SIZE),
            );
            for m in METHODS {
                let words: Vec<&str> = m.split_whitespace().collect();
                let settings = Settings {
                    width: SIZE,
                    height: SIZE,
                    method: Method::parse(&words).expect("valid method"),
                    lines: LineDraw::Off,
                    ..Settings::default()
                };
                let mut times = Vec::new();
                let mut fb = None;
                for _ in 0..3 {
                    let t = Instant::now();
                    fb = Some(
                        render(&scene.volume, &scene.mapping, &view, &settings, None)
                            .expect("render")
                            .0,
                    );
                    times.push(t.elapsed().as_secs_f64());
                }
                times.sort_by(f64::total_cmp);
                let fb = fb.expect("rendered");
                let d: Vec<f64> = fb
                    .pixels
                    .iter()
                    .zip(&reference)
                    .flat_map(|(p, q)| (0..4).map(move |c| (f64::from(p[c]) - q[c]).abs()))
                    .collect();
                let max = d.iter().copied().fold(0.0, f64::max);
                let rms = (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt();
                let name = m.rsplit_once(' ').map_or(*m, |(n, _)| n);
                println!(
                    "| `{name}` | {max:.1e} | {rms:.1e} | {:.1} ms |",
                    times[1] * 1e3
                );
            }
            println!();
        }
    }
    degenerate();
}

fn frame(vol: &Volume, m: &Mapping, view: &View, size: usize, method: &str) -> Framebuffer {
    let words: Vec<&str> = method.split_whitespace().collect();
    let settings = Settings {
        width: size,
        height: size,
        method: Method::parse(&words).expect("valid method"),
        lines: LineDraw::Off,
        ..Settings::default()
    };
    render(vol, m, view, &settings, None).expect("render").0
}

/// Largest channel difference, `b` read through `at(x, y)`.
fn largest(a: &Framebuffer, at: impl Fn(usize, usize) -> [f64; 4]) -> f64 {
    let mut d: f64 = 0.0;
    for y in 0..a.height {
        for x in 0..a.width {
            let p = a.pixels[y * a.width + x];
            let q = at(x, y);
            for c in 0..4 {
                d = d.max((f64::from(p[c]) - q[c]).abs());
            }
        }
    }
    d
}

fn smooth(p: &[f64; 3]) -> f64 {
    (1.7 * p[0] + 0.3).sin() + (1.1 * p[1]).cos() * p[2] + 0.4 * p[2]
}

fn rotate(axis: [f64; 3], degrees: f64) -> TransformOp {
    TransformOp::Rotate { axis, degrees }
}

/// The degenerate-view section (same scenes as `tests/watertight.rs`).
fn degenerate() {
    println!("## Degenerate views, non-convex meshes, mirrors\n");
    for line in [
        "How the renderer stays exact where rays run within rounding of face planes, where rays leave",
        "and re-enter the mesh, and under mirroring transforms (`crates/vorang/src/render/faces.rs`, `runs.rs`):",
        "",
        "- A pixel's interval in a cell comes from the cell's entry and exit faces, chosen by exact",
        "  orientation predicates with the top-left rule. A face's crossing depth is computed once from",
        "  the face alone (its nodes in node-number order), so one cell's exit is the next one's entry",
        "  bit for bit and the intervals along a ray telescope; faces within rounding of edge-on get",
        "  their weights in double-double arithmetic.",
        "- Node positions on screen lie on a 2⁻²⁸ px grid: a view that is degenerate up to rounding (an",
        "  axis view after `vol_rotate 0 1 0 90`, an animation turned a full circle) is then exactly the",
        "  degenerate view, for every method, including the step rules, `interpolateColor` and `test`,",
        "  whose results depend on where cell boundaries fall along a ray.",
        "- A transform with negative determinant turns every orientation test; the sort and the face",
        "  classification account for it once per frame.",
        "- MPVO's order is exact for a convex mesh without cycles. Otherwise (several bodies, cavities,",
        "  anisotropic cells, visibility cycles) each pixel keeps runs of face-adjacent cells, joined",
        "  through the faces its ray crosses, and composites them sorted by depth: exact per pixel",
        "  for any mesh, whatever order the cells arrive in.",
        "",
        "Before this (build b07dc88, measured with the same scenes through the `vorang` program): the",
        "two-cube farbraum mesh at 32×16 after 12 × `vol_rotate 0 1 0 30` differed from the unturned",
        "image by up to 0.20 (`exact linear 0`), 0.12 (`exact constEA 0.05`, `interpolateCoeff`) and 0.44",
        "(`interpolateColor`) on 32 pixels; `vol_scale -1 1 1` on a 3 000-cell jittered box differed from",
        "the flipped image by up to 0.31 on 1 469 of 1 600 pixels. Now both are 0. More cases, each",
        "against an independent answer, are in `tests/watertight.rs`. Measured now (largest channel",
        "difference, 18² to 24² pixels):",
        "",
    ] {
        println!("{line}");
    }
    println!("| scene | compared with | method | max difference |");
    println!("|---|---|---|---:|");
    let size = 18;
    let (nodes, tets) = kuhn_box([4, 4, 4], [1.0; 3], 0.0, 1);
    let values: Vec<f64> = nodes.iter().map(smooth).collect();
    let vol = scalar_volume(nodes.clone(), tets.clone(), values.clone());
    let m = scalar_maps(&vol);
    let turned = |ops: Vec<TransformOp>| View {
        transforms: ops,
        ..View::default()
    };
    // The mesh turned by 180° about x exactly (coordinates), against the rotation matrix.
    let flipped: Vec<[f64; 3]> = nodes
        .iter()
        .map(|p| [p[0], 1.0 - p[1], 1.0 - p[2]])
        .collect();
    let exact = scalar_volume(flipped, tets.clone(), values);
    for method in [
        "exact linear 0 1",
        "interpolateCoeff linear 1",
        "exact constEA 0.07 1",
        "interpolateColor 1",
        "test 0.3",
    ] {
        let name = method.rsplit_once(' ').map_or(method, |(n, _)| n);
        let plain = frame(&vol, &m, &View::default(), size, method);
        let circle = frame(
            &vol,
            &m,
            &turned(vec![rotate([0.0, 1.0, 0.0], 30.0); 12]),
            size,
            method,
        );
        let d = largest(&circle, |x, y| plain.pixels[y * size + x].map(f64::from));
        println!("| Kuhn box 4³, 12 × 30° about y | unturned image | `{name}` | {d:.1e} |");
        let half = frame(
            &vol,
            &m,
            &turned(vec![rotate([1.0, 0.0, 0.0], 180.0)]),
            size,
            method,
        );
        let want = frame(&exact, &m, &View::default(), size, method);
        let d = largest(&half, |x, y| want.pixels[y * size + x].map(f64::from));
        println!("| Kuhn box 4³, 180° about x | mesh turned exactly | `{name}` | {d:.1e} |");
        if method.starts_with("exact linear") || method.starts_with("interpolateCoeff") {
            // Off the degenerate view by far more than rounding: slivers, not edge-on faces.
            let off = frame(
                &vol,
                &m,
                &turned(vec![rotate([0.0, 1.0, 0.0], 1e-5)]),
                size,
                method,
            );
            let d = largest(&off, |x, y| plain.pixels[y * size + x].map(f64::from));
            println!("| Kuhn box 4³, 10⁻⁵° about y | unturned image | `{name}` | {d:.1e} |");
        }
    }
    // Holes: a jittered box with 3 % of its cells removed, against the reference.
    let (nodes, mut tets) = kuhn_box([4, 4, 4], [1.0; 3], 0.12, 5);
    let mut rng = SplitMix64(17);
    tets.retain(|_| rng.next_f64() > 0.03);
    let values = nodes.iter().map(smooth).collect();
    let holes = scalar_volume(nodes, tets, values);
    let m = scalar_maps(&holes);
    let view = turned(vec![rotate([0.3, 1.0, 0.1], 37.0)]);
    let fb = frame(&holes, &m, &view, 24, "exact linear 0 1");
    let r = reference::render(&holes, &m, &view, &Options::new(24, 24));
    let d = largest(&fb, |x, y| r[y * 24 + x]);
    println!("| jittered box 4³, 3 % of cells removed | reference | `exact linear 0` | {d:.1e} |");
    // A mirror: vol_scale −1 1 1 against the unmirrored image flipped.
    let (nodes, tets) = kuhn_box([3, 3, 3], [1.0; 3], 0.12, 4);
    let values = nodes.iter().map(smooth).collect();
    let vol = scalar_volume(nodes, tets, values);
    let m = scalar_maps(&vol);
    for method in ["exact linear 0 1", "interpolateColor 1"] {
        let name = method.rsplit_once(' ').map_or(method, |(n, _)| n);
        let plain = frame(&vol, &m, &View::default(), 20, method);
        let mirror = frame(
            &vol,
            &m,
            &turned(vec![TransformOp::Scale([-1.0, 1.0, 1.0])]),
            20,
            method,
        );
        let d = largest(&mirror, |x, y| plain.pixels[y * 20 + 19 - x].map(f64::from));
        println!(
            "| jittered box 3³, `vol_scale -1 1 1` | unmirrored, flipped | `{name}` | {d:.1e} |"
        );
    }
    println!();
}
