//! What a render is asked for besides the volume, the mapping and the view: the image size,
//! the method, the order, grid lines, background, tiling and lights (thesis A.1, the script
//! commands that set them), and the limits every caller checks sizes against.

use super::approx::Method;
use super::composite::Order;
use super::lines::LineDraw;
use crate::framebuffer::Background;

/// [`Settings::tile`] for "choose per frame" ([`auto_tile`](crate::render::auto_tile)).
pub const TILE: usize = 0;

/// The largest image, in pixels (2^27: a 2 GiB float framebuffer).
pub const MAX_PIXELS: usize = 1 << 27;

/// Everything a render needs besides the volume, the mapping and the view.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub width: usize,
    pub height: usize,
    pub method: Method,
    pub order: Order,
    pub lines: LineDraw,
    pub background: Background,
    /// Edge length of the screen tiles rendered in parallel (any value gives the same image);
    /// [`TILE`] (0): chosen per frame by [`auto_tile`](crate::render::auto_tile).
    pub tile: usize,
    /// Let whole cells go through the SIMD span kernels where they apply
    /// ([`span`](crate::render::span)); off, every pixel takes the scalar reference path (for
    /// tests and comparisons).
    pub span_kernels: bool,
    /// `addlight`: the lights of the scene, for `LIT_EMITTER` ([`crate::scene::light`]); none
    /// = one white light at the camera.
    pub lights: Vec<crate::scene::Light>,
}

impl Default for Settings {
    /// 512 × 512, `test 0.5`, back to front, all grid lines, white background (thesis A.1).
    fn default() -> Self {
        Settings {
            width: 512,
            height: 512,
            method: Method::default(),
            order: Order::BackToFront,
            lines: LineDraw::All,
            background: Background::default(),
            tile: TILE,
            span_kernels: true,
            lights: Vec::new(),
        }
    }
}

/// Checks an image size: at least 1 × 1 and at most [`MAX_PIXELS`].
pub fn check_size(width: usize, height: usize) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!(
            "the image size must be at least 1 × 1, found {width} × {height}"
        ));
    }
    if width.saturating_mul(height) > MAX_PIXELS || width > 1 << 20 || height > 1 << 20 {
        return Err(format!(
            "an image of {width} × {height} pixels is too large (at most {MAX_PIXELS} pixels, i.e. 2 GiB of float framebuffer)"
        ));
    }
    Ok(())
}
