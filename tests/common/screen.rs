//! A virtual X display for the window tests: Xvfb, started per test, and
//! screenshots read back from `xwd` files. CI installs both (`.ci/run`); where they are missing
//! the tests say so and skip.

#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};

/// A running Xvfb server, stopped when dropped.
pub struct Xvfb {
    child: Child,
    /// `:N`, for `DISPLAY`.
    pub display: String,
}

impl Xvfb {
    /// Starts Xvfb on a free display (24-bit TrueColor, so 8-bit pixels arrive unchanged), or
    /// `None` with a message where Xvfb or xwd is not installed.
    pub fn start() -> Option<Xvfb> {
        for tool in ["Xvfb", "xwd"] {
            if Command::new("sh")
                .args(["-c", &format!("command -v {tool}")])
                .stdout(Stdio::null())
                .status()
                .map_or(true, |s| !s.success())
            {
                skip_or_fail(&format!(
                    "{tool} is not installed (apt-get install xvfb x11-apps; .ci/run installs them)"
                ));
                return None;
            }
        }
        // -displayfd: Xvfb picks a free display itself and writes its number once it is ready.
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1280x1024x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start Xvfb");
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("Xvfb's stdout"))
            .read_line(&mut line)
            .expect("read Xvfb's display number");
        let number = line.trim();
        assert!(!number.is_empty(), "Xvfb gave no display number");
        let x = Xvfb {
            child,
            display: format!(":{number}"),
        };
        // The windows load Tk at run time: without it there is nothing to test here.
        let tk = Command::new(env!("CARGO_BIN_EXE_vorang"))
            .args(["-e", "package require Tk 8.6"])
            .env("DISPLAY", &x.display)
            .output()
            .expect("run vorang");
        if !tk.status.success() {
            skip_or_fail(&format!(
                "Tk 8.6 cannot be loaded (apt-get install tk-dev): {}",
                String::from_utf8_lossy(&tk.stderr).trim()
            ));
            return None;
        }
        Some(x)
    }
}

/// Says why a window test is skipped — or fails, under `.ci/run`, which installs everything
/// the window tests need (`VORANG_WINDOW_TESTS=required`).
fn skip_or_fail(why: &str) {
    assert!(
        std::env::var_os("VORANG_WINDOW_TESTS").is_none_or(|v| v != "required"),
        "{why}"
    );
    eprintln!("skipping: {why}");
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// An X window dump (`xwd`, ZPixmap, TrueColor) as 8-bit RGB rows.
pub struct Shot {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<[u8; 3]>,
}

impl Shot {
    /// Reads an `xwd` file.
    pub fn read(path: &Path) -> Shot {
        let data = std::fs::read(path).expect("read the xwd file");
        let field = |i: usize| u32::from_be_bytes(data[4 * i..4 * i + 4].try_into().unwrap());
        let (header, format, width, height) = (field(0), field(2), field(4), field(5));
        let (byte_order, bpp, stride) = (field(7), field(11), field(12));
        let masks = [field(14), field(15), field(16)];
        let ncolors = field(19);
        assert_eq!(format, 2, "ZPixmap");
        assert!(bpp == 32 || bpp == 24, "{bpp} bits per pixel");
        let start = header as usize + 12 * ncolors as usize;
        let bytes = bpp as usize / 8;
        let mut rgb = Vec::new();
        for y in 0..height as usize {
            for x in 0..width as usize {
                let at = start + y * stride as usize + x * bytes;
                let mut b = [0u8; 4];
                b[..bytes].copy_from_slice(&data[at..at + bytes]);
                let v = if byte_order == 0 {
                    u32::from_le_bytes(b)
                } else {
                    u32::from_be_bytes(b) >> (8 * (4 - bytes))
                };
                rgb.push(masks.map(|m| ((v & m) >> m.trailing_zeros()) as u8));
            }
        }
        Shot {
            width: width as usize,
            height: height as usize,
            rgb,
        }
    }
}

/// The RGB pixels of an image file.
pub fn image_rgb(path: &Path) -> (usize, usize, Vec<[u8; 3]>) {
    let img = image::open(path).expect("open the image").to_rgb8();
    let (w, h) = img.dimensions();
    (w as usize, h as usize, img.pixels().map(|p| p.0).collect())
}
