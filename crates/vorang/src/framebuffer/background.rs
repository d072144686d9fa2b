//! `background file|clear` (thesis A.1): a uniform colour (white by default) or an image under
//! the volume, resampled to the output size.

use std::path::Path;
use std::sync::Arc;

use super::codec::{self, Decoded};
use super::output::POSTSCRIPT;
use super::{FORMATS, Read};
use crate::error::Error;

/// The `image` crate's formats: by content, else by extension (TGA has no signature).
fn decode_with_image_crate(bytes: &[u8], path: &Path) -> Result<Decoded, String> {
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    if reader.format().is_none() {
        match image::ImageFormat::from_path(path) {
            Ok(f) => reader.set_format(f),
            Err(_) => {
                return Err(format!(
                    "the content is no known image format, and neither is the extension; formats: {}",
                    FORMATS
                        .iter()
                        .filter(|f| !matches!(f.read, Read::No(_)))
                        .map(|f| f.extensions[0])
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
        }
    }
    let img = reader.decode().map_err(|e| e.to_string())?;
    let rgb = img.to_rgb32f();
    Ok(Decoded {
        width: rgb.width() as usize,
        height: rgb.height() as usize,
        rgb: rgb.pixels().map(|p| p.0).collect(),
    })
}

/// What lies behind the volume: the intensity `I0` of the optical model.
#[derive(Debug, Clone, PartialEq)]
pub enum Background {
    Color([f64; 3]),
    Image(Arc<BackgroundImage>),
    /// `background none`: no background light (I0 = 0) and a transparent image file.
    None,
}

impl Default for Background {
    /// Uniform white.
    fn default() -> Self {
        Background::Color([1.0; 3])
    }
}

/// A loaded background image, linear RGB in [0, 1] (8-bit values / 255; float formats as
/// stored).
#[derive(Debug, Clone, PartialEq)]
pub struct BackgroundImage {
    pub source: String,
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<[f32; 3]>,
}

impl BackgroundImage {
    /// Reads an image in any format VoRANG writes that has a reader (see [`super::FORMATS`]),
    /// or any other the `image` crate reads. Formats with a signature are recognised by their
    /// content; the others (PCX, PICT, XWD, XBM, AVS, VIFF, TGA) by the extension.
    pub fn load(path: &Path) -> Result<BackgroundImage, Error> {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        let fail = |what: &str, e: String| {
            Error::Invalid(format!(
                "{}: cannot read the background image ({what}): {e}",
                path.display()
            ))
        };
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        let by_ext = FORMATS
            .iter()
            .find(|f| f.extensions.contains(&ext.as_str()));
        let sniffed: Option<(&str, codec::Reader)> = if codec::sgi::sniff(&bytes) {
            Some(("SGI", codec::sgi::read))
        } else if codec::sun_raster::sniff(&bytes) {
            Some(("Sun raster", codec::sun_raster::read))
        } else if codec::ilbm::sniff(&bytes) {
            Some(("ILBM", codec::ilbm::read))
        } else if codec::utah_rle::sniff(&bytes) {
            Some(("Utah RLE", codec::utah_rle::read))
        } else if bytes.starts_with(b"PF") || bytes.starts_with(b"Pf") {
            Some(("PFM", codec::pfm::decode))
        } else if bytes.starts_with(b"%!") {
            return Err(fail("PostScript", POSTSCRIPT.to_string()));
        } else {
            match by_ext.map(|f| (f.extensions[0], f.read)) {
                Some((name, Read::Own(r))) => Some((name, r)),
                Some((name, Read::No(why))) => return Err(fail(name, why.to_string())),
                _ => None,
            }
        };
        let decoded = match sniffed {
            Some((name, read)) => read(&bytes).map_err(|e| fail(name, e))?,
            None => decode_with_image_crate(&bytes, path)
                .map_err(|e| fail(if ext.is_empty() { "no extension" } else { &ext }, e))?,
        };
        Ok(BackgroundImage {
            source: path.display().to_string(),
            width: decoded.width,
            height: decoded.height,
            rgb: decoded.rgb,
        })
    }

    /// Bilinear resampling with pixel centres aligned (the image stretched over the output).
    pub fn resample(
        &self,
        width: usize,
        height: usize,
    ) -> Result<Vec<[f64; 3]>, crate::error::Error> {
        let mut out = super::try_pixels([0.0; 3], width, height, "the background image")?;
        out.clear();
        let at = |x: usize, y: usize| self.rgb[y * self.width + x];
        for j in 0..height {
            let sy = ((j as f64 + 0.5) * self.height as f64 / height as f64 - 0.5)
                .clamp(0.0, (self.height - 1) as f64);
            let (y0, fy) = (sy.floor() as usize, sy - sy.floor());
            let y1 = (y0 + 1).min(self.height - 1);
            for i in 0..width {
                let sx = ((i as f64 + 0.5) * self.width as f64 / width as f64 - 0.5)
                    .clamp(0.0, (self.width - 1) as f64);
                let (x0, fx) = (sx.floor() as usize, sx - sx.floor());
                let x1 = (x0 + 1).min(self.width - 1);
                out.push([0, 1, 2].map(|c| {
                    let top = f64::from(at(x0, y0)[c]) * (1.0 - fx) + f64::from(at(x1, y0)[c]) * fx;
                    let bottom =
                        f64::from(at(x0, y1)[c]) * (1.0 - fx) + f64::from(at(x1, y1)[c]) * fx;
                    top * (1.0 - fy) + bottom * fy
                }));
            }
        }
        Ok(out)
    }
}

impl Background {
    /// `I0` for every pixel of a `width × height` image.
    pub fn pixels(
        &self,
        width: usize,
        height: usize,
    ) -> Result<Vec<[f64; 3]>, crate::error::Error> {
        match self {
            Background::Color(c) => super::try_pixels(*c, width, height, "the background"),
            Background::Image(img) => img.resample(width, height),
            Background::None => super::try_pixels([0.0; 3], width, height, "the background"),
        }
    }
}
