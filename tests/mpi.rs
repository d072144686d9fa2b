//! `mpirun -np N vorang script.tcl` (docs/distributed.md), for builds with the `mpi` feature
//! (`cargo test --features mpi --test mpi`; Open MPI's `mpirun` on the PATH). For N = 1 … 5
//! one script per N renders every input from five views; its images equal those of
//! `vorang --virtual-ranks N` bit for bit, and those of the plain program (one process, the
//! whole mesh) to within one `f32` ulp per channel. Inputs: a HyperMesh file every rank reads
//! and splits by Morton order; `.pvtu` grids of contiguous pieces, of pieces scattered cell by
//! cell, with an empty piece; VTK's own pieces (vtkXMLPUnstructuredGridWriter,
//! tests/data/mpi) with ghost layers and `GlobalNodeIds`, 3 pieces (so N = 4, 5 have more
//! ranks than pieces) and 5 pieces; and a `.pvd` time series of `.pvtu` steps. Views: the
//! default (axis-aligned), rotated and framed by `view_all`, mirrored (`render_ftb`), the eye
//! inside the volume, perspective from outside framed by `view_all`. A missing piece, a
//! truncated piece, pieces with other arrays, a rank whose script fails before, while or after
//! the others render and a map that does not fit stop every rank with that message, printed
//! once, and a non-zero exit — never a hang (every run is under a time limit). The default
//! method `test` and an opaque `render_ftb` render on ranks. Two unbound ranks divide the
//! node's cores between their render threads unless `RAYON_NUM_THREADS` sets them.

#![cfg(feature = "mpi")]

use std::path::Path;
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

/// The inputs (as the ranks read them), each with the file one process renders whole.
fn inputs(dir: &Path) -> Vec<(String, String)> {
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
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let vtk = |f: &str| data.join("mpi").join(f).display().to_string();
    let mut out: Vec<(String, String)> =
        ["box.hm", "contiguous.pvtu", "scattered.pvtu", "empty.pvtu"]
            .iter()
            .map(|f| (f.to_string(), "box.hm".to_string()))
            .collect();
    out.push((vtk("box_g3.pvtu"), vtk("box.vtu")));
    out.push((vtk("box_p5.pvtu"), vtk("box.vtu")));
    out
}

/// The time series: VTK's `.pvtu` steps with ghost cells, listed by a `.pvd`.
fn series() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/series/flow_p.pvd")
        .display()
        .to_string()
}

/// Five views of the volume just loaded, into `{out}{k}.NNNN.pfm`.
fn views(k: usize, out: &str) -> String {
    format!(
        "imagesize 80 60
colormap c.map
alphamap a.map
method exact linear 0 1
output {out}{k}.pfm
render_btf
vol_rotate 1 0.6 0.2 33
view_all
render_btf
vol_scale -1 1 1
render_ftb
look_at 0.05 -0.1 0.12 0.4 0.2 -1 0 1 0
persp_camera 70 1.333 0.01 10
render_btf
look_at 1.6 1.2 2.5 0 0 0 0 1 0
persp_camera 40 1.333 0.1 10
view_all
render_btf
"
    )
}

/// One script rendering every input (`whole`: the one-process files instead) and two steps
/// of the time series; returns it and the number of images.
fn script(inputs: &[(String, String)], whole: bool, out: &str) -> (String, usize) {
    let mut text = String::new();
    for (k, (ranks, one)) in inputs.iter().enumerate() {
        text += &format!("volume {}\n", if whole { one } else { ranks });
        text += &views(k, out);
    }
    let k = inputs.len();
    text += &format!(
        "volume {}\nimagesize 80 60\ncolormap c.map\nalphamap a.map\nmethod exact linear 0 1\n\
         vol_rotate 0.3 1 0.2 25\nview_all\noutput {out}{k}.pfm\nrender_btf\ntimestep 2\nrender_btf\n",
        series()
    );
    (text, inputs.len() * 5 + 2)
}

/// The images a run wrote with file names starting `prefix`, by the rest of their name.
fn images(dir: &Path, prefix: &str) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().into_string().unwrap();
            let rest = name.strip_prefix(prefix)?.to_string();
            rest.ends_with(".pfm")
                .then(|| (rest, std::fs::read(dir.join(&name)).unwrap()))
        })
        .collect();
    out.sort();
    out
}

/// Channels that differ, and the most `f32` ulps one differs by.
fn ulps(a: &[u8], b: &[u8]) -> (usize, u32) {
    let (wa, ha, pa) = vorang::framebuffer::read_pfm(a).unwrap();
    let (wb, hb, pb) = vorang::framebuffer::read_pfm(b).unwrap();
    assert_eq!((wa, ha), (wb, hb));
    let (mut differ, mut most) = (0, 0);
    for (p, q) in pa.iter().zip(&pb) {
        for k in 0..3 {
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

#[test]
fn mpirun_equals_virtual_ranks_and_one_process() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let inputs = inputs(d);
    let (plain, count) = script(&inputs, true, "p");
    std::fs::write(d.join("p.tcl"), plain).unwrap();
    let mut cmd = Command::new(BIN);
    cmd.arg("p.tcl");
    let out = run(cmd, d);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let whole = images(d, "p");
    assert_eq!(whole.len(), count);
    for (name, bytes) in &whole {
        let (_, _, px) = vorang::framebuffer::read_pfm(bytes).unwrap();
        let most = px.iter().flatten().fold(0.0f32, |m, &v| m.max(v));
        assert!(most > 0.01, "{name}: nothing to see");
    }
    let mut report = Vec::new();
    for n in 1..=5 {
        let (m, v) = (format!("m{n}_"), format!("v{n}_"));
        std::fs::write(d.join("m.tcl"), script(&inputs, false, &m).0).unwrap();
        std::fs::write(d.join("v.tcl"), script(&inputs, false, &v).0).unwrap();
        let out = mpirun(n, "m.tcl", d);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "-np {n}: {err}");
        // Only rank 0 prints the per-frame lines.
        let lines = String::from_utf8_lossy(&out.stdout);
        assert_eq!(lines.matches(".pfm").count(), count, "-np {n}: {lines}");
        let out = virtual_ranks(n, "v.tcl", d);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (mi, vi) = (images(d, &m), images(d, &v));
        assert_eq!(mi.len(), count, "-np {n}");
        assert_eq!(vi.len(), count, "--virtual-ranks {n}");
        let (mut differ, mut most) = (0, 0);
        for (((name, a), (_, b)), (_, w)) in mi.iter().zip(&vi).zip(&whole) {
            assert!(a == b, "-np {n}, {name}: mpirun and virtual ranks differ");
            let (k, u) = ulps(a, w);
            assert!(
                u <= 1,
                "-np {n}, {name}: {k} channels differ from one process by up to {u} ulps"
            );
            differ += k;
            most = most.max(u);
        }
        report.push(format!(
            "-np {n}: {count} images equal --virtual-ranks {n} bit for bit; against one process {differ} channels differ (at most {most} ulp)"
        ));
    }
    eprintln!("{}", report.join("\n"));
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
    // A rank that fails while the others render: at its second frame of three.
    let during = format!(
        "volume box.hm\n{}for {{set i 0}} {{$i < 3}} {{incr i}} {{\n\
         if {{[rank] == 1 && $i == 1}} {{error \"rank 1 fails at frame 1\"}}\nrender_btf\n}}\n",
        &render[..render.len() - "render_btf\n".len()]
    );
    fails_with(3, &during, "rank 1 fails at frame 1", d);
}

/// VTK's 5 pieces with the point array `T` of the last piece renamed: one process, and each
/// rank merging its own pieces, see the pieces' arrays disagree; ranks that each read other
/// pieces compare their arrays at `volume` — the same message on every rank count.
#[test]
fn pieces_with_other_arrays_stop_every_rank() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    inputs(d);
    let vtk = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mpi");
    std::fs::create_dir_all(d.join("box_p5")).unwrap();
    for k in 0..5 {
        let name = format!("box_p5/box_p5_{k}.vtu");
        let mut bytes = std::fs::read(vtk.join(&name)).unwrap();
        if k == 4 {
            let text = String::from_utf8_lossy(&bytes).into_owned();
            let at = text.find("Name=\"T\"").expect("the array T");
            bytes[at + 6] = b'U';
        }
        std::fs::write(d.join(&name), bytes).unwrap();
    }
    std::fs::copy(vtk.join("box_p5.pvtu"), d.join("box_p5.pvtu")).unwrap();
    let script =
        "volume box_p5.pvtu\nimagesize 32 24\nmethod exact linear 0 1\noutput f.pfm\nrender_btf\n";
    for n in [1, 2, 3, 5] {
        fails_with(n, script, "the pieces' arrays disagree", d);
    }
}

/// The default method (`test`: each face once per ray, also the faces between two ranks'
/// cells) and `render_ftb` where pixels turn opaque (the ranks composite every cell, with a
/// note) on 1 … 3 ranks: the images of `--virtual-ranks` bit for bit, and of one process
/// (`render_btf` for the opaque one) within one `f32` ulp.
#[test]
fn the_default_method_and_an_opaque_render_ftb_on_ranks() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    inputs(d);
    std::fs::write(
        d.join("dense.map"),
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n400 0\n400 1\n",
    )
    .unwrap();
    let script = |out: &str| {
        format!(
            "volume box.hm\nimagesize 48 36\nview_all\noutput {out}t.pfm\nrender_btf\n\
             colormap c.map\nalphamap dense.map\nmethod exact linear 0 1\n\
             output {out}o.pfm\nrender_ftb\n"
        )
    };
    let one = script("p").replace("render_ftb", "render_btf");
    std::fs::write(d.join("p.tcl"), one).unwrap();
    let mut cmd = Command::new(BIN);
    cmd.arg("p.tcl");
    let out = run(cmd, d);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let whole = images(d, "p");
    assert_eq!(whole.len(), 2);
    for n in 1..=3 {
        let (m, v) = (format!("m{n}_"), format!("v{n}_"));
        std::fs::write(d.join("m.tcl"), script(&m)).unwrap();
        std::fs::write(d.join("v.tcl"), script(&v)).unwrap();
        let out = mpirun(n, "m.tcl", d);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "-np {n}: {err}");
        let said = format!("{err}{}", String::from_utf8_lossy(&out.stdout));
        assert_eq!(said.matches("turned opaque").count(), 1, "-np {n}: {said}");
        let out = virtual_ranks(n, "v.tcl", d);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (mi, vi) = (images(d, &m), images(d, &v));
        assert_eq!(mi.len(), 2, "-np {n}");
        for (((name, a), (_, b)), (_, w)) in mi.iter().zip(&vi).zip(&whole) {
            assert!(a == b, "-np {n}, {name}: mpirun and virtual ranks differ");
            let (k, u) = ulps(a, w);
            assert!(
                u <= 1,
                "-np {n}, {name}: {k} channels differ from one process by {u} ulps"
            );
        }
    }
}

/// The render threads of rank 0, from the timing line of its one frame.
fn threads_said(out: &Output) -> usize {
    let lines = String::from_utf8_lossy(&out.stdout);
    let said = lines
        .lines()
        .find_map(|l| l.split_once(" threads").map(|(head, _)| head))
        .and_then(|head| head.rsplit(' ').next())
        .and_then(|n| n.parse().ok());
    said.unwrap_or_else(|| panic!("no thread count in: {lines}"))
}

/// Two unbound ranks on one node divide its cores (each rank runs its part of the CPUs it may
/// run on, not all of them), `RAYON_NUM_THREADS` still sets the threads, and the image is the
/// same bit for bit.
#[test]
fn ranks_on_one_node_divide_its_cores() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    inputs(d);
    let script = |out: &str| {
        format!("volume box.hm\nimagesize 48 36\nview_all\noutput {out}.pfm\nrender_btf\n")
    };
    std::fs::write(d.join("s.tcl"), script("s")).unwrap();
    std::fs::write(d.join("r.tcl"), script("r")).unwrap();
    let two = |file: &str, threads: Option<&str>| {
        let mut cmd = Command::new("mpirun");
        cmd.args([
            "-np",
            "2",
            "--oversubscribe",
            "--bind-to",
            "none",
            BIN,
            file,
        ])
        .env("VORANG_TIMING", "1")
        .env_remove("RAYON_NUM_THREADS")
        .env_remove("RAYON_RS_NUM_CPUS");
        if let Some(n) = threads {
            cmd.env("RAYON_NUM_THREADS", n);
        }
        let out = run(cmd, d);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{file}: {err}");
        out
    };
    // Unbound, both ranks may run on the CPUs this test may run on.
    let mine = vorang_mpi::cores::affinity();
    let cpus: u32 = mine.iter().map(|w| w.count_ones()).sum();
    let part = vorang_mpi::cores::threads(&[mine.clone(), mine], 0);
    assert!(
        part <= (cpus as usize).div_ceil(2),
        "{part} threads of {cpus} CPUs"
    );
    assert_eq!(threads_said(&two("s.tcl", None)), part);
    assert_eq!(threads_said(&two("r.tcl", Some("3"))), 3);
    let (s, r) = (images(d, "s"), images(d, "r"));
    assert_eq!(s.len(), 1);
    assert!(s[0].1 == r[0].1, "the thread count changed the image");
}
