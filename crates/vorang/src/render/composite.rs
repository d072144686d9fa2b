//! Compositing a cell's contribution onto a pixel (thesis 6.3.2): back to front the intensity
//! becomes `I·θ + b` (`render_btf`), front to back the colour gains `T·b` (`render_ftb`, thesis
//! A.1).
//!
//! One definition for every path that composites — the tile loop's per-pixel path, the span
//! kernels and the screen-space fan — so that they give the same bits. It depends on nothing
//! else in the renderer, so each of them can import it without importing the others.

/// Compositing order: `render_btf` or `render_ftb`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Order {
    #[default]
    BackToFront,
    FrontToBack,
}

/// Front-to-back compositing stops for a pixel once its accumulated transparency falls below
/// this: what lies behind can change the pixel by at most this fraction of its background.
pub const EARLY_TERMINATION: f64 = 1e-6;

/// Composites a cell's `(b, θ)` onto a pixel's state: back to front the intensity becomes
/// `I·θ + b`; front to back the colour gains `T·b`. Either way the transparency `T` becomes `T·θ`.
#[inline]
pub(crate) fn composite(order: Order, a: &mut ([f64; 3], f64), (b, theta): ([f64; 3], f64)) {
    match order {
        Order::BackToFront => {
            for ch in 0..3 {
                a.0[ch] = a.0[ch] * theta + b[ch];
            }
        }
        Order::FrontToBack => {
            for ch in 0..3 {
                a.0[ch] += a.1 * b[ch];
            }
        }
    }
    a.1 *= theta;
}
