//! Gouraud shading over a Shirley–Tuchman fan, evaluated on the footprint's outline.
//!
//! The fan splits the footprint into 1–4 triangles around the thick point T; a value given at
//! the nodes and at T is interpolated linearly in each. Scan-converting those thin triangles
//! one by one costs a row set-up per triangle and row — more than the pixels themselves for
//! small cells. Instead the outline is scan-converted once, and per pixel the triangle and the
//! weights follow from the *tent*: T's weight `λ_T(p)` is 1 at T, 0 on the outline and linear in
//! each triangle, so (the outline being convex and T inside or on it) it is concave and equals
//! the smallest of the triangles' affine functions `λ_T^t(p)`; the smallest one also names the
//! triangle. Across a shared inner edge both triangles give the same value, so a pixel on one
//! is shaded the same whichever triangle wins.

use super::footprint::Footprint;
use super::project::THICK;

/// A pixel's contribution `(b, θ)` from the interpolated `[θ, η̄ (RGB)]`: the colour weighted by
/// the opacity `1 − θ` and the brightness (`interpolateColor`). One definition for the per-pixel
/// path and the lanes ([`crate::render::span::draw_fan`]).
#[inline(always)]
pub fn shade(brightness: f64, v: [f64; 4]) -> ([f64; 3], f64) {
    let (theta, k) = (v[0], brightness * (1.0 - v[0]));
    ([v[1] * k, v[2] * k, v[3] * k], theta)
}

/// An affine function of the screen position.
#[derive(Debug, Clone, Copy, Default)]
struct Plane {
    c: f64,
    x: f64,
    y: f64,
}

impl Plane {
    #[inline]
    fn at(&self, x: f64, y: f64) -> f64 {
        self.c + self.x * x + self.y * y
    }
}

/// One fan triangle `(n_i, n_j, T)`: T's weight, and the interpolated values, as functions of
/// the pixel.
#[derive(Debug, Clone, Copy, Default)]
struct Sector {
    thick: Plane,
    values: [Plane; 4],
}

/// The fan of one cell, ready to shade pixels.
#[derive(Debug, Clone)]
pub struct Fan {
    sectors: [Sector; 4],
    count: usize,
}

impl Fan {
    /// The fan of an unclipped footprint with `values[v]` at each fan vertex (0…3 the nodes,
    /// [`THICK`] the thick point). `None` for a footprint without a Shirley–Tuchman split.
    pub fn new(fp: &Footprint, values: &[[f64; 4]; 5]) -> Option<Fan> {
        fp.projection.as_ref()?;
        // Unused sectors never win: their T weight is +∞.
        let unused = Sector {
            thick: Plane {
                c: f64::INFINITY,
                x: 0.0,
                y: 0.0,
            },
            ..Sector::default()
        };
        let mut fan = Fan {
            sectors: [unused; 4],
            count: 0,
        };
        let vt = values[THICK as usize];
        for k in 0..fp.count {
            let corners = fp.corners[k];
            let t = corners.iter().position(|&c| c == THICK)?;
            // The two nodes in the triangle's own order after T (the orientation is irrelevant:
            // both weights are ratios of areas of the same sign).
            let (i, j) = ((t + 1) % 3, (t + 2) % 3);
            let v = fp.tris[k].v;
            let (pi, pj, pt) = (v[i], v[j], v[t]);
            let d = [pj[0] - pi[0], pj[1] - pi[1]];
            let e = [pt[0] - pi[0], pt[1] - pi[1]];
            let area = d[0] * e[1] - d[1] * e[0];
            if area == 0.0 || !area.is_finite() {
                continue;
            }
            // λ_T(p) = d × (p − P_i) / area, λ_j(p) = (p − P_i) × e / area.
            let thick = Plane {
                c: (d[1] * pi[0] - d[0] * pi[1]) / area,
                x: -d[1] / area,
                y: d[0] / area,
            };
            let second = Plane {
                c: (e[0] * pi[1] - e[1] * pi[0]) / area,
                x: e[1] / area,
                y: -e[0] / area,
            };
            // value = λ_T·v_T + (1 − λ_T − λ_j)·v_i + λ_j·v_j = v_i + λ_T·(v_T − v_i) + λ_j·(v_j − v_i).
            let (vi, vj) = (values[corners[i] as usize], values[corners[j] as usize]);
            let value = |k: usize| {
                let (dt, dj) = (vt[k] - vi[k], vj[k] - vi[k]);
                Plane {
                    c: vi[k] + thick.c * dt + second.c * dj,
                    x: thick.x * dt + second.x * dj,
                    y: thick.y * dt + second.y * dj,
                }
            };
            fan.sectors[fan.count] = Sector {
                thick,
                values: [value(0), value(1), value(2), value(3)],
            };
            fan.count += 1;
        }
        (fan.count > 0).then_some(fan)
    }

    /// [`Fan::at`] for `L` pixel centres at once: every sector's planes are evaluated and the
    /// winner selected per lane with the same comparisons, so each lane gets [`Fan::at`]'s bits
    /// and the loop has no per-lane branch or table lookup (it becomes vector selects).
    #[inline(always)]
    pub fn at_lanes<const L: usize>(&self, x: &[f64; L], y: &[f64; L]) -> [[f64; L]; 4] {
        // The coefficients as plain locals first: the lane loop then only broadcasts them.
        let planes: [[Plane; 5]; 4] = std::array::from_fn(|m| {
            let s = &self.sectors[m];
            [s.thick, s.values[0], s.values[1], s.values[2], s.values[3]]
        });
        let mut out = [[0.0; L]; 4];
        for l in 0..L {
            let (x, y) = (x[l], y[l]);
            let at = |m: usize, k: usize| planes[m][k].at(x, y);
            let first = at(1, 0) < at(0, 0);
            let second = at(3, 0) < at(2, 0);
            let la = if first { at(1, 0) } else { at(0, 0) };
            let lb = if second { at(3, 0) } else { at(2, 0) };
            let pick_b = lb < la;
            for (k, o) in out.iter_mut().enumerate() {
                let va = if first { at(1, k + 1) } else { at(0, k + 1) };
                let vb = if second { at(3, k + 1) } else { at(2, k + 1) };
                o[l] = if pick_b { vb } else { va };
            }
        }
        out
    }

    /// The interpolated value at the pixel centre `(x, y)` inside the outline.
    #[inline]
    pub fn at(&self, x: f64, y: f64) -> [f64; 4] {
        // All four, padded, so that the choice compiles to selects, not a loop.
        let l = [
            self.sectors[0].thick.at(x, y),
            self.sectors[1].thick.at(x, y),
            self.sectors[2].thick.at(x, y),
            self.sectors[3].thick.at(x, y),
        ];
        let (a, la) = if l[1] < l[0] { (1, l[1]) } else { (0, l[0]) };
        let (b, lb) = if l[3] < l[2] { (3, l[3]) } else { (2, l[2]) };
        let best = if lb < la { b } else { a };
        let v = &self.sectors[best].values;
        [v[0].at(x, y), v[1].at(x, y), v[2].at(x, y), v[3].at(x, y)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::footprint::footprint;
    use crate::render::raster::{Rect, rasterize};
    use crate::scene::{Camera, Projector};

    /// Against interpolating triangle by triangle, for cells of every class.
    #[test]
    fn the_tent_agrees_with_the_fan_triangles() {
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
        let cells = [
            // Class 1: the fourth node inside.
            [
                [2.0, 3.0, 0.0],
                [35.0, 5.0, 0.5],
                [15.0, 37.0, 1.0],
                [16.0, 14.0, 3.0],
            ],
            // Class 2: two edges cross.
            [
                [3.0, 3.0, 0.0],
                [36.0, 35.0, 0.0],
                [34.0, 4.0, 2.0],
                [5.0, 33.0, 2.5],
            ],
            // Class 3: the fourth node over an edge.
            [
                [3.0, 3.0, 0.0],
                [35.0, 3.0, 0.0],
                [19.0, 36.0, 1.0],
                [19.0, 3.0, 4.0],
            ],
        ];
        let values: [[f64; 4]; 5] = [
            [1.0, 0.2, 0.0, 0.5],
            [1.0, 0.9, 0.3, 0.0],
            [1.0, 0.1, 0.8, 0.2],
            [1.0, 0.4, 0.4, 0.9],
            [0.3, 0.6, 0.7, 0.1],
        ];
        let rect = Rect {
            x0: 0,
            y0: 0,
            x1: 40,
            y1: 40,
        };
        for eye in cells {
            let screen = eye.map(|p| proj.screen(p));
            let fp = footprint([0, 1, 2, 3], &eye, &screen, &proj).unwrap();
            let fan = Fan::new(&fp, &values).unwrap();
            let mut pixels = 0;
            for k in 0..fp.count {
                let corners = fp.corners[k];
                rasterize::<true>(&fp.tris[k], rect, |x, y, w| {
                    let want: [f64; 4] = std::array::from_fn(|ch| {
                        (0..3).map(|m| w[m] * values[corners[m] as usize][ch]).sum()
                    });
                    let got = fan.at(x as f64 + 0.5, y as f64 + 0.5);
                    for ch in 0..4 {
                        assert!(
                            (got[ch] - want[ch]).abs() < 1e-12,
                            "({x},{y}): {got:?} vs {want:?}"
                        );
                    }
                    pixels += 1;
                });
            }
            assert!(pixels > 100);
        }
    }
}
