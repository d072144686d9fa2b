//! The integration in lanes: every gathered pixel's segment through the cell integrated by the
//! `linear` rule ([`crate::integrate::linear_lanes`]) in batches of pixels, the same operations in
//! the same order in every lane, so the batch width changes no bit.

use super::buffer::{LANES, SpanBuffer};
use super::integrand::{Clip, SpanCell};
use crate::integrate::linear_lanes::{MAX_TERMS, madd, moments_with};

/// Integrates every pixel of `buf` for `cell` with the baseline kernel: fills `buf.b` and
/// `buf.theta` — or, for a cell with a [`Clip`], composites the piece's contribution behind what
/// they hold. (Rendering goes through [`draw`], which dispatches to the widest kernel; the tests
/// compare every kernel there.)
#[cfg(test)]
pub(super) fn shade(cell: &SpanCell, buf: &mut SpanBuffer) {
    integrate_piece::<LANES, false>(cell, buf)
}

/// [`kernel_body`] for `cell`'s clipping and projection, in batches of `WIDE` pixels.
#[inline(always)]
pub(super) fn integrate_piece<const WIDE: usize, const FMA: bool>(
    cell: &SpanCell,
    buf: &mut SpanBuffer,
) {
    match (cell.clip.is_some(), cell.rays.is_some()) {
        (false, false) => kernel_body::<WIDE, false, false, FMA>(cell, buf),
        (true, false) => kernel_body::<WIDE, true, false, FMA>(cell, buf),
        (false, true) => kernel_body::<WIDE, false, true, FMA>(cell, buf),
        (true, true) => kernel_body::<WIDE, true, true, FMA>(cell, buf),
    }
}

/// The kernel: the (padded) buffer in batches of `WIDE` pixels, the rest in batches of
/// [`LANES`]. A batch's series is one chain of dependent multiplications per lane; several
/// registers of lanes side by side keep the processor's pipelines full instead of waiting on
/// that chain (measured: the 8-lane AVX-512 kernel spent most of its time there). Lanes are
/// independent, so the batch width changes no bit.
#[inline(always)]
pub(super) fn kernel_body<
    const WIDE: usize,
    const CLIP: bool,
    const PERSP: bool,
    const FMA: bool,
>(
    cell: &SpanCell,
    buf: &mut SpanBuffer,
) {
    // Whole batches: the arrays hold at least this many (stale values past `len`).
    let n = buf.len().div_ceil(LANES) * LANES;
    let mut i = 0;
    while i + WIDE <= n {
        batch::<WIDE, CLIP, PERSP, FMA>(cell, buf, i);
        i += WIDE;
    }
    if WIDE > 16 && i + 16 <= n {
        batch::<16, CLIP, PERSP, FMA>(cell, buf, i);
        i += 16;
    }
    while i < n {
        batch::<LANES, CLIP, PERSP, FMA>(cell, buf, i);
        i += LANES;
    }
}

/// Pixels `i..i + L` of the buffer. With `CLIP`, only the part of each segment in the clip's
/// range, composited behind the buffer's contents; with `PERSP`, τ-coefficients that vary with x
/// and y and segment lengths `Δτ·|d|`.
#[inline(always)]
fn batch<const L: usize, const CLIP: bool, const PERSP: bool, const FMA: bool>(
    cell: &SpanCell,
    buf: &mut SpanBuffer,
    i: usize,
) {
    let terms = cell.terms.min(MAX_TERMS);
    let q = &cell.q;
    let lane = |s: &[f64]| -> [f64; L] {
        let mut a = [0.0; L];
        a.copy_from_slice(&s[i..i + L]);
        a
    };
    let (x, y, mut near, mut far) = (lane(&buf.x), lane(&buf.y), lane(&buf.near), lane(&buf.far));
    if CLIP {
        let clip = cell.clip.unwrap_or(Clip {
            s: [0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
        });
        let s = clip.s;
        for l in 0..L {
            // The depths where s reaches lo and hi (±∞ for the outer pieces).
            let base = s[0] + s[1] * x[l] + s[2] * y[l];
            let rate = if PERSP {
                s[3] + s[4] * x[l] + s[5] * y[l]
            } else {
                s[3]
            };
            let ta = (clip.lo - base) / rate;
            let tb = (clip.hi - base) / rate;
            let n = near[l].max(ta.min(tb));
            let f = far[l].min(ta.max(tb));
            near[l] = n;
            far[l] = f.max(n);
        }
        // No lane's segment reaches into this piece (most batches of a cell that a knot
        // crosses lie on one side of it): a segment of length zero adds nothing (b = 0) and
        // dims nothing (θ = 1), so skipping the batch gives the same bits.
        let mut reaches = false;
        for l in 0..L {
            reaches |= far[l] > near[l];
        }
        if !reaches {
            return;
        }
    }
    // Quantity k (η_r, η_g, η_b, χ) at the far and near end of lane l. The colours are only
    // needed after the series: computed there, the series' loop is not crowded out of the
    // registers by 24 values per lane waiting for it (the same expressions, the same bits).
    let ends = |k: usize, l: usize| {
        let base = madd::<FMA>(q[k][2], y[l], madd::<FMA>(q[k][1], x[l], q[k][0]));
        let rate = if PERSP {
            madd::<FMA>(q[k][5], y[l], madd::<FMA>(q[k][4], x[l], q[k][3]))
        } else {
            q[k][3]
        };
        (
            madd::<FMA>(rate, far[l], base),
            madd::<FMA>(rate, near[l], base),
        )
    };
    let mut len = [0.0; L];
    let mut c = [0.0; L];
    let mut d = [0.0; L];
    for l in 0..L {
        let (chi_far, chi_near) = ends(3, l);
        len[l] = far[l] - near[l];
        if PERSP {
            let d = cell.rays.unwrap_or([0.0; 4]);
            let (dx, dy) = (d[0] + d[1] * x[l], d[2] + d[3] * y[l]);
            len[l] *= (dx * dx + dy * dy + 1.0).sqrt();
        }
        // Negative absorption (unphysical) counts as none, as in the scalar rule.
        let a = (chi_far * len[l]).max(0.0);
        c[l] = (chi_near * len[l]).max(0.0);
        d[l] = a - c[l];
    }
    let (j0, j1, th) = moments_with::<L, FMA>(&c, &d, terms);
    let ot = &mut buf.theta[i..i + L];
    for (k, out) in buf.b.iter_mut().enumerate() {
        let out = &mut out[i..i + L];
        for l in 0..L {
            let (f, n) = ends(k, l);
            let b = cell.brightness * (len[l] * madd::<FMA>(n, j0[l], (f - n) * j1[l]));
            // Behind the nearer pieces already there: their transparency dims this one.
            out[l] = if CLIP { out[l] + ot[l] * b } else { b };
        }
    }
    for l in 0..L {
        ot[l] = if CLIP { ot[l] * th[l] } else { th[l] };
    }
}
