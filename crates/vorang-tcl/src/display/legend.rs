//! The viewer's colour legend: the transfer function over the data range, so that the colours
//! in the picture can be read as values.
//!
//! Drawn for the common one-dimensional case ([`vorang::mapping::Mapping::transfer`]: one scalar
//! field mapped by tables or constants). The upper band is the emission η, scaled so that its
//! largest channel over the range is 1 (a dim map stays readable; the picture's brightness is
//! the method's factor); the lower band is the absorption χ as a dark bar whose height is χ
//! relative to its largest value.

use vorang::mapping::Mapping;
use vorang::volume::Volume;

/// Height of the legend strip in pixels.
pub const HEIGHT: usize = 24;

/// A legend image and what its ends mean.
#[derive(Debug, Clone, PartialEq)]
pub struct Legend {
    pub width: usize,
    /// 8-bit RGBA, `width × HEIGHT`.
    pub rgba: Vec<u8>,
    /// The data range: the field's smallest and largest node value.
    pub min: f64,
    pub max: f64,
    /// The largest χ over the range (the height of a full bar).
    pub chi_max: f64,
}

/// The legend of `mapping` on `vol`, `width` pixels wide; `None` where the mapping is not a
/// function of one scalar (categories, vector fields, cell constants).
pub fn legend(mapping: &Mapping, vol: &Volume, width: usize) -> Option<Legend> {
    let transfer = mapping.transfer(vol)?;
    let values = &transfer.node_values;
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(min.is_finite() && max.is_finite()) || width == 0 {
        return None;
    }
    let at = |i: usize| {
        let t = (i as f64 + 0.5) / width as f64;
        transfer.eval(min + t * (max - min))
    };
    let samples: Vec<([f64; 3], f64)> = (0..width).map(at).collect();
    let eta_max = samples
        .iter()
        .flat_map(|s| s.0)
        .fold(0.0f64, f64::max)
        .max(1e-300);
    let chi_max = samples.iter().map(|s| s.1).fold(0.0f64, f64::max);
    let half = HEIGHT / 2;
    let mut rgba = vec![255u8; width * HEIGHT * 4];
    for (x, (eta, chi)) in samples.iter().enumerate() {
        let colour = eta.map(|c| (c / eta_max).clamp(0.0, 1.0) * 255.0);
        let bar = if chi_max > 0.0 {
            (chi / chi_max * half as f64).round() as usize
        } else {
            0
        };
        for y in 0..HEIGHT {
            let px = &mut rgba[(y * width + x) * 4..][..3];
            if y < half {
                px.copy_from_slice(&colour.map(|c| c.round() as u8));
            } else if HEIGHT - y <= bar {
                px.copy_from_slice(&[80, 80, 80]);
            }
        }
    }
    Some(Legend {
        width,
        rgba,
        min,
        max,
        chi_max,
    })
}
