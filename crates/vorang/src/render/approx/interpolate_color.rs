//! `interpolateColor <brightness>` (thesis 6.3.1, 2.1.1.2): Shirley–Tuchman projected
//! tetrahedra with Gouraud interpolation. θ and an effective emission η̄ are computed at the
//! projection's vertices — θ = 1 and η̄ = η at the outline vertices; at the thick point T
//! θ = exp(−½(χ_front+χ_back)·ℓ) and η̄ = η_back·θ + η_front·(1−θ) — and interpolated linearly
//! over the projected triangles; compositing is `I = I·θ + B·η̄·(1−θ)`.
//!
//! Where the camera clips a pixel's interval, θ is raised to the kept fraction of the length
//! (the optical depth scales with it). Cells reaching in front of a perspective near plane have
//! no Shirley–Tuchman split; their pixels are integrated like `interpolateCoeff constEA`.

use super::interpolate_coeff::{NodeCoefficients, interpolate, node_coefficients};
use super::{Approx, Method, MethodInfo, Pixel, Scratch, non_negative};
use crate::integrate::{Segment, const_ea::rule as const_ea_rule};
use crate::render::footprint::Footprint;
use crate::render::frame::Frame;
use crate::render::project::THICK;

pub const INFO: MethodInfo = MethodInfo {
    name: "interpolateColor",
    usage: "brightness",
    summary: "Shirley–Tuchman projected tetrahedra: θ and colour at the projection's vertices, Gouraud-interpolated",
    parse,
};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterpolateColor {
    pub brightness: f64,
}

fn parse(args: &[&str]) -> Result<Method, String> {
    Ok(Method::InterpolateColor(InterpolateColor {
        brightness: non_negative(args[0], "a brightness factor")?,
    }))
}

/// Per projection vertex (nodes 0…3, T = 4): θ and η̄; or, for a near-clipped cell, the node
/// coefficients for the fallback.
pub enum ColorCell {
    Gouraud([(f64, [f64; 3]); 5]),
    Clipped(NodeCoefficients),
}

impl Approx for InterpolateColor {
    type Cell = ColorCell;
    const SCREEN_SPACE: bool = true;

    fn fan_values(&self, c: &ColorCell) -> Option<[[f64; 4]; 5]> {
        match c {
            ColorCell::Gouraud(v) => Some(v.map(|(t, e)| [t, e[0], e[1], e[2]])),
            ColorCell::Clipped(_) => None,
        }
    }

    #[inline]
    fn screen_pixel(&self, v: [f64; 4]) -> ([f64; 3], f64) {
        crate::render::gouraud::shade(self.brightness, v)
    }

    fn gouraud_brightness(&self) -> Option<f64> {
        Some(self.brightness)
    }

    fn prepare(&self, f: &Frame, cell: usize, fp: &Footprint, s: &mut Scratch) -> ColorCell {
        let coeff = node_coefficients(f, cell, s);
        let Some(proj) = fp.projection else {
            return ColorCell::Clipped(coeff);
        };
        let mut v = [(1.0, [0.0; 3]); 5];
        for i in 0..4 {
            v[i] = (1.0, coeff[i].0);
        }
        let ray = f.projector.ray_at(proj.thick[0], proj.thick[1]);
        let (screen, eye) = (f.screen_corners(cell), f.eye_corners(cell));
        v[THICK as usize] = match proj.thick_ends(&screen, &eye, f.projector.is_perspective()) {
            Some(ends) => {
                let front = f.mapped(cell, &ends.near.0, &mut s.values);
                let back = f.mapped(cell, &ends.far.0, &mut s.values);
                let l = (ends.far.1 - ends.near.1) * ray.speed();
                let theta = (-0.5 * (front.1 + back.1) * l).exp();
                let eta = [0, 1, 2].map(|k| back.0[k] * theta + front.0[k] * (1.0 - theta));
                (theta, eta)
            }
            // A thick point on the outline (degenerate projection): no depth there.
            None => (1.0, proj.thick_node.map_or([0.0; 3], |n| coeff[n].0)),
        };
        ColorCell::Gouraud(v)
    }

    fn pixel(
        &self,
        _: &Frame,
        _: usize,
        c: &ColorCell,
        px: &Pixel,
        _: &mut Scratch,
    ) -> ([f64; 3], f64) {
        match c {
            ColorCell::Gouraud(v) => {
                let (mut theta, eta) = gouraud(v, px.corners, px.weights);
                let full = px.iv.far - px.iv.near;
                if px.far - px.near < full {
                    theta = theta.max(0.0).powf((px.far - px.near) / full);
                }
                let b = eta.map(|e| self.brightness * e * (1.0 - theta));
                (b, theta)
            }
            ColorCell::Clipped(coeff) => {
                let far = interpolate(coeff, &px.iv.lambda(px.far));
                let near = interpolate(coeff, &px.iv.lambda(px.near));
                let seg = Segment {
                    eta: [far.0, near.0],
                    chi: [far.1, near.1],
                    ds: (px.far - px.near) * px.speed,
                    eta_mid: None,
                };
                let (b, theta) = const_ea_rule(&seg);
                (b.map(|x| x * self.brightness), theta)
            }
        }
    }
}

/// θ and η̄ interpolated over a footprint triangle.
#[inline]
fn gouraud(v: &[(f64, [f64; 3]); 5], corners: [u8; 3], weights: [f64; 3]) -> (f64, [f64; 3]) {
    let mut theta = 0.0;
    let mut eta = [0.0; 3];
    for k in 0..3 {
        let (t, e) = v[corners[k] as usize];
        theta += weights[k] * t;
        for ch in 0..3 {
            eta[ch] += weights[k] * e[ch];
        }
    }
    (theta, eta)
}
