//! Span kernels: a cell's covered pixels integrated together, in SIMD lanes.
//!
//! Every quantity the `linear` rule needs is, along the ray of pixel (x, y), affine in the
//! depth τ with coefficients affine in x and y (for an orthographic view, affine in all three): η (RGB) and χ inside one piece of the transfer function
//! (`exact linear`), or interpolated from the nodes (`interpolateCoeff linear`). So a cell is
//! described once by four affine functions ([`SpanCell`]); the scan conversion only gathers its
//! pixels' entry and exit depths (from the watertight faces, [`super::faces`]) into a
//! [`SpanBuffer`], and [`shade`] integrates them all: the ends' η and χ, the moments of the rule
//! with a series length fixed per cell ([`crate::integrate::linear_lanes`]) and θ without `exp`.
//! The scalar per-pixel path stays the reference; cells whose segments may cross a table knot or
//! be optically thick take it.
//!
//! The kernel is compiled for the baseline target (SSE2) and, on x86-64, again with AVX2 and
//! AVX-512 enabled; the widest the processor has is chosen once. The AVX2 and AVX-512 kernels
//! use fused multiply-adds (every x86-64 processor with AVX2 has them): the same operations in
//! the same order, so they give the same bits, and fewer of them (about 5 % of an `exact`
//! frame). The baseline rounds each product and sum separately, so its images differ from theirs
//! in the last bits (≤ 10⁻¹⁴ in the tests); the thread count changes no bit on any of them.

use super::cell::CellRays;
use super::composite::{EARLY_TERMINATION, Order, composite};
use super::faces::{CellFaces, DepthRow, Row, max_select};
use super::gouraud::{self, Fan};
use super::raster::{Rect, rasterize_convex_rows};
use super::rows::CellRows;
use crate::integrate::linear_lanes::{MAX_TERMS, madd, moments_with, terms_for};

/// Pixels per batch: one AVX-512 register of f64, two AVX2 registers.
const LANES: usize = 8;

/// Pixels a row writes whatever its length ([`SpanBuffer::push_pixels`]): two batches. Room for
/// them is reserved past every row.
const PIXELS_AHEAD: usize = 2 * LANES;

/// One cell's integrand: `[η_r, η_g, η_b, χ]`, each `q[k][0] + q[k][1]·x + q[k][2]·y +
/// τ·(q[k][3] + q[k][4]·x + q[k][5]·y)` at pixel position (x, y) and depth τ — or one piece of
/// it ([`Clip`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpanCell {
    pub q: [[f64; 6]; 4],
    /// Perspective rays: their direction's x and y components `[d_x0, d_xx, d_y0, d_yy]`
    /// (`d_x = d_x0 + d_xx·x`, `d_y = d_y0 + d_yy·y`, `d_z = −1`), so that a segment's length is
    /// `Δτ·|d|`; `None` for orthographic rays (`|d| = 1`).
    pub rays: Option<[f64; 4]>,
    /// Where the cell's field crosses knots of the transfer function: the part of each segment
    /// where the field is in `[lo, hi)`.
    pub clip: Option<Clip>,
    /// Series terms for the moments: bounds the truncation error for every segment of the cell
    /// ([`crate::integrate::linear_lanes::terms_for`]).
    pub terms: usize,
    /// The method's brightness factor, applied to `b`.
    pub brightness: f64,
}

/// What a method needs of a cell's geometry to describe it for the kernel.
#[derive(Debug, Clone, Copy)]
pub struct SpanGeometry {
    /// λ along the rays ([`CellRays`]).
    pub rays: CellRays,
    /// The cell's depth range (the longest Δτ of a segment) and the longest segment in world
    /// units (Δτ times the largest ray speed).
    pub extent: f64,
    pub length: f64,
    /// The nodes on screen: the footprint is their convex hull.
    pub screen: [[f64; 2]; 4],
}

impl SpanGeometry {
    /// The largest `|a[3] + a[4]·x + a[5]·y|` over the footprint (at a node: it is affine).
    pub fn max_rate(&self, a: &[f64; 6]) -> f64 {
        self.screen
            .iter()
            .map(|p| (a[3] + a[4] * p[0] + a[5] * p[1]).abs())
            .fold(0.0, f64::max)
    }

    /// Whether `a[3] + a[4]·x + a[5]·y` has the same strict sign over the whole footprint: +1,
    /// −1, or 0 if not.
    pub fn rate_sign(&self, a: &[f64; 6]) -> i8 {
        let signs = self.screen.map(|p| {
            let r = a[3] + a[4] * p[0] + a[5] * p[1];
            (r > 0.0) as i8 - (r < 0.0) as i8
        });
        if signs.iter().all(|&s| s == signs[0]) && a.iter().all(|v| v.is_finite()) {
            signs[0]
        } else {
            0
        }
    }

    /// The series terms for a piece whose absorption is at most `chi` and changes at rate
    /// `chi_rate` (the χ row of the integrand) along the rays.
    pub fn terms(&self, chi: f64, chi_rate: &[f64; 6]) -> Option<usize> {
        terms_for(
            chi * self.length,
            0.5 * self.max_rate(chi_rate) * self.extent * self.length,
        )
    }
}

/// Most pieces of the transfer function one cell may span in the kernel (more: per pixel).
pub const MAX_PIECES: usize = 4;

/// A cell's pieces for the kernel, nearest to the eye first.
#[derive(Debug, Clone, Copy)]
pub struct SpanPieces {
    pub cells: [SpanCell; MAX_PIECES],
    pub count: usize,
}

impl SpanPieces {
    /// No pieces, to be filled by [`crate::render::approx::Approx::span_cell`].
    pub fn empty() -> SpanPieces {
        let cell = SpanCell {
            q: [[0.0; 6]; 4],
            rays: None,
            clip: None,
            terms: 0,
            brightness: 0.0,
        };
        SpanPieces {
            cells: [cell; MAX_PIECES],
            count: 0,
        }
    }

    pub fn one(cell: SpanCell) -> SpanPieces {
        SpanPieces {
            cells: [cell; MAX_PIECES],
            count: 1,
        }
    }

    pub fn pieces(&self) -> &[SpanCell] {
        &self.cells[..self.count]
    }
}

/// The part of a segment where the scalar `s = s[0] + s[1]·x + s[2]·y + τ·(s[3] + s[4]·x +
/// s[5]·y)` lies between `lo` and `hi` (±∞ allowed; the τ coefficient nonzero on the cell).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clip {
    pub s: [f64; 6],
    pub lo: f64,
    pub hi: f64,
}

/// A cell's covered pixels (inputs) and their contributions (outputs), structure of arrays,
/// reused from cell to cell. The arrays only grow: the first [`SpanBuffer::len`] entries are
/// this cell's, the rest up to a whole batch are stale values the kernel computes and ignores
/// (no per-cell clearing or padding).
#[derive(Debug, Default)]
pub struct SpanBuffer {
    n: usize,
    /// The footprint's rows `[y, from, to]`, gathered before their pixels.
    rows: Vec<[usize; 3]>,
    pub slot: Vec<u32>,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub near: Vec<f64>,
    pub far: Vec<f64>,
    /// `b` (RGB) and θ per pixel after [`shade`].
    pub b: [Vec<f64>; 3],
    pub theta: Vec<f64>,
    /// The gathered runs of [`draw`]: first pixel, pixel count, entry and exit face — what a
    /// per-pixel order ([`super::runs`]) needs to chain each pixel's fragment.
    pub runs: Vec<[u32; 4]>,
}

impl SpanBuffer {
    pub fn clear(&mut self) {
        self.n = 0;
        self.runs.clear();
    }

    /// Room for `more` pixels after the current ones, up to a whole batch.
    #[inline]
    fn reserve(&mut self, more: usize) {
        let want = (self.n + more).div_ceil(LANES) * LANES;
        if self.slot.len() < want {
            let want = want.max(2 * self.slot.len());
            self.slot.resize(want, 0);
            for v in [
                &mut self.x,
                &mut self.y,
                &mut self.near,
                &mut self.far,
                &mut self.theta,
            ] {
                v.resize(want, 0.0);
            }
            for v in &mut self.b {
                v.resize(want, 0.0);
            }
        }
    }

    /// Room for every pixel of a cell whose rows lie in `rows` (its pixel box): the rows are
    /// then pushed without asking again, row by row (a call per row before; rows average about
    /// twelve pixels).
    #[inline(always)]
    fn reserve_cell(&mut self, rows: &CellRows) {
        self.reserve(rows.area() + PIXELS_AHEAD);
    }

    /// One pixel (the tile loop gathers whole runs with [`SpanBuffer::push_run`]).
    #[cfg(test)]
    fn push(&mut self, slot: usize, x: f64, y: f64, near: f64, far: f64) {
        self.reserve(1);
        let i = self.n;
        self.slot[i] = slot as u32;
        self.x[i] = x;
        self.y[i] = y;
        self.near[i] = near;
        self.far[i] = far;
        self.n += 1;
    }

    /// Pixels `x0..x1` of the row at screen y = `py`, the first in tile slot `slot`, with entry
    /// and exit depths from the faces' rows `near` and `far`, `P` (≤ [`LANES`]) at a time. One
    /// pass writes every array.
    #[inline(always)]
    pub fn push_run<const P: usize, const RESERVED: bool>(
        &mut self,
        slot: usize,
        x0: usize,
        x1: usize,
        py: f64,
        near: DepthRow,
        far: DepthRow,
    ) {
        const { assert!(P <= LANES) };
        if near.perspective() {
            self.push_run_view::<true, P, RESERVED>(slot, x0, x1, py, near, far)
        } else {
            self.push_run_view::<false, P, RESERVED>(slot, x0, x1, py, near, far)
        }
    }

    #[inline(always)]
    fn push_run_view<const PERSP: bool, const P: usize, const RESERVED: bool>(
        &mut self,
        slot: usize,
        x0: usize,
        x1: usize,
        py: f64,
        near: DepthRow,
        far: DepthRow,
    ) {
        let len = x1 - x0;
        // Whole batches of `P` (≤ `LANES`, one vector register: 4 on AVX2, where runs of about
        // five pixels made most of a batch of eight wasted): the writes past the run are
        // overwritten by the next run or lie beyond `len` (stale lanes), and fixed-length loops
        // become vector instructions. `RESERVED`: the caller made room for the whole cell.
        if !RESERVED {
            self.reserve(len + LANES);
        }
        let px0 = x0 as f64 + 0.5;
        // The arrays as slices from here on: their addresses stay in registers (through `self`
        // they were read again after every store).
        let end = self.n + len.div_ceil(P) * P;
        let at = self.n..end;
        let (slots, xs, ys) = (
            &mut self.slot[at.clone()],
            &mut self.x[at.clone()],
            &mut self.y[at.clone()],
        );
        let (nears, fars) = (&mut self.near[at.clone()], &mut self.far[at]);
        let mut k = 0;
        // The batch's first pixel centre, counted along in `f64` (a conversion from a whole
        // number per batch was a chain of five instructions ahead of the depths).
        let mut pxk = px0;
        while k < len {
            let r = k..k + P;
            let mut sl = [0u32; P];
            let mut xv = [0.0; P];
            let mut ns = [0.0; P];
            let mut fs = [0.0; P];
            for l in 0..P {
                // Integers and halves: the same value as `(x0 + k + l) as f64 + 0.5`.
                let px = pxk + l as f64;
                let n = near.at_view::<PERSP>(px);
                sl[l] = (slot + k + l) as u32;
                xv[l] = px;
                ns[l] = n;
                // Rounding can put a face crossing ~1e-16 past the other one (a NaN becomes `n`,
                // as with `f64::max`).
                fs[l] = max_select(far.at_view::<PERSP>(px), n);
            }
            pxk += P as f64;
            slots[r.clone()].copy_from_slice(&sl);
            xs[r.clone()].copy_from_slice(&xv);
            ys[r.clone()].fill(py);
            nears[r.clone()].copy_from_slice(&ns);
            fars[r].copy_from_slice(&fs);
            k += P;
        }
        self.n += len;
    }

    /// Pixels `x0..x1` of the row at screen y = `py`, the first in tile slot `slot`, without
    /// depths (screen-space shading needs none). `RESERVED`: the caller made room for the whole
    /// cell ([`SpanBuffer::reserve_cell`]).
    #[inline(always)]
    fn push_pixels<const RESERVED: bool>(&mut self, slot: usize, x0: usize, x1: usize, py: f64) {
        let len = x1 - x0;
        if !RESERVED {
            self.reserve(len + PIXELS_AHEAD);
        }
        let px0 = x0 as f64 + 0.5;
        // Through slices taken once (see `push_run_view`).
        let at = self.n..self.n + len.div_ceil(LANES).max(PIXELS_AHEAD / LANES) * LANES;
        let (slots, xs, ys) = (
            &mut self.slot[at.clone()],
            &mut self.x[at.clone()],
            &mut self.y[at],
        );
        macro_rules! batch {
            ($k:expr) => {{
                let k: usize = $k;
                let r = k..k + LANES;
                let sl: [u32; LANES] = std::array::from_fn(|l| (slot + k + l) as u32);
                // Integers and halves: the same value as `(x0 + k + l) as f64 + 0.5`.
                let xv: [f64; LANES] = std::array::from_fn(|l| (px0 + k as f64) + l as f64);
                slots[r.clone()].copy_from_slice(&sl);
                xs[r.clone()].copy_from_slice(&xv);
                ys[r].fill(py);
            }};
        }
        // The first `PIXELS_AHEAD` unconditionally (most rows are shorter: the lanes past the
        // row are stale, overwritten by the next row or never read), so that a row's length
        // decides no branch unless it is long (a loop's data-dependent exit after one or two
        // batches, mispredicted often). A macro, not a closure: a closure is compiled for the
        // baseline target, not for the kernel's.
        batch!(0);
        batch!(LANES);
        let mut k = PIXELS_AHEAD;
        while k < len {
            batch!(k);
            k += LANES;
        }
        self.n += len;
    }

    /// [`SpanBuffer::push_run`] where the entry or exit face is a sliver (its depth in
    /// double-double, [`CellFaces::depth`]).
    #[cold]
    #[allow(clippy::too_many_arguments)]
    pub fn push_run_slivers(
        &mut self,
        slot: usize,
        x0: usize,
        x1: usize,
        py: f64,
        faces: &CellFaces,
        entry: usize,
        exit: usize,
    ) {
        let len = x1 - x0;
        self.reserve(len);
        for k in 0..len {
            let (i, px) = (self.n + k, (x0 + k) as f64 + 0.5);
            let n = faces.depth(entry, [px, py]);
            self.slot[i] = (slot + k) as u32;
            self.x[i] = px;
            self.y[i] = py;
            self.near[i] = n;
            self.far[i] = faces.depth(exit, [px, py]).max(n);
        }
        self.n += len;
    }

    /// Empty contributions (b = 0, θ = 1) for every pixel, to composite pieces into.
    pub fn reset(&mut self) {
        let padded = self.n.div_ceil(LANES) * LANES;
        for v in self.b.iter_mut() {
            v[..padded].fill(0.0);
        }
        self.theta[..padded].fill(1.0);
    }

    pub fn len(&self) -> usize {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }
}

/// Integrates every pixel of `buf` for `cell` with the baseline kernel: fills `buf.b` and
/// `buf.theta` — or, for a cell with a [`Clip`], composites the piece's contribution behind what
/// they hold. (Rendering goes through [`draw`], which dispatches to the widest kernel; the tests
/// compare every kernel there.)
#[cfg(test)]
pub fn shade(cell: &SpanCell, buf: &mut SpanBuffer) {
    match (cell.clip.is_some(), cell.rays.is_some()) {
        (false, false) => kernel_body::<LANES, false, false, false>(cell, buf),
        (true, false) => kernel_body::<LANES, true, false, false>(cell, buf),
        (false, true) => kernel_body::<LANES, false, true, false>(cell, buf),
        (true, true) => kernel_body::<LANES, true, true, false>(cell, buf),
    }
}

/// Draws a cell through the kernel: gathers the pixels of its footprint `hull` in `rect` (the
/// tile) with their entry and exit depths from `faces`, integrates every piece, and composites
/// the results into the tile's pixels `acc` (row-major in `rect`) in `order`. Returns the number
/// of pixels composited. Gathering and compositing are compiled with the kernel, for its width.
/// Without `acc` (a per-pixel order) the results stay in `buf` — `b`, `theta`, `near`, `far`,
/// `slot` per pixel and the runs' faces in `runs` — and the count is of those pixels.
#[allow(clippy::too_many_arguments)]
pub fn draw(
    pieces: &SpanPieces,
    screen: &[[f64; 2]; 4],
    hull: &[[f64; 2]],
    faces: &CellFaces,
    rect: Rect,
    buf: &mut SpanBuffer,
    acc: Option<&mut [([f64; 3], f64)]>,
    order: Order,
) -> u64 {
    draw_with(kernel(), pieces, screen, hull, faces, rect, buf, acc, order)
}

/// [`draw`] with the kernel compiled for `k` (the baseline one where the processor lacks
/// `k`'s features).
#[allow(clippy::too_many_arguments)]
fn draw_with(
    k: Kernel,
    pieces: &SpanPieces,
    screen: &[[f64; 2]; 4],
    hull: &[[f64; 2]],
    faces: &CellFaces,
    rect: Rect,
    buf: &mut SpanBuffer,
    acc: Option<&mut [([f64; 3], f64)]>,
    order: Order,
) -> u64 {
    let d = Draw {
        pieces,
        screen,
        hull,
        faces,
        rect,
        order,
    };
    match k {
        // SAFETY (both): the processor reported the features the function is compiled for.
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 if supported(k) => unsafe { draw_avx2(&d, buf, acc) },
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx512 if supported(k) => unsafe { draw_avx512(&d, buf, acc) },
        _ => draw_body::<LANES, false, LANES>(&d, buf, acc),
    }
}

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

/// [`draw`]'s arguments.
struct Draw<'a> {
    pieces: &'a SpanPieces,
    screen: &'a [[f64; 2]; 4],
    hull: &'a [[f64; 2]],
    faces: &'a CellFaces,
    rect: Rect,
    order: Order,
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn draw_avx2(d: &Draw, buf: &mut SpanBuffer, acc: Option<&mut [([f64; 3], f64)]>) -> u64 {
    draw_body::<16, true, 4>(d, buf, acc)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,fma")]
fn draw_avx512(d: &Draw, buf: &mut SpanBuffer, acc: Option<&mut [([f64; 3], f64)]>) -> u64 {
    draw_body::<32, true, 8>(d, buf, acc)
}

#[inline(always)]
fn draw_body<const WIDE: usize, const FMA: bool, const P: usize>(
    d: &Draw,
    buf: &mut SpanBuffer,
    acc: Option<&mut [([f64; 3], f64)]>,
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
        match (piece.clip.is_some(), piece.rays.is_some()) {
            (false, false) => kernel_body::<WIDE, false, false, FMA>(piece, buf),
            (true, false) => kernel_body::<WIDE, true, false, FMA>(piece, buf),
            (false, true) => kernel_body::<WIDE, false, true, FMA>(piece, buf),
            (true, true) => kernel_body::<WIDE, true, true, FMA>(piece, buf),
        }
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

/// Draws a cell shaded in screen space (`interpolateColor`): the Gouraud values of `fan` over
/// the footprint `hull` in `rect`, as [`super::gouraud::shade`] with `brightness`, composited
/// into `acc` in `order`, in lanes. The same bits as pixel by pixel ([`Fan::at_lanes`]).
/// Returns the number of pixels composited.
#[allow(clippy::too_many_arguments)]
pub fn draw_fan(
    fan: &Fan,
    brightness: f64,
    screen: &[[f64; 2]; 4],
    hull: &[[f64; 2]],
    rect: Rect,
    buf: &mut SpanBuffer,
    acc: &mut [([f64; 3], f64)],
    order: Order,
) -> u64 {
    draw_fan_with(
        kernel(),
        fan,
        brightness,
        screen,
        hull,
        rect,
        buf,
        acc,
        order,
    )
}

/// [`draw_fan`] compiled for `k` (the baseline where the processor lacks `k`'s features).
#[allow(clippy::too_many_arguments)]
fn draw_fan_with(
    k: Kernel,
    fan: &Fan,
    brightness: f64,
    screen: &[[f64; 2]; 4],
    hull: &[[f64; 2]],
    rect: Rect,
    buf: &mut SpanBuffer,
    acc: &mut [([f64; 3], f64)],
    order: Order,
) -> u64 {
    let d = FanDraw {
        fan,
        brightness,
        screen,
        hull,
        rect,
        order,
    };
    match k {
        // SAFETY (both): the processor reported the features the function is compiled for.
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 if supported(k) => unsafe { draw_fan_avx2(&d, buf, acc) },
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx512 if supported(k) => unsafe { draw_fan_avx512(&d, buf, acc) },
        _ => draw_fan_body::<LANES, { FanShade::Lanes as u8 }>(&d, buf, acc),
    }
}

/// [`draw_fan`]'s arguments.
struct FanDraw<'a> {
    fan: &'a Fan,
    brightness: f64,
    screen: &'a [[f64; 2]; 4],
    hull: &'a [[f64; 2]],
    rect: Rect,
    order: Order,
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn draw_fan_avx2(d: &FanDraw, buf: &mut SpanBuffer, acc: &mut [([f64; 3], f64)]) -> u64 {
    draw_fan_body::<LANES, { FanShade::Avx2 as u8 }>(d, buf, acc)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn draw_fan_avx512(d: &FanDraw, buf: &mut SpanBuffer, acc: &mut [([f64; 3], f64)]) -> u64 {
    draw_fan_body::<LANES, { FanShade::Avx512 as u8 }>(d, buf, acc)
}

/// How [`draw_fan_body`] shades: [`Fan::at_lanes`] (any target), or the fan's intrinsics,
/// only from the function compiled with their features.
#[derive(Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum FanShade {
    Lanes,
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    Avx2,
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    Avx512,
}

/// `SHADE`: a [`FanShade`].
#[inline(always)]
fn draw_fan_body<const L: usize, const SHADE: u8>(
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

/// Which compiled kernel this processor runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    Baseline,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Kernel {
    /// The instruction set, for the timing line.
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Baseline => "baseline",
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2 => "AVX2",
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 => "AVX-512",
        }
    }
}

/// The widest kernel the processor supports (decided once). `VORANG_KERNEL=baseline` or
/// `avx2` caps it, to measure or compare the narrower kernels on a wider processor (an
/// unknown name or a kernel the processor lacks changes nothing).
pub fn kernel() -> Kernel {
    static CHOICE: std::sync::OnceLock<Kernel> = std::sync::OnceLock::new();
    *CHOICE.get_or_init(|| {
        let cap = std::env::var("VORANG_KERNEL").unwrap_or_default();
        #[cfg(target_arch = "x86_64")]
        {
            let allowed = match cap.as_str() {
                "baseline" => &[][..],
                "avx2" => &[Kernel::Avx2][..],
                _ => &[Kernel::Avx512, Kernel::Avx2][..],
            };
            for &k in allowed {
                if supported(k) {
                    return k;
                }
            }
        }
        let _ = cap;
        Kernel::Baseline
    })
}

/// Whether this processor can run kernel `k`.
pub fn supported(k: Kernel) -> bool {
    match k {
        Kernel::Baseline => true,
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 => {
            std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
        }
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx512 => {
            std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("fma")
        }
    }
}

/// The kernel: the (padded) buffer in batches of `WIDE` pixels, the rest in batches of
/// [`LANES`]. A batch's series is one chain of dependent multiplications per lane; several
/// registers of lanes side by side keep the processor's pipelines full instead of waiting on
/// that chain (measured: the 8-lane AVX-512 kernel spent most of its time there). Lanes are
/// independent, so the batch width changes no bit.
#[inline(always)]
fn kernel_body<const WIDE: usize, const CLIP: bool, const PERSP: bool, const FMA: bool>(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Segment;
    use crate::integrate::linear::rule;

    fn cell() -> SpanCell {
        SpanCell {
            q: [
                [0.2, 0.01, -0.003, 0.05, 0.0, 0.0],
                [0.5, -0.002, 0.004, 0.1, 0.0, 0.0],
                [0.9, 0.0, 0.0, -0.02, 0.0, 0.0],
                [0.3, 0.001, 0.002, 0.4, 0.0, 0.0],
            ],
            rays: None,
            clip: None,
            terms: terms_for(0.45, 0.2).unwrap(),
            brightness: 1.5,
        }
    }

    fn buffer(n: usize) -> SpanBuffer {
        let mut buf = SpanBuffer::default();
        for i in 0..n {
            let (x, y) = (3.5 + i as f64, 7.5 - 0.5 * i as f64);
            let near = 0.1 + 0.01 * i as f64;
            buf.push(i, x, y, near, near + 0.05 * (i % 7) as f64);
        }
        buf
    }

    #[test]
    fn the_kernel_matches_the_scalar_rule() {
        let c = cell();
        let mut buf = buffer(21);
        shade(&c, &mut buf);
        assert_eq!(buf.len(), 21);
        for i in 0..21 {
            let (x, y, near, far) = (buf.x[i], buf.y[i], buf.near[i], buf.far[i]);
            let v = |k: usize, t: f64| c.q[k][0] + c.q[k][1] * x + c.q[k][2] * y + c.q[k][3] * t;
            let seg = Segment {
                eta: [
                    [v(0, far), v(1, far), v(2, far)],
                    [v(0, near), v(1, near), v(2, near)],
                ],
                chi: [v(3, far), v(3, near)],
                ds: far - near,
                eta_mid: None,
            };
            let (b, theta) = rule(&seg);
            for ch in 0..3 {
                let want = b[ch] * c.brightness;
                assert!(
                    (buf.b[ch][i] - want).abs() <= 1e-15 * (1.0 + want.abs()),
                    "{i}"
                );
            }
            assert!((buf.theta[i] - theta).abs() <= 1e-15, "{i}");
        }
    }

    /// The whole draw (gathering, the kernel in batches of 8, 16 or 32 lanes, compositing)
    /// compiled for each kernel, for one piece and for a cell cut into two pieces by a clip: the
    /// kernels with fused multiply-adds (AVX2, AVX-512) give the same bits, the baseline (a
    /// product and a sum, rounded twice) the same values to rounding.
    #[test]
    fn every_compiled_draw_gives_the_same_bits() {
        use crate::predicates::entry_sign;
        let screen = [[3.2, 4.1], [40.7, 9.3], [20.2, 37.9], [18.4, 15.6]];
        let depth = [1.0, 1.3, 0.8, 2.1];
        let faces = CellFaces::new([0, 1, 2, 3], &screen, &depth, entry_sign(false), false);
        let hull = &screen[..3];
        let rect = Rect {
            x0: 2,
            y0: 3,
            x1: 45,
            y1: 41,
        };
        let one = SpanPieces::one(cell());
        let mut two = SpanPieces::one(cell());
        let clip = |lo, hi| {
            Some(Clip {
                s: [0.0, 0.01, 0.0, 1.0, 0.0, 0.0],
                lo,
                hi,
            })
        };
        two.cells[0].clip = clip(f64::NEG_INFINITY, 1.2);
        two.cells[1].clip = clip(1.2, f64::INFINITY);
        two.count = 2;
        #[cfg(target_arch = "x86_64")]
        let kinds = [Kernel::Baseline, Kernel::Avx2, Kernel::Avx512];
        #[cfg(not(target_arch = "x86_64"))]
        let kinds = [Kernel::Baseline];
        for pieces in [&one, &two] {
            let (mut fused, mut baseline) = (None, None);
            for k in kinds.into_iter().filter(|&k| supported(k)) {
                let n = (rect.x1 - rect.x0) * (rect.y1 - rect.y0);
                let mut acc = vec![([0.1, 0.2, 0.3], 1.0); n];
                let mut buf = SpanBuffer::default();
                let drawn = draw_with(
                    k,
                    pieces,
                    &screen,
                    hull,
                    &faces,
                    rect,
                    &mut buf,
                    Some(&mut acc),
                    Order::BackToFront,
                );
                assert!(drawn > 300, "{drawn}");
                let values: Vec<f64> = acc
                    .iter()
                    .flat_map(|(c, t)| [c[0], c[1], c[2], *t])
                    .collect();
                if k == Kernel::Baseline {
                    baseline = Some(values);
                    continue;
                }
                let bits: Vec<u64> = values.iter().map(|v| v.to_bits()).collect();
                match &fused {
                    None => fused = Some((bits, values)),
                    Some((r, _)) => assert!(r == &bits, "{k:?}"),
                }
            }
            if let (Some(b), Some((_, f))) = (&baseline, &fused) {
                let most = b
                    .iter()
                    .zip(f)
                    .map(|(b, f)| (b - f).abs())
                    .fold(0.0, f64::max);
                assert!(most < 1e-14, "{most}");
            }
        }
    }

    /// The Gouraud fan drawn in lanes by each compiled kernel: the same bits as pixel by pixel.
    #[test]
    fn every_compiled_fan_draw_matches_the_pixels() {
        use crate::render::footprint::footprint;
        use crate::render::raster::rasterize_convex;
        use crate::scene::{Camera, Projector};
        let proj = Projector::new(
            Some(&Camera::Ortho {
                left: 0.0,
                right: 40.0,
                bottom: 0.0,
                top: 40.0,
                front: -10.0,
                back: 10.0,
            }),
            [1.0; 3],
            40,
            40,
        )
        .unwrap();
        // Cells of every class with a fan (1: the fourth node inside, 2: crossing edges,
        // 3: a node over an edge, 4: two nodes on one spot; fewer than four sectors leave
        // unused ones that must never win), then random cells with random values.
        let mut cells = vec![
            [
                [3.0, 3.0, 0.0],
                [36.0, 35.0, 0.0],
                [34.0, 4.0, 2.0],
                [5.0, 33.0, 2.5],
            ],
            [
                [2.0, 3.0, 0.0],
                [35.0, 5.0, 0.5],
                [15.0, 37.0, 1.0],
                [16.0, 14.0, 3.0],
            ],
            [
                [3.0, 3.0, 0.0],
                [35.0, 3.0, 0.0],
                [19.0, 36.0, 1.0],
                [19.0, 3.0, 4.0],
            ],
            [
                [3.0, 3.0, 0.0],
                [35.0, 6.0, 0.0],
                [19.0, 36.0, 1.0],
                [3.0, 3.0, 4.0],
            ],
        ];
        let mut rng = crate::mesh::generate::SplitMix64(0x2545_f491_4f6c_dd1d);
        let mut next = move || rng.next_f64();
        for _ in 0..300 {
            cells.push(std::array::from_fn(|_| {
                [next() * 44.0 - 2.0, next() * 44.0 - 2.0, next() * 8.0 - 4.0]
            }));
        }
        let mut values = [
            [0.9, 0.2, 0.0, 0.5],
            [0.8, 0.9, 0.3, 0.0],
            [1.0, 0.1, 0.8, 0.2],
            [0.7, 0.4, 0.4, 0.9],
            [0.3, 0.6, 0.7, 0.1],
        ];
        let rect = Rect {
            x0: 4,
            y0: 2,
            x1: 38,
            y1: 39,
        };
        let tw = rect.x1 - rect.x0;
        let n = tw * (rect.y1 - rect.y0);
        let start = vec![([0.1, 0.2, 0.3], 1.0); n];
        let mut classes = std::collections::HashSet::new();
        let mut pixels = 0;
        for (c, eye) in cells.iter().enumerate() {
            if c >= 4 {
                values = std::array::from_fn(|_| std::array::from_fn(|_| next()));
            }
            let screen = eye.map(|p| proj.screen(p));
            let Some(fp) = footprint([0, 1, 2, 3], eye, &screen, &proj) else {
                continue;
            };
            let (Some(fan), Some((v, count))) = (Fan::new(&fp, &values), fp.hull()) else {
                continue;
            };
            classes.insert(fp.projection.unwrap().class);
            let mut want = start.clone();
            rasterize_convex(&v[..count], rect, |x, y| {
                let px = gouraud::shade(1.5, fan.at(x as f64 + 0.5, y as f64 + 0.5));
                composite(
                    Order::BackToFront,
                    &mut want[(y - rect.y0) * tw + x - rect.x0],
                    px,
                );
                pixels += 1;
            });
            #[cfg(target_arch = "x86_64")]
            let kinds = [Kernel::Baseline, Kernel::Avx2, Kernel::Avx512];
            #[cfg(not(target_arch = "x86_64"))]
            let kinds = [Kernel::Baseline];
            for k in kinds.into_iter().filter(|&k| supported(k)) {
                let mut acc = start.clone();
                let mut buf = SpanBuffer::default();
                draw_fan_with(
                    k,
                    &fan,
                    1.5,
                    &screen,
                    &v[..count],
                    rect,
                    &mut buf,
                    &mut acc,
                    Order::BackToFront,
                );
                for (a, b) in acc.iter().zip(&want) {
                    assert_eq!(a.1.to_bits(), b.1.to_bits(), "{k:?} cell {c}");
                    for ch in 0..3 {
                        assert_eq!(a.0[ch].to_bits(), b.0[ch].to_bits(), "{k:?} cell {c}");
                    }
                }
            }
        }
        assert!(
            classes.len() >= 4 && pixels > 10_000,
            "{classes:?} {pixels}"
        );
    }
}
