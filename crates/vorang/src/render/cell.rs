//! One cell in eye space: where a pixel's ray enters and leaves it, and barycentric coordinates
//! along the ray.
//!
//! The barycentric coordinates λ_i are affine functions of position, positive inside the cell;
//! λ_i = 0 is the plane of face i. Along the ray of the pixel at screen position (x, y),
//! `o + τ·d`, each is `a_i + τ·b_i`, and both `a_i` and `b_i` are affine functions of (x, y) —
//! for orthographic rays `b_i` is even constant. [`CellRays`] holds those affine functions, so
//! that per pixel the interval costs a few multiply-adds and at most four divisions — exact for
//! perspective and orthographic rays alike.

use crate::mesh::barycentric_gradients;
use crate::scene::{Projector, Ray, RayPlanes};

/// A cell's barycentric functions λ_i(p) = g_i·p + h_i in eye space.
#[derive(Debug, Clone, Copy)]
pub struct EyeCell {
    pub g: [[f64; 3]; 4],
    pub h: [f64; 4],
}

/// The part of a ray inside a cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    /// Entry and exit parameter (depth) along the ray, `near ≤ far`.
    pub near: f64,
    pub far: f64,
    /// The faces the ray enters and leaves through.
    pub entry_face: usize,
    pub exit_face: usize,
    /// λ at the ray origin and its rate per unit τ.
    pub a: [f64; 4],
    pub b: [f64; 4],
}

impl Interval {
    /// Barycentric coordinates at parameter τ.
    #[inline]
    pub fn lambda(&self, tau: f64) -> [f64; 4] {
        [
            self.a[0] + tau * self.b[0],
            self.a[1] + tau * self.b[1],
            self.a[2] + tau * self.b[2],
            self.a[3] + tau * self.b[3],
        ]
    }
}

impl EyeCell {
    /// Whether [`EyeCell::new`] has an answer: the cell is not flat (the same test).
    pub fn is_proper(p: &[[f64; 3]; 4]) -> bool {
        crate::mesh::is_proper(p)
    }

    /// `None` for a degenerate (flat) cell.
    pub fn new(p: &[[f64; 3]; 4]) -> Option<EyeCell> {
        let g = barycentric_gradients(p)?;
        // λ_i(p_i) = 1 fixes the constant: h_i = 1 − g_i·p_i.
        let h =
            [0, 1, 2, 3].map(|i| 1.0 - (g[i][0] * p[i][0] + g[i][1] * p[i][1] + g[i][2] * p[i][2]));
        Some(EyeCell { g, h })
    }

    /// The part of `ray` inside the cell, or `None` if the ray misses it or only touches it.
    pub fn interval(&self, ray: &Ray) -> Option<Interval> {
        let (o, d) = (ray.origin, ray.dir);
        let a = [0, 1, 2, 3]
            .map(|i| self.g[i][0] * o[0] + self.g[i][1] * o[1] + self.g[i][2] * o[2] + self.h[i]);
        let b =
            [0, 1, 2, 3].map(|i| self.g[i][0] * d[0] + self.g[i][1] * d[1] + self.g[i][2] * d[2]);
        let d_len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let tol = self
            .g
            .map(|g| PARALLEL * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt() * d_len);
        clip(a, b, &tol)
    }
}

/// A face whose `|b|` is below this fraction of `|g|·|d|` is parallel to the ray: seen edge-on.
/// The ray runs in its plane only on the outline of the cell's footprint, where the scan
/// conversion has already decided, exactly once, which cell owns the pixel — so it bounds
/// nothing.
const PARALLEL: f64 = 1e-12;

/// The interval where all `a_i + τ·b_i ≥ 0`.
#[inline(always)]
fn clip(a: [f64; 4], b: [f64; 4], tol: &[f64; 4]) -> Option<Interval> {
    let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut entry_face, mut exit_face) = (0, 0);
    for i in 0..4 {
        if b[i].abs() <= tol[i] {
            if a[i] < -1e-9 {
                return None;
            }
            continue;
        }
        let t = -a[i] / b[i];
        if b[i] > 0.0 {
            // λ_i grows along the ray: the ray enters through face i at λ_i = 0.
            if t > near {
                near = t;
                entry_face = i;
            }
        } else if t < far {
            far = t;
            exit_face = i;
        }
    }
    (near < far).then_some(Interval {
        near,
        far,
        entry_face,
        exit_face,
        a,
        b,
    })
}

/// A cell's `a_i` and `b_i` as affine functions of the screen position: for every pixel of the
/// cell's footprint the ray interval without rebuilding the ray.
#[derive(Debug, Clone, Copy)]
pub struct CellRays {
    /// `a_i(x, y) = a[i][0] + a[i][1]·x + a[i][2]·y`.
    a: [[f64; 3]; 4],
    b: [[f64; 3]; 4],
    tol: [f64; 4],
}

impl CellRays {
    pub fn new(cell: &EyeCell, projector: &Projector) -> CellRays {
        let mut a = [[0.0; 3]; 4];
        let mut b = [[0.0; 3]; 4];
        let mut tol = [0.0; 4];
        let RayPlanes {
            origin: o,
            dir: d,
            max_speed: d_max,
        } = projector.ray_planes();
        for i in 0..4 {
            let g = cell.g[i];
            for k in 0..3 {
                a[i][k] = g[0] * o[0][k] + g[1] * o[1][k] + g[2] * o[2][k];
                b[i][k] = g[0] * d[0][k] + g[1] * d[1][k] + g[2] * d[2][k];
            }
            a[i][0] += cell.h[i];
            tol[i] = PARALLEL * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt() * d_max;
        }
        CellRays { a, b, tol }
    }

    /// `Σ v_i·λ_i` along the rays as a function of the pixel position and the depth:
    /// `c[0] + c[1]·x + c[2]·y + τ·(c[3] + c[4]·x + c[5]·y)` (for orthographic rays
    /// `c[4] = c[5] = 0`).
    pub fn affine(&self, v: &[f64; 4]) -> [f64; 6] {
        let dot = |m: &[[f64; 3]; 4], k: usize| {
            m[0][k] * v[0] + m[1][k] * v[1] + m[2][k] * v[2] + m[3][k] * v[3]
        };
        [
            dot(&self.a, 0),
            dot(&self.a, 1),
            dot(&self.a, 2),
            dot(&self.b, 0),
            dot(&self.b, 1),
            dot(&self.b, 2),
        ]
    }

    /// λ along the ray through screen position (x, y): `a_i + τ·b_i`.
    #[inline(always)]
    pub fn line(&self, x: f64, y: f64) -> ([f64; 4], [f64; 4]) {
        let (a, b) = (&self.a, &self.b);
        let a = [
            a[0][0] + a[0][1] * x + a[0][2] * y,
            a[1][0] + a[1][1] * x + a[1][2] * y,
            a[2][0] + a[2][1] * x + a[2][2] * y,
            a[3][0] + a[3][1] * x + a[3][2] * y,
        ];
        let b = [
            b[0][0] + b[0][1] * x + b[0][2] * y,
            b[1][0] + b[1][1] * x + b[1][2] * y,
            b[2][0] + b[2][1] * x + b[2][2] * y,
            b[3][0] + b[3][1] * x + b[3][2] * y,
        ];
        (a, b)
    }

    /// The interval of the ray through screen position (x, y), or `None`.
    #[inline(always)]
    pub fn interval(&self, x: f64, y: f64) -> Option<Interval> {
        let (a, b) = self.line(x, y);
        clip(a, b, &self.tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;

    #[test]
    fn a_ray_through_the_unit_corner() {
        let p = [
            [0.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [0.0, 1.0, -1.0],
            [0.0, 0.0, -2.0],
        ];
        let c = EyeCell::new(&p).unwrap();
        let ray = Ray {
            origin: [0.25, 0.25, 0.0],
            dir: [0.0, 0.0, -1.0],
        };
        let i = c.interval(&ray).unwrap();
        assert!(
            (i.near - 1.0).abs() < 1e-15 && (i.far - 1.5).abs() < 1e-15,
            "{i:?}"
        );
        assert_eq!(i.entry_face, 3);
        let l = i.lambda(1.25);
        assert!((l.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert!((l[3] - 0.25).abs() < 1e-15);
        let miss = Ray {
            origin: [0.9, 0.9, 0.0],
            dir: [0.0, 0.0, -1.0],
        };
        assert!(c.interval(&miss).is_none());
    }

    #[test]
    fn affine_setup_agrees_with_explicit_rays() {
        let p = [
            [0.1, -0.2, -2.0],
            [1.0, 0.1, -2.5],
            [-0.3, 0.9, -2.2],
            [0.2, 0.1, -3.4],
        ];
        let c = EyeCell::new(&p).unwrap();
        for cam in [
            Camera::Ortho {
                left: -1.0,
                right: 1.5,
                bottom: -1.0,
                top: 1.2,
                front: 0.0,
                back: 9.0,
            },
            Camera::Persp {
                fovy: 50.0,
                aspect: 1.3,
                near: 0.1,
                far: 9.0,
            },
        ] {
            let proj = Projector::new(Some(&cam), [1.0; 3], 40, 30).unwrap();
            let rays = CellRays::new(&c, &proj);
            let mut hits = 0;
            for j in 0..30 {
                for i in 0..40 {
                    let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
                    let slow = c.interval(&proj.ray_at(x, y));
                    let fast = rays.interval(x, y);
                    match (slow, fast) {
                        (Some(s), Some(f)) => {
                            hits += 1;
                            assert!(
                                (s.near - f.near).abs() < 1e-12 && (s.far - f.far).abs() < 1e-12,
                                "{s:?} {f:?}"
                            );
                        }
                        (None, None) => {}
                        other => panic!("disagree at ({i},{j}): {other:?}"),
                    }
                }
            }
            assert!(hits > 20);
        }
    }
}
