//! Every demonstration script in `examples/` runs and writes its images. The scripts run on a
//! copy of the folder, so nothing is written into the repository.

use std::path::Path;

use vorang::script::{Collect, Runner};

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
        let written = runner.session().written.clone();
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
