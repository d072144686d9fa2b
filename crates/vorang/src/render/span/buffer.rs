//! The span kernels' working set: a cell's covered pixels and their contributions as structure
//! of arrays, padded to whole batches of [`LANES`], reused from cell to cell so that gathering
//! a cell writes each array once and allocates nothing.

use crate::render::faces::{CellFaces, DepthRow, max_select};
use crate::render::rows::CellRows;

/// Pixels per batch: one AVX-512 register of f64, two AVX2 registers.
pub(super) const LANES: usize = 8;

/// Pixels a row writes whatever its length ([`SpanBuffer::push_pixels`]): two batches. Room for
/// them is reserved past every row.
const PIXELS_AHEAD: usize = 2 * LANES;

/// A cell's covered pixels (inputs) and their contributions (outputs), structure of arrays,
/// reused from cell to cell. The arrays only grow: the first [`SpanBuffer::len`] entries are
/// this cell's, the rest up to a whole batch are stale values the kernel computes and ignores
/// (no per-cell clearing or padding).
#[derive(Debug, Default)]
pub struct SpanBuffer {
    pub(super) n: usize,
    /// The footprint's rows `[y, from, to]`, gathered before their pixels.
    pub(super) rows: Vec<[usize; 3]>,
    pub slot: Vec<u32>,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub near: Vec<f64>,
    pub far: Vec<f64>,
    /// `b` (RGB) and θ per pixel after the kernel (`shade`).
    pub b: [Vec<f64>; 3],
    pub theta: Vec<f64>,
    /// The gathered runs of [`draw`](crate::render::span::draw): first pixel, pixel count, entry
    /// and exit face — what a per-pixel order ([`crate::render::runs`]) needs to chain each
    /// pixel's fragment.
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
    pub(super) fn reserve_cell(&mut self, rows: &CellRows) {
        self.reserve(rows.area() + PIXELS_AHEAD);
    }

    /// One pixel (the tile loop gathers whole runs with [`SpanBuffer::push_run`]).
    #[cfg(test)]
    pub(super) fn push(&mut self, slot: usize, x: f64, y: f64, near: f64, far: f64) {
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
    pub(super) fn push_pixels<const RESERVED: bool>(
        &mut self,
        slot: usize,
        x0: usize,
        x1: usize,
        py: f64,
    ) {
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
