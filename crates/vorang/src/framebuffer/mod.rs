//! The float RGBA framebuffer (thesis 4.2, docs/scripts.md): no 8-bit quantisation while compositing;
//! values may exceed 1 (the brightness factor is tuned by the largest channel reported after
//! each render) and are clipped only when written to an 8-bit format.

mod background;
pub mod codec;
mod output;

pub use background::{Background, BackgroundImage};
pub use codec::pfm::read as read_pfm;
pub use output::{FORMATS, FormatInfo, Read, encode_image, format_for, numbered, write_image};

/// An image of `width × height` RGBA pixels, row-major from the top-left pixel. Alpha is
/// 1 − the ray's total transparency.
#[derive(Debug, Clone, PartialEq)]
pub struct Framebuffer {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[f32; 4]>,
    /// Rendered with `background none`: the files get straight alpha (see
    /// [`Framebuffer::output_pixel`]); otherwise they are opaque.
    pub transparent: bool,
}

impl Framebuffer {
    pub fn new(width: usize, height: usize) -> Framebuffer {
        Framebuffer {
            width,
            height,
            pixels: vec![[0.0; 4]; width * height],
            transparent: false,
        }
    }

    /// [`Framebuffer::new`], or a clear error where memory does not suffice.
    pub fn try_new(width: usize, height: usize) -> Result<Framebuffer, crate::error::Error> {
        Ok(Framebuffer {
            width,
            height,
            pixels: try_pixels([0.0; 4], width, height, "the float framebuffer")?,
            transparent: false,
        })
    }

    /// The largest R, G or B value (what the thesis prints after a render to tune the
    /// brightness factor: above 1 the 8-bit output clips).
    pub fn max_channel(&self) -> f32 {
        self.pixels
            .iter()
            .flat_map(|p| &p[..3])
            .fold(0.0f32, |m, &v| m.max(v))
    }

    #[inline]
    pub fn get(&self, x: usize, y: usize) -> [f32; 4] {
        self.pixels[y * self.width + x]
    }

    /// What a file with an alpha channel holds for pixel `p` (docs/scripts.md):
    /// by default what the framebuffer shows — RGB composited over the background, opaque
    /// (alpha 1). Rendered with `background none` (no background light), straight alpha:
    /// alpha = the volume's opacity 1 − T and RGB = the emitted light divided by it (0 where
    /// nothing covers the pixel). Light emitted without absorption has no such form (alpha 0
    /// with colour): it is lost there; the opaque default keeps it.
    #[inline]
    pub fn output_pixel(&self, p: &[f32; 4]) -> [f32; 4] {
        output_pixel(p, self.transparent)
    }

    /// The pixels as 8-bit RGBA ([`Framebuffer::output_pixel`]), clipped to [0, 1] and rounded
    /// (an error where memory does not suffice for the copy).
    pub fn to_rgba8(&self) -> Result<Vec<u8>, String> {
        let mut out = self.bytes(4)?;
        out.extend(
            self.pixels
                .iter()
                .flat_map(|p| self.output_pixel(p).map(to_u8)),
        );
        Ok(out)
    }

    /// The pixels as 8-bit RGB.
    pub fn to_rgb8(&self) -> Result<Vec<u8>, String> {
        let mut out = self.bytes(3)?;
        out.extend(
            self.pixels
                .iter()
                .flat_map(|p| [to_u8(p[0]), to_u8(p[1]), to_u8(p[2])]),
        );
        Ok(out)
    }

    /// An empty buffer with room for `per_pixel` bytes per pixel, allocated fallibly.
    pub fn bytes(&self, per_pixel: usize) -> Result<Vec<u8>, String> {
        let n = self.pixels.len().saturating_mul(per_pixel);
        let mut v = Vec::new();
        v.try_reserve_exact(n).map_err(|_| {
            format!(
                "not enough memory to write a {}×{} image: its encoded copy needs {:.2} GB",
                self.width,
                self.height,
                n as f64 / 1e9
            )
        })?;
        Ok(v)
    }
}

/// [`Framebuffer::output_pixel`] for a pixel of a framebuffer that is `transparent` or not: also
/// for tiles not yet in a framebuffer, so that a window shows exactly what the file will hold.
#[inline]
pub fn output_pixel(p: &[f32; 4], transparent: bool) -> [f32; 4] {
    if !transparent {
        return [p[0], p[1], p[2], 1.0];
    }
    let a = p[3];
    if a > 0.0 {
        [p[0] / a, p[1] / a, p[2] / a, a]
    } else {
        [0.0; 4]
    }
}

/// The luminance of pixel `p` (Rec. 601 weights, channels clipped to [0, 1]): what the grey
/// and 1-bit formats store.
#[inline]
pub fn luma(p: &[f32; 4]) -> f32 {
    0.299 * p[0].clamp(0.0, 1.0) + 0.587 * p[1].clamp(0.0, 1.0) + 0.114 * p[2].clamp(0.0, 1.0)
}

/// Clip to [0, 1] and round to 0…255.
#[inline]
pub fn to_u8(v: f32) -> u8 {
    if v.is_nan() {
        0
    } else {
        (v.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}

/// A per-pixel buffer of `width × height` copies of `value`, allocated fallibly: a clear error
/// naming the size instead of an abort where memory does not suffice.
pub fn try_pixels<T: Clone>(
    value: T,
    width: usize,
    height: usize,
    what: &str,
) -> Result<Vec<T>, crate::error::Error> {
    let n = width.saturating_mul(height);
    let mut v = Vec::new();
    if v.try_reserve_exact(n).is_err() {
        let bytes = n as f64 * std::mem::size_of::<T>() as f64;
        return Err(crate::error::Error::Invalid(format!(
            "not enough memory for a {width}×{height} image: {what} needs {:.2} GB",
            bytes / 1e9
        )));
    }
    v.resize(n, value);
    Ok(v)
}
