//! `background file|clear` (thesis A.1): a uniform colour (white by default) or an image under
//! the volume, resampled to the output size.

use std::path::Path;
use std::sync::Arc;

use crate::error::Error;

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
    pub fn load(path: &Path) -> Result<BackgroundImage, Error> {
        let img = image::ImageReader::open(path)
            .map_err(|e| Error::io(path, e))?
            .with_guessed_format()
            .map_err(|e| Error::io(path, e))?
            .decode()
            .map_err(|e| {
                Error::Invalid(format!(
                    "{}: cannot read the background image: {e}",
                    path.display()
                ))
            })?;
        let rgb = img.to_rgb32f();
        let (width, height) = (rgb.width() as usize, rgb.height() as usize);
        Ok(BackgroundImage {
            source: path.display().to_string(),
            width,
            height,
            rgb: rgb.pixels().map(|p| p.0).collect(),
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
