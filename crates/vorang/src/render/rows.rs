//! A cell's footprint row by row, from its six projected edges at once.
//!
//! The span kernels need, per row of a cell's footprint, the covered pixels `from..to` and where
//! the inner edges split them into runs of one entry and one exit face ([`super::faces`]). Both
//! come from the same kind of question — on which side of a projected cell edge does a pixel
//! centre lie — asked of the outline's edges (scan conversion, [`super::raster`]) and of the
//! faces' inner edges ([`CellFaces::row`]). Here every edge is asked once per row, all in one
//! batch of lanes: the crossing is estimated by one multiply-add per edge, and where no pixel
//! centre lies within the estimate's error bound of it, the estimate settles the side of every
//! pixel; otherwise the exact predicate decides ([`boundary`]), as before. The decisions are those
//! of the exact predicates either way, so the rows, runs and faces are the same as the general
//! path's — pixel for pixel.

#[cfg(doc)]
use super::faces::CellFaces;
use super::faces::{EDGE_OF, Row, max_select, min_select};
use super::raster::{Rect, pixel_box};
use crate::mesh::EDGE_NODES;
use crate::predicates::{ROOT_ERROR, boundary, inside, orient_sign};

/// Lanes: the six cell edges, padded.
const EDGES: usize = 8;

/// A cell's projected edges prepared for its rows.
#[derive(Debug, Clone, Copy)]
pub struct CellRows {
    /// Per cell edge (in [`EDGE_NODES`] order, from its lower to its higher local node u → v):
    /// u, and `(v.x − u.x)/(v.y − u.y)` — the crossing of the row at y is `u.x + (y − u.y)·inv`.
    ux: [f64; EDGES],
    uy: [f64; EDGES],
    inv: [f64; EDGES],
    ends: [[[f64; 2]; 2]; 6],
    /// Pixels inside the edge from its crossing on (else before it).
    rising: [bool; 6],
    /// The edges asked about: the outline's and the inner ones the faces test (1 in a lane per
    /// edge, so that the rows test them all at once).
    need: [u64; EDGES],
    /// The outline edges as caps per edge lane, for rows bounded in vector registers: a split s
    /// counts as `min(s, after_cap)` towards the row's first pixel (+∞ where the footprint lies
    /// inside the edge from its crossing on, else −∞, which drops out of the maximum) and as
    /// `max(s, before_floor)` towards its end (−∞ where it lies inside before the crossing, else
    /// +∞).
    after_cap: [f64; EDGES],
    before_floor: [f64; EDGES],
    /// Pixel centres of the outline's bounding box within the tile.
    x0: usize,
    x1: usize,
    y0: usize,
    y1: usize,
}

impl CellRows {
    /// The rows of the footprint with outline `hull` (three or four node positions in order
    /// around it, [`super::footprint::Footprint::hull`]) within `rect`. `None` where the outline
    /// cannot be named by the cell's edges (two nodes on the same screen position): the general
    /// scan conversion takes such a cell.
    /// `inner`: the cell edges whose splits the rows must also carry (bit e for
    /// [`EDGE_NODES`]`[e]`; [`CellFaces::needed`], or none). Inlined: built in the caller's
    /// frame, not copied there (it is 500 bytes).
    #[inline(always)]
    pub fn new(
        screen: &[[f64; 2]; 4],
        hull: &[[f64; 2]],
        inner: u8,
        rect: Rect,
    ) -> Option<CellRows> {
        // The outline's vertices as nodes.
        let mut nodes = [0usize; 4];
        for (k, p) in hull.iter().enumerate() {
            let mut found = None;
            for (n, q) in screen.iter().enumerate() {
                if p == q {
                    if found.is_some() {
                        return None;
                    }
                    found = Some(n);
                }
            }
            nodes[k] = found?;
        }
        let count = hull.len();
        let mut rows = CellRows {
            ux: [0.0; EDGES],
            uy: [0.0; EDGES],
            inv: [f64::NAN; EDGES],
            ends: [[[0.0; 2]; 2]; 6],
            rising: [true; 6],
            need: std::array::from_fn(|e| (inner >> e) as u64 & 1),
            after_cap: [f64::NEG_INFINITY; EDGES],
            before_floor: [f64::INFINITY; EDGES],
            x0: 0,
            x1: 0,
            y0: 0,
            y1: 0,
        };
        for (e, &[i, j]) in EDGE_NODES.iter().enumerate() {
            let (u, v) = (screen[i], screen[j]);
            rows.ux[e] = u[0];
            rows.uy[e] = u[1];
            rows.inv[e] = (v[0] - u[0]) / (v[1] - u[1]);
            rows.ends[e] = [u, v];
            rows.rising[e] = u[1] - v[1] >= 0.0;
        }
        // The outline's orientation, as the scan conversion takes it: an edge-on outline
        // covers nothing.
        let o = orient_sign(hull[0], hull[1], hull[2]);
        if o == 0 {
            return Some(rows);
        }
        for k in 0..count {
            let (mut a, mut b) = (nodes[k], nodes[(k + 1) % count]);
            if o < 0 {
                std::mem::swap(&mut a, &mut b);
            }
            // Inside the outline means inside a → b: inside the cell edge where a is its lower
            // node, outside it otherwise (the two sides, ties included, are complementary).
            let e = EDGE_OF[a][b] as usize;
            let flip = a > b;
            rows.need[e] = 1;
            if rows.rising[e] != flip {
                rows.after_cap[e] = f64::INFINITY;
            } else {
                rows.before_floor[e] = f64::NEG_INFINITY;
            }
        }
        // Pixel centres within the outline's bounding box, as the scan conversion takes them.
        if let Some([x0, x1, y0, y1]) = pixel_box(hull, rect) {
            (rows.x0, rows.x1, rows.y0, rows.y1) = (x0, x1, y0, y1);
        }
        Some(rows)
    }

    /// How many pixel centres the outline's bounding box holds: at least the rows' pixels.
    pub fn area(&self) -> usize {
        (self.x1 - self.x0) * (self.y1 - self.y0)
    }

    /// The rows `y` holding pixel centres of the outline's bounding box.
    pub fn ys(&self) -> std::ops::Range<usize> {
        self.y0..self.y1
    }

    /// Row `y`: the covered pixels `from..to` and the splits for [`CellFaces::spans`]; `None`
    /// for a row the footprint misses.
    #[inline(always)]
    pub fn row(&self, y: usize) -> Option<(usize, usize, Row)> {
        let py = y as f64 + 0.5;
        let (x0, x1) = (self.x0 as f64, self.x1 as f64);
        // Comparisons and selects, not `f64::max`/`min` (a NaN `a` gives `b`; no NaN reaches
        // `b`).
        let (max, min) = (max_select, min_select);
        let mut root = [0.0; EDGES];
        let mut margin = [0.0; EDGES];
        let mut split = [0.0; EDGES];
        // Per lane 1 where the estimate leaves a pixel centre in doubt and the edge is needed
        // (whole-number lanes, not `bool`s: those are packed byte by byte).
        let mut doubt = [0u64; EDGES];
        for e in 0..EDGES {
            let t = (py - self.uy[e]) * self.inv[e];
            let r = self.ux[e] + t;
            // The estimate is within a few ulps of its terms of the exact crossing.
            let m = ROOT_ERROR * (self.ux[e].abs() + t.abs() + r.abs());
            let first = (r - 0.5).floor() + 1.0;
            root[e] = r;
            margin[e] = m;
            // No pixel centre within the margin: every centre's side is certain. A NaN or
            // infinite estimate fails both comparisons (∞ − ∞ is NaN), so it is never sure.
            // (`&`, not `&&`: no branches, so the loop runs in vector registers.)
            let sure = (r - (first - 0.5) > m) & ((first + 0.5) - r > m);
            doubt[e] = (!sure) as u64 & self.need[e];
            // A whole number in [x0, x1]; a NaN (an edge along the row) becomes x0.
            split[e] = min(max(first, x0), x1);
        }
        // The edges whose estimate left a pixel centre in doubt: the exact predicate (rare).
        // First one test for all lanes at once, then edge by edge only where one is in doubt.
        let mut any = 0;
        for d in doubt {
            any |= d;
        }
        if any != 0 {
            for (e, &[u, v]) in self.ends.iter().enumerate() {
                if doubt[e] != 0 {
                    let test = |x: usize| inside(u, v, [x as f64 + 0.5, py]);
                    split[e] =
                        boundary(test, root[e], margin[e], u[1] - v[1], self.x0, self.x1) as f64;
                }
            }
        }
        // Without branches, still in vector registers: the outline's edges bound the row from
        // the left (`after`) or the right (`before`); the caps drop the others out (the padding
        // lanes too: −∞ and +∞). The splits are whole numbers, so the bounds are exact.
        let mut lo = [0.0; EDGES];
        let mut hi = [0.0; EDGES];
        for e in 0..EDGES {
            lo[e] = min(split[e], self.after_cap[e]);
            hi[e] = max(split[e], self.before_floor[e]);
        }
        // Halving the lanes each step: whole registers until the last pair.
        let mut w = EDGES / 2;
        while w > 0 {
            for e in 0..w {
                lo[e] = max(lo[e], lo[e + w]);
                hi[e] = min(hi[e], hi[e + w]);
            }
            w /= 2;
        }
        let (from, to) = (max(x0, lo[0]), min(x1, hi[0]));
        // Whole numbers in [x0, x1], below 2³¹: their values are the low bits of their sums
        // with 2⁵² — vector additions instead of saturating conversions.
        let whole = |v: f64| ((v + TWO_52).to_bits() as u32) as usize;
        let (from, to) = (whole(from), whole(to));
        let at6 = std::array::from_fn(|e| whole(split[e]));
        (from < to).then(|| (from, to, Row::new(at6, self.rising)))
    }
}

/// 2⁵²: a whole number `0 ≤ v < 2³¹` is the low 32 bits of `v + 2⁵²` (see [`CellRows::row`]).
const TWO_52: f64 = 4_503_599_627_370_496.0;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::predicates::entry_sign;
    use crate::render::faces::CellFaces;
    use crate::render::footprint::footprint;
    use crate::render::raster::rasterize_convex_rows;
    use crate::scene::{Camera, Projector};

    /// Against the general path (scan conversion of the outline, then the faces' own row
    /// split): the same rows, runs and faces, for random cells with nodes on a grid of halves —
    /// so that pixel centres fall exactly on edges and nodes, where ownership decides — and
    /// for random cells off the grid, clipped by a tile.
    #[test]
    fn the_rows_are_those_of_the_scan_conversion_and_the_faces() {
        let proj = Projector::new(
            Some(&Camera::Ortho {
                left: 0.0,
                right: 32.0,
                bottom: 0.0,
                top: 32.0,
                front: -40.0,
                back: 40.0,
            }),
            [1.0; 3],
            32,
            32,
        )
        .unwrap();
        let mut rng = crate::mesh::generate::SplitMix64(17);
        let tiles = [
            Rect {
                x0: 0,
                y0: 0,
                x1: 32,
                y1: 32,
            },
            Rect {
                x0: 5,
                y0: 9,
                x1: 21,
                y1: 17,
            },
        ];
        let (mut cells, mut on_grid) = (0, 0);
        for trial in 0..3000 {
            let grid = trial % 2 == 0;
            let eye: [[f64; 3]; 4] = std::array::from_fn(|_| {
                std::array::from_fn(|k| {
                    let r = rng.next_f64();
                    if k == 2 {
                        r * 8.0 - 4.0
                    } else if grid {
                        (r * 48.0).floor() * 0.5 + 4.0
                    } else {
                        r * 24.0 + 4.0
                    }
                })
            });
            let ids = [3, 0, 2, 1].map(|k| (k + trial) as u32 % 4);
            let screen = eye.map(|p| proj.screen(p));
            let depth = eye.map(|p| -p[2]);
            let Some(fp) = footprint(ids, &eye, &screen, &proj) else {
                continue;
            };
            let Some((hull, count)) = fp.hull() else {
                continue;
            };
            for mirrored in [false, true] {
                let cf = CellFaces::new(ids, &screen, &depth, entry_sign(mirrored), false);
                for &rect in &tiles {
                    let mut want = Vec::new();
                    rasterize_convex_rows(&hull[..count], rect, |y, from, to| {
                        let row = cf.row(y, from, to);
                        want.push((y, from, to, cf.spans(&row, from, to).runs().to_vec()));
                    });
                    let Some(rows) = CellRows::new(&screen, &hull[..count], cf.needed(), rect)
                    else {
                        continue;
                    };
                    let mut got = Vec::new();
                    for y in rows.ys() {
                        if let Some((from, to, row)) = rows.row(y) {
                            got.push((y, from, to, cf.spans(&row, from, to).runs().to_vec()));
                        }
                    }
                    assert_eq!(got, want, "trial {trial}: {screen:?}");
                    cells += 1;
                    // Cells whose nodes lie on the grid of halves: pixel centres on their edges.
                    on_grid += (grid && !want.is_empty()) as usize;
                }
            }
        }
        assert!(
            cells > 5000 && on_grid > 1000,
            "{cells} cells, {on_grid} on the grid"
        );
    }
}
