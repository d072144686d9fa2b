//! Files that hold their own time steps — VTKHDF, XDMF + HDF5, Exodus II (netCDF-4 and
//! classic) — docs/formats.md: every step of every file renders the image of the same data
//! loaded from a `.vtu`, bit for bit, and has the same fields (name, type, range); steps on the
//! same grid share the mesh; `vorang info` lists the steps; bad and truncated files are
//! errors naming the file, never a panic.
//!
//! The data files in `tests/data/multistep/` are made by `tests/data/multistep/generate.py`
//! with the tools users write them with (VTK's vtkHDFWriter, h5py in dolfinx's layout,
//! meshio, netCDF4-python).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use vorang::Volume;
use vorang::formats::collection::Series;
use vorang::formats::{Described, describe_file};
use vorang::session::Session;
use vorang_tcl::script::{Collect, Runner};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/multistep")
        .join(name)
}

/// Renders the given steps of `file` (after `volume FILE` and `scene`, `timestep K; render`
/// each) and returns each image's PFM bytes.
fn render_steps(file: &Path, steps: &[usize], scene: &str) -> Vec<Vec<u8>> {
    let tmp = tempfile::tempdir().unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    let mut script = format!(
        "imagesize 40 32\noutput {{{}}}\nvolume {{{}}}\n{scene}\n",
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

/// The scene: field 0 over `lo … hi`, and the method (per-pixel exact integration, or the
/// cheaper interpolateCoeff for quadratic fields, which the debug build evaluates slowly).
fn scene(lo: f64, hi: f64, method: &str) -> String {
    format!(
        "colormap preset viridis {lo} {hi} 0; alphamap ramp {lo} {hi} 0.8 0; method {method}; linedraw off; vol_rotate 1 1 0 30"
    )
}

const EXACT: &str = "exact linear 0 1";

/// Each field's name, type, interpolator and range.
fn fields_of(vol: &Volume) -> Vec<String> {
    (0..vol.data.fields.len())
        .map(|i| {
            let f = &vol.data.fields[i];
            format!(
                "{:?} {:?} {:?} {:?}",
                f.name,
                f.ty,
                f.interpolator,
                vol.field_range(i)
            )
        })
        .collect()
}

/// Every step of `file` is its reference `.vtu`: the image, the fields, the mesh size.
fn check_steps(file: &str, references: &[&str], lo: f64, hi: f64) {
    check_steps_with(file, references, lo, hi, EXACT);
}

fn check_steps_with(file: &str, references: &[&str], lo: f64, hi: f64, method: &str) {
    let steps: Vec<usize> = (0..references.len()).collect();
    // Forwards then backwards: each step is its own image whatever came before.
    let order: Vec<usize> = steps.iter().chain(steps.iter().rev()).copied().collect();
    let images = render_steps(&data(file), &order, &scene(lo, hi, method));
    let series = Series::read(&data(file)).unwrap();
    assert_eq!(series.len(), references.len(), "{file}: steps");
    let mut previous = None;
    for (k, reference) in references.iter().enumerate() {
        let expected = render_steps(&data(reference), &[0], &scene(lo, hi, method)).remove(0);
        for (img, _) in images.iter().zip(&order).filter(|(_, s)| **s == k) {
            assert!(img == &expected, "{file} step {k} differs from {reference}");
        }
        let (step, _) = series.load_step(k, previous.as_ref()).unwrap();
        let (vol, _) = Volume::load(&data(reference)).unwrap();
        assert_eq!(fields_of(&step.volume), fields_of(&vol), "{file} step {k}");
        assert_eq!(
            step.volume.mesh.nodes(),
            vol.mesh.nodes(),
            "{file} step {k}"
        );
        previous = Some(step);
    }
}

#[test]
fn vtkhdf_steps_render_their_vtu_bit_for_bit() {
    let refs = ["ref_0.vtu", "ref_1.vtu", "ref_2.vtu"];
    check_steps("flow.vtkhdf", &refs, 1.0, 2.9);
    check_steps("parts.vtkhdf", &refs, 1.0, 2.9);
    check_steps(
        "moving.vtkhdf",
        &["ref_0.vtu", "ref_1.vtu", "ref_moved_2.vtu"],
        1.0,
        2.9,
    );
}

#[test]
fn xdmf_steps_render_their_vtu_bit_for_bit() {
    check_steps(
        "dolfinx.xdmf",
        &[
            "dolfinx_ref_0.vtu",
            "dolfinx_ref_1.vtu",
            "dolfinx_ref_2.vtu",
        ],
        1.0,
        2.9,
    );
    check_steps_with(
        "dolfinx_p2.xdmf",
        &[
            "dolfinx_p2_ref_0.vtu",
            "dolfinx_p2_ref_1.vtu",
            "dolfinx_p2_ref_2.vtu",
        ],
        1.0,
        2.9,
        "interpolateCoeff linear 1",
    );
    check_steps(
        "meshio.xdmf",
        &["ref_0.vtu", "ref_1.vtu", "ref_2.vtu"],
        1.0,
        2.9,
    );
    check_steps("mixed.xdmf", &["mixed_ref.vtu"], -1.0, 4.0);
}

#[test]
fn exodus_steps_render_their_vtu_bit_for_bit() {
    let refs = ["exo_ref_0.vtu", "exo_ref_1.vtu", "exo_ref_2.vtu"];
    for file in ["flow.exo", "flow_classic.e", "flow_cdf1.e"] {
        check_steps(file, &refs, 1.0, 2.9);
    }
    // The continuation file holds step 2 on a stretched grid.
    check_steps(
        "cont.e",
        &["exo_ref_0.vtu", "exo_ref_1.vtu", "exo_moved_2.vtu"],
        1.0,
        2.9,
    );
}

/// HEX27, WEDGE18 and PYRAMID14 elements are the degree-2 Lagrange cells VTK stores them as
/// (Exodus numbers their nodes otherwise: `tests/data/multistep/generate_higher.py`), a HEX20
/// VTK's quadratic hexahedron; `Hexahedron_27` and `Wedge_18` in XDMF as well. The field is
/// no quadratic, so a node out of place changes the image: the same cells with the Exodus
/// node order taken for VTK's render otherwise.
#[test]
fn higher_order_exodus_and_xdmf_cells_render_their_vtu_bit_for_bit() {
    // Exact integration samples the quadratic field inside the cells (interpolateCoeff would
    // map it at the corners only and not see the mid-edge nodes).
    let method = "exact linear 0.1 1";
    let refs = ["higher_ref_0.vtu", "higher_ref_1.vtu"];
    for file in ["higher.e", "higher_classic.e"] {
        check_steps_with(file, &refs, -1.5, 1.9, method);
    }
    check_steps_with("higher.xdmf", &["higher_xdmf_ref.vtu"], -1.5, 1.9, method);
    let scene = scene(-1.5, 1.9, method);
    let right = render_steps(&data("higher_ref_0.vtu"), &[0], &scene);
    let wrong = render_steps(&data("higher_wrong_0.vtu"), &[0], &scene);
    assert!(
        right != wrong,
        "the test data cannot tell the node orders apart"
    );
    let (_, warnings) = Volume::load(&data("higher.e")).unwrap();
    // Nothing is approximated. (The wedge's tetrahedra are re-oriented, as those of the same
    // Lagrange wedge in the .vtu are: VTK's linear wedge, whose split it uses, has its bottom
    // triangle the other way round.)
    let messages: Vec<&str> = warnings.iter().map(|w| w.message.as_str()).collect();
    assert!(
        !messages.iter().any(|m| m.contains("read as")),
        "{messages:?}"
    );
    let (_, reference) = Volume::load(&data("higher_ref_0.vtu")).unwrap();
    assert_eq!(
        warnings.len(),
        reference.len(),
        "{messages:?} {reference:?}"
    );
}

#[test]
fn exodus_blocks_become_the_byte_field_block_and_shells_are_skipped() {
    let (vol, warnings) = Volume::load(&data("flow.exo")).unwrap();
    let block = vol
        .data
        .fields
        .iter()
        .position(|f| f.name.as_deref() == Some("block"))
        .unwrap();
    assert_eq!(
        vol.data.fields[block].ty,
        vorang::data::DataType::scalar(vorang::data::ScalarType::Byte)
    );
    assert_eq!(vol.field_range(block).unwrap(), [(10.0, 20.0)]);
    assert!(
        warnings.iter().any(|w| w
            .message
            .contains("block 30 (SHELL4, 4 nodes) is not a volume block")),
        "{warnings:?}"
    );
    // meshio's own Exodus writer: one step, its point data.
    let (m, _) = Volume::load(&data("meshio.e")).unwrap();
    let (r, _) = Volume::load(&data("ref_0.vtu")).unwrap();
    assert_eq!(m.mesh.nodes(), r.mesh.nodes());
    assert_eq!(m.data.fields[0].name.as_deref(), Some("T"));
    assert_eq!(m.field_range(0), r.field_range(0));
}

#[test]
fn steps_on_the_same_grid_share_the_mesh() {
    for (file, moving) in [
        ("flow.vtkhdf", false),
        ("moving.vtkhdf", true),
        ("dolfinx.xdmf", false),
        ("flow.exo", false),
        ("cont.e", true),
    ] {
        let mut session = Session::new();
        session.load_volume(&data(file)).unwrap();
        let mesh_of = |s: &Session| Arc::clone(&s.volume().unwrap().mesh);
        let first = mesh_of(&session);
        session.set_timestep(1).unwrap();
        assert!(Arc::ptr_eq(&first, &mesh_of(&session)), "{file}: step 1");
        session.set_timestep(2).unwrap();
        assert_eq!(
            !Arc::ptr_eq(&first, &mesh_of(&session)),
            moving,
            "{file}: step 2"
        );
        assert_eq!(session.timesteps(), [0.0, 0.5, 1.25], "{file}");
        assert_eq!(session.nearest_timestep(1.0).unwrap(), 2, "{file}");
    }
}

#[test]
fn info_lists_the_steps_of_each_format() {
    for (file, kind) in [
        ("flow.vtkhdf", "VTKHDF file"),
        ("dolfinx.xdmf", "XDMF file"),
        ("flow_classic.e", "Exodus II file"),
    ] {
        let (described, _) = describe_file(&data(file)).unwrap();
        assert!(matches!(described, Described::Series { .. }), "{file}");
        let (text, _) = vorang::info::describe(&described, false);
        for line in [
            &format!("({kind})"),
            "steps        3, t = 0 … 1.25",
            "     2  t = 1.25",
            "over all 3 steps",
        ] {
            assert!(text.contains(line), "{line:?} not in\n{text}");
        }
    }
    let (described, _) = describe_file(&data("cont.e")).unwrap();
    let (text, _) = vorang::info::describe(&described, false);
    assert!(text.contains("cont.e-s0002 [step 0]"), "{text}");
}

#[test]
fn the_registry_reads_step_0_from_bytes_and_the_format_from_the_content() {
    for (file, reference) in [
        ("flow.vtkhdf", "ref_0.vtu"),
        ("parts.vtkhdf", "ref_0.vtu"),
        ("flow.exo", "exo_ref_0.vtu"),
        ("flow_cdf1.e", "exo_ref_0.vtu"),
        ("dolfinx.xdmf", "dolfinx_ref_0.vtu"),
    ] {
        let bytes = std::fs::read(data(file)).unwrap();
        let name = data(file).display().to_string();
        let (vol, _) = vorang::formats::volume_from_bytes(&bytes, &name).unwrap();
        let (r, _) = Volume::load(&data(reference)).unwrap();
        assert_eq!(fields_of(&vol), fields_of(&r), "{file}");
    }
    // Exodus by content whatever the name: classic and netCDF-4.
    for file in ["flow.exo", "flow_classic.e", "cont.e-s0002"] {
        let bytes = std::fs::read(data(file)).unwrap();
        let f = vorang::formats::detect(&bytes, Path::new("renamed.bin")).map(|f| f.name);
        assert_eq!(f, Some("Exodus II"), "{file}");
    }
    let head = std::fs::read(data("dolfinx.xdmf")).unwrap();
    assert_eq!(
        vorang::formats::detect(&head, Path::new("x.txt")).map(|f| f.name),
        Some("XDMF")
    );
}

/// Every prefix of a file (a few hundred lengths) is an error naming the file, never a panic.
fn truncations_are_errors(file: &str) {
    let bytes = std::fs::read(data(file)).unwrap();
    let step = (bytes.len() / 150).max(1);
    let name = format!("cut_{file}");
    for len in (0..bytes.len()).step_by(step) {
        if let Err(e) = vorang::formats::volume_from_bytes(&bytes[..len], &name) {
            assert!(e.file == name, "{file} cut at {len}: {e}");
        }
    }
}

#[test]
fn truncated_files_are_errors_not_panics() {
    for file in [
        "flow.vtkhdf",
        "parts.vtkhdf",
        "flow.exo",
        "flow_classic.e",
        "flow_cdf1.e",
        "mixed.xdmf",
        "higher_classic.e",
        "higher.xdmf",
    ] {
        truncations_are_errors(file);
    }
}

#[test]
fn bad_xdmf_is_located_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(data("dolfinx.xdmf")).unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    // The HDF5 file is missing: the DataItem's line names it.
    let p = write("lost.xdmf", &text);
    let e = Volume::load(&p).unwrap_err().to_string();
    assert!(e.contains("lost.xdmf:10: "), "{e}");
    assert!(e.contains("dolfinx.h5: no such HDF5 file"), "{e}");
    // A dataset that is not in the file.
    std::fs::copy(data("dolfinx.h5"), dir.path().join("dolfinx.h5")).unwrap();
    let p = write(
        "gone.xdmf",
        &text.replace("/Mesh/mesh/geometry", "/Mesh/nothing"),
    );
    let e = Volume::load(&p).unwrap_err().to_string();
    assert!(e.contains("gone.xdmf:10: "), "{e}");
    assert!(e.contains("dataset /Mesh/nothing"), "{e}");
    // Dimensions that do not match the data.
    let p = write(
        "dims.xdmf",
        &text.replace("Dimensions=\"64 3\"", "Dimensions=\"60 3\""),
    );
    let e = Volume::load(&p).unwrap_err().to_string();
    assert!(e.contains("dims.xdmf:10: "), "{e}");
    assert!(e.contains("means 180 values, found 192"), "{e}");
    // A topology VoRANG has no cells for.
    let p = write(
        "poly.xdmf",
        &text.replace(
            "TopologyType=\"Tetrahedron\"",
            "TopologyType=\"Polyhedron\"",
        ),
    );
    let e = Volume::load(&p).unwrap_err().to_string();
    assert!(
        e.contains("poly.xdmf:6: TopologyType=\"Polyhedron\""),
        "{e}"
    );
}

#[test]
fn bad_vtkhdf_and_exodus_name_the_dataset() {
    let dir = tempfile::tempdir().unwrap();
    // An HDF5 file that is no VTKHDF file.
    let p = dir.path().join("plain.vtkhdf");
    std::fs::copy(data("dolfinx.h5"), &p).unwrap();
    let e = Volume::load(&p).unwrap_err().to_string();
    assert!(
        e.contains("plain.vtkhdf: group /VTKHDF: not in the file"),
        "{e}"
    );
    // A netCDF file that is no Exodus file (no coordinates).
    let p = dir.path().join("plain.exo");
    let mut bytes = std::fs::read(data("flow_classic.e")).unwrap();
    let at = bytes.windows(6).position(|w| w == b"coordx").unwrap();
    bytes[at..at + 6].copy_from_slice(b"coordq");
    let at = bytes.windows(6).position(|w| w == b"coordy").unwrap();
    bytes[at..at + 6].copy_from_slice(b"coordr");
    std::fs::write(&p, bytes).unwrap();
    let e = Volume::load(&p).unwrap_err().to_string();
    assert!(
        e.contains("plain.exo: variable coordx: not in the file"),
        "{e}"
    );
}

/// A netCDF-4 file whose group holds a link to itself (h5py: `tests/data/multistep/
/// generate.py`, `write_cyclic`) is an error, from a file and from bytes — not a stack
/// overflow in the netCDF layer (found by fuzzing).
#[test]
fn a_netcdf4_file_whose_groups_are_no_tree_is_an_error() {
    let e = Volume::load(&data("cyclic.e")).unwrap_err().to_string();
    assert!(
        e.contains("cyclic.e: not a readable netCDF file: group"),
        "{e}"
    );
    assert!(e.contains("is reached twice"), "{e}");
    let bytes = std::fs::read(data("cyclic.e")).unwrap();
    let e = vorang::formats::exodus::read(&bytes, "cyclic.e").unwrap_err();
    assert!(e.to_string().contains("is reached twice"), "{e}");
}
