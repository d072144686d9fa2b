//! `exact <integration> <step> <brightness>` (thesis 6.3.1 „Exakte Methode“): per pixel, the
//! cell's ray interval is split into pieces of at most `step` world units; the field is
//! evaluated with its own interpolator and mapped at every piece end, and each piece is
//! integrated with the chosen rule. A step larger than the interval (or 0) integrates the
//! whole interval at once.
//!
//! With the `linear` rule (an addition to the thesis) the interval is also cut where the maps
//! change slope (table values, category boundaries). Between cuts, for Linear fields, χ is linear and η
//! linear or quadratic along the ray, which the rule integrates exactly — so `exact linear 0 B`
//! is exact up to floating point. Where the field or map is not polynomial along the ray (e.g.
//! GaussTest, BARY_SHADING 3), pieces are refined adaptively until halving no longer changes
//! the result (to 1e-9, at most 12 halvings); `step > 0` adds uniform sub-steps on top. On the
//! gauss example that gives a measured error of 3.4e-6 against the reference renderer, at about
//! the cost of `exact constEA 0.0005` with the same error (docs/performance.md).

use super::{Approx, Method, MethodInfo, Pixel, Scratch, accumulate, non_negative, rule};
use crate::error::Error;
use crate::integrate::{Contribution, RuleInfo, Segment};
use crate::mapping::{Lines, Shape, Transfer1D};
use crate::render::footprint::Footprint;
use crate::render::frame::Frame;
use crate::render::span::{self, Clip, SpanCell, SpanGeometry, SpanPieces};

/// The most pieces `exact` may cut one ray through the whole volume into.
pub const MAX_PIECES: f64 = 1e6;

/// Refuses an `exact` step so small that a ray through the volume would need more than
/// [`MAX_PIECES`] pieces (the frame would take days and its cut lists terabytes): every cell
/// interval is at most the diagonal of the transformed volume's bounding box. With the method,
/// not the frame schedule, that asks for it: the limit is the method's own.
pub(crate) fn check_step(step: f64, eye_nodes: &[[f64; 3]]) -> Result<(), Error> {
    if step <= 0.0 {
        return Ok(());
    }
    let size = crate::mesh::Aabb::of_points(eye_nodes).size();
    let diagonal = (size[0] * size[0] + size[1] * size[1] + size[2] * size[2]).sqrt();
    if diagonal / step > MAX_PIECES {
        return Err(Error::Invalid(format!(
            "method exact: a step of {step:e} would cut a ray through the volume (diagonal {diagonal:.3e}) into more than {MAX_PIECES:e} pieces; use a step of at least {:.3e}, or 0 for one piece per cell",
            diagonal / MAX_PIECES
        )));
    }
    Ok(())
}

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
    /// [`Approx::span_cell`] for `exact`: `None` where the cell goes pixel by pixel.
    fn span_pieces(
        &self,
        f: &Frame,
        cell: usize,
        geometry: &SpanGeometry,
        out: &mut SpanPieces,
    ) -> Option<()> {
        if !self.rule.exact_for_linear || (self.step > 0.0 && geometry.length > self.step) {
            return None;
        }
        let (t, values) = f.transfer_of(cell)?;
        let v = f.gather(cell, values);
        if !v.iter().all(|x| x.is_finite()) {
            return None;
        }
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            });
        let (first, last) = (t.piece(lo), t.piece(hi));
        let count = last - first + 1;
        let s = geometry.rays.affine(&v);
        // Along every ray the field must run one way through the pieces.
        let direction = geometry.rate_sign(&s);
        if count > span::MAX_PIECES || (count > 1 && direction == 0) {
            return None;
        }
        for (i, slot) in out.cells.iter_mut().take(count).enumerate() {
            // Nearest first: where the field grows with depth, the lowest piece is in front.
            let p = if direction > 0 { first + i } else { last - i };
            let (from, base, slope) = t.affine_piece(p)?;
            let q: [[f64; 6]; 4] = std::array::from_fn(|k| {
                [
                    base[k] + (s[0] - from) * slope[k],
                    slope[k] * s[1],
                    slope[k] * s[2],
                    slope[k] * s[3],
                    slope[k] * s[4],
                    slope[k] * s[5],
                ]
            });
            // χ is affine in the field: largest at an end of the cell's range in this piece.
            let (plo, phi) = t.piece_range(p);
            let chi = [lo.max(plo), hi.min(phi)]
                .iter()
                .map(|&x| base[3] + (x - from) * slope[3])
                .fold(0.0, f64::max);
            *slot = SpanCell {
                q,
                clip: (count > 1).then_some(Clip {
                    s,
                    lo: plo,
                    hi: phi,
                }),
                rays: None,
                terms: geometry.terms(chi, &q[3])?,
                brightness: self.brightness,
            };
        }
        out.count = count;
        Some(())
    }

    /// How many uniform sub-steps the pixel's segment gets, and its length.
    #[inline]
    fn pieces(&self, px: &Pixel) -> (usize, f64) {
        let length = (px.far - px.near) * px.speed;
        let pieces = if self.step > 0.0 && length > self.step {
            // Bounded by the check at the start of the render ([`check_step`]).
            (length / self.step).ceil().min(MAX_PIECES) as usize
        } else {
            1
        };
        (pieces, length)
    }

    /// The contribution of the piece `[u0, u1]` with the `linear` rule: exact where η is at most
    /// quadratic and χ linear along it, refined by halving otherwise. `known`: the piece's
    /// one-segment contribution with the map lines it was computed for, when the caller has it
    /// already (each halving computes both halves as single segments to estimate its error; a
    /// half that needs refining again reuses that instead of sampling it once more).
    #[allow(clippy::too_many_arguments)]
    fn linear_piece(
        &self,
        ray: &Ray,
        u0: f64,
        u1: f64,
        length: f64,
        s: &mut Scratch,
        depth: u32,
        known: Option<(Lines, Contribution)>,
    ) -> Contribution {
        let um = 0.5 * (u0 + u1);
        ray.sample(um, &mut s.values);
        let lines = ray.f.mapping.lines_at(&s.values);
        let (eta_shape, chi_shape) = ray.f.mapping.piece_shapes(&s.values);
        let exact = chi_shape <= Shape::Linear && eta_shape <= Shape::Quadratic;
        let quadratic = eta_shape == Shape::Quadratic;
        let one = match known {
            // Computed as a quadratic segment with the same lines: the same numbers.
            Some((l, c)) if l == lines && (quadratic || !exact) => c,
            _ => self.linear_segment(ray, lines, u0, u1, length, quadratic, s),
        };
        if exact || depth >= REFINE_DEPTH {
            return one;
        }
        let first = self.linear_segment(ray, lines, u0, um, length, true, s);
        let second = self.linear_segment(ray, lines, um, u1, length, true, s);
        let mut two = first;
        accumulate(&mut two, second);
        let change = (0..3)
            .map(|c| (one.0[c] - two.0[c]).abs())
            .fold((one.1 - two.1).abs(), f64::max);
        if change <= REFINE_TOLERANCE {
            return two;
        }
        let mut acc = self.linear_piece(ray, u0, um, length, s, depth + 1, Some((lines, first)));
        accumulate(
            &mut acc,
            self.linear_piece(ray, um, u1, length, s, depth + 1, Some((lines, second))),
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
        self.rule.apply(&seg)
    }
}

impl Exact {
    /// The pixel with the mapping as a merged 1D transfer function: the field along the ray is
    /// `s(τ) = Σ (a_i + τ·b_i)·v_i`, linear, so its values at the ends give every breakpoint
    /// crossing directly, and each piece between them is one call of the rule with η and χ
    /// from one piece of the table. Same pieces and values as the general path below.
    #[inline]
    fn transfer_pixel(
        &self,
        t: &Transfer1D,
        v: &[f64; 4],
        px: &Pixel,
        s: &mut Scratch,
    ) -> Contribution {
        let (pieces, length) = self.pieces(px);
        let (a, b) = (&px.iv.a, &px.iv.b);
        let s0 = a[0] * v[0] + a[1] * v[1] + a[2] * v[2] + a[3] * v[3];
        let slope = b[0] * v[0] + b[1] * v[1] + b[2] * v[2] + b[3] * v[3];
        let (s_far, s_near) = (s0 + px.far * slope, s0 + px.near * slope);
        let at = |u: f64| s_far + u * (s_near - s_far);
        if !self.rule.exact_for_linear {
            // The thesis's rules: values at the piece ends, from the far end to the near end.
            let ds = length / pieces as f64;
            let mut acc = ([0.0; 3], 1.0);
            let mut far = t.eval(s_far);
            for k in 1..=pieces {
                let near = t.eval(at(k as f64 / pieces as f64));
                let seg = Segment {
                    eta: [far.0, near.0],
                    chi: [far.1, near.1],
                    ds,
                    eta_mid: None,
                };
                accumulate(&mut acc, self.rule.apply(&seg));
                far = near;
            }
            return acc;
        }
        let quadratic = t.quadratic_eta();
        let segment = |u0: f64, u1: f64, p: usize| {
            let (s0, s1) = (at(u0), at(u1));
            let mid = 0.5 * (s0 + s1);
            let far = t.eval_in(p, s0);
            let near = t.eval_in(p, s1);
            let seg = Segment {
                eta: [far.0, near.0],
                chi: [far.1, near.1],
                ds: (u1 - u0) * length,
                eta_mid: if quadratic {
                    Some(t.eval_in(p, mid).0)
                } else {
                    None
                },
            };
            self.rule.apply(&seg)
        };
        let piece = |u0: f64, u1: f64| segment(u0, u1, t.piece(0.5 * (at(u0) + at(u1))));
        // The common case: both ends in the same piece of the table, no sub-steps.
        let p = t.piece(s_far);
        if pieces == 1 && t.piece(s_near) == p {
            return segment(0.0, 1.0, p);
        }
        let knots = t.knots_between(s_far, s_near);
        s.cuts.clear();
        s.cuts
            .extend((0..=pieces).map(|k| k as f64 / pieces as f64));
        s.cuts
            .extend(knots.iter().map(|&x| (x - s_far) / (s_near - s_far)));
        s.cuts.sort_by(f64::total_cmp);
        s.cuts.dedup();
        let mut acc = ([0.0; 3], 1.0);
        for w in s.cuts.windows(2) {
            if w[1] > w[0] {
                accumulate(&mut acc, piece(w[0], w[1]));
            }
        }
        acc
    }
}

impl Approx for Exact {
    /// The transfer function's field at the cell's nodes (zeros without one).
    type Cell = [f64; 4];

    const SPAN: bool = true;

    /// No sub-steps and the `linear` rule: inside each piece of the merged table η and χ are
    /// affine in the position. A cell whose field spans several pieces is cut along every ray
    /// where the field crosses a knot (the same cuts as [`Exact::transfer_pixel`]).
    fn span_cell(
        &self,
        f: &Frame,
        cell: usize,
        geometry: &SpanGeometry,
        _: &mut Scratch,
        out: &mut SpanPieces,
    ) -> bool {
        self.span_pieces(f, cell, geometry, out).is_some()
    }

    fn prepare(&self, f: &Frame, cell: usize, _: &Footprint, _: &mut Scratch) -> [f64; 4] {
        f.node_values(cell)
    }

    fn pixel(
        &self,
        f: &Frame,
        cell: usize,
        v: &[f64; 4],
        px: &Pixel,
        s: &mut Scratch,
    ) -> ([f64; 3], f64) {
        if let Some((t, _)) = f.transfer_of(cell) {
            let acc = self.transfer_pixel(t, v, px, s);
            let k = self.brightness;
            return ([acc.0[0] * k, acc.0[1] * k, acc.0[2] * k], acc.1);
        }
        let (pieces, length) = self.pieces(px);
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
                    accumulate(
                        &mut acc,
                        self.linear_piece(&ray, w[0], w[1], length, s, 0, None),
                    );
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
                accumulate(&mut acc, self.rule.apply(&seg));
            }
        }
        (acc.0.map(|b| b * self.brightness), acc.1)
    }
}
