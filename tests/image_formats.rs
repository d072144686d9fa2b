//! The hand-written image formats (`crates/vorang/src/framebuffer/codec/`) checked against independent
//! readers. `tests/data/images/` holds two small sample pictures written in each format and, in
//! `expected/`, what Pillow, ImageMagick, Netpbm and Ghostscript decode from those very files
//! (made by `tests/data/images/make_expected.py`, which says how to run it). The tests here:
//!
//! 1. the writers still produce exactly the committed sample files (so the independent
//!    decodings apply to today's writers; `VORANG_BLESS=1` rewrites the samples, after which the
//!    script must be run again);
//! 2. every independent decoding holds the pixels the writer meant: 8-bit RGB of the
//!    framebuffer, or black and white by the luminance threshold for the 1-bit formats;
//! 3. `background` reads every written format that has a reader back to those pixels;
//! 4. the readers refuse truncated and corrupted files with a message, never a panic.

use std::path::{Path, PathBuf};

use vorang::framebuffer::{BackgroundImage, FORMATS, Framebuffer, Read, write_image};

/// The formats checked here, by canonical extension, with the readers whose decodings are
/// committed (each must exist for every sample).
const CHECKED: &[(&str, &[&str])] = &[
    ("rgb", &["pillow", "imagemagick", "netpbm"]),
    ("pbm", &["pillow", "imagemagick"]),
    ("xbm", &["imagemagick", "netpbm", "pillow"]),
    ("xwd", &["imagemagick", "netpbm"]),
    ("ras", &["pillow", "imagemagick", "netpbm"]),
    ("pcx", &["pillow", "imagemagick", "netpbm"]),
    ("eps", &["pillow", "ghostscript"]),
    ("ps", &["ghostscript"]),
    ("pict", &["imagemagick"]),
    ("iff", &["netpbm"]),
    ("x", &["imagemagick"]),
    ("viff", &["imagemagick"]),
    ("rle", &["imagemagick", "netpbm"]),
];

/// The 1-bit formats: white where the luminance is at least 0.5.
const ONE_BIT: &[&str] = &["pbm", "xbm"];

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/images")
}

/// `small`: 7 × 5 (an odd width, to catch row padding) of distinct colours with values above
/// 1 and below 0, bright values (≥ 0xC0, PCX's run marker) and a uniform bottom row (runs).
/// `wide`: 300 × 2, long runs (over 63, 128 and 255 pixels: every coder's longest) and a
/// ramp, and rows over 250 bytes (PICT's two-byte counts).
fn samples() -> Vec<(&'static str, Framebuffer)> {
    let (w, h) = (7, 5);
    let mut small = Framebuffer::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let r = x as f32 / (w - 1) as f32;
            let g = y as f32 / (h - 1) as f32;
            let b = [2.5, -0.5, 0.25, 0.9, 0.6, 0.1, 0.75][x];
            small.pixels[y * w + x] = if y == h - 1 {
                [0.8, 0.3, 1.5, 1.0]
            } else {
                [r, g, b, 1.0]
            };
        }
    }
    let mut wide = Framebuffer::new(300, 2);
    for x in 0..300 {
        let step = if x < 280 { 0.2 } else { 0.9 };
        wide.pixels[x] = [step, 1.0 - step, 0.5, 1.0];
        let ramp = (x % 256) as f32 / 255.0;
        wide.pixels[300 + x] = [ramp, 1.0 - ramp, (x % 7) as f32 / 6.0, 1.0];
    }
    vec![("small", small), ("wide", wide)]
}

/// What an 8-bit reader must see at pixel `p` (clipped, rounded), or the 1-bit threshold.
fn intended(p: &[f32; 4], one_bit: bool) -> [u8; 3] {
    let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    if one_bit {
        let y = 0.299 * p[0].clamp(0.0, 1.0)
            + 0.587 * p[1].clamp(0.0, 1.0)
            + 0.114 * p[2].clamp(0.0, 1.0);
        [if y >= 0.5 { 255 } else { 0 }; 3]
    } else {
        [q(p[0]), q(p[1]), q(p[2])]
    }
}

/// A binary `P6` file with maximum value 255: (width, height, RGB bytes).
fn read_ppm(path: &Path) -> (usize, usize, Vec<u8>) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut fields = Vec::new();
    let mut pos = 0;
    while fields.len() < 4 {
        while bytes[pos].is_ascii_whitespace() || bytes[pos] == b'#' {
            if bytes[pos] == b'#' {
                while bytes[pos] != b'\n' {
                    pos += 1;
                }
            }
            pos += 1;
        }
        let start = pos;
        while !bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        fields.push(String::from_utf8_lossy(&bytes[start..pos]).into_owned());
    }
    assert_eq!(fields[0], "P6", "{}", path.display());
    assert_eq!(fields[3], "255", "{}", path.display());
    let (w, h) = (fields[1].parse().unwrap(), fields[2].parse().unwrap());
    let rgb = bytes[pos + 1..].to_vec();
    assert_eq!(rgb.len(), w * h * 3, "{}", path.display());
    (w, h, rgb)
}

#[test]
fn writers_still_produce_the_checked_files() {
    let bless = std::env::var_os("VORANG_BLESS").is_some();
    let dir = tempfile::tempdir().unwrap();
    let mut stale = Vec::new();
    for (name, fb) in samples() {
        for (ext, _) in CHECKED {
            let file = format!("{name}.{ext}");
            let written = dir.path().join(&file);
            write_image(&fb, &written).unwrap();
            let now = std::fs::read(&written).unwrap();
            let committed = data().join(&file);
            if bless {
                std::fs::write(&committed, &now).unwrap();
            } else if std::fs::read(&committed).ok().as_ref() != Some(&now) {
                stale.push(file);
            }
        }
    }
    assert!(
        stale.is_empty(),
        "{stale:?} differ from what the writers produce now: run `VORANG_BLESS=1 cargo test \
         --test image_formats`, then `tests/data/images/make_expected.py` to check them again"
    );
}

#[test]
fn independent_readers_see_the_intended_pixels() {
    let mut checked = 0;
    for (name, fb) in samples() {
        for (ext, readers) in CHECKED {
            for reader in *readers {
                let path = data().join(format!("expected/{name}.{ext}.{reader}.ppm"));
                let (w, h, rgb) = read_ppm(&path);
                assert_eq!((w, h), (fb.width, fb.height), "{}", path.display());
                // Pillow maps an XBM's bits straight to its 1-bit mode, where 1 is white: the
                // inverse of X11's convention (1 = foreground, black) that Xlib, ImageMagick and
                // Netpbm follow and VoRANG writes.
                let inverted = *ext == "xbm" && *reader == "pillow";
                for (i, (p, got)) in fb.pixels.iter().zip(rgb.chunks_exact(3)).enumerate() {
                    let mut want = intended(p, ONE_BIT.contains(ext));
                    if inverted {
                        want = want.map(|v| 255 - v);
                    }
                    assert_eq!(
                        got,
                        want,
                        "{}: pixel ({}, {})",
                        path.display(),
                        i % w,
                        i / w
                    );
                }
                checked += 1;
            }
        }
    }
    assert_eq!(
        checked,
        2 * CHECKED.iter().map(|c| c.1.len()).sum::<usize>()
    );
}

/// Every format in the table that has a reader: written, then loaded as a background.
#[test]
fn every_readable_format_loads_back_as_a_background() {
    let dir = tempfile::tempdir().unwrap();
    let mut loaded = 0;
    for (name, fb) in samples() {
        for format in FORMATS {
            if matches!(format.read, Read::No(_)) {
                continue;
            }
            for ext in format.extensions {
                if matches!(*ext, "ico" | "jpg" | "jpeg" | "gif" | "webp" | "hdr") {
                    continue; // lossy, quantised or size-limited: tested in tests/output.rs
                }
                let path = dir.path().join(format!("{name}.{ext}"));
                write_image(&fb, &path).unwrap();
                let img = BackgroundImage::load(&path).unwrap_or_else(|e| panic!("{ext}: {e}"));
                assert_eq!((img.width, img.height), (fb.width, fb.height), "{ext}");
                let float = matches!(*ext, "pfm" | "exr");
                let one_bit = ONE_BIT.contains(ext) || *ext == "pbm";
                for (i, (p, q)) in fb.pixels.iter().zip(&img.rgb).enumerate() {
                    if float {
                        assert_eq!(&p[..3], &q[..], "{ext}: pixel {i}");
                        continue;
                    }
                    let want = intended(p, one_bit);
                    let got = q.map(|v| (v * 255.0).round() as u8);
                    if *ext == "pgm" {
                        continue; // grey: the luminance, checked in tests/output.rs
                    }
                    assert_eq!(
                        got,
                        want,
                        "{ext}: pixel ({}, {})",
                        i % fb.width,
                        i / fb.width
                    );
                }
                loaded += 1;
            }
        }
    }
    assert!(loaded >= 2 * 25, "{loaded}");
}

/// The committed files (decoded independently) read back through VoRANG's own readers too.
#[test]
fn own_readers_agree_with_the_independent_decodings() {
    for (name, fb) in samples() {
        for (ext, readers) in CHECKED {
            let path = data().join(format!("{name}.{ext}"));
            let format = FORMATS.iter().find(|f| f.extensions[0] == *ext).unwrap();
            if matches!(format.read, Read::No(_)) {
                continue;
            }
            let img = BackgroundImage::load(&path).unwrap_or_else(|e| panic!("{e}"));
            let (w, h, rgb) =
                read_ppm(&data().join(format!("expected/{name}.{ext}.{}.ppm", readers[0])));
            assert_eq!((img.width, img.height), (w, h));
            assert_eq!((w, h), (fb.width, fb.height));
            for (q, r) in img.rgb.iter().zip(rgb.chunks_exact(3)) {
                assert_eq!(
                    q.map(|v| (v * 255.0).round() as u8),
                    [r[0], r[1], r[2]],
                    "{ext}"
                );
            }
        }
    }
}

/// Every prefix of every sample file and of the other programs' files, and copies with bytes
/// flipped, give an image or an error
/// naming the file — never a panic (the fuzz target `image_read` does this at random).
#[test]
fn damaged_files_are_refused_with_a_message() {
    let dir = tempfile::tempdir().unwrap();
    let mut files: Vec<PathBuf> = samples()
        .iter()
        .flat_map(|(name, _)| {
            CHECKED
                .iter()
                .map(move |(ext, _)| data().join(format!("{name}.{ext}")))
        })
        .collect();
    for entry in std::fs::read_dir(data().join("foreign")).unwrap() {
        files.push(entry.unwrap().path());
    }
    for file in files {
        let ext = file.extension().unwrap().to_string_lossy();
        let good = std::fs::read(&file).unwrap();
        let path = dir.path().join(format!("damaged.{ext}"));
        let step = (good.len() / 50).max(1);
        for len in (0..good.len()).step_by(step) {
            std::fs::write(&path, &good[..len]).unwrap();
            if let Err(e) = BackgroundImage::load(&path) {
                assert!(e.to_string().contains("damaged"), "{e}");
            }
        }
        for i in (0..good.len()).step_by(step) {
            for flip in [0xFF, 0x80, 0x01] {
                let mut bad = good.clone();
                bad[i] ^= flip;
                std::fs::write(&path, &bad).unwrap();
                if let Err(e) = BackgroundImage::load(&path) {
                    assert!(e.to_string().contains("damaged"), "{e}");
                }
            }
        }
    }
    // Headers that claim huge images are refused before anything is allocated.
    let huge: &[(&str, Vec<u8>)] = &[
        (
            "ras",
            [0x59a6_6a95u32, 1 << 30, 1 << 30, 24, 0, 1, 0, 0]
                .iter()
                .flat_map(|v| v.to_be_bytes())
                .collect(),
        ),
        (
            "x",
            [0xFFFF_FFFFu32, 0xFFFF_FFFF]
                .iter()
                .flat_map(|v| v.to_be_bytes())
                .collect(),
        ),
        ("pfm", b"PF\n100000 100000\n-1.0\n".to_vec()),
    ];
    for (ext, bytes) in huge {
        let path = dir.path().join(format!("huge.{ext}"));
        std::fs::write(&path, bytes).unwrap();
        let e = BackgroundImage::load(&path).unwrap_err().to_string();
        assert!(e.contains("huge") && e.contains("pixels"), "{ext}: {e}");
    }
}

#[test]
fn postscript_backgrounds_are_refused_with_the_way_out() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bg.eps");
    write_image(&samples()[0].1, &path).unwrap();
    let e = BackgroundImage::load(&path).unwrap_err().to_string();
    assert!(
        e.contains("bg.eps") && e.contains("gs -sDEVICE=png16m"),
        "{e}"
    );
}

/// Row padding and run limits at many widths: every hand-written format with a reader reads
/// back what it wrote. (The same sizes of the colour formats were checked once against the
/// independent readers of make_expected.py: 1158 of 1159 decodings exact; ImageMagick refuses
/// the 1 × 1 RLE file, which Netpbm reads.)
#[test]
fn every_width_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    for w in (1..=18).chain(60..=70) {
        for h in [1, 3] {
            let mut fb = Framebuffer::new(w, h);
            for (i, p) in fb.pixels.iter_mut().enumerate() {
                let (x, y) = (i % w, i / w);
                *p = [
                    ((x * 37 + y * 11) % 256) as f32 / 255.0,
                    ((x * 91 + 200) % 256) as f32 / 255.0,
                    ((y * 50 + x) % 256) as f32 / 255.0,
                    1.0,
                ];
            }
            for ext in [
                "rgb", "xbm", "xwd", "ras", "pcx", "pict", "iff", "x", "pfm", "viff", "rle",
            ] {
                let path = dir.path().join(format!("{w}x{h}.{ext}"));
                write_image(&fb, &path).unwrap();
                let img = BackgroundImage::load(&path).unwrap_or_else(|e| panic!("{e}"));
                assert_eq!((img.width, img.height), (w, h), "{ext}");
                for (p, q) in fb.pixels.iter().zip(&img.rgb) {
                    let want = intended(p, ONE_BIT.contains(&ext));
                    assert_eq!(q.map(|v| (v * 255.0).round() as u8), want, "{ext} {w}x{h}");
                }
            }
        }
    }
}

/// The user documentation names every format: `help output` (and so docs/commands.md) and the
/// table in docs/formats.md.
#[test]
fn every_format_is_documented() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let commands = std::fs::read_to_string(root.join("docs/commands.md")).unwrap();
    let formats = std::fs::read_to_string(root.join("docs/formats.md")).unwrap();
    let table = &formats[formats.find("# Image files").unwrap()..];
    let output_help = commands
        .lines()
        .find(|l| l.starts_with("The format follows the extension"))
        .unwrap();
    for format in FORMATS {
        let ext = format.extensions[0];
        assert!(
            table.contains(&format!("| `{ext}`")),
            "docs/formats.md lacks {ext}"
        );
        assert!(
            output_help.contains(&format!(" {ext}")) || output_help.contains(&format!("{ext}/")),
            "help output lacks {ext}"
        );
    }
}

/// Files written by Netpbm and ImageMagick (their own variants: colour maps, run lengths, X10
/// bitmaps, 8-bit PseudoColor dumps …; made by make_expected.py) read to the reference
/// picture, itself an independent decoding shown above to hold the intended pixels.
#[test]
fn files_written_by_other_programs_are_read() {
    let dir = data().join("foreign");
    let (w, h, colour) = read_ppm(&dir.join("reference.ppm"));
    let (_, _, bw) = read_ppm(&dir.join("reference_bw.ppm"));
    let reference = |name: &str| {
        let p = data().join(format!("expected/small.{name}.netpbm.ppm"));
        read_ppm(&p).2
    };
    assert_eq!(colour, reference("rgb"));
    assert_eq!(bw, reference("xbm"));
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path
            .file_name()
            .unwrap()
            .to_string_lossy()
            .starts_with("reference")
        {
            continue;
        }
        let img = BackgroundImage::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((img.width, img.height), (w, h), "{}", path.display());
        let want = if path.extension().unwrap() == "xbm" {
            &bw
        } else {
            &colour
        };
        for (q, r) in img.rgb.iter().zip(want.chunks_exact(3)) {
            let got = q.map(|v| (v * 255.0).round() as u8);
            assert_eq!(got, [r[0], r[1], r[2]], "{}", path.display());
        }
        n += 1;
    }
    assert_eq!(n, 20);
}

/// Through the program: `background FILE` with the sample in each hand-written format renders
/// the same picture as with the same sample written as PNG.
#[test]
fn the_background_command_takes_every_readable_format() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("small.png");
    write_image(&samples()[0].1, &png).unwrap();
    let ex = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/selfMade");
    let mut script = format!(
        "imagesize 21 15\nvolume {{{}}}\ncolormap {{{}}}\nalphamap {{{}}}\nlinedraw off\n\
         ortho_camera -1.2 1.2 -0.6 0.6 -10 10\nmethod exact linear 0 1\n",
        ex.join("selfMade.hmesh").display(),
        ex.join("glow.cmap").display(),
        ex.join("ramp.amap").display(),
    );
    let readable: Vec<&str> = CHECKED
        .iter()
        .map(|c| c.0)
        .filter(|ext| !matches!(*ext, "eps" | "ps"))
        .collect();
    for (name, file) in std::iter::once(("png", png.clone())).chain(
        readable
            .iter()
            .map(|e| (*e, data().join(format!("small.{e}")))),
    ) {
        let out = dir.path().join(format!("with_{name}.pfm"));
        script += &format!(
            "background {{{}}}\noutput {{{}}}\nrender_btf\n",
            file.display(),
            out.display()
        );
    }
    // The background shows through: with a uniform one the picture differs.
    script += &format!(
        "background clear\noutput {{{}}}\nrender_btf\n",
        dir.path().join("with_clear.pfm").display()
    );
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
        .arg("-e")
        .arg(&script)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let read = |name: &str| {
        let path = dir.path().join(format!("with_{name}.0001.pfm"));
        vorang::framebuffer::read_pfm(&std::fs::read(&path).unwrap()).unwrap()
    };
    let reference = read("png");
    assert_ne!(read("clear"), reference);
    for ext in readable {
        if ONE_BIT.contains(&ext) {
            continue; // black and white: a different background
        }
        assert_eq!(read(ext), reference, "background small.{ext}");
    }
}
