//! `exact <integration> <step> <brightness>` (thesis 6.3.1 „Exakte Methode“): per pixel, the
//! cell's ray interval is split into pieces of at most `step` world units; the field is
//! evaluated with its own interpolator and mapped at every piece end, and each piece is
//! integrated with the chosen rule. A step larger than the interval (or 0) integrates the
//! whole interval at once.
//!
//! With the `linear` rule (SPEC §3 **Beyond**) the interval is also cut where the maps change
//! slope (table values, category boundaries). Between cuts, for Linear fields, χ is linear and η
//! linear or quadratic along the ray, which the rule integrates exactly — so `exact linear 0 B`
//! is exact up to floating point. Where the field or map is not polynomial along the ray (e.g.
//! GaussTest, BARY_SHADING 3), pieces are refined adaptively until halving no longer changes
//! the result (to 1e-9); `step > 0` adds uniform sub-steps on top.

use super::{Approx, Method, MethodInfo, Pixel, Scratch, accumulate, non_negative, rule};
use crate::integrate::{Contribution, RuleInfo, Segment};
use crate::mapping::{Lines, Shape};
use crate::render::cell::EyeCell;
use crate::render::footprint::Footprint;
use crate::render::frame::Frame;

pub const INFO: MethodInfo = MethodInfo {
    name: "exact",
    usage: "integration step brightness",
    summary: "true field values and mapping at sample points at most 'step' apart, integrated with the rule; 'exact linear 0 B' is exact",
    parse,
};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exact {
    pub rule: &'static RuleInfo,
    pub step: f64,
    pub brightness: f64,
}

fn parse(args: &[&str]) -> Result<Method, String> {
    Ok(Method::Exact(Exact {
        rule: rule(args[0])?,
        step: non_negative(args[1], "a step length")?,
        brightness: non_negative(args[2], "a brightness factor")?,
    }))
}

/// Refinement stops when halving a piece changes its contribution by less than this.
const REFINE_TOLERANCE: f64 = 1e-9;
/// …or after this many halvings.
const REFINE_DEPTH: u32 = 12;

/// Field values and position along one pixel's ray through a cell.
struct Ray<'a> {
    f: &'a Frame<'a>,
    cell: usize,
    px: &'a Pixel,
}

impl Ray<'_> {
    /// Field values at `u ∈ [0, 1]` (0: far end, 1: near end) into `buf`; returns the position.
    fn sample(&self, u: f64, buf: &mut Vec<f64>) -> [f64; 3] {
        let tau = self.px.far - u * (self.px.far - self.px.near);
        let lambda = self.px.iv.lambda(tau);
        let tet = self.f.vol.mesh.tets()[self.cell];
        let nodes = self.f.vol.mesh.nodes();
        let mut pos = [0.0; 3];
        for i in 0..4 {
            for k in 0..3 {
                pos[k] += lambda[i] * nodes[tet[i] as usize][k];
            }
        }
        buf.resize(self.f.mapping.width(), 0.0);
        self.f
            .mapping
            .sample_fields(self.f.vol, self.cell, &lambda, pos, buf);
        pos
    }

    /// (η, χ) at `u` with the given map lines.
    fn mapped(&self, u: f64, lines: Lines, buf: &mut Vec<f64>) -> ([f64; 3], f64) {
        let pos = self.sample(u, buf);
        self.f.mapping.eval_on(lines, buf, self.cell, pos)
    }
}

impl Exact {
    /// The contribution of the piece `[u0, u1]` with the `linear` rule: exact where η is at most
    /// quadratic and χ linear along it, refined by halving otherwise.
    fn linear_piece(
        &self,
        ray: &Ray,
        u0: f64,
        u1: f64,
        length: f64,
        s: &mut Scratch,
        depth: u32,
    ) -> Contribution {
        let um = 0.5 * (u0 + u1);
        ray.sample(um, &mut s.values);
        let lines = ray.f.mapping.lines_at(&s.values);
        let (eta_shape, chi_shape) = ray.f.mapping.piece_shapes(&s.values);
        let exact = chi_shape <= Shape::Linear && eta_shape <= Shape::Quadratic;
        let one = self.linear_segment(ray, lines, u0, u1, length, eta_shape == Shape::Quadratic, s);
        if exact || depth >= REFINE_DEPTH {
            return one;
        }
        let mut two = self.linear_segment(ray, lines, u0, um, length, true, s);
        accumulate(
            &mut two,
            self.linear_segment(ray, lines, um, u1, length, true, s),
        );
        let change = (0..3)
            .map(|c| (one.0[c] - two.0[c]).abs())
            .fold((one.1 - two.1).abs(), f64::max);
        if change <= REFINE_TOLERANCE {
            return two;
        }
        let mut acc = self.linear_piece(ray, u0, um, length, s, depth + 1);
        accumulate(
            &mut acc,
            self.linear_piece(ray, um, u1, length, s, depth + 1),
        );
        acc
    }

    /// One segment with the rule, η sampled in the middle if `quadratic`.
    #[allow(clippy::too_many_arguments)]
    fn linear_segment(
        &self,
        ray: &Ray,
        lines: Lines,
        u0: f64,
        u1: f64,
        length: f64,
        quadratic: bool,
        s: &mut Scratch,
    ) -> Contribution {
        let far = ray.mapped(u0, lines, &mut s.values);
        let near = ray.mapped(u1, lines, &mut s.values);
        let eta_mid = quadratic.then(|| ray.mapped(0.5 * (u0 + u1), lines, &mut s.values).0);
        let seg = Segment {
            eta: [far.0, near.0],
            chi: [far.1, near.1],
            ds: (u1 - u0) * length,
            eta_mid,
        };
        (self.rule.rule)(&seg)
    }
}

impl Approx for Exact {
    type Cell = ();

    fn prepare(&self, _: &Frame, _: usize, _: &EyeCell, _: &Footprint, _: &mut Scratch) {}

    fn pixel(
        &self,
        f: &Frame,
        cell: usize,
        _: &(),
        px: &Pixel,
        s: &mut Scratch,
    ) -> ([f64; 3], f64) {
        let length = (px.far - px.near) * px.ray.speed();
        let pieces = if self.step > 0.0 && length > self.step {
            (length / self.step).ceil() as usize
        } else {
            1
        };
        let ray = Ray { f, cell, px };
        let mut acc = ([0.0; 3], 1.0);
        if self.rule.exact_for_linear {
            // Cuts: uniform sub-steps and the maps' breakpoints between the two ends.
            s.cuts.clear();
            s.cuts
                .extend((0..=pieces).map(|k| k as f64 / pieces as f64));
            ray.sample(0.0, &mut s.values);
            ray.sample(1.0, &mut s.values2);
            f.mapping.cuts(&s.values, &s.values2, &mut s.cuts);
            s.cuts.sort_by(f64::total_cmp);
            s.cuts.dedup();
            let cuts = std::mem::take(&mut s.cuts);
            for w in cuts.windows(2) {
                if w[1] > w[0] {
                    accumulate(&mut acc, self.linear_piece(&ray, w[0], w[1], length, s, 0));
                }
            }
            s.cuts = cuts;
        } else {
            // The thesis's rules: values at the piece ends, from the far end to the near end.
            s.ends.clear();
            for k in 0..=pieces {
                let u = k as f64 / pieces as f64;
                let pos = ray.sample(u, &mut s.values);
                s.ends.push(f.mapping.eval(&s.values, cell, pos));
            }
            let ds = length / pieces as f64;
            for k in 0..pieces {
                let (far, near) = (s.ends[k], s.ends[k + 1]);
                let seg = Segment {
                    eta: [far.0, near.0],
                    chi: [far.1, near.1],
                    ds,
                    eta_mid: None,
                };
                accumulate(&mut acc, (self.rule.rule)(&seg));
            }
        }
        (acc.0.map(|b| b * self.brightness), acc.1)
    }
}
