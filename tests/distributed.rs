//! Distributed rendering without MPI (docs/distributed.md): a volume cut into pieces, each
//! rendered by its own virtual rank (a thread) through the distributed frame — runs, the
//! all-to-all, the owners' compositing, the gather — gives the image of the whole volume
//! rendered in one process: to the bit almost everywhere, and nowhere more than one `f32` ulp
//! per channel (a run of one process that crosses a piece boundary is two runs there, composed
//! in another order of the same products). Partitions: contiguous, scattered cell by cell, one
//! empty piece, more ranks than pieces; views: default, rotated, mirrored, axis-aligned,
//! perspective from outside and from inside the volume. Also: VTK's own pieces (ghost layers,
//! `GlobalNodeIds`) on 1 … 5 ranks, `view_all` and time steps on ranks, the method `test`
//! (each face drawn once per ray, also between ranks) and `render_ftb` where pixels turn
//! opaque (docs/distributed.md).

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

/// A file of tests/data (VTK's pieces: tests/data/mpi/generate.py).
fn data(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(path)
}

/// A session of `ranks` virtual ranks (`None`: one process) with `path` loaded, the test
/// maps and `exact`.
fn session(path: &std::path::Path, ranks: Option<usize>) -> vorang::session::Session {
    use vorang::session::{Ranks, Session};
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
    s
}

fn image(s: &mut vorang::session::Session, order: Order) -> Result<Framebuffer, String> {
    use vorang::session::Hooks;
    let cancel = AtomicBool::new(false);
    let hooks = Hooks {
        progress: None,
        tile: None,
        cancel: &cancel,
    };
    s.render_image(order, &hooks).map(|i| i.framebuffer)
}

/// Pieces written by VTK's vtkXMLPUnstructuredGridWriter — ghost layers, `GlobalNodeIds` —
/// read by 1 … 5 virtual ranks (contiguous ranges of pieces, and more ranks than pieces) give
/// the image of the whole grid as VTK wrote it in one file, rendered by one process.
#[test]
fn vtk_pieces_on_one_to_five_ranks_give_the_whole_grids_image() {
    let views = views();
    for (vname, view) in [&views[0], &views[2], &views[5]] {
        let whole = session_image(&data("mpi/box.vtu"), None, view);
        assert!(whole.max_channel() > 0.01, "{vname}");
        for file in ["mpi/box_g3.pvtu", "mpi/box_p5.pvtu"] {
            for ranks in 1..=5 {
                let fb = session_image(&data(file), Some(ranks), view);
                let (differ, most) = ulps(&whole, &fb);
                assert!(
                    most <= 1,
                    "{file}, {vname}, {ranks} ranks: {differ} channels differ by up to {most} ulps"
                );
            }
        }
    }
}

/// A rank's piece of VTK's pieces numbers its nodes by their `GlobalNodeIds` (the key every
/// rank shares, so that a face between two ranks gives both the same depths): ascending ids.
#[test]
fn a_ranks_nodes_follow_global_node_ids() {
    use vorang::distributed::load::load_share;
    for (file, ranks) in [
        ("mpi/box_g3.pvtu", 2),
        ("mpi/box_g3.pvtu", 5),
        ("mpi/box_p5.pvtu", 3),
    ] {
        let mut cells = 0;
        for r in 0..ranks {
            let (vol, _) = load_share(&data(file), r, ranks).unwrap();
            assert!(
                matches!(NodeKey::of(&vol, false), NodeKey::Ids(_)),
                "{file}"
            );
            let f = vol
                .data
                .fields
                .iter()
                .find(|f| f.name.as_deref() == Some("GlobalNodeIds"))
                .expect("GlobalNodeIds is a field");
            let raw = &vol.data.raw[f.sources[0]];
            let ids: Vec<f64> = (0..raw.elements()).map(|n| raw.value(n, 0)).collect();
            assert_eq!(ids.len(), vol.mesh.node_count());
            assert!(
                ids.windows(2).all(|w| w[0] < w[1]),
                "{file}, rank {r} of {ranks}: nodes not in id order"
            );
            cells += vol.mesh.tet_count();
        }
        // Ghost cells dropped: every cell on exactly one rank.
        assert_eq!(cells, 1296, "{file} on {ranks} ranks");
    }
}

/// `view_all` on ranks frames the whole volume from every rank's nodes: the camera of one
/// process, to the bit (orthographic and perspective).
#[test]
fn view_all_on_ranks_is_one_process_camera() {
    use vorang::scene::{Camera, TransformOp};
    for file in ["mpi/box_g3.pvtu", "mpi/box_p5.pvtu"] {
        for persp in [false, true] {
            let camera = |s: &mut vorang::session::Session| {
                s.set_view(View {
                    transforms: vec![TransformOp::Rotate {
                        axis: [1.0, 0.6, 0.2],
                        degrees: 33.0,
                    }],
                    ..View::default()
                });
                if persp {
                    s.set_camera(Camera::Persp {
                        fovy: 40.0,
                        aspect: 4.0 / 3.0,
                        near: 0.1,
                        far: 10.0,
                    })
                    .unwrap();
                }
                s.view_all().unwrap();
                s.view().clone()
            };
            let one = camera(&mut session(&data(file), None));
            for ranks in [2, 3, 5] {
                let got = camera(&mut session(&data(file), Some(ranks)));
                assert_eq!(
                    format!("{got:?}"),
                    format!("{one:?}"),
                    "{file}, {ranks} ranks"
                );
            }
        }
    }
}

/// A `.pvd` whose steps are `.pvtu` grids: ranks read their share of each step; `timestep`
/// keeps the scene and gives one process's image of that step.
#[test]
fn time_steps_of_pvtu_grids_on_ranks() {
    let path = data("series/flow_p.pvd");
    let mut one = session(&path, None);
    one.set_timestep(2).unwrap();
    let whole = image(&mut one, Order::BackToFront).unwrap();
    assert!(whole.max_channel() > 0.01);
    for ranks in [1, 2, 3] {
        let mut s = session(&path, Some(ranks));
        assert_eq!(s.timesteps(), vec![0.0, 0.5, 1.25]);
        s.set_timestep(2).unwrap();
        assert_eq!(s.timestep(), Some((2, 1.25)));
        let fb = image(&mut s, Order::BackToFront).unwrap();
        let (differ, most) = ulps(&whole, &fb);
        assert!(
            most <= 1,
            "{ranks} ranks: {differ} channels by up to {most} ulps"
        );
        let e = s.set_timestep(3).unwrap_err();
        assert!(e.contains("out of range"), "{e}");
    }
}

/// The method `test` on ranks: each face drawn once per ray, also the faces between two
/// ranks' cells, which both ranks drew (the owner removes one: docs/distributed.md). Every
/// partition and view, convex and non-convex, both orders, opaque and half-transparent faces.
#[test]
fn virtual_ranks_give_the_single_render_with_test() {
    let convex = vorang::volume::jittered_box(900, 0.1, 3);
    let holes = vorang::volume::jittered_box_with_holes(900, 0.1, 13, 0.25);
    // Transparencies stay above front-to-back's early termination, except with opaque faces
    // (where stopping changes nothing).
    for (vol, opacity) in [(&convex, "0.3"), (&holes, "0.2"), (&convex, "1")] {
        for order in [Order::BackToFront, Order::FrontToBack] {
            let s = settings(&format!("test {opacity}"), LineDraw::Off, order);
            let n = check(vol, &views(), &s, &NodeKey::Numbers);
            eprintln!("test {opacity}, {order:?}: {n} channels differ by one ulp");
        }
    }
}

/// `test`, the default method, on VTK's pieces read by 1 … 5 ranks of a session (a regular
/// grid: rays along faces and through edges).
#[test]
fn test_method_on_vtk_pieces() {
    let test = Method::parse(&["test", "0.3"]).unwrap();
    for file in ["mpi/box_g3.pvtu", "mpi/box_p5.pvtu"] {
        let path = data(file);
        let mut one = session(&path, None);
        one.set_method(test);
        for order in [Order::BackToFront, Order::FrontToBack] {
            let whole = image(&mut one, order).unwrap();
            assert!(whole.max_channel() > 0.01);
            for ranks in 1..=5 {
                let mut s = session(&path, Some(ranks));
                s.set_method(test);
                let fb = image(&mut s, order).unwrap();
                let (differ, most) = ulps(&whole, &fb);
                assert!(
                    most <= 1,
                    "{file}, {ranks} ranks, {order:?}: {differ} channels by up to {most} ulps"
                );
            }
        }
    }
}

/// `render_ftb` where pixels turn opaque: one process stops compositing a convex mesh there,
/// the ranks composite every cell — the image of `render_btf`, within the early termination's
/// threshold of one process's `render_ftb`, and a note says how many pixels.
#[test]
fn an_opaque_render_ftb_on_ranks_composites_every_cell() {
    use vorang::session::Hooks;
    let path = data("mpi/box_p5.pvtu");
    let a = "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n400 0\n400 5\n";
    let dense = parse_map::<dyn AlphaShading>(a.as_bytes(), "a.map")
        .unwrap()
        .0;
    let mut one = session(&path, None);
    one.set_alphamap(dense.clone()).unwrap();
    let btf = image(&mut one, Order::BackToFront).unwrap();
    let ftb = image(&mut one, Order::FrontToBack).unwrap();
    for ranks in [2, 3] {
        let mut s = session(&path, Some(ranks));
        s.set_alphamap(dense.clone()).unwrap();
        let cancel = AtomicBool::new(false);
        let hooks = Hooks {
            progress: None,
            tile: None,
            cancel: &cancel,
        };
        let img = s.render_image(Order::FrontToBack, &hooks).unwrap();
        assert!(img.stats.opaque_pixels > 100, "{}", img.stats.opaque_pixels);
        let note = img
            .notices
            .iter()
            .map(|n| format!("{n:?}"))
            .find(|n| n.contains("turned opaque"));
        assert!(note.is_some(), "{:?}", img.notices);
        let fb = img.framebuffer;
        let (differ, most) = ulps(&btf, &fb);
        assert!(
            most <= 1,
            "{ranks} ranks against render_btf: {differ} channels by up to {most} ulps"
        );
        let far = fb
            .pixels
            .iter()
            .zip(&ftb.pixels)
            .flat_map(|(p, q)| (0..4).map(move |k| (p[k] - q[k]).abs()))
            .fold(0.0f32, f32::max);
        assert!(
            far < 2e-6,
            "{ranks} ranks against one process's render_ftb: {far}"
        );
    }
    // Not opaque: render_ftb on ranks is one process's image, and no note.
    let mut s = session(&path, Some(3));
    let mut one = session(&path, None);
    let (a, b) = (
        image(&mut s, Order::FrontToBack).unwrap(),
        image(&mut one, Order::FrontToBack).unwrap(),
    );
    let (differ, most) = ulps(&a, &b);
    assert!(most <= 1, "{differ} channels by up to {most} ulps");
}

/// Pieces whose arrays differ stop the volume on every virtual rank count.
#[test]
fn pieces_with_other_arrays_are_every_ranks_error() {
    use vorang::session::{Ranks, Session};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir_all(d.join("box_p5")).unwrap();
    for k in 0..5 {
        let name = format!("box_p5/box_p5_{k}.vtu");
        let mut bytes = std::fs::read(data("mpi").join(&name)).unwrap();
        if k == 0 {
            let at = String::from_utf8_lossy(&bytes).find("Name=\"T\"").unwrap();
            bytes[at + 6] = b'U';
        }
        std::fs::write(d.join(&name), bytes).unwrap();
    }
    std::fs::copy(data("mpi/box_p5.pvtu"), d.join("box_p5.pvtu")).unwrap();
    for ranks in 1..=5 {
        let mut s = Session::new();
        s.set_ranks(Ranks::Virtual(ranks));
        let e = s.load_volume(&d.join("box_p5.pvtu")).unwrap_err();
        assert!(
            e.contains("the pieces' arrays disagree"),
            "{ranks} ranks: {e}"
        );
        assert!(s.volume().is_none());
    }
}

/// The legend of a CONSTANT colormap spans the field's data range over every rank's cells
/// (combined at `volume`), so rank 0 draws one process's legend although it holds one piece.
#[test]
fn the_legend_spans_the_whole_grids_data_range() {
    use vorang::legend::Place;
    use vorang::mapping::ColorMap;
    let path = data("mpi/box_p5.pvtu");
    let shot = |ranks: Option<usize>| {
        let mut s = session(&path, ranks);
        s.set_colormap(ColorMap::default_map()).unwrap();
        s.set_image_size(240, 160).unwrap();
        s.set_legend(Some(Place::Right));
        image(&mut s, Order::BackToFront).unwrap()
    };
    let whole = shot(None);
    for ranks in [2, 5] {
        let (differ, most) = ulps(&whole, &shot(Some(ranks)));
        assert!(
            most <= 1,
            "{ranks} ranks: {differ} channels by up to {most} ulps"
        );
    }
}
