//! Drawing one cell through the kernels: its footprint's rows gathered into the buffer with
//! their entry and exit depths, integrated ([`super::shade`]) or shaded from the Gouraud fan, and
//! composited into the tile. The bodies here are `#[inline(always)]`: each is compiled into the
//! baseline, AVX2 and AVX-512 entry points of [`super::dispatch`], for that target's width.

use super::buffer::SpanBuffer;
use super::integrand::{SpanCell, SpanPieces};
use super::shade::integrate_piece;
use crate::render::composite::{EARLY_TERMINATION, Order, composite};
use crate::render::faces::{CellFaces, Row};
use crate::render::gouraud::{self, Fan};
use crate::render::raster::{Rect, rasterize_convex_rows};
use crate::render::rows::CellRows;

/// The runs of row `y`, pixels `from..to` (splits in `row`), into the buffer with their depths,
/// in batches of `P` pixels ([`SpanBuffer::push_run`]); with `record_runs`, each run's first
/// pixel, length and faces into `buf.runs` too.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn push_row<const P: usize, const RESERVED: bool>(
    buf: &mut SpanBuffer,
    cf: &CellFaces,
    rect: Rect,
    y: usize,
    from: usize,
    to: usize,
    row: &Row,
    record_runs: bool,
) {
    let py = y as f64 + 0.5;
    let first = (y - rect.y0) * (rect.x1 - rect.x0);
    for run in cf.spans(row, from, to).runs() {
        let (entry, exit) = (run.entry as usize, run.exit as usize);
        let slot = first + run.x0 - rect.x0;
        if record_runs {
            buf.runs.push([
                buf.n as u32,
                (run.x1 - run.x0) as u32,
                entry as u32,
                exit as u32,
            ]);
        }
        match (cf.depth_row(entry, py), cf.depth_row(exit, py)) {
            (Some(n), Some(f)) => buf.push_run::<P, RESERVED>(slot, run.x0, run.x1, py, n, f),
            _ => buf.push_run_slivers(slot, run.x0, run.x1, py, cf, entry, exit),
        }
    }
}

/// [`draw`](crate::render::span::draw)'s arguments.
pub(super) struct Draw<'a> {
    pub(super) pieces: &'a SpanPieces,
    pub(super) screen: &'a [[f64; 2]; 4],
    pub(super) hull: &'a [[f64; 2]],
    pub(super) faces: &'a CellFaces,
    pub(super) rect: Rect,
    pub(super) order: Order,
}

#[inline(always)]
pub(super) fn draw_body<const WIDE: usize, const FMA: bool, const P: usize>(
    d: &Draw,
    buf: &mut SpanBuffer,
    acc: Option<&mut [([f64; 3], f64)]>,
) -> u64 {
    draw_body_with::<P>(d, buf, acc, |piece, buf| {
        integrate_piece::<WIDE, FMA>(piece, buf)
    })
}

/// [`draw_body`] with the integration of each piece given: inlined, or a call to a kernel
/// compiled for other instructions than the gathering and compositing around it.
#[inline(always)]
pub(super) fn draw_body_with<const P: usize>(
    d: &Draw,
    buf: &mut SpanBuffer,
    acc: Option<&mut [([f64; 3], f64)]>,
    integrate: impl Fn(&SpanCell, &mut SpanBuffer),
) -> u64 {
    let (cf, rect) = (d.faces, d.rect);
    // Only a per-pixel order (no `acc`) reads the runs' faces afterwards.
    let record = acc.is_none();
    buf.clear();
    if let Some(rows) = CellRows::new(d.screen, d.hull, cf.needed(), rect) {
        buf.reserve_cell(&rows);
        for y in rows.ys() {
            if let Some((from, to, row)) = rows.row(y) {
                push_row::<P, true>(buf, cf, rect, y, from, to, &row, record);
            }
        }
    } else {
        // The rows first, then their pixels in this function's own loop: a closure would be
        // compiled for the baseline target, not for the kernel's.
        buf.rows.clear();
        rasterize_convex_rows(d.hull, rect, |y, from, to| buf.rows.push([y, from, to]));
        for i in 0..buf.rows.len() {
            let [y, from, to] = buf.rows[i];
            let row = cf.row(y, from, to);
            push_row::<P, false>(buf, cf, rect, y, from, to, &row, record);
        }
    }
    if d.pieces.count > 1 {
        buf.reset();
    }
    for piece in d.pieces.pieces() {
        integrate(piece, buf);
    }
    match acc {
        Some(acc) => composite_all(buf, acc, d.order),
        None => buf.len() as u64,
    }
}

/// Composites every pixel of `buf` (after shading) into the tile's pixels; returns how many.
#[inline(always)]
fn composite_all(buf: &SpanBuffer, acc: &mut [([f64; 3], f64)], order: Order) -> u64 {
    let n = buf.len();
    let [r, g, b] = &buf.b;
    let (r, g, b, theta) = (&r[..n], &g[..n], &b[..n], &buf.theta[..n]);
    let slots = &buf.slot[..n];
    if order == Order::BackToFront {
        for i in 0..n {
            let a = &mut acc[slots[i] as usize];
            let t = theta[i];
            // [`composite`] back to front, as one operation on the pixel's four numbers: the
            // transparency gains `+ 0`, which changes no value (it is never −0: θ ≥ 0), so that
            // all four lanes do the same product and sum (the same bits as channel by channel).
            // Here, not in `composite` itself: there it made `interpolateColor` 27 % slower
            // (150k, one thread, 3 alternating runs: median frame 345 → 439 ms).
            let v = [r[i], g[i], b[i], 0.0];
            let p = [a.0[0], a.0[1], a.0[2], a.1];
            let out: [f64; 4] = std::array::from_fn(|k| p[k] * t + v[k]);
            *a = ([out[0], out[1], out[2]], out[3]);
        }
        n as u64
    } else {
        let mut drawn = 0;
        for i in 0..n {
            let a = &mut acc[slots[i] as usize];
            if a.1 < EARLY_TERMINATION {
                continue;
            }
            drawn += 1;
            composite(order, a, ([r[i], g[i], b[i]], theta[i]));
        }
        drawn
    }
}

/// [`draw_fan`](crate::render::span::draw_fan)'s arguments.
pub(super) struct FanDraw<'a> {
    pub(super) fan: &'a Fan,
    pub(super) brightness: f64,
    pub(super) screen: &'a [[f64; 2]; 4],
    pub(super) hull: &'a [[f64; 2]],
    pub(super) rect: Rect,
    pub(super) order: Order,
}

/// How [`draw_fan_body`] shades: [`Fan::at_lanes`] (any target), or the fan's intrinsics,
/// only from the function compiled with their features.
#[derive(Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub(super) enum FanShade {
    Lanes,
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    Avx2,
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    Avx512,
}

/// `SHADE`: a [`FanShade`].
#[inline(always)]
pub(super) fn draw_fan_body<const L: usize, const SHADE: u8>(
    d: &FanDraw,
    buf: &mut SpanBuffer,
    acc: &mut [([f64; 3], f64)],
) -> u64 {
    let rect = d.rect;
    let tw = rect.x1 - rect.x0;
    buf.clear();
    let slot = |y: usize, from: usize| (y - rect.y0) * tw + from - rect.x0;
    if let Some(rows) = CellRows::new(d.screen, d.hull, 0, rect) {
        buf.reserve_cell(&rows);
        for y in rows.ys() {
            if let Some((from, to, _)) = rows.row(y) {
                buf.push_pixels::<true>(slot(y, from), from, to, y as f64 + 0.5);
            }
        }
    } else {
        buf.rows.clear();
        rasterize_convex_rows(d.hull, rect, |y, from, to| buf.rows.push([y, from, to]));
        for i in 0..buf.rows.len() {
            let [y, from, to] = buf.rows[i];
            buf.push_pixels::<false>(slot(y, from), from, to, y as f64 + 0.5);
        }
    }
    let n = buf.len().div_ceil(L) * L;
    // Through slices taken once (see `push_run_view`).
    let (xs, ys) = (&buf.x[..n], &buf.y[..n]);
    let [r, g, b] = &mut buf.b;
    let (r, g, b, th) = (&mut r[..n], &mut g[..n], &mut b[..n], &mut buf.theta[..n]);
    #[cfg(target_arch = "x86_64")]
    if SHADE != FanShade::Lanes as u8 {
        // SAFETY: only `draw_fan_avx512` and `draw_fan_avx2` pass these, and they run where
        // the processor has those features.
        unsafe {
            if SHADE == FanShade::Avx512 as u8 {
                d.fan.shade_avx512(d.brightness, n, xs, ys, [r, g, b, th]);
            } else {
                d.fan.shade_avx2(d.brightness, n, xs, ys, [r, g, b, th]);
            }
        }
        return composite_all(buf, acc, d.order);
    }
    let mut i = 0;
    while i < n {
        let lane = |s: &[f64]| -> [f64; L] {
            let mut a = [0.0; L];
            a.copy_from_slice(&s[i..i + L]);
            a
        };
        let v = d.fan.at_lanes::<L>(&lane(xs), &lane(ys));
        let mut out = [[0.0; L]; 4];
        for l in 0..L {
            let (b, theta) = gouraud::shade(d.brightness, [v[0][l], v[1][l], v[2][l], v[3][l]]);
            for ch in 0..3 {
                out[ch][l] = b[ch];
            }
            out[3][l] = theta;
        }
        for (dst, src) in [&mut *r, &mut *g, &mut *b, &mut *th].into_iter().zip(&out) {
            dst[i..i + L].copy_from_slice(src);
        }
        i += L;
    }
    composite_all(buf, acc, d.order)
}
