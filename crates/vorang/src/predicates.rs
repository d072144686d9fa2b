//! Exact screen predicates: on which side of a projected edge a point lies (thesis 2.2.2.2, the
//! orientation tests of the Shirley–Tuchman classification; `docs/accuracy.md`, "Degenerate
//! views").
//!
//! The visibility sort, the scan conversion and the per-pixel choice of a cell's entry and exit
//! faces all ask the same question of the same screen points — which way round three of them
//! lie, and which polygon owns a pixel centre exactly on an edge. If two of them answered it
//! differently (one in floating point, one exactly), a face within rounding of edge-on could be
//! an entry face to the sort and an exit face to the rasteriser, or a pixel could fall between
//! two cells. So it is answered once, here, exactly: Shewchuk's adaptive `orient2d` for the
//! orientation, and the top-left rule for points on an edge, which is the same as moving every
//! pixel centre by an infinitesimal `(ε, ε²)`.
//!
//! This module sits below every caller (the sort, the rasteriser, the faces, the projection
//! classes): it imports nothing from the crate, so none of them depends on another for it.

use robust::{Coord, orient2d};

/// Whether a positively oriented polygon owns the points exactly on its edge `u → v` (top-left
/// rule, y pointing down): a top edge runs towards +x, a left edge towards −y. Equivalent to
/// testing the point moved by `(ε, ε²)`.
#[inline]
pub fn owns(u: [f64; 2], v: [f64; 2]) -> bool {
    let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
    dy < 0.0 || (dy == 0.0 && dx > 0.0)
}

/// Exact: is `p` inside (left of, or on and owning) the directed edge `u → v` of a positively
/// oriented polygon?
#[inline]
pub fn inside(u: [f64; 2], v: [f64; 2], p: [f64; 2]) -> bool {
    let e = orient2d(coord(u), coord(v), coord(p));
    e > 0.0 || (e == 0.0 && owns(u, v))
}

#[inline]
fn coord(p: [f64; 2]) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

/// Sign of the exact orientation of three screen points: +1 counter-clockwise (in a y-up frame),
/// −1 clockwise, 0 collinear.
#[inline]
pub fn orient_sign(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> i8 {
    let o = orient2d(coord(a), coord(b), coord(c));
    (o > 0.0) as i8 - (o < 0.0) as i8
}

/// The frame's constant for telling entry from exit faces: cells are positively oriented in
/// model space and [`crate::mesh::FACE_NODES`] lists each face counter-clockwise seen from
/// outside. Screen y points down, which turns orientations around; a transform with negative
/// determinant (a mirror) turns them again. A face is an entry face where
/// `entry_sign · orient_sign > 0` — for the sort and the renderer alike.
pub fn entry_sign(mirrored: bool) -> i8 {
    if mirrored { 1 } else { -1 }
}

/// Where a half-line of pixels along a row ends: `test(x)` (pixel centre x + ½ inside an edge) is
/// monotone in x — increasing for `slope > 0` (inside from the result on), decreasing for
/// `slope < 0` (inside before the result), constant for `slope = 0` (the result is `x0` if
/// inside, else `x1`). `root` estimates where the edge crosses the row; it is accurate to far
/// below a pixel, so the two pixels around it settle the end unless a centre lies exactly on
/// the edge, where ownership decides — then it walks. Where the root is known to be within
/// `margin` of the exact crossing and no pixel centre is that close to it, the estimate is the
/// answer without a test. Result in `x0..=x1`.
#[inline]
pub fn boundary(
    test: impl Fn(usize) -> bool,
    root: f64,
    margin: f64,
    slope: f64,
    x0: usize,
    x1: usize,
) -> usize {
    if slope == 0.0 || slope.is_nan() {
        return if x0 < x1 && test(x0) { x0 } else { x1 };
    }
    let first = floor(root - 0.5) + 1.0;
    if root.is_finite() && root - (first - 0.5) > margin && (first + 0.5) - root > margin {
        // No centre within the margin: every centre's side is certain.
        return first.clamp(x0 as f64, x1 as f64) as usize;
    }
    let mut x = if root.is_finite() {
        first.clamp(x0 as f64, x1 as f64) as usize
    } else if slope > 0.0 {
        x0
    } else {
        x1
    };
    let before = x > x0 && test(x - 1);
    let at = x < x1 && test(x);
    if slope > 0.0 {
        // Inside from some x on: find the first.
        if before || !at {
            while x > x0 && test(x - 1) {
                x -= 1;
            }
            while x < x1 && !test(x) {
                x += 1;
            }
        }
    } else if !before || at {
        // Inside up to some x: find the end (exclusive).
        while x < x1 && test(x) {
            x += 1;
        }
        while x > x0 && !test(x - 1) {
            x -= 1;
        }
    }
    x
}

/// Relative error bound used for root estimates: ~45 ulps, far above the few roundings in them.
pub const ROOT_ERROR: f64 = 1e-14;

/// `⌊x⌋` without a library call (the baseline x86-64 target has no rounding instruction);
/// saturating for values beyond ±2⁶³, which the callers clamp anyway. Shared with the scan
/// conversion's pixel box, so that both round a crossing the same way.
#[inline]
pub(crate) fn floor(x: f64) -> f64 {
    let t = x as i64 as f64;
    if t > x { t - 1.0 } else { t }
}
