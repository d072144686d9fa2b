//! Every output format is written and read back with the expected values.

#![allow(clippy::needless_range_loop)]

use std::path::Path;

use vorang::framebuffer::{FORMATS, Framebuffer, numbered, read_pfm, write_image};

/// A small image with known values: a gradient, values above 1 and below 0, and varying alpha.
fn sample() -> Framebuffer {
    let (w, h) = (7, 5);
    let mut fb = Framebuffer::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let r = x as f32 / (w - 1) as f32;
            let g = y as f32 / (h - 1) as f32;
            let b = if x == 0 {
                2.5
            } else if x == 1 {
                -0.5
            } else {
                0.25
            };
            fb.pixels[y * w + x] = [r, g, b, 1.0 - 0.1 * y as f32];
        }
    }
    fb
}

fn expect8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// What a file with alpha must hold for a pixel (docs/scripts.md): opaque RGB as
/// the framebuffer shows it; after `background none`, straight alpha.
fn shown(p: &[f32; 4], transparent: bool) -> [f32; 4] {
    if !transparent {
        [p[0], p[1], p[2], 1.0]
    } else if p[3] > 0.0 {
        [p[0] / p[3], p[1] / p[3], p[2] / p[3], p[3]]
    } else {
        [0.0; 4]
    }
}

#[test]
fn every_format_writes_and_reads_back() {
    for transparent in [false, true] {
        let mut fb = sample();
        fb.transparent = transparent;
        every_format(&fb);
    }
}

fn every_format(fb: &Framebuffer) {
    let dir = tempfile::tempdir().unwrap();
    let fb = fb.clone();
    let transparent = fb.transparent;
    for format in FORMATS {
        for ext in format.extensions {
            let path = dir.path().join(format!("nested/img.{ext}"));
            write_image(&fb, &path).unwrap_or_else(|e| panic!("{ext}: {e}"));
            let bytes = std::fs::read(&path).unwrap();
            assert!(!bytes.is_empty(), "{ext}");
            match *ext {
                "pfm" => {
                    let (w, h, rgb) = read_pfm(&bytes).unwrap();
                    assert_eq!((w, h), (fb.width, fb.height));
                    for (p, q) in fb.pixels.iter().zip(&rgb) {
                        assert_eq!(&p[..3], &q[..], "pfm keeps floats exactly");
                    }
                }
                "rgb" | "sgi" | "rgba" => {
                    assert_eq!(u16::from_be_bytes([bytes[0], bytes[1]]), 474);
                    let channels = u16::from_be_bytes([bytes[10], bytes[11]]) as usize;
                    assert_eq!(channels, if *ext == "rgba" { 4 } else { 3 });
                    let (w, h) = (fb.width, fb.height);
                    assert_eq!(bytes.len(), 512 + w * h * channels);
                    // Planes, bottom row first: pixel (x, y) of channel c.
                    for c in 0..channels {
                        for y in 0..h {
                            for x in 0..w {
                                let got = bytes[512 + c * w * h + (h - 1 - y) * w + x];
                                let p = fb.get(x, y);
                                let want = if channels == 4 {
                                    shown(&p, transparent)[c]
                                } else {
                                    p[c]
                                };
                                assert_eq!(got, expect8(want), "{ext} channel {c} at ({x},{y})");
                            }
                        }
                    }
                }
                "x" | "avs" => {
                    // AVS X: width, height, then A R G B per pixel (alpha as PNG's).
                    assert_eq!(bytes.len(), 8 + 4 * fb.width * fb.height, "{ext}");
                    for (p, q) in fb.pixels.iter().zip(bytes[8..].chunks_exact(4)) {
                        let want = shown(p, transparent).map(expect8);
                        assert_eq!([q[1], q[2], q[3], q[0]], want, "{ext}");
                    }
                }
                // Checked against independent readers in tests/image_formats.rs.
                "pbm" | "xbm" | "xwd" | "ras" | "sun" | "pcx" | "eps" | "epsf" | "ps" | "pict"
                | "pct" | "iff" | "ilbm" | "viff" | "xv" | "rle" | "rlc" => {}
                _ => {
                    let img = image::open(&path).unwrap_or_else(|e| panic!("{ext}: {e}"));
                    assert_eq!(
                        (img.width() as usize, img.height() as usize),
                        (fb.width, fb.height),
                        "{ext}"
                    );
                    match *ext {
                        "exr" => {
                            let f = img.to_rgba32f();
                            for (p, q) in fb.pixels.iter().zip(f.pixels()) {
                                // Premultiplied (OpenEXR's convention): RGB as it is.
                                let a = if transparent { p[3] } else { 1.0 };
                                assert_eq!([p[0], p[1], p[2], a], q.0, "exr keeps floats exactly");
                            }
                        }
                        "hdr" => {
                            let f = img.to_rgb32f();
                            for (p, q) in fb.pixels.iter().zip(f.pixels()) {
                                // RGBE: 8-bit mantissas under one shared exponent per pixel.
                                let max = p[..3].iter().fold(0.0f32, |m, v| m.max(*v));
                                for c in 0..3 {
                                    let want = p[c].max(0.0);
                                    assert!(
                                        (q.0[c] - want).abs() <= max / 128.0,
                                        "hdr: {} vs {want}",
                                        q.0[c]
                                    );
                                }
                            }
                        }
                        "pgm" => {
                            let l = img.to_luma8();
                            for (p, q) in fb.pixels.iter().zip(l.pixels()) {
                                let y = 0.299 * p[0].clamp(0.0, 1.0)
                                    + 0.587 * p[1].clamp(0.0, 1.0)
                                    + 0.114 * p[2].clamp(0.0, 1.0);
                                assert!((q.0[0] as i32 - expect8(y) as i32).abs() <= 1);
                            }
                        }
                        _ => {
                            let lossy = matches!(*ext, "jpg" | "jpeg" | "gif");
                            let with_alpha = matches!(
                                *ext,
                                "png" | "tiff" | "tif" | "tga" | "pam" | "ico" | "qoi" | "webp"
                            );
                            let rgba = img.to_rgba8();
                            for (p, q) in fb.pixels.iter().zip(rgba.pixels()) {
                                let want = if with_alpha {
                                    shown(p, transparent)
                                } else {
                                    [p[0], p[1], p[2], 1.0]
                                };
                                for c in 0..3 {
                                    let d = (q.0[c] as i32 - expect8(want[c]) as i32).abs();
                                    assert!(
                                        d <= if lossy { 24 } else { 0 },
                                        "{ext} channel {c}: {} vs {}",
                                        q.0[c],
                                        expect8(want[c])
                                    );
                                }
                                assert_eq!(q.0[3], expect8(want[3]), "{ext} alpha");
                            }
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn no_partial_file_and_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let fb = sample();
    // Unknown extension: nothing written.
    let bad = dir.path().join("x.xyz");
    assert!(write_image(&fb, &bad).is_err());
    assert!(!bad.exists());
    // An unwritable place: a "folder" that is a file.
    let file = dir.path().join("plain");
    std::fs::write(&file, b"x").unwrap();
    let e = write_image(&fb, &file.join("img.png")).unwrap_err();
    assert!(e.to_string().contains("plain"), "{e}");
    // ICO is limited to 256 × 256: the error names the format and no file is left behind.
    let big = Framebuffer::new(300, 10);
    let ico = dir.path().join("big.ico");
    assert!(write_image(&big, &ico).is_err());
    assert!(!ico.exists());
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(
        leftovers
            .iter()
            .all(|n| !n.to_string_lossy().contains(".tmp")),
        "{leftovers:?}"
    );
}

#[test]
fn image_numbers_start_at_0001() {
    assert_eq!(
        numbered(Path::new("a/b.tiff"), 1),
        Path::new("a/b.0001.tiff")
    );
}

/// , end to end: a volume that glows without absorbing (where the scalar is
/// 0, `examples/selfMade`) over a black background. By default the PNG is opaque and shows what
/// the framebuffer (and the PFM) shows; with `background none` its alpha is the volume's opacity
/// and its colour the emitted light divided by it.
#[test]
fn png_alpha_shows_the_picture_and_is_transparent_only_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let ex = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/selfMade");
    let script = |background: &str, out: &str| {
        format!(
            "imagesize 60 30\nbackground {background}\nvolume {}\ncolormap {}\nalphamap {}\n\
             linedraw off\northo_camera -1.2 1.2 -0.6 0.6 -10 10\nmethod exact linear 0 1\n\
             output {out}.png\nrender_btf\noutput {out}.pfm\nrender_btf\n",
            ex.join("selfMade.hmesh").display(),
            ex.join("glow.cmap").display(),
            ex.join("ramp.amap").display(),
        )
    };
    for (background, name) in [("0 0 0", "opaque"), ("none", "clear")] {
        let base = dir.path().join(name);
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
            .arg("-e")
            .arg(script(background, &base.display().to_string()))
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{}",
            String::from_utf8_lossy(&status.stderr)
        );
        let png = image::open(format!("{}.0001.png", base.display()))
            .unwrap()
            .to_rgba8();
        let (w, h, rgb) =
            read_pfm(&std::fs::read(format!("{}.0002.pfm", base.display())).unwrap()).unwrap();
        assert_eq!((w, h), (60, 30));
        let mut glowing_but_clear = 0;
        for (i, q) in png.pixels().enumerate() {
            let p = rgb[i];
            if background == "0 0 0" {
                assert_eq!(q.0[3], 255, "opaque by default");
                for c in 0..3 {
                    assert_eq!(q.0[c], expect8(p[c]), "the PNG shows the framebuffer");
                }
            } else if q.0[3] == 0 {
                // (Almost) nothing absorbs here: whatever glows is lost.
                if p.iter().any(|&v| v > 0.01) {
                    glowing_but_clear += 1;
                }
            } else {
                let a = f32::from(q.0[3]) / 255.0;
                for c in 0..3 {
                    // Straight colour times alpha gives back the emitted light (8-bit rounding).
                    let back = f32::from(q.0[c]) / 255.0 * a;
                    assert!(
                        (back - p[c].min(a)).abs() <= 2.0 / 255.0,
                        "{c}: {back} vs {}",
                        p[c]
                    );
                }
            }
        }
        if background == "none" {
            // The documented loss: emission without absorption has no straight-alpha form.
            assert!(glowing_but_clear > 0);
        }
    }
}

/// `set_nr` sets the number of the next image (thesis A.1), also when `output` follows it; a
/// new base name without a `set_nr` since the last image starts at 1, and the same base keeps
/// counting.
#[test]
fn set_nr_before_output_holds_until_the_next_image() {
    let dir = tempfile::tempdir().unwrap();
    let cube = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/formats/cube.hmesh");
    let script = format!(
        "volume {{{}}}\nimagesize 8 8\nlinedraw off\n\
         set_nr 500\noutput out/base.pfm\nrender_btf\n\
         output out/base.pfm\nrender_btf\n\
         output out/other.pfm\nrender_btf\n\
         set_nr 7\noutput out/third.pfm\noutput out/fourth.pfm\nrender_btf\n",
        cube.display()
    );
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
        .arg("-e")
        .arg(script)
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut files: Vec<String> = std::fs::read_dir(dir.path().join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(
        files,
        [
            "base.0500.pfm",
            "base.0501.pfm",
            "fourth.0007.pfm",
            "other.0001.pfm"
        ]
    );
}
