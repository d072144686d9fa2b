//! Image files: the format follows the extension (docs/scripts.md). 8-bit formats clip
//! to [0, 1]; `exr`, `pfm` and `hdr` keep the floats. Formats with an alpha channel are opaque
//! (alpha 1: the picture composited over the background, as the framebuffer shows it); after a
//! render with `background none` they hold alpha = 1 − total transparency, straight in the 8-bit
//! formats and premultiplied in OpenEXR (each format's convention). Every file is written to a
//! temporary name and renamed.

use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};

use image::codecs::pnm::{PnmEncoder, PnmSubtype, SampleEncoding};
use image::{ExtendedColorType, ImageEncoder};

use super::Framebuffer;
use super::codec::{self, Reader};
use crate::atomic::write_atomically;
use crate::error::Error;

type Out<'a> = &'a mut BufWriter<std::fs::File>;
type Writer = fn(&Framebuffer, Out) -> Result<(), String>;

/// One output format.
pub struct FormatInfo {
    /// File extensions (lower case), the first one canonical.
    pub extensions: &'static [&'static str],
    pub summary: &'static str,
    pub write: Writer,
    /// How `background` reads it.
    pub read: Read,
}

/// How a format is read back (for `background`).
#[derive(Clone, Copy)]
pub enum Read {
    /// By the `image` crate.
    Image,
    /// By VoRANG's own reader.
    Own(Reader),
    /// Not at all, for this reason.
    No(&'static str),
}

/// A hand-written codec's result as the table's.
fn own(r: std::io::Result<()>) -> Result<(), String> {
    r.map_err(|e| e.to_string())
}

fn img<E: ImageEncoder>(
    enc: E,
    fb: &Framebuffer,
    data: &[u8],
    ct: ExtendedColorType,
) -> Result<(), String> {
    enc.write_image(data, fb.width as u32, fb.height as u32, ct)
        .map_err(|e| e.to_string())
}

fn floats(fb: &Framebuffer, channels: usize) -> Result<Vec<u8>, String> {
    let mut out = fb.bytes(4 * channels)?;
    // OpenEXR's alpha is premultiplied: the framebuffer's RGB as it is, alpha 1 unless the
    // render was transparent.
    let alpha = |p: &[f32; 4]| if fb.transparent { p[3] } else { 1.0 };
    out.extend(fb.pixels.iter().flat_map(|p| {
        let v = [p[0], p[1], p[2], alpha(p)];
        (0..channels).flat_map(move |c| v[c].to_ne_bytes())
    }));
    Ok(out)
}

fn seekable<W: Write + Seek>(w: W) -> W {
    w
}

impl std::fmt::Debug for FormatInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.extensions[0])
    }
}

/// Every format VoRANG writes.
pub const FORMATS: &[FormatInfo] = &[
    FormatInfo {
        extensions: &["tiff", "tif"],
        summary: "TIFF, 8-bit RGBA (the default output format)",
        write: |fb, w| {
            img(
                image::codecs::tiff::TiffEncoder::new(seekable(w)),
                fb,
                &fb.to_rgba8()?,
                ExtendedColorType::Rgba8,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["png"],
        summary: "PNG, 8-bit RGBA",
        write: |fb, w| {
            img(
                image::codecs::png::PngEncoder::new(w),
                fb,
                &fb.to_rgba8()?,
                ExtendedColorType::Rgba8,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["bmp"],
        summary: "Windows bitmap, 8-bit RGB",
        write: |fb, w| {
            img(
                image::codecs::bmp::BmpEncoder::new(w),
                fb,
                &fb.to_rgb8()?,
                ExtendedColorType::Rgb8,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["tga"],
        summary: "Truevision Targa, 8-bit RGBA",
        write: |fb, w| {
            img(
                image::codecs::tga::TgaEncoder::new(w),
                fb,
                &fb.to_rgba8()?,
                ExtendedColorType::Rgba8,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["ppm", "pnm"],
        summary: "portable pixmap (binary P6), 8-bit RGB",
        write: |fb, w| {
            let e = PnmEncoder::new(w).with_subtype(PnmSubtype::Pixmap(SampleEncoding::Binary));
            img(e, fb, &fb.to_rgb8()?, ExtendedColorType::Rgb8)
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["pgm"],
        summary: "portable graymap (binary P5), 8-bit luminance (Rec. 601 weights)",
        write: |fb, w| {
            let mut luma = fb.bytes(1)?;
            luma.extend(fb.pixels.iter().map(|p| super::to_u8(super::luma(p))));
            let e = PnmEncoder::new(w).with_subtype(PnmSubtype::Graymap(SampleEncoding::Binary));
            img(e, fb, &luma, ExtendedColorType::L8)
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["pam"],
        summary: "portable arbitrary map, 8-bit RGB_ALPHA",
        write: |fb, w| {
            let e = PnmEncoder::new(w).with_subtype(PnmSubtype::ArbitraryMap);
            img(e, fb, &fb.to_rgba8()?, ExtendedColorType::Rgba8)
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["jpg", "jpeg"],
        summary: "JPEG, 8-bit RGB, quality 95",
        write: |fb, w| {
            img(
                image::codecs::jpeg::JpegEncoder::new_with_quality(w, 95),
                fb,
                &fb.to_rgb8()?,
                ExtendedColorType::Rgb8,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["gif"],
        summary: "GIF, 8-bit RGB (quantised to 256 colours)",
        write: |fb, w| {
            let mut rgba = fb.bytes(4)?;
            rgba.extend(fb.pixels.iter().flat_map(|p| {
                [
                    super::to_u8(p[0]),
                    super::to_u8(p[1]),
                    super::to_u8(p[2]),
                    255,
                ]
            }));
            img(
                image::codecs::gif::GifEncoder::new(w),
                fb,
                &rgba,
                ExtendedColorType::Rgba8,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["ico"],
        summary: "Windows icon, 8-bit RGBA (at most 256 × 256)",
        write: |fb, w| {
            img(
                image::codecs::ico::IcoEncoder::new(w),
                fb,
                &fb.to_rgba8()?,
                ExtendedColorType::Rgba8,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["qoi"],
        summary: "Quite OK Image, 8-bit RGBA",
        write: |fb, w| {
            img(
                image::codecs::qoi::QoiEncoder::new(w),
                fb,
                &fb.to_rgba8()?,
                ExtendedColorType::Rgba8,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["webp"],
        summary: "WebP (lossless), 8-bit RGBA",
        write: |fb, w| {
            img(
                image::codecs::webp::WebPEncoder::new_lossless(w),
                fb,
                &fb.to_rgba8()?,
                ExtendedColorType::Rgba8,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["hdr"],
        summary: "Radiance HDR, float RGB",
        write: |fb, w| {
            img(
                image::codecs::hdr::HdrEncoder::new(w),
                fb,
                &floats(fb, 3)?,
                ExtendedColorType::Rgb32F,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["exr"],
        summary: "OpenEXR, 32-bit float RGBA",
        write: |fb, w| {
            img(
                image::codecs::openexr::OpenExrEncoder::new(seekable(w)),
                fb,
                &floats(fb, 4)?,
                ExtendedColorType::Rgba32F,
            )
        },
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["pfm"],
        summary: "portable float map: RGB float32, little-endian, rows bottom to top",
        write: |fb, w| own(codec::pfm::write(fb, w)),
        read: Read::Own(codec::pfm::decode),
    },
    FormatInfo {
        extensions: &["rgb", "sgi", "rgba"],
        summary: "SGI image (the thesis's example format): 8-bit RGB, RGBA for .rgba",
        write: |fb, w| own(codec::sgi::write(fb, w, false)),
        read: Read::Own(codec::sgi::read),
    },
    FormatInfo {
        extensions: &["pbm"],
        summary: "portable bitmap (binary P4), 1-bit: white where the luminance is at least 0.5, black elsewhere",
        write: |fb, w| own(codec::pbm::write(fb, w)),
        read: Read::Image,
    },
    FormatInfo {
        extensions: &["xbm"],
        summary: "X11 bitmap, 1-bit: white where the luminance is at least 0.5, black elsewhere",
        write: |fb, w| own(codec::xbm::write(fb, w)),
        read: Read::Own(codec::xbm::read),
    },
    FormatInfo {
        extensions: &["xwd"],
        summary: "X window dump, 8-bit RGB (24-bit TrueColor)",
        write: |fb, w| own(codec::xwd::write(fb, w)),
        read: Read::Own(codec::xwd::read),
    },
    FormatInfo {
        extensions: &["ras", "sun"],
        summary: "Sun rasterfile, 8-bit RGB",
        write: |fb, w| own(codec::sun_raster::write(fb, w)),
        read: Read::Own(codec::sun_raster::read),
    },
    FormatInfo {
        extensions: &["pcx"],
        summary: "ZSoft PC Paintbrush, 8-bit RGB (three planes, run-length coded)",
        write: |fb, w| own(codec::pcx::write(fb, w)),
        read: Read::Own(codec::pcx::read),
    },
    FormatInfo {
        extensions: &["eps", "epsf"],
        summary: "Encapsulated PostScript, 8-bit RGB image, one pixel per point",
        write: |fb, w| own(codec::postscript::write(fb, w, true)),
        read: Read::No(POSTSCRIPT),
    },
    FormatInfo {
        extensions: &["ps"],
        summary: "PostScript, one page the size of the image, 8-bit RGB, one pixel per point",
        write: |fb, w| own(codec::postscript::write(fb, w, false)),
        read: Read::No(POSTSCRIPT),
    },
    FormatInfo {
        extensions: &["pict", "pct"],
        summary: "Apple QuickDraw PICT version 2, 8-bit RGB (at most 4095 pixels wide)",
        write: |fb, w| own(codec::pict::write(fb, w)),
        read: Read::Own(codec::pict::read),
    },
    FormatInfo {
        extensions: &["iff", "ilbm"],
        summary: "Amiga IFF ILBM, 24-bit (8-bit RGB)",
        write: |fb, w| own(codec::ilbm::write(fb, w)),
        read: Read::Own(codec::ilbm::read),
    },
    FormatInfo {
        extensions: &["x", "avs"],
        summary: "AVS X image, 8-bit ARGB",
        write: |fb, w| own(codec::avs::write(fb, w)),
        read: Read::Own(codec::avs::read),
    },
    FormatInfo {
        extensions: &["viff", "xv"],
        summary: "Khoros VIFF, 8-bit RGB (three byte bands)",
        write: |fb, w| own(codec::viff::write(fb, w)),
        read: Read::Own(codec::viff::read),
    },
    FormatInfo {
        extensions: &["rle", "rlc"],
        summary: "Utah Raster Toolkit RLE, 8-bit RGB",
        write: |fb, w| own(codec::utah_rle::write(fb, w)),
        read: Read::Own(codec::utah_rle::read),
    },
];

pub(super) const POSTSCRIPT: &str = "reading PostScript needs an interpreter: convert it first, e.g. `gs -sDEVICE=png16m -o bg.png FILE`";

/// The format for a file name, from its extension (case-insensitive).
pub fn format_for(path: &Path) -> Result<&'static FormatInfo, Error> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    FORMATS
        .iter()
        .find(|f| f.extensions.contains(&ext.as_str()))
        .ok_or_else(|| {
            let all: Vec<&str> = FORMATS
                .iter()
                .flat_map(|f| f.extensions.iter().copied())
                .collect();
            Error::Invalid(format!(
                "{}: unknown image format '{}': expected one of {}",
                path.display(),
                if ext.is_empty() {
                    "(no extension)"
                } else {
                    &ext
                },
                all.join(", ")
            ))
        })
}

/// `base.ext` with image number `nr` → `base.0001.ext` (docs/scripts.md: the first image is 0001).
pub fn numbered(base: &Path, nr: u32) -> PathBuf {
    let stem = base
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = match base.extension() {
        Some(ext) => format!("{stem}.{nr:04}.{}", ext.to_string_lossy()),
        None => format!("{stem}.{nr:04}"),
    };
    base.with_file_name(name)
}

/// `fb` encoded in the image format of extension `ext` (`png`, `tiff`, …), as a file of that
/// format would hold it (Python's inline images show exactly the CLI's PNG).
pub fn encode_image(fb: &Framebuffer, ext: &str) -> Result<Vec<u8>, Error> {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(0);
    // The codecs write files (buffered, atomically): encode through a private temporary one.
    let path = std::env::temp_dir().join(format!(
        "vorang-encode-{}-{}.{ext}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    ));
    let result =
        write_image(fb, &path).and_then(|()| std::fs::read(&path).map_err(|e| Error::io(&path, e)));
    let _ = std::fs::remove_file(&path);
    result
}

/// Writes `fb` to `path` in the format of its extension, atomically; creates missing folders.
pub fn write_image(fb: &Framebuffer, path: &Path) -> Result<(), Error> {
    let format = format_for(path)?;
    let is_sgi_rgba = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("rgba"));
    let mut failure = None;
    let result = write_atomically(path, |w| {
        let r = if is_sgi_rgba {
            codec::sgi::write(fb, w, true).map_err(|e| e.to_string())
        } else {
            (format.write)(fb, w)
        };
        r.map_err(|msg| {
            failure = Some(msg.clone());
            std::io::Error::other(msg)
        })
    });
    match (result, failure) {
        (Err(_), Some(msg)) => Err(Error::Invalid(format!(
            "{}: cannot write {}: {msg}",
            path.display(),
            format.extensions[0]
        ))),
        (r, _) => r,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbering_inserts_four_digits_before_the_extension() {
        assert_eq!(
            numbered(Path::new("out/test.rgb"), 1),
            PathBuf::from("out/test.0001.rgb")
        );
        assert_eq!(
            numbered(Path::new("vorang.tiff"), 36),
            PathBuf::from("vorang.0036.tiff")
        );
        assert_eq!(
            numbered(Path::new("a.b.png"), 12345),
            PathBuf::from("a.b.12345.png")
        );
    }

    #[test]
    fn formats_come_from_the_extension() {
        assert_eq!(format_for(Path::new("x.PNG")).unwrap().extensions[0], "png");
        assert_eq!(
            format_for(Path::new("x.tif")).unwrap().extensions[0],
            "tiff"
        );
        let e = format_for(Path::new("x.xyz")).unwrap_err().to_string();
        assert!(e.contains("unknown image format 'xyz'"), "{e}");
        assert!(format_for(Path::new("noext")).is_err());
    }
}
