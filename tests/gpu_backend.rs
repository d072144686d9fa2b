//! The GPU backend's switch and its shaders' rules, in every build: `backend` without the
//! feature (or without an adapter) is an error naming what is missing, and no WGSL source
//! calls a transcendental function (Vulkan defines `exp`, `log`, `pow` … for 32-bit floats
//! only; the shaders are f64 throughout: crates/vorang/src/gpu/).

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
