//! `interpolateCoeff <integration> <brightness>` (thesis 6.3.1): one whole-cell integral per
//! pixel with the chosen rule; η and χ at the entry and exit points are interpolated from values
//! mapped once at the cell's four nodes (the mapping is not applied per pixel).

use super::{Approx, Method, MethodInfo, Pixel, Scratch, non_negative, rule};
use crate::integrate::{RuleInfo, Segment};
use crate::render::footprint::Footprint;
use crate::render::frame::Frame;
use crate::render::span::{SpanCell, SpanGeometry, SpanPieces};

pub const INFO: MethodInfo = MethodInfo {
    name: "interpolateCoeff",
    usage: "integration brightness",
    summary: "η and χ mapped at the cell's nodes, interpolated to entry and exit, one integral per pixel",
    parse,
};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterpolateCoeff {
    pub rule: &'static RuleInfo,
    pub brightness: f64,
}

fn parse(args: &[&str]) -> Result<Method, String> {
    Ok(Method::InterpolateCoeff(InterpolateCoeff {
        rule: rule(args[0])?,
        brightness: non_negative(args[1], "a brightness factor")?,
    }))
}

/// η and χ mapped at the four nodes.
pub type NodeCoefficients = [([f64; 3], f64); 4];

/// Maps the field at each node of a cell.
pub fn node_coefficients(f: &Frame, cell: usize, s: &mut Scratch) -> NodeCoefficients {
    if let Some(mapped) = &f.node_mapped {
        return f.vol.mesh.gather(cell, mapped);
    }
    std::array::from_fn(|i| {
        let mut lambda = [0.0; 4];
        lambda[i] = 1.0;
        f.mapped(cell, &lambda, &mut s.values)
    })
}

/// Interpolates node coefficients at barycentric coordinates `l`.
#[inline]
pub fn interpolate(c: &NodeCoefficients, l: &[f64; 4]) -> ([f64; 3], f64) {
    let mut eta = [0.0; 3];
    let mut chi = 0.0;
    for i in 0..4 {
        for k in 0..3 {
            eta[k] += l[i] * c[i].0[k];
        }
        chi += l[i] * c[i].1;
    }
    (eta, chi)
}

impl Approx for InterpolateCoeff {
    type Cell = NodeCoefficients;

    const SPAN: bool = true;

    /// With the `linear` rule: η and χ interpolated from the nodes are affine in the position.
    fn span_cell(
        &self,
        f: &Frame,
        cell: usize,
        geometry: &SpanGeometry,
        s: &mut Scratch,
        out: &mut SpanPieces,
    ) -> bool {
        if !self.rule.exact_for_linear {
            return false;
        }
        let c = node_coefficients(f, cell, s);
        let value = |i: usize, k: usize| if k < 3 { c[i].0[k] } else { c[i].1 };
        if !(0..4).all(|i| (0..4).all(|k| value(i, k).is_finite())) {
            return false;
        }
        let q: [[f64; 6]; 4] =
            std::array::from_fn(|k| geometry.rays.affine(&std::array::from_fn(|i| value(i, k))));
        let chi = c.iter().map(|n| n.1).fold(0.0, f64::max);
        let Some(terms) = geometry.terms(chi, &q[3]) else {
            return false;
        };
        out.cells[0] = SpanCell {
            q,
            clip: None,
            rays: None,
            terms,
            brightness: self.brightness,
        };
        out.count = 1;
        true
    }

    fn prepare(&self, f: &Frame, cell: usize, _: &Footprint, s: &mut Scratch) -> NodeCoefficients {
        node_coefficients(f, cell, s)
    }

    fn pixel(
        &self,
        _: &Frame,
        _: usize,
        c: &NodeCoefficients,
        px: &Pixel,
        _: &mut Scratch,
    ) -> ([f64; 3], f64) {
        let far = interpolate(c, &px.iv.lambda(px.far));
        let near = interpolate(c, &px.iv.lambda(px.near));
        let seg = Segment {
            eta: [far.0, near.0],
            chi: [far.1, near.1],
            ds: (px.far - px.near) * px.speed,
            eta_mid: None,
        };
        let (b, theta) = self.rule.apply(&seg);
        let k = self.brightness;
        ([b[0] * k, b[1] * k, b[2] * k], theta)
    }
}
