//! Scan conversion of screen triangles with exact pixel-centre coverage.
//!
//! A pixel belongs to a triangle if its centre (i + ½, j + ½) is inside, or on an edge that is a
//! *top* or *left* edge (the usual top-left rule). So a pixel centre on an edge shared by two
//! triangles is counted once, and none is lost. For the rule to be consistent, both triangles
//! must compute exactly opposite edge values: every edge function is evaluated with its end
//! points in a canonical order (by vertex identity) and negated as needed, so the two sides see
//! `E` and `−E` bit for bit.

use robust::{Coord, orient2d};

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
    if (a[0], a[1]) <= (b[0], b[1]) {
        (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
    } else {
        -((a[0] - b[0]) * (p[1] - b[1]) - (a[1] - b[1]) * (p[0] - b[0]))
    }
}

/// Calls `f(x, y, w)` for every pixel of `rect` covered by the triangle, with `w` the
/// screen-space barycentric weights of the pixel centre (for Gouraud interpolation, in the
/// order of `tri.v`).
#[inline]
pub fn rasterize(tri: &ScreenTriangle, rect: Rect, mut f: impl FnMut(usize, usize, [f64; 3])) {
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
    let min_x = v[0][0].min(v[1][0]).min(v[2][0]);
    let max_x = v[0][0].max(v[1][0]).max(v[2][0]);
    let min_y = v[0][1].min(v[1][1]).min(v[2][1]);
    let max_y = v[0][1].max(v[1][1]).max(v[2][1]);
    // Pixel centres i + ½ within [min, max].
    let lo = |m: f64, r0: usize| ((m - 0.5).ceil().max(r0 as f64)) as usize;
    let hi = |m: f64, r1: usize| (((m - 0.5).floor() + 1.0).min(r1 as f64).max(0.0)) as usize;
    let (x0, x1) = (lo(min_x, rect.x0), hi(max_x, rect.x1));
    let (y0, y1) = (lo(min_y, rect.y0), hi(max_y, rect.y1));
    if x0 >= x1 || y0 >= y1 {
        return;
    }
    // Top-left ownership of each edge k: v[k] → v[k+1]. With positive orientation and y
    // pointing down, a top edge runs towards +x and a left edge towards −y. An edge shared with
    // another triangle runs the other way there, so exactly one of the two owns it.
    let owns = [0, 1, 2].map(|k| {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        dy < 0.0 || (dy == 0.0 && dx > 0.0)
    });
    let area = edge(v[0], v[1], v[2]);
    for y in y0..y1 {
        let py = y as f64 + 0.5;
        for x in x0..x1 {
            let p = [x as f64 + 0.5, py];
            let e = [0, 1, 2].map(|k| {
                let j = (k + 1) % 3;
                edge(v[k], v[j], p)
            });
            let inside = (0..3).all(|k| e[k] > 0.0 || (e[k] == 0.0 && owns[k]));
            if inside {
                // Weight of vertex k is the edge value opposite it.
                let w = [e[1] / area, e[2] / area, e[0] / area];
                let mut out = [0.0; 3];
                for k in 0..3 {
                    out[perm[k]] = w[k];
                }
                f(x, y, out);
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
        rasterize(t, ALL, |x, y, w| {
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
