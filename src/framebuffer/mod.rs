//! The float RGBA framebuffer (thesis 4.2, SPEC §6): no 8-bit quantisation while compositing;
//! values may exceed 1 (the brightness factor is tuned by the largest channel reported after
//! each render) and are clipped only when written to an 8-bit format.

mod background;
mod output;
mod pfm;
mod sgi;

pub use background::{Background, BackgroundImage};
pub use output::{FORMATS, FormatInfo, format_for, numbered, write_image};
pub use pfm::read as read_pfm;

/// An image of `width × height` RGBA pixels, row-major from the top-left pixel. Alpha is
/// 1 − the ray's total transparency.
#[derive(Debug, Clone, PartialEq)]
pub struct Framebuffer {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[f32; 4]>,
}

impl Framebuffer {
    pub fn new(width: usize, height: usize) -> Framebuffer {
        Framebuffer {
            width,
            height,
            pixels: vec![[0.0; 4]; width * height],
        }
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

    /// The pixels as 8-bit RGBA, clipped to [0, 1] and rounded.
    pub fn to_rgba8(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|p| p.map(to_u8)).collect()
    }

    /// The pixels as 8-bit RGB.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| [to_u8(p[0]), to_u8(p[1]), to_u8(p[2])])
            .collect()
    }
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
