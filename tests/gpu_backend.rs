//! The GPU backend's switch and its shaders' rules, in every build: `backend` without the
//! feature (or without an adapter) is an error naming what is missing, and no WGSL source
//! calls a transcendental function (Vulkan defines `exp`, `log`, `pow` … for 32-bit floats
//! only; the shaders are f64 throughout: crates/vorang/src/gpu/).

#[cfg(feature = "gpu")]
mod common;

use std::path::PathBuf;

use vorang::Session;

#[test]
fn backend_switches_and_names_what_is_missing() {
    let mut s = Session::new();
    assert_eq!(s.backend().describe(), "cpu");
    assert_eq!(s.set_backend("cpu").unwrap(), "cpu");
    assert!(
        s.set_backend("tpu")
            .unwrap_err()
            .contains("expected cpu or gpu")
    );
    match s.set_backend("gpu") {
        Ok(name) => {
            if !cfg!(feature = "gpu") {
                panic!("a build without the gpu feature opened a GPU: {name}");
            }
            assert!(name.starts_with("gpu "), "{name}");
        }
        Err(e) => {
            assert!(e.starts_with("backend gpu: "), "{e}");
            if cfg!(feature = "gpu") {
                assert!(e.contains("Vulkan") || e.contains("SHADER_F64"), "{e}");
            } else {
                assert!(e.contains("--features gpu"), "{e}");
            }
            // Never a silent fallback: the session stays where it was.
            assert_eq!(s.backend().describe(), "cpu");
        }
    }
}

/// Words that name an f64 transcendental in WGSL (or its f32 versions, which the f64 shaders
/// must not reach for either).
const FORBIDDEN: &[&str] = &["exp", "exp2", "log", "log2", "pow", "erf", "erfc"];

#[test]
fn no_wgsl_source_calls_exp_log_pow_or_erf() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("crates/vorang/src/gpu/wgsl");
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "wgsl") {
            continue;
        }
        files += 1;
        let text = std::fs::read_to_string(&path).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            // Identifiers followed by '(' are calls.
            let chars: Vec<char> = code.chars().collect();
            let mut i = 0;
            while i < chars.len() {
                if chars[i].is_alphabetic() || chars[i] == '_' {
                    let start = i;
                    while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                        i += 1;
                    }
                    let word: String = chars[start..i].iter().collect();
                    let rest =
                        code[code.char_indices().nth(i).map_or(code.len(), |c| c.0)..].trim_start();
                    assert!(
                        !(FORBIDDEN.contains(&word.as_str()) && rest.starts_with('(')),
                        "{}:{}: `{word}` is not defined for f64 in Vulkan: use the series (integrate::linear_lanes)",
                        path.display(),
                        n + 1
                    );
                } else {
                    i += 1;
                }
            }
        }
    }
    assert!(files >= 4, "{files} WGSL files in {}", dir.display());
}

/// `vorang view` on the GPU (`backend gpu` before `view`, as `vorang view --gpu` sets it):
/// previews with `interpolateCoeff linear` and the refined frame on the GPU, and the saved
/// refined image is the CPU's. Needs Xvfb and a Vulkan adapter with 64-bit floats; skips
/// without them unless `VORANG_GPU_TESTS=required`.
#[cfg(feature = "gpu")]
#[test]
fn the_viewer_previews_and_refines_on_the_gpu() {
    let Some(x) = common::screen::Xvfb::start() else {
        return;
    };
    let mut probe = Session::new();
    if let Err(e) = probe.set_backend("gpu") {
        assert!(
            std::env::var("VORANG_GPU_TESTS").as_deref() != Ok("required"),
            "VORANG_GPU_TESTS=required but no GPU: {e}"
        );
        eprintln!("skipping the GPU viewer test: {e}");
        return;
    }
    let ex = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/hyperthermia");
    let scene = format!(
        "volume {{{}}}\ncolormap {{{}}}\nalphamap {{{}}}\nimagesize 64 48\nmethod exact linear 0 1\n",
        ex.join("hyperthermia.hmesh").display(),
        ex.join("red.cmap").display(),
        ex.join("heat.amap").display()
    );
    let dir = tempfile::tempdir().unwrap();
    let script = format!(
        r#"backend gpu
{scene}output saved.png
proc when_refined {{script}} {{
    if {{[string match "*·  refined  ·*" $::vorang::view_status]}} {{
        uplevel #0 $script
    }} else {{
        after 50 [list when_refined $script]
    }}
}}
after 300 {{when_refined {{
    event generate .vorang_view <KeyPress> -keysym p
    event generate .vorang_view <KeyPress> -keysym s
    event generate .vorang_view <KeyPress> -keysym q
}}}}
after 300000 {{event generate .vorang_view <KeyPress> -keysym q}}
view
"#
    );
    let run = |script: &str, display: Option<&str>| {
        std::fs::write(dir.path().join("script.tcl"), script).unwrap();
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"));
        c.arg("script.tcl")
            .current_dir(dir.path())
            .env("VORANG_TIMING", "1");
        match display {
            Some(d) => c.env("DISPLAY", d),
            None => c.env_remove("DISPLAY"),
        };
        c.output().unwrap()
    };
    let out = run(&script, Some(&x.display));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    let all = format!("{stdout}{stderr}");
    assert!(
        all.contains("interpolateCoeff linear (GPU)"),
        "the previews ran on the GPU: {all}"
    );
    let printed: Vec<&str> = stdout
        .lines()
        .skip_while(|l| !l.starts_with("# view:"))
        .skip(1)
        .take_while(|l| !l.contains("saved from the viewer"))
        .collect();
    let again = format!(
        "{scene}output again.png\n{}\nrender_btf\n",
        printed.join("\n")
    );
    let out = run(&again, None);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let saved = image::open(dir.path().join("saved.0001.png")).unwrap();
    let cpu = image::open(dir.path().join("again.0001.png")).unwrap();
    assert!(
        saved.to_rgba8() == cpu.to_rgba8(),
        "the GPU's refined frame is the CPU's image"
    );
}

/// The numbers of a PFM image (`PF`/`Pf`, width height, scale: little-endian when negative).
#[cfg(feature = "gpu")]
fn pfm(path: &std::path::Path) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap();
    let mut at = 0;
    let mut line = || {
        let end = at + bytes[at..].iter().position(|&b| b == b'\n').unwrap();
        let text = String::from_utf8(bytes[at..end].to_vec()).unwrap();
        at = end + 1;
        text
    };
    let (_, _, scale) = (line(), line(), line());
    let little = scale.trim().parse::<f64>().unwrap() < 0.0;
    bytes[at..]
        .chunks_exact(4)
        .map(|c| {
            let b = [c[0], c[1], c[2], c[3]];
            if little {
                f32::from_le_bytes(b)
            } else {
                f32::from_be_bytes(b)
            }
        })
        .collect()
}

/// Maps of many knots (256, emission weighted by absorption: a colormap sampled as
/// `vorang.plot` samples one) on
/// `examples/inclusion`, every method the GPU renders, both orders: the GPU's image is the
/// CPU's. With 70 knots and more the GPU's image once differed by up to 0.9: lavapipe cut the
/// march's loops short (docs/gpu.md).
#[cfg(feature = "gpu")]
#[test]
fn maps_with_many_knots_give_the_cpus_image_on_the_gpu() {
    if Session::new().set_backend("gpu").is_err() {
        assert!(
            std::env::var("VORANG_GPU_TESTS").as_deref() != Ok("required"),
            "VORANG_GPU_TESTS=required but no GPU"
        );
        eprintln!("no GPU adapter: skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let volume = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/inclusion/inclusion.vtu");
    let methods = [
        ("exact", "exact linear 0 1"),
        ("coeff", "interpolateCoeff linear 1"),
        ("color", "interpolateColor 1"),
    ];
    for (knots, colors) in [
        (70, "SIMPLE_EMITTER"),
        (256, "SIMPLE_EMITTER"),
        (256, "ABSORPTION_WEIGHTED"),
    ] {
        let mut cmap = format!("# VoRANG Colormap 1.0\n{colors} @1\n@1\n");
        let mut amap = String::from("# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n");
        for i in 0..knots {
            let t = i as f64 / (knots - 1) as f64;
            let s = 0.1 + 0.5 * t;
            cmap += &format!("{t} {} 0.5 {s}\n", 1.0 - t);
            amap += &format!("{} {s}\n", 0.5 + 3.0 * t * t);
        }
        std::fs::write(dir.path().join("m.cmap"), cmap).unwrap();
        std::fs::write(dir.path().join("m.amap"), amap).unwrap();
        let mut script = format!(
            "imagesize 64 48\nvolume {{{}}}\ncolormap m.cmap\nalphamap m.amap\nlinedraw off\nview_all\n",
            volume.display()
        );
        for (name, method) in methods {
            for order in ["btf", "ftb"] {
                for backend in ["cpu", "gpu"] {
                    script += &format!(
                        "method {method}\nbackend {backend}\noutput {backend}_{name}_{order}.pfm\nrender_{order}\n"
                    );
                }
            }
        }
        std::fs::write(dir.path().join("s.tcl"), script).unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
            .arg("s.tcl")
            .current_dir(dir.path())
            .env("XDG_RUNTIME_DIR", std::env::temp_dir())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{colors} {knots} knots: {}{}",
            String::from_utf8_lossy(&out.stderr),
            String::from_utf8_lossy(&out.stdout)
        );
        for (name, _) in methods {
            for order in ["btf", "ftb"] {
                let read = |b: &str| pfm(&dir.path().join(format!("{b}_{name}_{order}.0001.pfm")));
                let (cpu, gpu) = (read("cpu"), read("gpu"));
                assert_eq!(cpu.len(), gpu.len());
                let (mut over, mut worst) = (0, 0.0f64);
                for (a, b) in cpu.iter().zip(&gpu) {
                    let d = (f64::from(*a) - f64::from(*b)).abs();
                    over += usize::from(d > 1e-12);
                    worst = worst.max(d);
                }
                let what = format!("{colors} {knots} knots {name} {order}");
                eprintln!("{what}: {over} channels differ, largest {worst:e}");
                assert!(over == 0, "{what}: {over} channels differ, up to {worst:e}");
            }
        }
    }
}
