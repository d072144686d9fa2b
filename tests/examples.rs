//! Every demonstration script in `examples/` runs and writes its images. The scripts run on a
//! copy of the folder, so nothing is written into the repository.

use std::path::Path;

use vorang::Volume;
use vorang_tcl::script::{Collect, Runner};

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            if e.file_name() != "out" {
                copy_dir(&e.path(), &target);
            }
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

#[test]
fn every_example_script_runs() {
    let tmp = tempfile::tempdir().unwrap();
    copy_dir(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"),
        tmp.path(),
    );
    let mut scripts: Vec<_> = std::fs::read_dir(tmp.path())
        .unwrap()
        .flat_map(|d| std::fs::read_dir(d.unwrap().path()).into_iter().flatten())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "tcl"))
        .collect();
    scripts.sort();
    assert!(scripts.len() >= 7, "{scripts:?}");
    for script in &scripts {
        let t = std::time::Instant::now();
        let mut runner = Runner::new(Box::new(Collect::default()));
        runner
            .run_file(script)
            .unwrap_or_else(|e| panic!("{e}\n{}", e.trace));
        let written = runner.session().written().to_vec();
        assert!(!written.is_empty(), "{} wrote no image", script.display());
        for w in &written {
            assert!(w.exists(), "{}", w.display());
        }
        eprintln!(
            "{}: {} images in {:?}",
            script.display(),
            written.len(),
            t.elapsed()
        );
    }
}

/// The generated data sets (`examples/*/generate.py` write a `.hmesh` with their own HyperMesh
/// writer and a `.summary` of what it holds, computed with numpy): VoRANG must read every
/// fact of the summary back — counts, orientation, total volume, field ranges, material names
/// and cell counts — so its reader is checked against an independent writer.
#[test]
fn generated_data_sets_read_as_their_generators_wrote_them() {
    use vorang::data::Values;

    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut summaries: Vec<_> = std::fs::read_dir(&examples)
        .unwrap()
        .flat_map(|d| std::fs::read_dir(d.unwrap().path()).into_iter().flatten())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "summary"))
        .collect();
    summaries.sort();
    assert!(summaries.len() >= 2, "{summaries:?}");
    for summary in &summaries {
        let text = std::fs::read_to_string(summary).unwrap();
        let dir = summary.parent().unwrap();
        let mut vol = None;
        let mut checked = 0;
        for line in text.lines().filter(|l| !l.starts_with('#')) {
            let w: Vec<&str> = line.split_whitespace().collect();
            let at = format!("{}: {line}", summary.display());
            if w[0] == "file" {
                vol = Some(Volume::load(&dir.join(w[1])).unwrap().0);
                continue;
            }
            let v: &Volume = vol.as_ref().expect("a 'file' line first");
            let m = &v.mesh;
            let raw_of = |name: &str| {
                let f = v
                    .data
                    .fields
                    .iter()
                    .find(|f| f.name.as_deref() == Some(name));
                &v.data.raw[f.unwrap_or_else(|| panic!("{at}: no field")).sources[0]].values
            };
            match w[0] {
                "nodes" => assert_eq!(m.node_count(), w[1].parse::<usize>().unwrap(), "{at}"),
                "tetrahedra" => {
                    assert_eq!(m.tet_count(), w[1].parse::<usize>().unwrap(), "{at}");
                    // The writer orients every cell right-handed (thesis appendix B, docs/formats.md).
                    assert_eq!(m.reoriented(), 0, "{at}");
                }
                "volume" => {
                    let total: f64 = (0..m.tet_count()).map(|t| m.tet_volume(t)).sum();
                    let want: f64 = w[1].parse().unwrap();
                    assert!((total - want).abs() <= 1e-9 * want, "{at}: {total}");
                }
                "field" => {
                    let Values::F32(values) = raw_of(w[1]) else {
                        panic!("{at}: not float data")
                    };
                    let lo = values.iter().copied().fold(f32::INFINITY, f32::min);
                    let hi = values.iter().copied().fold(f32::NEG_INFINITY, f32::max);
                    assert_eq!(f64::from(lo), w[2].parse::<f64>().unwrap(), "{at}");
                    assert_eq!(f64::from(hi), w[3].parse::<f64>().unwrap(), "{at}");
                }
                "material" => {
                    let Values::U8(values) = raw_of(w[1]) else {
                        panic!("{at}: not byte data")
                    };
                    let id: u8 = w[2].parse().unwrap();
                    let materials = v.data.materials.as_ref().expect("a Materials block");
                    assert_eq!(
                        materials.get(id).map(|m| m.name.as_str()),
                        Some(w[3]),
                        "{at}"
                    );
                    let count = values.iter().filter(|&&b| b == id).count();
                    assert_eq!(count, w[4].parse::<usize>().unwrap(), "{at}");
                }
                other => panic!("{at}: unknown fact '{other}'"),
            }
            checked += 1;
        }
        assert!(checked >= 6, "{}: {checked} facts", summary.display());
    }
}
