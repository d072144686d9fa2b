//! `exact linear 0` is exact: it matches the reference ray caster to 1e-6 (f32 output) on every
//! scene of the accuracy report, in orthographic and perspective views.

use vorang::accuracy::{scenes, views};
use vorang::reference::{self, Options};
use vorang::render::{LineDraw, Method, Settings, render};

#[test]
fn exact_linear_matches_the_reference_on_every_report_scene() {
    let size = 24;
    for scene in scenes() {
        for (view_name, view) in views(&scene) {
            let reference = reference::render(
                &scene.volume,
                &scene.mapping,
                &view,
                &Options::new(size, size),
            );
            let settings = Settings {
                width: size,
                height: size,
                method: Method::parse(&["exact", "linear", "0", "1"]).unwrap(),
                lines: LineDraw::Off,
                ..Settings::default()
            };
            let (fb, _) = render(&scene.volume, &scene.mapping, &view, &settings, None).unwrap();
            let err = fb
                .pixels
                .iter()
                .zip(&reference)
                .flat_map(|(p, q)| (0..4).map(move |c| (f64::from(p[c]) - q[c]).abs()))
                .fold(0.0, f64::max);
            let covered = reference.iter().filter(|p| p[3] > 1e-3).count();
            eprintln!(
                "{} {view_name}: max error {err:.2e} ({covered} pixels covered)",
                scene.name
            );
            assert!(
                covered > size * size / 8,
                "{} {view_name}: the volume is barely in view",
                scene.name
            );
            assert!(err <= 1e-6, "{} {view_name}: max error {err:e}", scene.name);
        }
    }
}
