//! Random script commands with hostile arguments — image sizes, methods and steps, transforms,
//! cameras, backgrounds, image numbers — run on a small mesh: every command must succeed or fail
//! with a message, never panic, abort or hang.
#![no_main]

use std::fmt::Write;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use vorang_tcl::script::{Collect, Runner};

/// Numbers the fuzzer picks from: the edges of every parameter's range and beyond.
const NUMBERS: &[&str] = &[
    "0",
    "1",
    "-1",
    "2",
    "0.5",
    "90",
    "180",
    "360",
    "-90",
    "1e-300",
    "-1e-300",
    "1e300",
    "-1e300",
    "1e308",
    "1.797e308",
    "4.9e-324",
    "nan",
    "inf",
    "-inf",
    "1e-20",
    "1e-7",
    "0.01",
    "179.99999999",
    "1e6",
    "4294967295",
    "4294967294",
    "-0",
    "3",
    "7",
    "x",
    "",
];

/// Image sizes: small valid ones (a 4096² frame takes over 10 s in the instrumented build, which
/// is not what this target looks for) and ones that must be refused.
const SIZES: &[&str] = &[
    "1", "2", "7", "33", "64", "0", "-3", "2000000", "1048577", "300", "x",
];

const METHODS: &[&str] = &[
    "exact linear",
    "exact constEA",
    "exact trapez",
    "exact weightedConstEA",
    "interpolateCoeff linear",
    "interpolateCoeff constEA",
    "interpolateColor",
    "test",
    "exact simpson",
    "splat",
];

fn dir() -> &'static std::path::Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| tempfile::tempdir().expect("temporary folder"))
        .path()
}

struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn byte(&mut self) -> Option<u8> {
        let (&b, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(b)
    }
    fn pick<'a>(&mut self, from: &'a [&'a str]) -> Option<&'a str> {
        Some(from[self.byte()? as usize % from.len()])
    }
    fn num(&mut self) -> Option<String> {
        let b = self.byte()?;
        if b < 200 {
            return Some(NUMBERS[b as usize % NUMBERS.len()].to_string());
        }
        // A random double from the next eight bytes.
        let mut bits = [0u8; 8];
        for x in &mut bits {
            *x = self.byte()?;
        }
        Some(format!("{:e}", f64::from_le_bytes(bits)))
    }
}

fn script(data: &[u8]) -> String {
    let mut b = Bytes(data);
    let mut s = String::new();
    let mesh = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/two_tets_data.hmesh"
    );
    let _ = writeln!(s, "volume {{{mesh}}}");
    let _ = writeln!(s, "imagesize 8 8");
    let _ = writeln!(s, "output {{{}/f.pfm}}", dir().display());
    for _ in 0..12 {
        let Some(op) = b.byte() else { break };
        let line = match op % 16 {
            0 => format!(
                "imagesize {} {}",
                b.pick(SIZES).unwrap_or("1"),
                b.pick(SIZES).unwrap_or("1")
            ),
            1 => {
                let m = b.pick(METHODS).unwrap_or("test");
                match m {
                    "interpolateColor" | "test" | "splat" => {
                        format!("method {m} {}", b.num().unwrap_or_default())
                    }
                    _ if m.starts_with("interpolateCoeff") => {
                        format!("method {m} {}", b.num().unwrap_or_default())
                    }
                    _ => format!(
                        "method {m} {} {}",
                        b.num().unwrap_or_default(),
                        b.num().unwrap_or_default()
                    ),
                }
            }
            2 => format!(
                "vol_rotate {} {} {} {}",
                b.num().unwrap_or_default(),
                b.num().unwrap_or_default(),
                b.num().unwrap_or_default(),
                b.num().unwrap_or_default()
            ),
            3 => format!(
                "vol_scale {} {} {}",
                b.num().unwrap_or_default(),
                b.num().unwrap_or_default(),
                b.num().unwrap_or_default()
            ),
            4 => format!(
                "vol_translate {} {} {}",
                b.num().unwrap_or_default(),
                b.num().unwrap_or_default(),
                b.num().unwrap_or_default()
            ),
            5 => {
                let v: Vec<String> = (0..9).map(|_| b.num().unwrap_or_default()).collect();
                format!("look_at {}", v.join(" "))
            }
            6 => {
                let v: Vec<String> = (0..4).map(|_| b.num().unwrap_or_default()).collect();
                format!("persp_camera {}", v.join(" "))
            }
            7 => {
                let v: Vec<String> = (0..6).map(|_| b.num().unwrap_or_default()).collect();
                format!("ortho_camera {}", v.join(" "))
            }
            8 => format!(
                "background {} {} {}",
                b.num().unwrap_or_default(),
                b.num().unwrap_or_default(),
                b.num().unwrap_or_default()
            ),
            9 => format!("set_nr {}", b.num().unwrap_or_default()),
            10 => format!(
                "linedraw {}",
                b.pick(&["on", "off", "all", "boundary", "x"])
                    .unwrap_or("off")
            ),
            11 => "render_ftb".to_string(),
            12 => format!(
                "background {}",
                b.pick(&["clear", "none", "x.png"]).unwrap_or("clear")
            ),
            _ => "render_btf".to_string(),
        };
        s.push_str(&line);
        s.push('\n');
    }
    s.push_str("render_btf\n");
    s
}

fuzz_target!(|data: &[u8]| {
    let text = script(data);
    let mut runner = Runner::new(Box::new(Collect::default()));
    // Each command in its own evaluation, so that one error does not stop the rest.
    for line in text.lines() {
        let _ = runner.run_string(&format!("catch {{{line}}}"), "fuzz");
    }
});
