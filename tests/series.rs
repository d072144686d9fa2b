//! Collections and time series (docs/formats.md, "Time series and collections"): every step of
//! every collection format — `.pvd`, `.series`, `.pvtu` (pieces with ghost cells), `.vtm`
//! (blocks, one skipped) — renders the image of the same step loaded as a single `.vtu`, bit
//! for bit; a step with the same points and cells shares the mesh, a changed one is loaded
//! anew; `vorang info` gives ranges over all steps; the label prints the time into images and
//! movie frames.
//!
//! The data files in `tests/data/series/` are made by `tests/data/series/generate.py`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use vorang::Volume;
use vorang::formats::collection::Series;
use vorang::formats::{Described, describe_file};
use vorang::framebuffer::read_pfm;
use vorang::session::Session;
use vorang_tcl::script::{Collect, Runner};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/series")
        .join(name)
}

/// The scene every image is rendered with: set once, after `volume`.
const SCENE: &str = "colormap preset viridis 1 2.9 0; alphamap ramp 1 2.9 0.8 0; method exact linear 0 1; linedraw off; vol_rotate 1 1 0 30";

/// Renders the given steps of `file` (after `volume FILE` and the scene, `timestep K; render`
/// each) and returns each image's PFM bytes.
fn render_steps(file: &Path, steps: &[usize], extra: &str) -> Vec<Vec<u8>> {
    let tmp = tempfile::tempdir().unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    let mut script = format!(
        "imagesize 48 40\noutput {{{}}}\nvolume {{{}}}\n{SCENE}\n{extra}\n",
        tmp.path().join("img.pfm").display(),
        file.display()
    );
    for k in steps {
        script.push_str(&format!("timestep {k}\nrender_btf\n"));
    }
    runner
        .run_string(&script, "test")
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let written = runner.session().written().to_vec();
    assert_eq!(written.len(), steps.len());
    written.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

fn single(k: usize) -> Vec<u8> {
    render_steps(&data(&format!("flow_{k}.vtu")), &[0], "").remove(0)
}

#[test]
fn every_step_of_every_collection_renders_the_single_file_bit_for_bit() {
    let reference: Vec<Vec<u8>> = (0..3).map(single).collect();
    assert_ne!(reference[0], reference[1], "the steps differ");
    let (_, _, rgb) = read_pfm(&reference[0]).unwrap();
    assert!(
        rgb.iter().flatten().any(|&v| v < 0.9),
        "the volume is visible"
    );
    for file in [
        "flow.pvd",
        "flow.vtu.series",
        "flow_p.pvd",
        "flow_m.vtm.series",
    ] {
        // Forwards, backwards and jumping: each step is its own image whatever came before.
        let order = [0, 1, 2, 0, 2, 1];
        let images = render_steps(&data(file), &order, "");
        for (img, &k) in images.iter().zip(&order) {
            assert!(
                img == &reference[k],
                "{file} step {k} differs from flow_{k}.vtu"
            );
        }
    }
    for file in ["flow_p_0.pvtu", "flow_m_0.vtm", "parts.pvd"] {
        let img = render_steps(&data(file), &[0], "").remove(0);
        assert!(img == reference[0], "{file} differs from flow_0.vtu");
    }
    let parts_1 = render_steps(&data("parts.pvd"), &[1], "").remove(0);
    assert!(parts_1 == reference[1]);
}

#[test]
fn a_two_piece_pvtu_without_ghosts_is_the_single_vtu() {
    let tmp = tempfile::tempdir().unwrap();
    let pvtu = tmp.path().join("two.pvtu");
    let piece = |name: &str| data(&format!("flow_m_0/{name}")).display().to_string();
    std::fs::write(
        &pvtu,
        format!(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\">\n<PUnstructuredGrid GhostLevel=\"0\">\n<Piece Source=\"{}\"/>\n<Piece Source=\"{}\"/>\n</PUnstructuredGrid>\n</VTKFile>\n",
            piece("flow_m_0_0.vtu"),
            piece("flow_m_0_1.vtu")
        ),
    )
    .unwrap();
    let (vol, warnings) = Volume::load(&pvtu).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let (whole, _) = Volume::load(&data("flow_0.vtu")).unwrap();
    assert_eq!(vol.mesh.node_count(), whole.mesh.node_count());
    assert_eq!(vol.mesh.tet_count(), whole.mesh.tet_count());
    // The faces between the pieces are interior again.
    assert_eq!(
        vol.mesh.boundary_face_count(),
        whole.mesh.boundary_face_count()
    );
    let names: Vec<_> = vol.data.fields.iter().map(|f| f.name.clone()).collect();
    let want: Vec<_> = whole.data.fields.iter().map(|f| f.name.clone()).collect();
    assert_eq!(names, want);
    assert!(render_steps(&pvtu, &[0], "").remove(0) == single(0));
}

#[test]
fn a_step_with_the_same_mesh_shares_it_and_a_changed_mesh_is_loaded_anew() {
    let mut session = Session::new();
    session.load_volume(&data("moving.pvd")).unwrap();
    let mesh_of = |s: &Session| Arc::clone(&s.volume().unwrap().mesh);
    let first = mesh_of(&session);
    session.set_timestep(1).unwrap();
    assert!(
        Arc::ptr_eq(&first, &mesh_of(&session)),
        "step 1 shares the mesh"
    );
    assert_ne!(session.volume().unwrap().data.raw, {
        let (v0, _) = Volume::load(&data("flow_0.vtu")).unwrap();
        v0.data.raw
    });
    session.set_timestep(2).unwrap();
    let moved = mesh_of(&session);
    assert!(!Arc::ptr_eq(&first, &moved), "step 2 has its own mesh");
    assert_eq!(moved.bbox().max[0], 3.75);
    session.set_timestep(0).unwrap();
    assert_eq!(mesh_of(&session).bbox().max[0], 3.0);
    // Directly on the series: the pieces of a .pvtu merge to the same grid every step.
    let series = Series::read(&data("flow_p.pvd")).unwrap();
    let (a, _) = series.load_step(0, None).unwrap();
    let (b, _) = series.load_step(2, Some(&a)).unwrap();
    assert!(b.shares_mesh(&a));
    assert!(Arc::ptr_eq(&a.volume.mesh, &b.volume.mesh));
}

#[test]
fn the_scene_stays_across_steps_and_volume_resets_it() {
    let mut session = Session::new();
    session.load_volume(&data("flow.pvd")).unwrap();
    session
        .transform(vorang::scene::TransformOp::Translate([1.0, 0.0, 0.0]))
        .unwrap();
    session.set_image_size(20, 10).unwrap();
    let before = session.script();
    let notices = session.set_timestep(2).unwrap();
    assert!(notices.is_empty(), "{notices:?}");
    assert_eq!(session.script(), before);
    assert_eq!(session.timestep(), Some((2, 1.25)));
    assert_eq!(session.timesteps(), [0.0, 0.5, 1.25]);
    // A map that the step's fields cannot take is refused and the step stays.
    let e = session.set_timestep(7).unwrap_err();
    assert!(e.contains("step 7 is out of range"), "{e}");
    assert!(e.contains("has 3 time steps (0 … 2)"), "{e}");
    assert_eq!(session.timestep(), Some((2, 1.25)));
    // A new volume is a new scene, and a single file is one step.
    session.load_volume(&data("flow_1.vtu")).unwrap();
    assert!(session.series().is_none());
    assert_eq!(session.timesteps(), [0.0]);
}

#[test]
fn info_lists_the_steps_and_ranges_over_all_steps() {
    let (described, _) = describe_file(&data("flow.pvd")).unwrap();
    let Described::Series { ranges, series, .. } = &described else {
        panic!("not a series");
    };
    assert_eq!(series.len(), 3);
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for k in 0..3 {
        let (v, _) = Volume::load(&data(&format!("flow_{k}.vtu"))).unwrap();
        let r = v.field_range(0).unwrap()[0];
        lo = lo.min(r.0);
        hi = hi.max(r.1);
    }
    assert_eq!(ranges[0].as_ref().unwrap()[0], (lo, hi));
    let (text, clean) = vorang::info::describe(&described, false);
    assert!(clean);
    for line in [
        "steps        3, t = 0 … 1.25",
        "     2  t = 1.25",
        &format!(
            "range [{}, {}] over all 3 steps",
            vorang::info::num(lo),
            vorang::info::num(hi)
        ),
        &format!(
            "try   colormap preset viridis {} {} 0;",
            vorang::info::num(lo),
            vorang::info::num(hi)
        ),
    ] {
        assert!(text.contains(line), "{line:?} not in\n{text}");
    }
}

#[test]
fn the_registry_loads_step_0_for_volume_data_and_bytes() {
    let (vol, _) = Volume::load(&data("flow.vtu.series")).unwrap();
    let (v0, _) = Volume::load(&data("flow_0.vtu")).unwrap();
    assert_eq!(vol.mesh.nodes(), v0.mesh.nodes());
    assert_eq!(vol.data.raw, v0.data.raw);
    let (with, _) = vorang::formats::load_data(&v0, &data("flow.pvd"), true).unwrap();
    assert_eq!(with.data.fields.len(), 2 * v0.data.fields.len());
    // The pieces of a .pvtu merge to the same grid with its points in another order: 'data'
    // needs the very same nodes and cells.
    let e = vorang::formats::load_data(&v0, &data("flow_p.pvd"), true).unwrap_err();
    assert!(e.to_string().contains("'data' needs the same mesh"), "{e}");
    let bytes = std::fs::read(data("flow.pvd")).unwrap();
    let name = data("flow.pvd").display().to_string();
    let (from_bytes, _) = vorang::formats::volume_from_bytes(&bytes, &name).unwrap();
    assert_eq!(from_bytes.data.raw, v0.data.raw);
}

#[test]
fn the_label_prints_the_time_into_images_and_movie_frames() {
    let plain = render_steps(&data("flow.pvd"), &[1], "").remove(0);
    let labelled = render_steps(&data("flow.pvd"), &[1], "label {t = %.3g s}").remove(0);
    let (w, h, a) = read_pfm(&plain).unwrap();
    let (_, _, b) = read_pfm(&labelled).unwrap();
    // The label is in the top rows (read_pfm gives the top row first).
    let changed: Vec<(usize, usize)> = (0..w * h)
        .filter(|&i| a[i] != b[i])
        .map(|i| (i % w, i / w))
        .collect();
    assert!(!changed.is_empty());
    assert!(changed.iter().all(|&(x, y)| y < 14 && x < w), "{changed:?}");
    assert!(b.contains(&[1.0, 1.0, 1.0]), "white text");
    // With the legend on top the label goes to the bottom.
    let bottom = render_steps(&data("flow.pvd"), &[1], "label {%d}; legend on top").remove(0);
    let top = render_steps(&data("flow.pvd"), &[1], "legend on top").remove(0);
    let (_, _, c) = read_pfm(&bottom).unwrap();
    let (_, _, d) = read_pfm(&top).unwrap();
    let moved: Vec<usize> = (0..w * h).filter(|&i| c[i] != d[i]).collect();
    assert!(!moved.is_empty());
    assert!(moved.iter().all(|&i| i / w >= h - 14), "{moved:?}");
    // Movie frames carry it too: three frames, one per step.
    let tmp = tempfile::tempdir().unwrap();
    let movie = tmp.path().join("flow.gif");
    let mut runner = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "imagesize 48 40\nvolume {{{}}}\n{SCENE}\nlabel {{t = %.2f}}\nmovie {{{}}} 5\nforeach t [timesteps] {{ timestep -time $t; render_btf }}\nmovie close\n",
        data("flow.pvd").display(),
        movie.display()
    );
    runner.run_string(&script, "test").unwrap();
    let bytes = std::fs::read(&movie).unwrap();
    let frames = image::codecs::gif::GifDecoder::new(std::io::Cursor::new(bytes))
        .map(|d| image::AnimationDecoder::into_frames(d).count())
        .unwrap();
    assert_eq!(frames, 3);
}
