//! Hostile inputs that once crashed, hung or corrupted silently: each test is named after what it
//! guards.

use vorang::Volume;
use vorang::hypermesh::read_bytes;
use vorang::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
use vorang::render::{LineDraw, Method, Settings, render};
use vorang::scene::View;

const TWO_TETS: &str = "# HyperMesh 3D ASCII 0.7\nnNodes = 5\nnTetrahedra = 2\nNodes { double[3] Coordinates } = @1\nTetrahedra { int[4] Nodes } = @2\nNodeData { double } = @3\nField \"s\" { double } = Linear(@3)\n@1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n@2\n1 2 3 4\n2 3 4 5\n@3\n";

/// Constant red emission and absorption 1.
fn red_absorber(vol: &Volume) -> Mapping {
    let cm = parse_map::<dyn ColorShading>(b"# VoRANG Colormap 1.0\nCONSTANT @1\n@1\n1 0 0\n", "c")
        .unwrap()
        .0;
    let am = parse_map::<dyn AlphaShading>(b"# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n1\n", "a")
        .unwrap()
        .0;
    Mapping::new(&cm, &am, vol).unwrap().0
}

fn mesh_with(values: [&str; 5]) -> String {
    format!("{TWO_TETS}{}\n", values.join("\n"))
}

#[test]
fn a_byte_order_mark_before_the_title_is_accepted() {
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend_from_slice(mesh_with(["0", "1", "0", "1", "0.5"]).as_bytes());
    let file = read_bytes(&bytes, "bom.hmesh").expect("a BOM is not part of the title");
    assert_eq!(Volume::from_file(file).unwrap().mesh.node_count(), 5);
    let map = b"\xEF\xBB\xBF# VoRANG Colormap 1.0\nCONSTANT @1\n@1\n1 0 0\n";
    parse_map::<dyn ColorShading>(map, "bom.map").expect("a BOM before a map title");
}

#[test]
fn an_endless_first_line_is_refused_not_read_to_exhaustion() {
    // What `volume /dev/zero` reads: bytes without a newline.
    let zeros = vec![0u8; 17 << 20];
    let err = read_bytes(&zeros, "zeros").unwrap_err().to_string();
    assert!(
        err.contains("zeros:1:") && err.contains("longer than"),
        "{err}"
    );
}

#[test]
fn values_beyond_the_safe_range_are_refused_at_load() {
    let err = read_bytes(
        mesh_with(["1.797e308", "0", "0", "0", "0"]).as_bytes(),
        "huge.hmesh",
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("huge.hmesh:18:") && err.contains("too large"),
        "{err}"
    );
}

/// The largest accepted data, maps with the largest accepted numbers and with breakpoints 1e-300
/// apart: every method renders finite pixels (no overflow to NaN or infinity).
#[test]
fn extreme_but_accepted_values_render_finite_pixels() {
    let text = mesh_with(["1e150", "-1e150", "1e150", "-1e150", "0.5"]);
    let file = read_bytes(text.as_bytes(), "extreme.hmesh").unwrap();
    let vol = Volume::from_file(file).unwrap();
    let colormaps = [
        "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n1e150 0 0 -1e150\n0 0 1e150 1e150\n",
        "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n1 0 0 0\n0 0 1 1e-300\n",
    ];
    let alphamaps = [
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n1e150 0\n2 1\n",
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.5 -1e-300\n2 1e-300\n",
    ];
    for c in colormaps {
        for a in alphamaps {
            let cm = parse_map::<dyn ColorShading>(c.as_bytes(), "c").unwrap().0;
            let am = parse_map::<dyn AlphaShading>(a.as_bytes(), "a").unwrap().0;
            let mapping = Mapping::new(&cm, &am, &vol).unwrap().0;
            for method in [
                "exact linear 0 1",
                "exact constEA 0.1 1",
                "exact trapez 0.1 1",
                "interpolateCoeff linear 1",
                "interpolateColor 1",
                "test 0.5",
            ] {
                let words: Vec<&str> = method.split_whitespace().collect();
                let settings = Settings {
                    width: 12,
                    height: 12,
                    method: Method::parse(&words).unwrap(),
                    lines: LineDraw::All,
                    ..Settings::default()
                };
                let (fb, stats) =
                    render(&vol, &mapping, &View::default(), &settings, None).unwrap();
                assert_eq!(stats.non_finite, 0, "{method}\n{c}\n{a}");
                assert!(fb.pixels.iter().flatten().all(|v| v.is_finite()));
            }
        }
    }
}

#[test]
fn a_step_that_would_need_more_than_a_million_pieces_is_refused() {
    let text = mesh_with(["0", "1", "0", "1", "0.5"]);
    let vol = Volume::from_file(read_bytes(text.as_bytes(), "m").unwrap()).unwrap();
    let mapping = red_absorber(&vol);
    for step in ["1e-20", "1e-15", "1e-10", "1e-300"] {
        for rule in ["linear", "constEA"] {
            let words = ["exact", rule, step, "1"];
            let settings = Settings {
                width: 8,
                height: 8,
                method: Method::parse(&words).unwrap(),
                ..Settings::default()
            };
            let err = match render(&vol, &mapping, &View::default(), &settings, None) {
                Ok(_) => panic!("step {step} with {rule} was accepted"),
                Err(e) => e.to_string(),
            };
            assert!(err.contains("step") && err.contains("pieces"), "{err}");
        }
    }
}

#[test]
fn an_image_too_large_for_memory_is_a_clear_error() {
    let err = vorang::framebuffer::try_pixels([0.0f32; 4], 1 << 40, 1 << 20, "the framebuffer")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("not enough memory") && err.contains("GB"),
        "{err}"
    );
}

/// Under a 1.5 GB address-space limit a 11585² image (2.1 GB of float framebuffer, under the
/// pixel cap) is refused with a message, not an allocation abort.
#[cfg(target_os = "linux")]
#[test]
fn an_image_beyond_a_memory_limit_is_refused_without_an_abort() {
    let mesh = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/two_tets_nodes.hmesh"
    );
    let dir = tempfile::tempdir().unwrap();
    let script = format!(
        "volume {mesh}; imagesize 11585 11585; linedraw off; output {}/big.png; render_btf",
        dir.path().display()
    );
    let out = std::process::Command::new("sh")
        // Few threads: each reserves address space of its own (stack, allocator arena).
        .env("RAYON_NUM_THREADS", "2")
        .arg("-c")
        .arg(format!(
            "ulimit -v 1500000; exec {} -e '{script}'",
            env!("CARGO_BIN_EXE_vorang")
        ))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("not enough memory for a 11585×11585 image"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked") && !stderr.contains("memory allocation of"));
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "no file written"
    );
}

/// Two tetrahedra that interpenetrate without sharing a face (a bad merge) are reported by the
/// render; touching bodies and valid non-convex meshes are not.
#[test]
fn interpenetrating_cells_are_reported_along_the_rays() {
    let text = "# HyperMesh 3D ASCII 0.7\nnNodes = 8\nnTetrahedra = 2\nNodes { double[3] Coordinates } = @1\nTetrahedra { int[4] Nodes } = @2\n@1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.2 0.2 0.2\n1.2 0.2 0.2\n0.2 1.2 0.2\n0.2 0.2 1.2\n@2\n1 2 3 4\n5 6 7 8\n";
    let touching = "# HyperMesh 3D ASCII 0.7\nnNodes = 8\nnTetrahedra = 2\nNodes { double[3] Coordinates } = @1\nTetrahedra { int[4] Nodes } = @2\n@1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n1 0 0\n0 1 0\n0 0 -1\n@2\n1 2 3 4\n5 6 7 8\n";
    for (text, overlapping) in [(text, true), (touching, false)] {
        let vol = Volume::from_file(read_bytes(text.as_bytes(), "m").unwrap()).unwrap();
        let mapping = red_absorber(&vol);
        let settings = Settings {
            width: 16,
            height: 16,
            method: Method::parse(&["exact", "linear", "0", "1"]).unwrap(),
            lines: LineDraw::Off,
            ..Settings::default()
        };
        let view = vorang::scene::View {
            transforms: vec![vorang::scene::TransformOp::Rotate {
                axis: [1.0, 0.3, 0.0],
                degrees: 20.0,
            }],
            ..View::default()
        };
        let (_, stats) = render(&vol, &mapping, &view, &settings, None).unwrap();
        if overlapping {
            assert!(stats.overlap_pixels > 10, "{}", stats.overlap_pixels);
            assert_eq!(stats.overlap_cells, vec![(0, 1)]);
        } else {
            assert_eq!(stats.overlap_pixels, 0);
        }
    }
}

/// `vorang info --check` finds interpenetrating cells without rendering and says so in its
/// exit status; a valid mesh passes.
#[test]
fn info_check_finds_interpenetrating_cells() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("overlap.hmesh");
    std::fs::write(&bad, "# HyperMesh 3D ASCII 0.7\nnNodes = 8\nnTetrahedra = 2\nNodes { double[3] Coordinates } = @1\nTetrahedra { int[4] Nodes } = @2\n@1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.2 0.2 0.2\n1.2 0.2 0.2\n0.2 1.2 0.2\n0.2 0.2 1.2\n@2\n1 2 3 4\n5 6 7 8\n").unwrap();
    let good = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/farbraum/farbraum.hmesh"
    );
    let run = |path: &std::path::Path| {
        std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
            .args(["info", "--check"])
            .arg(path)
            .output()
            .unwrap()
    };
    let out = run(&bad);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(
        text.contains("1 pairs of cells interpenetrate, e.g. cells 1 and 2"),
        "{text}"
    );
    let out = run(std::path::Path::new(good));
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("no interpenetrating cells"));
}
