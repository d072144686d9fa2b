//! `mpirun -np N vorang script.tcl` (docs/distributed.md), for builds with the `mpi` feature
//! (`cargo test --features mpi --test mpi`; Open MPI's `mpirun` on the PATH): for N = 1 … 4
//! the images equal those of `vorang --virtual-ranks N` bit for bit — a single file split by
//! Morton order, `.pvtu` grids of contiguous and scattered pieces and with an empty piece, views
//! from outside, mirrored and from inside — and a missing piece, a truncated piece or a rank
//! whose script fails stop every rank with that message and a non-zero exit, never a hang
//! (every run is under a time limit).

#![cfg(feature = "mpi")]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use vorang::distributed::write::write_pvtu;
use vorang::hypermesh::{Encoding, Layout, WriteOptions};

const BIN: &str = env!("CARGO_BIN_EXE_vorang");

/// A run may take this long; past it, it counts as a hang.
const LIMIT: Duration = Duration::from_secs(120);

/// Runs `cmd` in `dir` under [`LIMIT`], killing it on a hang.
fn run(mut cmd: Command, dir: &Path) -> Output {
    cmd.current_dir(dir)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("mpirun (Open MPI) must be on the PATH");
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return child.wait_with_output().unwrap();
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            let out = child.wait_with_output().unwrap();
            panic!(
                "{cmd:?} hung; stderr: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn mpirun(n: usize, script: &str, dir: &Path) -> Output {
    let mut cmd = Command::new("mpirun");
    cmd.args([
        "-np",
        &n.to_string(),
        "--oversubscribe",
        "--bind-to",
        "none",
        BIN,
        script,
    ]);
    run(cmd, dir)
}

fn virtual_ranks(n: usize, script: &str, dir: &Path) -> Output {
    let mut cmd = Command::new(BIN);
    cmd.args(["--virtual-ranks", &n.to_string(), script]);
    run(cmd, dir)
}

const MAPS: [(&str, &str); 2] = [
    (
        "c.map",
        "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 1 0.2\n1 1 0 0.5\n1 0 0 0.8\n",
    ),
    (
        "a.map",
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.5 0.2\n4 0.5\n1 0.8\n",
    ),
];

/// The inputs: a HyperMesh file (every rank reads it, keeps its Morton part) and `.pvtu` grids.
fn inputs(dir: &Path) -> Vec<String> {
    for (name, text) in MAPS {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let vol = vorang::volume::jittered_box_with_holes(3000, 0.1, 9, 0.1);
    let opts = WriteOptions {
        encoding: Encoding::Binary,
        layout: Layout::Small,
    };
    vorang::formats::save_volume(&vol, &dir.join("box.hm"), opts).unwrap();
    let n = vol.mesh.tet_count() as u32;
    let contiguous: Vec<Vec<u32>> = (0..3)
        .map(|p| (p * n / 3..(p + 1) * n / 3).collect())
        .collect();
    let scattered: Vec<Vec<u32>> = (0..3)
        .map(|p| (0..n).filter(|c| c % 3 == p).collect())
        .collect();
    let empty = vec![(0..n / 2).collect(), Vec::new(), (n / 2..n).collect()];
    write_pvtu(&vol, &dir.join("contiguous.pvtu"), &contiguous).unwrap();
    write_pvtu(&vol, &dir.join("scattered.pvtu"), &scattered).unwrap();
    write_pvtu(&vol, &dir.join("empty.pvtu"), &empty).unwrap();
    ["box.hm", "contiguous.pvtu", "scattered.pvtu", "empty.pvtu"]
        .map(String::from)
        .to_vec()
}

/// A script rendering `input` from four views into `out.NNNN.exr`.
fn views_script(input: &str, out: &str) -> String {
    format!(
        "volume {input}
imagesize 96 72
colormap c.map
alphamap a.map
method exact linear 0 1
output {out}.exr
render_btf
vol_rotate 1 0.6 0.2 33
render_btf
vol_scale -1 1 1
render_ftb
look_at 0.05 -0.1 0.12 0.4 0.2 -1 0 1 0
persp_camera 70 1.333 0.01 10
render_btf
"
    )
}

fn frames(dir: &Path, out: &str) -> Vec<PathBuf> {
    (1..=4)
        .map(|k| dir.join(format!("{out}.{k:04}.exr")))
        .collect()
}

#[test]
fn mpirun_equals_virtual_ranks_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for input in inputs(d) {
        for n in 1..=4 {
            let (m, v) = (format!("m{n}"), format!("v{n}"));
            std::fs::write(d.join("m.tcl"), views_script(&input, &m)).unwrap();
            std::fs::write(d.join("v.tcl"), views_script(&input, &v)).unwrap();
            let out = mpirun(n, "m.tcl", d);
            assert!(
                out.status.success(),
                "{input}, -np {n}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            // Only rank 0 prints the per-frame lines.
            let lines = String::from_utf8_lossy(&out.stdout);
            assert_eq!(
                lines.matches(".exr").count(),
                4,
                "{input}, -np {n}: {lines}"
            );
            let out = virtual_ranks(n, "v.tcl", d);
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            for (a, b) in frames(d, &m).iter().zip(frames(d, &v)) {
                let (a, b) = (std::fs::read(a).unwrap(), std::fs::read(&b).unwrap());
                assert!(a == b, "{input}, -np {n}: the images differ");
            }
        }
    }
}

/// Runs a failing script on `n` ranks: a non-zero exit, and `message` printed once.
fn fails_with(n: usize, script: &str, message: &str, dir: &Path) {
    std::fs::write(dir.join("f.tcl"), script).unwrap();
    let out = mpirun(n, "f.tcl", dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "-np {n} succeeded: {err}");
    assert_eq!(err.matches(message).count(), 1, "-np {n}: {err}");
}

#[test]
fn an_error_on_any_rank_stops_every_rank() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    inputs(d);
    // A missing piece: only the rank that reads it fails, every rank stops.
    let listed = std::fs::read_to_string(d.join("contiguous.pvtu")).unwrap();
    std::fs::write(
        d.join("missing.pvtu"),
        listed.replace("contiguous_2.vtu", "nowhere_2.vtu"),
    )
    .unwrap();
    let render = "imagesize 32 24\nmethod exact linear 0 1\noutput f.exr\nrender_btf\n";
    for n in [2, 3] {
        fails_with(
            n,
            &format!("volume missing.pvtu\n{render}"),
            "no such file",
            d,
        );
    }
    // A truncated piece.
    let piece = d.join("contiguous/contiguous_1.vtu");
    let bytes = std::fs::read(&piece).unwrap();
    std::fs::create_dir_all(d.join("cut")).unwrap();
    std::fs::write(d.join("cut/contiguous_1.vtu"), &bytes[..bytes.len() / 2]).unwrap();
    std::fs::write(
        d.join("cut.pvtu"),
        listed.replace("contiguous/contiguous_1.vtu", "cut/contiguous_1.vtu"),
    )
    .unwrap();
    fails_with(
        3,
        &format!("volume cut.pvtu\n{render}"),
        "contiguous_1.vtu",
        d,
    );
    // A rank whose script fails: the others stop at their next collective step, or at the end.
    let early =
        format!("volume box.hm\nif {{[rank] == 1}} {{error \"rank 1 gives up\"}}\n{render}");
    fails_with(3, &early, "rank 1 gives up", d);
    let late = format!("volume box.hm\n{render}if {{[rank] == 2}} {{error \"rank 2 gives up\"}}\n");
    fails_with(3, &late, "rank 2 gives up", d);
    // A map that does not fit the volume: every rank's error, printed once.
    std::fs::write(
        d.join("bad.map"),
        "# VoRANG Colormap 1.0\nSIMPLE_EMITTER field:7 @1\n@1\n0 0 1 0.2\n1 0 0 0.8\n",
    )
    .unwrap();
    fails_with(
        2,
        "volume box.hm\ncolormap bad.map\n",
        "has only field 0",
        d,
    );
}
