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
#[derive(Debug, Clone, Default)]
pub struct Fan {
    sectors: [Sector; 4],
    count: usize,
}

/// The shading kernels' precondition: `n` whole batches of `step` pixels, and every slice
/// holding them (the kernels read and write through raw pointers up to `n`).
#[cfg(target_arch = "x86_64")]
fn shade_bounds(step: usize, n: usize, xs: &[f64], ys: &[f64], out: &[&mut [f64]; 4]) {
    assert!(
        n.is_multiple_of(step)
            && xs.len() >= n
            && ys.len() >= n
            && out.iter().all(|o| o.len() >= n)
    );
}

impl Fan {
    /// The fan of an unclipped footprint with `values[v]` at each fan vertex (0…3 the nodes,
    /// [`THICK`] the thick point). `None` for a footprint without a Shirley–Tuchman split.
    pub fn new(fp: &Footprint, values: &[[f64; 4]; 5]) -> Option<Fan> {
        let mut fan = Fan {
            sectors: [Sector::default(); 4],
            count: 0,
        };
        fan.build(fp, values).then_some(fan)
    }

    /// [`Fan::new`] into `self`, which the tile loop reuses from cell to cell (returned, the
    /// fan's 480 bytes were copied once more per cell). `false` where [`Fan::new`] gives `None`.
    pub fn build(&mut self, fp: &Footprint, values: &[[f64; 4]; 5]) -> bool {
        if fp.projection.is_none() {
            return false;
        }
        // Unused sectors never win: their T weight is +∞.
        let unused = Sector {
            thick: Plane {
                c: f64::INFINITY,
                x: 0.0,
                y: 0.0,
            },
            ..Sector::default()
        };
        let fan = self;
        fan.sectors = [unused; 4];
        fan.count = 0;
        let vt = values[THICK as usize];
        for k in 0..fp.count {
            let corners = fp.corners[k];
            let Some(t) = corners.iter().position(|&c| c == THICK) else {
                return false;
            };
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
        fan.count > 0
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

    /// Per plane k (T's weight, θ, R, G, B) and coefficient (c, x, y): the four sectors'
    /// numbers, as the shading kernels load them into lanes 0…3.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn coefficients(&self) -> [[[f64; 4]; 3]; 5] {
        // Plain loops (no closures: those are compiled for the baseline target, and this runs
        // once per cell inside the kernels).
        let mut t = [[[0.0; 4]; 3]; 5];
        for (m, s) in self.sectors.iter().enumerate() {
            for (k, p) in [s.thick, s.values[0], s.values[1], s.values[2], s.values[3]]
                .iter()
                .enumerate()
            {
                t[k][0][m] = p.c;
                t[k][1][m] = p.x;
                t[k][2][m] = p.y;
            }
        }
        t
    }

    /// [`Fan::at_lanes`] followed by [`shade`] with `brightness`, over the first `n` pixels
    /// (a multiple of 8) of `xs`, `ys`, into `out` (`b` RGB and θ), with AVX-512. Each lane
    /// picks its sector with [`Fan::at_lanes`]' comparisons, then evaluates only that sector's
    /// four value planes, its coefficients fetched per lane by a permutation (`vpermpd`) —
    /// the same operations in the same order as [`Plane::at`], so the same bits, for eight
    /// plane evaluations per pixel instead of twenty.
    ///
    /// # Safety
    /// Only where the processor has AVX-512F.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    pub fn shade_avx512(
        &self,
        brightness: f64,
        n: usize,
        xs: &[f64],
        ys: &[f64],
        out: [&mut [f64]; 4],
    ) {
        use std::arch::x86_64::*;
        shade_bounds(8, n, xs, ys, &out);
        let t = self.coefficients();
        let table: [[__m512d; 3]; 5] = std::array::from_fn(|k| {
            std::array::from_fn(|c| {
                let [a, b, c, d] = t[k][c];
                _mm512_setr_pd(a, b, c, d, 0.0, 0.0, 0.0, 0.0)
            })
        });
        let bright = _mm512_set1_pd(brightness);
        let one = _mm512_set1_pd(1.0);
        let [r, g, b, th] = out;
        for i in (0..n).step_by(8) {
            // SAFETY: `i + 8 ≤ n` and every slice holds at least `n` (asserted above).
            let (x, y) = unsafe {
                (
                    _mm512_loadu_pd(xs.as_ptr().add(i)),
                    _mm512_loadu_pd(ys.as_ptr().add(i)),
                )
            };
            // `c + X·x + Y·y`, as `Plane::at` rounds it.
            let at = |[c, px, py]: [__m512d; 3]| {
                _mm512_add_pd(_mm512_add_pd(c, _mm512_mul_pd(px, x)), _mm512_mul_pd(py, y))
            };
            let sector = |m: i64| {
                let m = _mm512_set1_epi64(m);
                table[0].map(|v| _mm512_permutexvar_pd(m, v))
            };
            let l = [at(sector(0)), at(sector(1)), at(sector(2)), at(sector(3))];
            // The comparisons of `at_lanes`: ordered less-than (false with a NaN).
            let first = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(l[1], l[0]);
            let second = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(l[3], l[2]);
            let la = _mm512_mask_blend_pd(first, l[0], l[1]);
            let lb = _mm512_mask_blend_pd(second, l[2], l[3]);
            let pick_b = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(lb, la);
            let ia = _mm512_mask_blend_epi64(first, _mm512_set1_epi64(0), _mm512_set1_epi64(1));
            let ib = _mm512_mask_blend_epi64(second, _mm512_set1_epi64(2), _mm512_set1_epi64(3));
            let best = _mm512_mask_blend_epi64(pick_b, ia, ib);
            let v: [__m512d; 4] =
                std::array::from_fn(|k| at(table[k + 1].map(|c| _mm512_permutexvar_pd(best, c))));
            // `shade`: θ, and the colour times `brightness·(1 − θ)`.
            let k = _mm512_mul_pd(bright, _mm512_sub_pd(one, v[0]));
            // SAFETY: as for the loads.
            unsafe {
                _mm512_storeu_pd(r.as_mut_ptr().add(i), _mm512_mul_pd(v[1], k));
                _mm512_storeu_pd(g.as_mut_ptr().add(i), _mm512_mul_pd(v[2], k));
                _mm512_storeu_pd(b.as_mut_ptr().add(i), _mm512_mul_pd(v[3], k));
                _mm512_storeu_pd(th.as_mut_ptr().add(i), v[0]);
            }
        }
    }

    /// [`Fan::shade_avx512`] with AVX2, four lanes at a time: the four sectors' coefficients
    /// fill one register, and a lane's pick is a permutation of its 32-bit halves
    /// (`vpermps`, indices `2m, 2m + 1` for sector `m`). The same bits as [`Fan::at`].
    ///
    /// # Safety
    /// Only where the processor has AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub fn shade_avx2(
        &self,
        brightness: f64,
        n: usize,
        xs: &[f64],
        ys: &[f64],
        out: [&mut [f64]; 4],
    ) {
        use std::arch::x86_64::*;
        shade_bounds(4, n, xs, ys, &out);
        let t = self.coefficients();
        // SAFETY: four f64 per entry, as the load reads.
        let table: [[__m256d; 3]; 5] = std::array::from_fn(|k| {
            std::array::from_fn(|c| unsafe { _mm256_loadu_pd(t[k][c].as_ptr()) })
        });
        // Sector m's 32-bit halves, in every lane.
        let pick = |m: i32| {
            _mm256_castsi256_pd(_mm256_setr_epi32(
                2 * m,
                2 * m + 1,
                2 * m,
                2 * m + 1,
                2 * m,
                2 * m + 1,
                2 * m,
                2 * m + 1,
            ))
        };
        let permute = |idx: __m256d, v: __m256d| {
            _mm256_castps_pd(_mm256_permutevar8x32_ps(
                _mm256_castpd_ps(v),
                _mm256_castpd_si256(idx),
            ))
        };
        let picks = [pick(0), pick(1), pick(2), pick(3)];
        let bright = _mm256_set1_pd(brightness);
        let one = _mm256_set1_pd(1.0);
        let [r, g, b, th] = out;
        for i in (0..n).step_by(4) {
            // SAFETY: `i + 4 ≤ n` and every slice holds at least `n` (asserted above).
            let (x, y) = unsafe {
                (
                    _mm256_loadu_pd(xs.as_ptr().add(i)),
                    _mm256_loadu_pd(ys.as_ptr().add(i)),
                )
            };
            // `c + X·x + Y·y`, as `Plane::at` rounds it.
            let at = |[c, px, py]: [__m256d; 3]| {
                _mm256_add_pd(_mm256_add_pd(c, _mm256_mul_pd(px, x)), _mm256_mul_pd(py, y))
            };
            let l: [__m256d; 4] =
                std::array::from_fn(|m| at(table[0].map(|v| permute(picks[m], v))));
            // The comparisons of `at_lanes`: ordered less-than (false with a NaN).
            let first = _mm256_cmp_pd::<_CMP_LT_OQ>(l[1], l[0]);
            let second = _mm256_cmp_pd::<_CMP_LT_OQ>(l[3], l[2]);
            let la = _mm256_blendv_pd(l[0], l[1], first);
            let lb = _mm256_blendv_pd(l[2], l[3], second);
            let pick_b = _mm256_cmp_pd::<_CMP_LT_OQ>(lb, la);
            let ia = _mm256_blendv_pd(picks[0], picks[1], first);
            let ib = _mm256_blendv_pd(picks[2], picks[3], second);
            let best = _mm256_blendv_pd(ia, ib, pick_b);
            let v: [__m256d; 4] =
                std::array::from_fn(|k| at(table[k + 1].map(|c| permute(best, c))));
            let k = _mm256_mul_pd(bright, _mm256_sub_pd(one, v[0]));
            // SAFETY: as for the loads.
            unsafe {
                _mm256_storeu_pd(r.as_mut_ptr().add(i), _mm256_mul_pd(v[1], k));
                _mm256_storeu_pd(g.as_mut_ptr().add(i), _mm256_mul_pd(v[2], k));
                _mm256_storeu_pd(b.as_mut_ptr().add(i), _mm256_mul_pd(v[3], k));
                _mm256_storeu_pd(th.as_mut_ptr().add(i), v[0]);
            }
        }
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
