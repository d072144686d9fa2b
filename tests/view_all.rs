//! `view_all`: the whole transformed volume fits the image with the
//! margin, touching it, for orthographic and perspective cameras, keeping the viewing direction.

use vorang::Volume;
use vorang::scene::{Camera, FIT_MARGIN, LookAt, Projector, TransformOp, View};

/// The screen extent (in pixels) of all nodes after the view.
fn screen_box(vol: &Volume, view: &View, w: usize, h: usize) -> [f64; 4] {
    let bbox = vol.mesh.bbox();
    let to_eye = view
        .view_matrix()
        .after(&view.model(bbox.center()).unwrap());
    let p = Projector::new(view.camera.as_ref(), bbox.size(), w, h).unwrap();
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for &n in vol.mesh.nodes() {
        let e = to_eye.apply(n);
        assert!(-e[2] > 0.0 || matches!(view.camera, Some(Camera::Ortho { .. })));
        let s = p.screen(e);
        b = [
            b[0].min(s[0]),
            b[1].min(s[1]),
            b[2].max(s[0]),
            b[3].max(s[1]),
        ];
    }
    b
}

fn check_fit(b: [f64; 4], w: usize, h: usize) {
    let (mx, my) = (FIT_MARGIN * w as f64, FIT_MARGIN * h as f64);
    let tol = 1e-6 * w.max(h) as f64;
    // Inside the margin everywhere…
    assert!(b[0] >= mx - tol && b[2] <= w as f64 - mx + tol, "{b:?}");
    assert!(b[1] >= my - tol && b[3] <= h as f64 - my + tol, "{b:?}");
    // …and touching it on some side.
    let gaps = [
        b[0] - mx,
        b[1] - my,
        w as f64 - mx - b[2],
        h as f64 - my - b[3],
    ];
    let least = gaps.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(least.abs() <= 1e-3 * w.max(h) as f64, "{b:?} gaps {gaps:?}");
}

#[test]
fn the_volume_fits_with_the_margin() {
    let (vol, _) = Volume::load(std::path::Path::new("examples/farbraum/farbraum.hmesh")).unwrap();
    let turned = vec![
        TransformOp::Rotate {
            axis: [1.0, 1.0, 0.0],
            degrees: 50.0,
        },
        TransformOp::Scale([2.0, 1.0, 3.0]),
        TransformOp::Translate([5.0, -2.0, 1.0]),
    ];
    for (w, h) in [(300, 200), (160, 400)] {
        for camera in [
            None,
            Some(Camera::Ortho {
                left: -1.0,
                right: 1.0,
                bottom: -1.0,
                top: 1.0,
                front: -1.0,
                back: 1.0,
            }),
            Some(Camera::Persp {
                fovy: 40.0,
                aspect: w as f64 / h as f64,
                near: 1.0,
                far: 2.0,
            }),
        ] {
            let mut view = View {
                transforms: turned.clone(),
                camera,
                look_at: LookAt {
                    eye: [0.3, 0.2, 4.0],
                    reference: [0.0, 0.0, 0.0],
                    up: [0.0, 1.0, 0.0],
                },
            };
            let before = view.view_matrix();
            view.fit(vol.mesh.nodes(), vol.mesh.bbox().center(), w, h)
                .unwrap();
            // The kind stays, the viewing direction too.
            assert_eq!(
                matches!(view.camera, Some(Camera::Persp { .. })),
                matches!(camera, Some(Camera::Persp { .. }))
            );
            let after = view.view_matrix();
            for i in 0..3 {
                for k in 0..3 {
                    assert!((before.0[i][k] - after.0[i][k]).abs() < 1e-12);
                }
            }
            check_fit(screen_box(&vol, &view, w, h), w, h);
        }
    }
}
