//! Distributed rendering without MPI (docs/distributed.md): a volume cut into pieces, each
//! rendered by its own virtual rank (a thread) through the distributed frame — runs, the
//! all-to-all, the owners' compositing, the gather — gives the image of the whole volume
//! rendered in one process: to the bit almost everywhere, and nowhere more than one `f32` ulp
//! per channel (a run of one process that crosses a piece boundary is two runs there, composed
//! in another order of the same products). Partitions: contiguous, scattered cell by cell, one
//! empty piece, more ranks than pieces; views: default, rotated, mirrored, axis-aligned,
//! perspective from outside and from inside the volume. (`test`, which draws each face once per
//! ray by remembering the previous cell of the pixel, draws a face between two ranks' cells
//! once per rank: docs/distributed.md.)

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use vorang::Volume;
use vorang::distributed::frame::{render_virtual, split};
use vorang::distributed::partition::NodeKey;
use vorang::framebuffer::Framebuffer;
use vorang::mapping::{AlphaMap, AlphaShading, ColorMap, ColorShading, Mapping, parse_map};
use vorang::render::{LineDraw, Method, Order, Settings, render};
use vorang::scene::{Camera, LookAt, TransformOp, View};

fn maps() -> (ColorMap, AlphaMap) {
    let c = "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 1 0.2\n1 1 0 0.5\n1 0 0 0.8\n";
    let a = "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.5 0.2\n4 0.5\n1 0.8\n";
    (
        parse_map::<dyn ColorShading>(c.as_bytes(), "c.map")
            .unwrap()
            .0,
        parse_map::<dyn AlphaShading>(a.as_bytes(), "a.map")
            .unwrap()
            .0,
    )
}

fn settings(method: &str, lines: LineDraw, order: Order) -> Settings {
    let words: Vec<&str> = method.split_whitespace().collect();
    Settings {
        width: 70,
        height: 54,
        method: Method::parse(&words).unwrap(),
        lines,
        order,
        ..Settings::default()
    }
}

/// How far two images are apart: channels that differ, and the most `f32` ulps one differs by.
fn ulps(a: &Framebuffer, b: &Framebuffer) -> (usize, u32) {
    let mut differ = 0;
    let mut most = 0;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for k in 0..4 {
            if p[k].to_bits() != q[k].to_bits() {
                differ += 1;
                let d = if p[k].is_sign_negative() == q[k].is_sign_negative() {
                    p[k].to_bits().abs_diff(q[k].to_bits())
                } else {
                    u32::MAX
                };
                most = most.max(d);
            }
        }
    }
    (differ, most)
}

fn views() -> Vec<(&'static str, View)> {
    let rotated = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 0.6, 0.2],
            degrees: 33.0,
        }],
        ..View::default()
    };
    let mirrored = View {
        transforms: vec![
            TransformOp::Scale([-1.0, 1.0, 1.0]),
            TransformOp::Rotate {
                axis: [0.3, 1.0, 0.1],
                degrees: 21.0,
            },
        ],
        ..View::default()
    };
    let axis_aligned = View {
        transforms: vec![TransformOp::Rotate {
            axis: [0.0, 1.0, 0.0],
            degrees: 90.0,
        }],
        ..View::default()
    };
    let perspective = View {
        camera: Some(Camera::Persp {
            fovy: 40.0,
            aspect: 70.0 / 54.0,
            near: 0.1,
            far: 10.0,
        }),
        look_at: LookAt {
            eye: [1.2, 0.9, 1.9],
            reference: [0.0; 3],
            up: [0.0, 1.0, 0.0],
        },
        ..rotated.clone()
    };
    let inside = View {
        camera: Some(Camera::Persp {
            fovy: 70.0,
            aspect: 70.0 / 54.0,
            near: 0.01,
            far: 10.0,
        }),
        look_at: LookAt {
            eye: [0.05, -0.1, 0.12],
            reference: [0.4, 0.2, -1.0],
            up: [0.0, 1.0, 0.0],
        },
        ..View::default()
    };
    vec![
        ("default", View::default()),
        ("rotated", rotated),
        ("mirrored", mirrored),
        ("axis-aligned", axis_aligned),
        ("perspective", perspective),
        ("eye inside", inside),
    ]
}

/// Partitions of `n` cells into pieces, with the number of ranks to render them on.
fn partitions(n: u32) -> Vec<(&'static str, Vec<Vec<u32>>, usize)> {
    let contiguous = |k: u32| -> Vec<Vec<u32>> {
        (0..k)
            .map(|p| (p * n / k..(p + 1) * n / k).collect())
            .collect()
    };
    let scattered: Vec<Vec<u32>> = (0..3)
        .map(|p| (0..n).filter(|c| c % 3 == p).collect())
        .collect();
    let mut with_empty = contiguous(3);
    with_empty.insert(1, Vec::new());
    vec![
        ("one piece", contiguous(1), 1),
        ("contiguous", contiguous(4), 4),
        ("contiguous, 2 per rank", contiguous(4), 2),
        ("scattered", scattered, 3),
        ("one empty piece", with_empty, 4),
        ("more ranks than pieces", contiguous(2), 3),
        ("one piece on 4 ranks", contiguous(1), 4),
    ]
}

/// Renders `vol` whole and by virtual ranks for every partition, and checks they agree.
fn check(vol: &Volume, views: &[(&str, View)], settings: &Settings, key: &NodeKey) -> usize {
    let (c, a) = maps();
    let mapping = Mapping::new(&c, &a, vol).unwrap().0;
    let cancel = AtomicBool::new(false);
    let mut differing = 0;
    for (name, view) in views {
        let (whole, _) = render(vol, &mapping, view, settings, None).unwrap();
        assert!(whole.max_channel() > 0.01, "{name}: nothing to see");
        for (pname, pieces, ranks) in partitions(vol.mesh.tet_count() as u32) {
            let parts: Vec<Arc<Volume>> = split(vol, &pieces, ranks, key).unwrap();
            let (fb, stats) = render_virtual(&parts, (&c, &a), view, settings, &cancel).unwrap();
            assert_eq!(stats.cells, vol.mesh.tet_count(), "{pname}");
            let (differ, most) = ulps(&whole, &fb);
            assert!(
                most <= 1,
                "{name}, {pname} on {ranks} ranks, {:?}: {differ} channels differ, by up to {most} ulps",
                settings.method
            );
            differing += differ;
        }
    }
    differing
}

#[test]
fn virtual_ranks_give_the_single_render_convex() {
    let vol = vorang::volume::jittered_box(1500, 0.1, 7);
    for (method, lines) in [
        ("exact linear 0 1", LineDraw::Off),
        ("interpolateCoeff linear 1", LineDraw::All),
        ("interpolateColor 1", LineDraw::Off),
    ] {
        let s = settings(method, lines, Order::BackToFront);
        let n = check(&vol, &views(), &s, &NodeKey::Numbers);
        eprintln!("{method}: {n} channels differ by one ulp");
    }
}

#[test]
fn virtual_ranks_give_the_single_render_non_convex() {
    let vol = vorang::volume::jittered_box_with_holes(1500, 0.1, 11, 0.25);
    for order in [Order::BackToFront, Order::FrontToBack] {
        let s = settings("exact linear 0 1", LineDraw::All, order);
        let n = check(&vol, &views(), &s, &NodeKey::Numbers);
        eprintln!("{order:?}: {n} channels differ by one ulp");
    }
}

#[test]
fn nodes_numbered_by_coordinates_give_the_same_image() {
    let vol = vorang::volume::jittered_box_with_holes(1200, 0.1, 5, 0.2);
    let s = settings("exact linear 0 1", LineDraw::Off, Order::BackToFront);
    let n = check(&vol, &views()[..3], &s, &NodeKey::Coordinates);
    eprintln!("coordinates: {n} channels differ by one ulp");
}

/// A session rendering `path` with virtual ranks (`Some(n)`) or in one process.
fn session_image(path: &std::path::Path, ranks: Option<usize>, view: &View) -> Framebuffer {
    use vorang::session::{Hooks, Ranks, Session};
    let mut s = Session::new();
    if let Some(n) = ranks {
        s.set_ranks(Ranks::Virtual(n));
    }
    s.load_volume(path).unwrap();
    let (c, a) = maps();
    s.set_colormap(c).unwrap();
    s.set_alphamap(a).unwrap();
    s.set_method(Method::parse(&["exact", "linear", "0", "1"]).unwrap());
    s.set_image_size(64, 48).unwrap();
    s.set_view(view.clone());
    let cancel = AtomicBool::new(false);
    let hooks = Hooks {
        progress: None,
        tile: None,
        cancel: &cancel,
    };
    s.render_image(Order::BackToFront, &hooks)
        .unwrap()
        .framebuffer
}

/// A `.pvtu` read by virtual ranks — each rank reading its own pieces, or its Morton part of
/// one — gives the image of the `.pvtu` read whole: contiguous and scattered pieces, an empty
/// piece, more ranks than pieces.
#[test]
fn pvtu_pieces_read_by_ranks_give_the_whole_image() {
    use vorang::distributed::write::write_pvtu;
    let vol = vorang::volume::jittered_box_with_holes(1200, 0.1, 5, 0.15);
    let dir = tempfile::tempdir().unwrap();
    let n = vol.mesh.tet_count() as u32;
    let cases: Vec<(&str, Vec<Vec<u32>>)> = vec![
        (
            "contiguous",
            (0..3)
                .map(|p| (p * n / 3..(p + 1) * n / 3).collect())
                .collect(),
        ),
        (
            "scattered",
            (0..2)
                .map(|p| (0..n).filter(|c| c % 2 == p).collect())
                .collect(),
        ),
        (
            "empty",
            vec![(0..n / 2).collect(), Vec::new(), (n / 2..n).collect()],
        ),
    ];
    let views = views();
    for (name, pieces) in cases {
        let path = dir.path().join(format!("{name}.pvtu"));
        write_pvtu(&vol, &path, &pieces).unwrap();
        for (vname, view) in &views[..4] {
            let whole = session_image(&path, None, view);
            assert!(whole.max_channel() > 0.01);
            for ranks in 1..=4 {
                let fb = session_image(&path, Some(ranks), view);
                let (differ, most) = ulps(&whole, &fb);
                assert!(
                    most <= 1,
                    "{name}, {vname}, {ranks} ranks: {differ} channels differ by up to {most} ulps"
                );
            }
        }
    }
}

/// A `.pvtu` with ghost cells (written by VTK): the ranks drop them as one process does.
#[test]
fn pvtu_with_ghost_cells_read_by_ranks() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/series/flow_p_0.pvtu");
    let view = &views()[1].1;
    let whole = session_image(&path, None, view);
    assert!(whole.max_channel() > 0.01, "{}", whole.max_channel());
    for ranks in 1..=4 {
        let fb = session_image(&path, Some(ranks), view);
        let (differ, most) = ulps(&whole, &fb);
        assert!(
            most <= 1,
            "{ranks} ranks: {differ} channels differ by up to {most} ulps"
        );
    }
}

/// A missing or truncated piece stops the volume on every virtual rank with the reading rank's
/// message (the ranks that read other pieces wait for nobody).
#[test]
fn a_missing_or_truncated_piece_is_every_ranks_error() {
    use vorang::distributed::write::write_pvtu;
    use vorang::session::{Ranks, Session};
    let vol = vorang::volume::jittered_box(600, 0.1, 2);
    let dir = tempfile::tempdir().unwrap();
    let n = vol.mesh.tet_count() as u32;
    let pieces: Vec<Vec<u32>> = (0..3)
        .map(|p| (p * n / 3..(p + 1) * n / 3).collect())
        .collect();
    let path = dir.path().join("g.pvtu");
    write_pvtu(&vol, &path, &pieces).unwrap();
    let piece = dir.path().join("g/g_2.vtu");
    let bytes = std::fs::read(&piece).unwrap();
    std::fs::write(&piece, &bytes[..bytes.len() / 3]).unwrap();
    for ranks in [1, 2, 3, 4] {
        let mut s = Session::new();
        s.set_ranks(Ranks::Virtual(ranks));
        let e = s.load_volume(&path).unwrap_err();
        assert!(e.contains("g_2.vtu"), "{ranks} ranks: {e}");
        assert!(s.volume().is_none());
    }
    std::fs::remove_file(&piece).unwrap();
    let mut s = Session::new();
    s.set_ranks(Ranks::Virtual(3));
    let e = s.load_volume(&path).unwrap_err();
    assert!(e.contains("g_2.vtu: no such file"), "{e}");
}
