//! Mesh file formats: the same mesh and fields from HyperMesh, every `.vtu`
//! encoding, legacy `.vtk` and Gmsh `.msh` render bit-identical images; mixed cells split
//! conformingly; fields by name in map files; `.vtu` writing round-trips; bad inputs fail with
//! a located message and leave the loaded volume alone.
//!
//! The data files in `tests/data/formats/` are made by `tests/data/formats/generate.py`.

use std::path::{Path, PathBuf};

use vorang::Volume;
use vorang::field::Interpolator;
use vorang::formats;
use vorang::framebuffer::read_pfm;
use vorang_tcl::script::{Collect, Runner};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/formats")
        .join(name)
}

fn all_cube_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(data(""))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            n.starts_with("cube") && !n.ends_with(".py")
        })
        .collect();
    files.sort();
    files
}

const COLORMAP: &str = "# VoRANG Colormap 1.0
DataField \"temperature\"
SIMPLE_EMITTER @1
@1
0 0.2 1   0
1 0.5 0   3.25
";

const ALPHAMAP: &str = "# VoRANG Alphamap 1.0
DataField \"temperature\"
CategoryField \"CAT\"
SIMPLE_ABSORBER from:1 to:2 @1
CONST_CELL field:\"CAT\" from:2 to:3 @2
@1
0.5 0
3   3.25
@2
0.5 1
1.5 2
";

/// Renders `file` with the given maps (exact method, closed-form integration: exact up to
/// rounding) and returns the RGB floats.
fn render(file: &Path, colormap: &str, alphamap: &str, view: &str) -> Vec<f32> {
    let tmp = tempfile::tempdir().unwrap();
    let cmap = tmp.path().join("c.map");
    let amap = tmp.path().join("a.map");
    std::fs::write(&cmap, colormap).unwrap();
    std::fs::write(&amap, alphamap).unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "imagesize 40 32\noutput {{{}}}\nvolume {{{}}}\ncolormap {{{}}}\nalphamap {{{}}}\nlinedraw off\nmethod exact linear 0 1\n{view}\nrender_btf\n",
        tmp.path().join("img.pfm").display(),
        file.display(),
        cmap.display(),
        amap.display()
    );
    runner
        .run_string(&script, "test")
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let written = runner.session().written().to_vec();
    let bytes = std::fs::read(&written[0]).unwrap();
    let (_, _, rgb) = read_pfm(&bytes).unwrap();
    rgb.into_iter().flatten().collect()
}

#[test]
fn every_format_and_encoding_renders_the_same_image_bit_for_bit() {
    let view = "vol_rotate 1 1 0 30";
    let reference = render(
        &data("cube.hmesh"),
        COLORMAP,
        &ALPHAMAP.replace("CAT", "material"),
        view,
    );
    assert!(reference.iter().any(|&v| v < 0.9), "the volume is visible");
    let files = all_cube_files();
    assert!(files.len() >= 30, "{files:?}");
    for f in files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        // Gmsh files written by Gmsh itself carry the material as the physical group.
        let cat = if name.contains("entities") {
            "gmsh:physical"
        } else {
            "material"
        };
        let img = render(&f, COLORMAP, &ALPHAMAP.replace("CAT", cat), view);
        assert!(
            img == reference,
            "{name} renders differently (largest difference {})",
            img.iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f32::max)
        );
    }
}

#[test]
fn every_cube_file_has_the_same_mesh_and_fields() {
    let (reference, _) = Volume::load(&data("cube.hmesh")).unwrap();
    for f in all_cube_files() {
        let (vol, _) = Volume::load(&f).unwrap();
        let name = f.display();
        assert_eq!(vol.mesh.nodes(), reference.mesh.nodes(), "{name}");
        assert_eq!(vol.mesh.tets(), reference.mesh.tets(), "{name}");
        for field in ["temperature", "velocity", "material", "pressure"] {
            let Some(n) = vol
                .data
                .fields
                .iter()
                .position(|x| x.name.as_deref() == Some(field))
            else {
                assert!(
                    f.to_string_lossy().contains("entities"),
                    "{name} lacks {field}"
                );
                continue;
            };
            let r = reference
                .data
                .fields
                .iter()
                .position(|x| x.name.as_deref() == Some(field))
                .unwrap();
            assert_eq!(
                vol.field_range(n),
                reference.field_range(r),
                "{name} {field}"
            );
            assert_eq!(
                vol.field(n).unwrap().interpolator,
                reference.field(r).unwrap().interpolator
            );
            assert_eq!(
                vol.field(n).unwrap().is_byte_constant(&vol.data.raw),
                reference
                    .field(r)
                    .unwrap()
                    .is_byte_constant(&reference.data.raw),
                "{name} {field}"
            );
        }
    }
}

#[test]
fn fields_are_numbered_point_arrays_first_then_cell_arrays_in_file_order() {
    let (vol, _) = Volume::load(&data("cube_raw_zlib.vtu")).unwrap();
    let names: Vec<&str> = vol
        .data
        .fields
        .iter()
        .map(|f| f.name.as_deref().unwrap())
        .collect();
    assert_eq!(names, ["temperature", "velocity", "material", "pressure"]);
    let kinds: Vec<Interpolator> = vol.data.fields.iter().map(|f| f.interpolator).collect();
    assert_eq!(
        kinds,
        [
            Interpolator::Linear,
            Interpolator::Linear,
            Interpolator::Constant,
            Interpolator::Constant
        ]
    );
    assert_eq!(vol.field(1).unwrap().components(), 3);
    assert!(vol.field(2).unwrap().is_byte_constant(&vol.data.raw));
    // 3-component arrays are float[3] (HyperMesh's vector type), whatever the file stores.
    let float3 = vorang::hypermesh::DataType::array(vorang::hypermesh::ScalarType::Float, 3);
    for f in all_cube_files() {
        if f.extension().is_some_and(|e| e == "hmesh") {
            continue;
        }
        let (v, _) = Volume::load(&f).unwrap();
        let velocity = v
            .data
            .fields
            .iter()
            .find(|x| x.name.as_deref() == Some("velocity"));
        if let Some(velocity) = velocity {
            assert_eq!(velocity.ty, float3, "{}", f.display());
            assert_eq!(v.data.raw[velocity.sources[0]].ty, float3);
        }
    }
    // Gmsh: physical groups as an integer cell field, float-coded material ids as bytes.
    let (msh, _) = Volume::load(&data("cube_22_ascii.msh")).unwrap();
    let names: Vec<&str> = msh
        .data
        .fields
        .iter()
        .map(|f| f.name.as_deref().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "temperature",
            "velocity",
            "gmsh:physical",
            "material",
            "pressure"
        ]
    );
    assert!(msh.field(2).unwrap().is_byte_constant(&msh.data.raw));
    assert!(msh.field(3).unwrap().is_byte_constant(&msh.data.raw));
}

#[test]
fn a_mixed_mesh_renders_like_another_conforming_split_of_it() {
    let cmap =
        "# VoRANG Colormap 1.0\nDataField \"f\"\nSIMPLE_EMITTER @1\n@1\n1 0 0 0.5\n0 0.5 1 3.5\n";
    let amap = "# VoRANG Alphamap 1.0\nDataField \"f\"\nSIMPLE_ABSORBER @1\n@1\n0.2 0.5\n1.5 3.5\n";
    for view in [
        "",
        "vol_rotate 0 1 0 35\nvol_rotate 1 0 0 20",
        "vol_rotate 1 2 3 70",
    ] {
        let a = render(&data("mixed.vtu"), cmap, amap, view);
        let b = render(&data("mixed_split.vtu"), cmap, amap, view);
        let diff = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f32::max);
        assert!(diff <= 1e-6, "view '{view}': largest difference {diff}");
        assert!(a.iter().any(|&v| v < 0.9));
    }
    let (mixed, warnings) = Volume::load(&data("mixed.vtu")).unwrap();
    assert_eq!(mixed.mesh.tet_count(), 6 + 2 * 3 + 6 * 2 + 6);
    assert!(
        mixed.mesh.is_convex(),
        "a conforming split has no inner boundary"
    );
    assert!(
        warnings.iter().all(|w| !w.message.contains("skipped")),
        "{warnings:?}"
    );
}

#[test]
fn cells_that_are_not_volumes_are_skipped_with_one_warning() {
    let (vol, warnings) = Volume::load(&data("mixed_with_faces.vtu")).unwrap();
    assert_eq!(vol.mesh.tet_count(), 30);
    let skipped: Vec<_> = warnings
        .iter()
        .filter(|w| w.message.contains("skipped"))
        .collect();
    assert_eq!(skipped.len(), 1, "{warnings:?}");
    assert!(
        skipped[0].message.contains("skipped 2 cells"),
        "{}",
        skipped[0]
    );
    assert!(skipped[0].message.contains("1 × triangle"));
}

#[test]
fn quadratic_tetrahedra_carry_a_p2_field() {
    let (vol, _) = Volume::load(&data("quadratic.vtu")).unwrap();
    assert_eq!(vol.mesh.tet_count(), 2);
    let f = vol.field(0).unwrap();
    assert_eq!(f.interpolator, Interpolator::HigherOrder);
    assert_eq!(f.name.as_deref(), Some("q"));
    // q = x² + y·z is quadratic, so P2 reproduces it everywhere.
    for cell in 0..2 {
        let c = vol.mesh.corners(cell);
        for l in [[0.1, 0.2, 0.3, 0.4], [0.25; 4], [0.7, 0.1, 0.1, 0.1]] {
            let p: [f64; 3] = [0, 1, 2].map(|d| (0..4).map(|i| l[i] * c[i][d]).sum());
            let mut out = [0.0];
            f.eval(&vol.support(), cell, &l, p, &mut out);
            let want = p[0] * p[0] + p[1] * p[2];
            assert!((out[0] - want).abs() < 1e-12, "{} vs {want}", out[0]);
        }
    }
    assert!(vol.field(1).unwrap().is_byte_constant(&vol.data.raw));
}

#[test]
fn hypermesh_to_vtu_and_back_keeps_mesh_and_fields() {
    let tmp = tempfile::tempdir().unwrap();
    for src in ["cube.hmesh", "cube_float32.vtu", "mixed.vtu"] {
        let (vol, _) = Volume::load(&data(src)).unwrap();
        let vtu = tmp.path().join("out.vtu");
        let warnings =
            formats::save_volume(&vol, &vtu, vorang::hypermesh::WriteOptions::default()).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        let bytes = std::fs::read(&vtu).unwrap();
        assert!(bytes.starts_with(b"<?xml"), "a .vtu name writes VTK XML");
        assert!(bytes.windows(21).any(|w| w == b"vtkZLibDataCompressor"));
        let (back, _) = Volume::load(&vtu).unwrap();
        assert_eq!(back.mesh.nodes(), vol.mesh.nodes(), "{src}");
        assert_eq!(back.mesh.tets(), vol.mesh.tets(), "{src}");
        assert_eq!(back.coord_type, vol.coord_type, "{src}");
        assert_eq!(back.data.fields.len(), vol.data.fields.len());
        for (a, b) in back.data.fields.iter().zip(&vol.data.fields) {
            assert_eq!(a.name, b.name);
            assert_eq!(a.ty, b.ty);
            assert_eq!(a.interpolator, b.interpolator);
            assert_eq!(
                back.data.raw[a.sources[0]].values,
                vol.data.raw[b.sources[0]].values
            );
        }
        // And on to HyperMesh (BINARY), which gives the same volume again.
        let hm = tmp.path().join("out.hmesh");
        let opts = vorang::hypermesh::WriteOptions {
            encoding: vorang::hypermesh::Encoding::Binary,
            layout: vorang::hypermesh::Layout::Small,
        };
        formats::save_volume(&back, &hm, opts).unwrap();
        let (again, _) = Volume::load(&hm).unwrap();
        assert_eq!(again.mesh.tets(), vol.mesh.tets());
        assert_eq!(again.data.fields.len(), vol.data.fields.len());
    }
}

#[test]
fn convert_writes_vtu_for_a_vtu_name() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("g.vtu");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
        .args(["convert"])
        .arg(data("cube.hmesh"))
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    assert!(std::fs::read(&out).unwrap().starts_with(b"<?xml"));
    let info = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
        .arg("info")
        .arg(&out)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(text.contains("VTK XML UnstructuredGrid"), "{text}");
    assert!(text.contains("0: \"temperature\""), "{text}");
    assert!(text.contains("2: \"material\" { byte }"), "{text}");
    assert!(text.contains("range [0, 3.25]"), "{text}");
    // Formats VoRANG reads but does not write are refused by name.
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
        .arg("convert")
        .arg(data("cube.hmesh"))
        .arg(tmp.path().join("g.msh"))
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("cannot write Gmsh"));
}

#[test]
fn an_unknown_field_name_lists_the_names() {
    let tmp = tempfile::tempdir().unwrap();
    let cmap = tmp.path().join("c.map");
    std::fs::write(
        &cmap,
        "# VoRANG Colormap 1.0\nDataField \"temperatur\"\nSIMPLE_EMITTER @1\n@1\n0 0 0 0\n1 1 1 1\n",
    )
    .unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "imagesize 8 8\noutput {{{}}}\nvolume {{{}}}\ncolormap {{{}}}\nrender_btf\n",
        tmp.path().join("i.pfm").display(),
        data("cube_raw.vtu").display(),
        cmap.display()
    );
    let e = runner.run_string(&script, "t").unwrap_err();
    assert!(e.message.contains("c.map:2:"), "{e}");
    assert!(e.message.contains("no field named \"temperatur\""), "{e}");
    assert!(
        e.message
            .contains("0 \"temperature\", 1 \"velocity\", 2 \"material\", 3 \"pressure\""),
        "{e}"
    );
}

// ---------------------------------------------------------------------------------------------
// Bad input

/// Loads `bytes` as a file named `name`: must fail (no panic) with a message naming the file
/// and a line.
fn must_fail(bytes: &[u8], name: &str) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    match Volume::load(&path) {
        Ok(_) => panic!("{name}: loaded a bad file"),
        Err(e) => {
            let msg = e.to_string();
            let prefix = format!("{}:", path.display());
            assert!(msg.starts_with(&prefix), "{name}: {msg}");
            let line = msg[prefix.len()..].split(':').next().unwrap();
            assert!(line.parse::<usize>().is_ok(), "{name}: no line in {msg}");
            msg
        }
    }
}

fn replace_once(bytes: &[u8], from: &str, to: &str) -> Vec<u8> {
    let text = bytes;
    let k = text
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap_or_else(|| panic!("'{from}' not found"));
    [&text[..k], to.as_bytes(), &text[k + from.len()..]].concat()
}

#[test]
fn truncated_files_fail_cleanly_at_every_length() {
    for f in all_cube_files()
        .into_iter()
        .chain([data("mixed.vtu"), data("quadratic.vtu")])
    {
        let bytes = std::fs::read(&f).unwrap();
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        if name.ends_with(".hmesh") {
            continue;
        }
        // Every length for small prefixes, then a stride (the whole sweep stays fast).
        let step = (bytes.len() / 300).max(1);
        let mut cut = 0;
        while cut < bytes.len() {
            let short = &bytes[..cut];
            if let Ok((vol, _)) = formats::volume_from_bytes(short, &name) {
                // A cut in trailing text (closing tags, end markers) may leave a whole mesh.
                assert_eq!(vol.mesh.tet_count(), 48.min(vol.mesh.tet_count()));
            }
            cut += if cut < 64 { 1 } else { step };
        }
        let e = must_fail(&bytes[..bytes.len() / 2], &name);
        assert!(!e.is_empty());
    }
}

#[test]
fn bad_vtu_inputs_name_the_file_and_the_line() {
    let raw = std::fs::read(data("cube_raw_zlib.vtu")).unwrap();
    let ascii = std::fs::read(data("cube_ascii.vtu")).unwrap();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "wrong offset",
            replace_once(&raw, "offset=\"0\"", "offset=\"999999\""),
            "beyond the appended data",
        ),
        (
            "points count",
            replace_once(&ascii, "NumberOfPoints=\"27\"", "NumberOfPoints=\"28\""),
            "values",
        ),
        (
            "connectivity out of range",
            replace_once(&ascii, "NumberOfPoints=\"27\"", "NumberOfPoints=\"20\""),
            "",
        ),
        (
            "unknown compressor",
            replace_once(&raw, "vtkZLibDataCompressor", "vtkZstdDataCompressor"),
            "compressor",
        ),
        (
            "not a grid",
            replace_once(&ascii, "type=\"UnstructuredGrid\"", "type=\"PolyData\""),
            "UnstructuredGrid",
        ),
        (
            "bad number",
            replace_once(&ascii, "0.0 0.0 0.0", "0.0 zero 0.0"),
            "expected a number",
        ),
        (
            "NaN coordinate",
            replace_once(&ascii, "0.0 0.0 0.0", "0.0 nan 0.0"),
            "non-finite",
        ),
        (
            "tiny coordinate",
            replace_once(&ascii, "0.0 0.0 0.0", "0.0 1e-300 0.0"),
            "too small",
        ),
        (
            "wrong cell type for the offsets",
            replace_once(&ascii, ">\n10 10 10", ">\n12 10 10"),
            "needs 8 nodes",
        ),
    ];
    for (what, bytes, fragment) in cases {
        let msg = must_fail(&bytes, "bad.vtu");
        assert!(msg.contains(fragment), "{what}: {msg}");
    }
    // A corrupt compressed block: flip bytes inside the appended data.
    let start = raw
        .windows(15)
        .position(|w| w == b"encoding=\"raw\">")
        .unwrap();
    let mut corrupt = raw.clone();
    for k in (start + 60..corrupt.len() - 40).step_by(37) {
        corrupt[k] ^= 0x5a;
    }
    let msg = must_fail(&corrupt, "corrupt.vtu");
    assert!(
        msg.contains("zlib") || msg.contains("block") || msg.contains("bytes"),
        "{msg}"
    );
}

#[test]
fn bad_legacy_and_gmsh_inputs_name_the_file_and_the_line() {
    let vtk = std::fs::read(data("cube_hand_ascii.vtk")).unwrap();
    let msh = std::fs::read(data("cube_22_ascii.msh")).unwrap();
    let msg = must_fail(&replace_once(&vtk, "POINTS 27", "POINTS 26"), "bad.vtk");
    assert!(msg.contains("bad.vtk:"), "{msg}");
    let msg = must_fail(
        &replace_once(&vtk, "CELLS 48 240", "CELLS 48 241"),
        "bad.vtk",
    );
    assert!(msg.contains("CELLS"), "{msg}");
    let msg = must_fail(
        &replace_once(&vtk, "POINT_DATA 27", "POINT_DATA 26"),
        "bad.vtk",
    );
    assert!(msg.contains("unexpected '"), "{msg}");
    let msg = must_fail(&replace_once(&msh, "$Nodes\n27", "$Nodes\n26"), "bad.msh");
    assert!(msg.contains("bad.msh:"), "{msg}");
    let msg = must_fail(&replace_once(&msh, "2.2 0 8", "3.0 0 8"), "bad.msh");
    assert!(msg.contains("bad.msh:2:"), "{msg}");
}

#[test]
fn a_failed_load_keeps_the_previous_volume() {
    let tmp = tempfile::tempdir().unwrap();
    let bad = tmp.path().join("bad.vtu");
    let good = std::fs::read(data("cube_raw_lz4.vtu")).unwrap();
    std::fs::write(&bad, &good[..good.len() - 100]).unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "volume {{{}}}\nif {{![catch {{volume {{{}}}}} msg]}} {{error \"loaded\"}}\nset msg",
        data("cube_raw.vtu").display(),
        bad.display()
    );
    let msg = runner.run_string(&script, "t").unwrap();
    assert!(msg.contains("bad.vtu:"), "{msg}");
    let session = runner.session();
    let vol = session.volume().unwrap();
    assert_eq!(vol.mesh.tet_count(), 48);
    assert!(vol.source.ends_with("cube_raw.vtu"));
}

#[test]
fn data_loads_the_fields_of_a_vtu_onto_the_grid() {
    let mut runner = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "volume {{{}}}\ndata + {{{}}}",
        data("cube.hmesh").display(),
        data("cube_b64_zlib.vtu").display()
    );
    let out = runner.run_string(&script, "t").unwrap();
    assert_eq!(out, "8 fields");
    let wrong = format!("data {{{}}}", data("mixed.vtu").display());
    let e = runner.run_string(&wrong, "t").unwrap_err();
    assert!(e.message.contains("same mesh"), "{e}");
}

#[test]
fn save_volume_writes_vtu_from_a_script() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("saved.vtu");
    let mut runner = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "volume {{{}}}\nsave_volume {{{}}}\nvolume {{{}}}",
        data("quadratic.vtu").display(),
        out.display(),
        out.display()
    );
    let summary = runner.run_string(&script, "t").unwrap();
    // The HigherOrder field (a P2 field from the quadratic cells) comes back too: VoRANG's
    // layout keeps its edge data.
    assert_eq!(summary, "14 nodes, 2 tetrahedra, 2 fields");
    let refused = format!("save_volume {{{}}} binary", out.display());
    let e = runner.run_string(&refused, "t").unwrap_err();
    assert!(e.message.contains("HyperMesh encoding"), "{e}");
}

#[test]
fn files_written_by_gmsh_itself_agree_across_versions_and_encodings() {
    let mut first: Option<Volume> = None;
    for name in [
        "gmsh_41_ascii.msh",
        "gmsh_41_binary.msh",
        "gmsh_22_ascii.msh",
        "gmsh_22_binary.msh",
    ] {
        let (vol, warnings) = Volume::load(&data(name)).unwrap();
        assert!(
            warnings
                .iter()
                .any(|w| w.message.contains("skipped 48 cells")),
            "{name}: the interface triangles are skipped with a warning: {warnings:?}"
        );
        let f = vol.field(0).unwrap();
        assert_eq!(f.name.as_deref(), Some("gmsh:physical"));
        assert!(f.is_byte_constant(&vol.data.raw));
        assert_eq!(vol.field_range(0), Some(vec![(1.0, 2.0)]), "{name}");
        match &first {
            None => first = Some(vol),
            Some(a) => {
                // Gmsh prints 16 significant digits in ASCII: equal to rounding.
                for (p, q) in a.mesh.nodes().iter().zip(vol.mesh.nodes()) {
                    for k in 0..3 {
                        assert!((p[k] - q[k]).abs() < 1e-14, "{name}: {p:?} {q:?}");
                    }
                }
                assert_eq!(a.mesh.tets(), vol.mesh.tets(), "{name}");
                assert_eq!(a.data.raw, vol.data.raw, "{name}");
            }
        }
    }
}

#[test]
fn a_corrupt_xz_footer_is_an_error() {
    // Found by fuzzing: lzma-rs overflows on a backward size of 2^32 − 1.
    let bytes = std::fs::read(data("bad/xz_footer_overflow.vtu")).unwrap();
    let e = formats::volume_from_bytes(&bytes, "xz.vtu").unwrap_err();
    assert!(
        e.message.contains("lzma") || e.message.contains("bytes"),
        "{e}"
    );
}

/// Every HyperMesh file in the repository (examples and test data) that holds a grid.
fn hypermesh_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["examples", "tests/data"] {
        let mut stack = vec![root.join(dir)];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).unwrap() {
                let p = e.unwrap().path();
                if p.is_dir() {
                    stack.push(p);
                } else if std::fs::read(&p).unwrap().starts_with(b"# HyperMesh 3D") {
                    files.push(p);
                }
            }
        }
    }
    files.sort();
    files
}

/// A small render of scalar field `n` of `file` (emission and absorption over its range).
fn render_field(file: &Path, n: usize, lo: f64, hi: f64) -> Vec<f32> {
    let hi = if hi > lo { hi } else { lo + 1.0 };
    let cmap = format!(
        "# VoRANG Colormap 1.0\nDataField {n}\nSIMPLE_EMITTER @1\n@1\n0 0.2 1 {lo}\n1 0.5 0 {hi}\n"
    );
    let amap =
        format!("# VoRANG Alphamap 1.0\nDataField {n}\nSIMPLE_ABSORBER @1\n@1\n0.2 {lo}\n3 {hi}\n");
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("c.map"), cmap).unwrap();
    std::fs::write(tmp.path().join("a.map"), amap).unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "imagesize 24 20\noutput {{{}}}\nvolume {{{}}}\ncolormap {{{}}}\nalphamap {{{}}}\nmethod exact trapez 0.05 1\nvol_rotate 1 1 0 30\nrender_btf\n",
        tmp.path().join("img.pfm").display(),
        file.display(),
        tmp.path().join("c.map").display(),
        tmp.path().join("a.map").display()
    );
    runner
        .run_string(&script, "test")
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let bytes = std::fs::read(&runner.session().written()[0]).unwrap();
    let (_, _, rgb) = read_pfm(&bytes).unwrap();
    rgb.into_iter().flatten().collect()
}

#[test]
fn every_hypermesh_file_goes_to_vtu_and_back_unchanged() {
    let tmp = tempfile::tempdir().unwrap();
    let files = hypermesh_files();
    assert!(files.len() >= 10, "{files:?}");
    let mut converted = 0;
    for src in files {
        let name = src.display().to_string();
        let Ok((vol, _)) = Volume::load(&src) else {
            continue; // data-only files have no grid to write
        };
        let vtu = tmp.path().join("out.vtu");
        let warnings =
            formats::save_volume(&vol, &vtu, vorang::hypermesh::WriteOptions::default()).unwrap();
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        let (back, _) = Volume::load(&vtu).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(back.mesh.nodes(), vol.mesh.nodes(), "{name}: nodes");
        assert_eq!(back.mesh.tets(), vol.mesh.tets(), "{name}: tets");
        assert_eq!(back.mesh.neighbors(), vol.mesh.neighbors(), "{name}");
        assert_eq!(back.coord_type, vol.coord_type, "{name}: coordinate type");
        assert_eq!(back.edges, vol.edges, "{name}: edges");
        assert_eq!(back.triangles, vol.triangles, "{name}: triangles");
        for c in 0..vol.mesh.tet_count() {
            assert_eq!(back.tet_edges(c), vol.tet_edges(c), "{name}: edges of {c}");
        }
        assert_eq!(back.data.materials, vol.data.materials, "{name}: materials");
        assert_eq!(back.data.counts, vol.data.counts, "{name}: counts");
        assert_eq!(back.data.raw, vol.data.raw, "{name}: raw data");
        assert_eq!(back.data.fields.len(), vol.data.fields.len(), "{name}");
        for (f, g) in back.data.fields.iter().zip(&vol.data.fields) {
            assert_eq!(
                (&f.name, f.ty, &f.denominator, f.interpolator, &f.sources),
                (&g.name, g.ty, &g.denominator, g.interpolator, &g.sources),
                "{name}: field"
            );
        }
        // And the images: every scalar field, bit for bit.
        let hm = tmp.path().join("out.hmesh");
        formats::save_volume(&vol, &hm, vorang::hypermesh::WriteOptions::default()).unwrap();
        for n in 0..vol.data.fields.len() {
            if !vol.field(n).unwrap().is_scalar() {
                continue;
            }
            let r = vol.field_range(n).unwrap()[0];
            let a = render_field(&src, n, r.0, r.1);
            let b = render_field(&vtu, n, r.0, r.1);
            assert!(a == b, "{name}: field {n} renders differently");
            assert!(a.iter().any(|&v| v < 0.99), "{name}: field {n} is visible");
        }
        converted += 1;
    }
    assert!(converted >= 10, "{converted}");
}

#[test]
fn a_vtu_changed_by_another_program_is_read_as_a_plain_vtu() {
    let tmp = tempfile::tempdir().unwrap();
    let (vol, _) = Volume::load(&data("cube.hmesh")).unwrap();
    let vtu = tmp.path().join("out.vtu");
    formats::save_volume(&vol, &vtu, vorang::hypermesh::WriteOptions::default()).unwrap();
    // Renaming a point array (as an edit in ParaView would) detaches VoRANG's layout.
    let bytes = replace_once(&std::fs::read(&vtu).unwrap(), "\"velocity\"", "\"speed\"");
    std::fs::write(&vtu, bytes).unwrap();
    let (back, warnings) = Volume::load(&vtu).unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.message.contains("no longer matches")),
        "{warnings:?}"
    );
    let names: Vec<&str> = back
        .data
        .fields
        .iter()
        .map(|f| f.name.as_deref().unwrap())
        .collect();
    assert_eq!(names, ["temperature", "speed", "material", "pressure"]);
}
