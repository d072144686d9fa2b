//! Scan conversion of screen triangles with exact pixel-centre coverage.
//!
//! A pixel belongs to a triangle if its centre (i + ½, j + ½) is inside, or on an edge that is a
//! *top* or *left* edge (the usual top-left rule). So a pixel centre on an edge shared by two
//! triangles is counted once, and none is lost. For the rule to be consistent, both triangles
//! must compute exactly opposite edge values: every edge function is evaluated with its end
//! points in a canonical order (by vertex identity) and negated as needed, so the two sides see
//! `E` and `−E` bit for bit.

use robust::{Coord, orient2d};

/// The exact predicates and the half-line search live below the rasteriser, with the sort and
/// the faces that share them; re-exported where they were first defined.
pub use crate::predicates::{ROOT_ERROR, boundary};
use crate::predicates::{floor, inside as exact_inside};

/// A triangle on screen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenTriangle {
    pub v: [[f64; 2]; 3],
}

/// A rectangle of pixels `[x0, x1) × [y0, y1)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    pub x0: usize,
    pub y0: usize,
    pub x1: usize,
    pub y1: usize,
}

/// `(b − a) × (p − a)` with a and b in canonical order (lexicographically smaller first),
/// negated if swapped.
#[inline]
fn edge(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    Edge::new(a, b).at(p[0], p[1])
}

/// One edge function in canonical form: `E(p) = sign·(d.x·(p.y − c.y) − d.y·(p.x − c.x))` with
/// `c` the canonical start and `d` the edge vector from it. Splitting it so lets a scanline
/// hoist the row term while computing the same bits as [`edge`].
#[derive(Debug, Clone, Copy)]
struct Edge {
    c: [f64; 2],
    d: [f64; 2],
    sign: f64,
}

impl Edge {
    #[inline]
    fn new(a: [f64; 2], b: [f64; 2]) -> Edge {
        if (a[0], a[1]) <= (b[0], b[1]) {
            Edge {
                c: a,
                d: [b[0] - a[0], b[1] - a[1]],
                sign: 1.0,
            }
        } else {
            Edge {
                c: b,
                d: [a[0] - b[0], a[1] - b[1]],
                sign: -1.0,
            }
        }
    }

    /// `d.x·(p.y − c.y)`: the part that is fixed along a row.
    #[inline]
    fn row(&self, py: f64) -> f64 {
        self.d[0] * (py - self.c[1])
    }

    #[inline]
    fn at_row(&self, row: f64, px: f64) -> f64 {
        self.sign * (row - self.d[1] * (px - self.c[0]))
    }

    #[inline]
    fn at(&self, px: f64, py: f64) -> f64 {
        self.at_row(self.row(py), px)
    }
}

/// Calls `f(x, y, w)` for every pixel of `rect` covered by the triangle. With `WEIGHTS`, `w`
/// holds the screen-space barycentric weights of the pixel centre (for Gouraud interpolation,
/// in the order of `tri.v`); without, zeros.
#[inline]
pub fn rasterize<const WEIGHTS: bool>(
    tri: &ScreenTriangle,
    rect: Rect,
    mut f: impl FnMut(usize, usize, [f64; 3]),
) {
    let c = |p: [f64; 2]| Coord { x: p[0], y: p[1] };
    let o = orient2d(c(tri.v[0]), c(tri.v[1]), c(tri.v[2]));
    if o == 0.0 {
        return;
    }
    // Orient so that the inside has positive edge values; remember the permutation for w.
    let (v, perm) = if o > 0.0 {
        (tri.v, [0, 1, 2])
    } else {
        ([tri.v[0], tri.v[2], tri.v[1]], [0, 2, 1])
    };
    let Some(shape) = Convex::new(v, rect) else {
        return;
    };
    let inv_area = 1.0 / edge(v[0], v[1], v[2]);
    shape.scan(|x, y, rows| {
        let mut out = [0.0; 3];
        if WEIGHTS {
            // Weight of vertex k is the edge value opposite it.
            let px = x as f64 + 0.5;
            let e = &shape.edges;
            out[perm[0]] = e[1].at_row(rows[1], px) * inv_area;
            out[perm[1]] = e[2].at_row(rows[2], px) * inv_area;
            out[perm[2]] = e[0].at_row(rows[0], px) * inv_area;
        }
        f(x, y, out);
    });
}

/// Calls `f(x, y)` for every pixel of `rect` covered by a convex polygon of three or four
/// vertices given in order around it (either way round), with the same top-left rule as
/// [`rasterize`]: the union of a triangulation of the polygon covers the same pixels, except
/// possibly a pixel centre exactly on a vertex, where the rule depends on the inner edges.
#[inline]
pub fn rasterize_convex(poly: &[[f64; 2]], rect: Rect, f: impl FnMut(usize, usize)) {
    let mut f = f;
    rasterize_convex_rows(poly, rect, |y, from, to| {
        for x in from..to {
            f(x, y);
        }
    });
}

/// [`rasterize_convex`] by rows: `f(y, from, to)` for the covered pixels `from..to` of row y.
#[inline]
pub fn rasterize_convex_rows(poly: &[[f64; 2]], rect: Rect, f: impl FnMut(usize, usize, usize)) {
    let c = |p: [f64; 2]| Coord { x: p[0], y: p[1] };
    let o = orient2d(c(poly[0]), c(poly[1]), c(poly[2]));
    if o == 0.0 {
        return;
    }
    let mut f = f;
    let forward = o > 0.0;
    match poly.len() {
        3 => {
            let v = if forward {
                [poly[0], poly[1], poly[2]]
            } else {
                [poly[0], poly[2], poly[1]]
            };
            if let Some(shape) = Convex::new(v, rect) {
                shape.scan_rows(|y, from, to, _| f(y, from, to));
            }
        }
        4 => {
            let v = if forward {
                [poly[0], poly[1], poly[2], poly[3]]
            } else {
                [poly[0], poly[3], poly[2], poly[1]]
            };
            if let Some(shape) = Convex::new(v, rect) {
                shape.scan_rows(|y, from, to, _| f(y, from, to));
            }
        }
        _ => unreachable!("footprint hulls have three or four vertices"),
    }
}

/// A positively oriented convex polygon prepared for scan conversion, clipped to a rectangle.
struct Convex<const N: usize> {
    edges: [Edge; N],
    /// The edges' end points `v[k] → v[k+1]`, for the exact inside test.
    ends: [[[f64; 2]; 2]; N],
    /// 1/d.y per edge, for the root estimate (∞ for a horizontal edge).
    inv_dy: [f64; N],
    x0: usize,
    x1: usize,
    y0: usize,
    y1: usize,
}

/// The pixels `[x0, x1, y0, y1]` (exclusive ends) of `rect` whose centres `i + ½` lie in the
/// bounding box of `points`; `None` if there are none. One definition for every scan of an
/// outline, so they all start from the same pixels.
#[inline]
pub(super) fn pixel_box(points: &[[f64; 2]], rect: Rect) -> Option<[usize; 4]> {
    let (mut min_x, mut max_x, mut min_y, mut max_y) =
        (points[0][0], points[0][0], points[0][1], points[0][1]);
    for p in &points[1..] {
        min_x = min_x.min(p[0]);
        max_x = max_x.max(p[0]);
        min_y = min_y.min(p[1]);
        max_y = max_y.max(p[1]);
    }
    let lo = |m: f64, r0: usize| ((-floor(0.5 - m)).max(r0 as f64)) as usize;
    let hi = |m: f64, r1: usize| ((floor(m - 0.5) + 1.0).min(r1 as f64).max(0.0)) as usize;
    let (x0, x1) = (lo(min_x, rect.x0), hi(max_x, rect.x1));
    let (y0, y1) = (lo(min_y, rect.y0), hi(max_y, rect.y1));
    (x0 < x1 && y0 < y1).then_some([x0, x1, y0, y1])
}

impl<const N: usize> Convex<N> {
    /// `None` if no pixel centre of `rect` lies in its bounding box.
    #[inline]
    fn new(v: [[f64; 2]; N], rect: Rect) -> Option<Self> {
        let [x0, x1, y0, y1] = pixel_box(&v, rect)?;
        // Top-left ownership of each edge k: v[k] → v[k+1] ([`owns`]). An edge shared with
        // another polygon runs the other way there, so exactly one of the two owns it.
        let ends = std::array::from_fn(|k| [v[k], v[(k + 1) % N]]);
        let edges: [Edge; N] = std::array::from_fn(|k| Edge::new(v[k], v[(k + 1) % N]));
        let inv_dy = std::array::from_fn(|k| 1.0 / edges[k].d[1]);
        Some(Convex {
            edges,
            ends,
            inv_dy,
            x0,
            x1,
            y0,
            y1,
        })
    }

    /// Calls `f(x, y, rows)` for every covered pixel, `rows` the edges' row terms.
    #[inline]
    fn scan(&self, mut f: impl FnMut(usize, usize, &[f64; N])) {
        self.scan_rows(|y, from, to, rows| {
            for x in from..to {
                f(x, y, rows);
            }
        });
    }

    /// Calls `f(y, from, to, rows)` for every row with covered pixels `from..to`.
    ///
    /// Each edge function is monotone in x along a row: the pixels inside one edge form a
    /// half-line, those inside all of them a run. Per edge, the end of its half-line is estimated
    /// from the root (E_k = 0 at px = c.x + row/d.y) and settled with the exact test of that edge
    /// alone ([`boundary`]) — usually two evaluations.
    #[inline]
    fn scan_rows(&self, mut f: impl FnMut(usize, usize, usize, &[f64; N])) {
        let (x0, x1) = (self.x0, self.x1);
        for y in self.y0..self.y1 {
            let py = y as f64 + 0.5;
            let rows: [f64; N] = std::array::from_fn(|k| self.edges[k].row(py));
            let (mut from, mut to) = (x0, x1);
            for k in 0..N {
                let e = &self.edges[k];
                // The exact predicate decides (`crate::predicates`): the same answer for every
                // polygon with this edge, whatever rounding did to the edge function.
                let [u, v] = self.ends[k];
                let test = |x: usize| exact_inside(u, v, [x as f64 + 0.5, py]);
                let slope = -e.sign * e.d[1];
                let q = rows[k] * self.inv_dy[k];
                let root = e.c[0] + q;
                // A generous bound on the rounding of the root (a few ulps of its terms).
                let margin = ROOT_ERROR * (e.c[0].abs() + q.abs());
                let x = boundary(test, root, margin, slope, x0, x1);
                if slope >= 0.0 {
                    from = from.max(x);
                } else {
                    to = to.min(x);
                }
            }
            if from < to {
                f(y, from, to, &rows);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: Rect = Rect {
        x0: 0,
        y0: 0,
        x1: 16,
        y1: 16,
    };

    fn cover(t: &ScreenTriangle) -> Vec<(usize, usize)> {
        let mut v = Vec::new();
        rasterize::<true>(t, ALL, |x, y, w| {
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            v.push((x, y));
        });
        v
    }

    #[test]
    fn a_square_split_along_its_diagonal_covers_every_pixel_once() {
        // Corners on pixel centres, so many centres lie exactly on edges.
        let (a, b, c, d) = ([2.5, 2.5], [10.5, 2.5], [10.5, 10.5], [2.5, 10.5]);
        for (t1, t2) in [
            (
                ScreenTriangle { v: [a, b, c] },
                ScreenTriangle { v: [a, c, d] },
            ),
            (
                ScreenTriangle { v: [c, b, a] },
                ScreenTriangle { v: [d, a, c] },
            ),
        ] {
            let mut count = vec![0; 256];
            for (x, y) in cover(&t1).into_iter().chain(cover(&t2)) {
                count[y * 16 + x] += 1;
            }
            // The top and left edges of the square own their pixels, the right and bottom ones
            // do not: exactly x, y ∈ 2…9, each once, whichever way the diagonal runs.
            for y in 0..16 {
                for x in 0..16 {
                    let expect = i32::from((2..10).contains(&x) && (2..10).contains(&y));
                    assert_eq!(count[y * 16 + x], expect, "pixel ({x},{y})");
                }
            }
            assert_eq!(count.iter().sum::<i32>(), 64);
        }
    }

    #[test]
    fn a_fan_around_a_shared_vertex_has_no_cracks_or_overlaps() {
        // Eight triangles around (8.5, 8.5) inside an octagon-ish square.
        let c = [8.5, 8.5];
        let ring = [
            [1.5, 1.5],
            [8.5, 0.5],
            [15.5, 1.5],
            [15.5, 8.5],
            [15.5, 15.5],
            [8.5, 15.5],
            [1.5, 15.5],
            [0.5, 8.5],
        ];
        let mut count = vec![0; 256];
        for k in 0..8 {
            let t = ScreenTriangle {
                v: [c, ring[k], ring[(k + 1) % 8]],
            };
            for (x, y) in cover(&t) {
                count[y * 16 + x] += 1;
            }
        }
        assert!(count.iter().all(|&n| n <= 1));
        assert_eq!(
            count[8 * 16 + 8],
            1,
            "the shared vertex's pixel is owned once"
        );
    }
}
