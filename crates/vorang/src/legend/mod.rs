//! The colour legend (`legend on|off ?position?`): the colour transfer function
//! drawn as a bar with its range and a few labelled values, into the framebuffer after the
//! render — so every output format, and every movie frame, carries it.
//!
//! The bar runs from the map's lowest value (bottom or left) to its highest; each bar pixel has
//! the colour of the value at its centre ([`Layout::value_at`]). Labels and ticks are white with
//! a black outline, readable on any background; vertical bars carry them on their right,
//! horizontal bars below.

mod font;
pub mod label;
mod scale;

pub use scale::ColorScale;

use crate::framebuffer::Framebuffer;

/// Where the bar sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    Right,
    Left,
    Top,
    Bottom,
}

impl Place {
    pub const NAMES: [&'static str; 4] = ["right", "left", "top", "bottom"];

    pub fn parse(word: &str) -> Option<Place> {
        match word {
            "right" => Some(Place::Right),
            "left" => Some(Place::Left),
            "top" => Some(Place::Top),
            "bottom" => Some(Place::Bottom),
            _ => None,
        }
    }

    fn vertical(self) -> bool {
        matches!(self, Place::Right | Place::Left)
    }
}

/// A labelled value: where along the bar (pixels from the low end) and its text.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    pub at: usize,
    pub text: String,
}

/// The legend's geometry in a `width × height` image.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    pub place: Place,
    /// The bar: pixels `x0..x1` × `y0..y1`.
    pub x0: usize,
    pub x1: usize,
    pub y0: usize,
    pub y1: usize,
    /// Font pixels are `scale × scale` image pixels.
    pub scale: usize,
    pub labels: Vec<Label>,
    lo: f64,
    hi: f64,
}

/// A short label: about 4 significant digits, trailing zeros dropped, exponents outside
/// 1e-3 … 1e5.
pub fn label_text(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
        trim(format!("{v:.decimals$}"))
    } else {
        let s = format!("{v:.2e}");
        let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
        format!("{}e{exp}", trim(mantissa.to_string()))
    }
}

/// From the bar's edge to its labels: a tick of `2s + 1` pixels, then `3s + 1` of space (the
/// outlines take two of them).
fn label_gap(s: usize) -> usize {
    5 * s + 2
}

/// Round steps (1, 2, 5 × 10ᵏ) giving about four intervals over `[lo, hi]`.
fn nice_step(lo: f64, hi: f64) -> f64 {
    let raw = (hi - lo) / 4.0;
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p)
}

impl Layout {
    /// The layout for `scale` in a `width × height` image; `None` where the image is too small
    /// for a legend (under 48 pixels either way).
    pub fn new(place: Place, width: usize, height: usize, scale: &ColorScale) -> Option<Layout> {
        let short = width.min(height);
        if short < 48 {
            return None;
        }
        let s = (short / 256).max(1);
        let margin = (short / 40).max(4);
        let thickness = (short / 30).max(6);
        let gap = label_gap(s);
        let (lo, hi) = (scale.lo, scale.hi);
        let along = if place.vertical() { height } else { width };
        let len = along - 2 * (along / 5);
        let labels = Self::labels(place, lo, hi, len, s);
        let label_w = labels
            .iter()
            .map(|l| font::text_width(&l.text) * s)
            .max()
            .unwrap_or(0);
        let label_h = font::HEIGHT * s;
        let (start, end) = (along / 5, along / 5 + len);
        let (x0, x1, y0, y1) = match place {
            Place::Left => (margin, margin + thickness, start, end),
            Place::Right => {
                let x1 = width.checked_sub(margin + label_w + gap)?;
                (x1.checked_sub(thickness)?, x1, start, end)
            }
            Place::Top => (start, end, margin, margin + thickness),
            Place::Bottom => {
                let y1 = height.checked_sub(margin + label_h + gap)?;
                (start, end, y1.checked_sub(thickness)?, y1)
            }
        };
        Some(Layout {
            place,
            x0,
            x1,
            y0,
            y1,
            scale: s,
            labels,
            lo,
            hi,
        })
    }

    /// The ends and the round values between them that leave room for their labels.
    fn labels(place: Place, lo: f64, hi: f64, len: usize, s: usize) -> Vec<Label> {
        let at = |v: f64| {
            (((v - lo) / (hi - lo)) * len as f64)
                .round()
                .clamp(0.0, (len - 1) as f64) as usize
        };
        let step = nice_step(lo, hi);
        let mut values = vec![lo];
        let mut k = (lo / step).floor() + 1.0;
        while k * step < hi {
            let v = k * step;
            values.push(if v.abs() < step * 1e-9 { 0.0 } else { v });
            k += 1.0;
        }
        values.push(hi);
        let mut labels: Vec<Label> = Vec::new();
        // Labels take their height (vertical bars) or their width (horizontal ones) plus a gap.
        let room = |text: &str| {
            if place.vertical() {
                (font::HEIGHT + 5) * s
            } else {
                (font::text_width(text) + 4) * s
            }
        };
        let last = values.len() - 1;
        for (i, v) in values.into_iter().enumerate() {
            let label = Label {
                at: at(v),
                text: label_text(v),
            };
            let fits = |other: &Label| {
                label.at.abs_diff(other.at) >= (room(&label.text) + room(&other.text)).div_ceil(2)
            };
            if i == last {
                // The high end always shows: it replaces a round value too close to it.
                while labels.len() > 1 && !labels.last().is_some_and(fits) {
                    labels.pop();
                }
                labels.push(label);
            } else if labels.last().is_none_or(fits) {
                labels.push(label);
            }
        }
        labels
    }

    /// The number of bar pixels from the low end to the high end.
    pub fn len(&self) -> usize {
        if self.place.vertical() {
            self.y1 - self.y0
        } else {
            self.x1 - self.x0
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The data value whose colour bar pixel `(x, y)` shows (at the pixel's centre).
    pub fn value_at(&self, x: usize, y: usize) -> f64 {
        let k = if self.place.vertical() {
            self.y1 - 1 - y
        } else {
            x - self.x0
        };
        self.lo + (k as f64 + 0.5) / self.len() as f64 * (self.hi - self.lo)
    }

    /// Whether `(x, y)` is a bar pixel.
    pub fn in_bar(&self, x: usize, y: usize) -> bool {
        (self.x0..self.x1).contains(&x) && (self.y0..self.y1).contains(&y)
    }
}

/// Draws the legend of `scale` into `fb` (opaque pixels). `false` where the image is too small
/// for one.
pub fn draw(fb: &mut Framebuffer, place: Place, scale: &ColorScale) -> bool {
    let Some(layout) = Layout::new(place, fb.width, fb.height, scale) else {
        return false;
    };
    let (w, h) = (fb.width, fb.height);
    let mut set = |x: usize, y: usize, rgb: [f64; 3]| {
        if x < w && y < h {
            fb.pixels[y * w + x] = [rgb[0] as f32, rgb[1] as f32, rgb[2] as f32, 1.0];
        }
    };
    // A black frame one pixel outside the bar.
    for x in layout.x0.saturating_sub(1)..=layout.x1 {
        for y in [layout.y0.wrapping_sub(1), layout.y1] {
            set(x, y, [0.0; 3]);
        }
    }
    for y in layout.y0.saturating_sub(1)..=layout.y1 {
        for x in [layout.x0.wrapping_sub(1), layout.x1] {
            set(x, y, [0.0; 3]);
        }
    }
    for y in layout.y0..layout.y1 {
        for x in layout.x0..layout.x1 {
            set(x, y, scale.color(layout.value_at(x, y)));
        }
    }
    // Ticks and labels: collect the white pixels, outline them in black, then draw them.
    let s = layout.scale;
    let gap = label_gap(s);
    let tick = 2 * s + 1;
    let mut ink: Vec<(usize, usize)> = Vec::new();
    for label in &layout.labels {
        let text_w = font::text_width(&label.text) * s;
        let text_h = font::HEIGHT * s;
        let (tx, ty) = if layout.place.vertical() {
            let y = layout.y1 - 1 - label.at;
            for t in 0..tick {
                ink.push((layout.x1 + 1 + t, y));
            }
            (
                layout.x1 + gap,
                y.saturating_sub(text_h / 2).min(h.saturating_sub(text_h)),
            )
        } else {
            let x = layout.x0 + label.at;
            for t in 0..tick {
                ink.push((x, layout.y1 + 1 + t));
            }
            (
                x.saturating_sub(text_w / 2).min(w.saturating_sub(text_w)),
                layout.y1 + gap,
            )
        };
        font::ink_of(&label.text, tx, ty, s, &mut ink);
    }
    paint(fb, &ink, |x, y| !layout.in_bar(x, y));
    true
}

/// Paints text (the pixels `ink`) white with a black outline one pixel wide, the outline only
/// where `outline(x, y)`: readable on any background.
fn paint(fb: &mut Framebuffer, ink: &[(usize, usize)], outline: impl Fn(usize, usize) -> bool) {
    let (w, h) = (fb.width, fb.height);
    let mut set = |x: usize, y: usize, v: f32| {
        if x < w && y < h {
            fb.pixels[y * w + x] = [v, v, v, 1.0];
        }
    };
    for &(x, y) in ink {
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                if nx >= 0 && ny >= 0 && outline(nx as usize, ny as usize) {
                    set(nx as usize, ny as usize, 0.0);
                }
            }
        }
    }
    for &(x, y) in ink {
        set(x, y, 1.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_short() {
        assert_eq!(label_text(0.0), "0");
        assert_eq!(label_text(0.893815), "0.8938");
        assert_eq!(label_text(-2.5), "-2.5");
        assert_eq!(label_text(1234.0), "1234");
        assert_eq!(label_text(1.56522e-12), "1.57e-12");
        assert_eq!(label_text(1e6), "1e6");
        assert_eq!(label_text(0.30000000000000004), "0.3");
    }

    #[test]
    fn round_steps() {
        assert_eq!(nice_step(0.0, 1.0), 0.5);
        assert_eq!(nice_step(0.0, 10.0), 5.0);
        assert_eq!(nice_step(0.0, 0.8), 0.2);
        assert_eq!(nice_step(-3.0, 3.0), 2.0);
    }
}
