//! One cell in eye space: where a ray enters and leaves it, and barycentric coordinates along
//! the ray.
//!
//! The barycentric coordinates λ_i are affine functions of position, positive inside the cell;
//! λ_i = 0 is the plane of face i. Along a ray `o + τ·d` each is `a_i + τ·b_i`, so the ray is
//! inside for τ in the intersection of four half-lines — exact for perspective and orthographic
//! rays alike.

use crate::mesh::barycentric_gradients;
use crate::scene::Ray;

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
        [0, 1, 2, 3].map(|i| self.a[i] + tau * self.b[i])
    }
}

impl EyeCell {
    /// `None` for a degenerate (flat) cell.
    pub fn new(p: &[[f64; 3]; 4]) -> Option<EyeCell> {
        let g = barycentric_gradients(p)?;
        // λ_i(p_i) = 1 fixes the constant: h_i = 1 − g_i·p_i.
        let h =
            [0, 1, 2, 3].map(|i| 1.0 - (g[i][0] * p[i][0] + g[i][1] * p[i][1] + g[i][2] * p[i][2]));
        Some(EyeCell { g, h })
    }

    /// The part of `ray` inside the cell, or `None` if the ray misses it or only touches it.
    #[inline]
    pub fn interval(&self, ray: &Ray) -> Option<Interval> {
        let (o, d) = (ray.origin, ray.dir);
        let mut a = [0.0; 4];
        let mut b = [0.0; 4];
        let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
        let (mut entry_face, mut exit_face) = (0, 0);
        let d_len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        for i in 0..4 {
            let g = self.g[i];
            a[i] = g[0] * o[0] + g[1] * o[1] + g[2] * o[2] + self.h[i];
            b[i] = g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
            // A face (numerically) parallel to the ray is seen edge-on: the ray runs in its
            // plane only on the outline of the cell's footprint, where the scan conversion has
            // already decided, exactly once, which cell owns the pixel. It bounds nothing.
            let g_len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
            if b[i].abs() <= 1e-12 * g_len * d_len {
                if a[i] < -1e-9 {
                    return None;
                }
                continue;
            }
            if b[i] > 0.0 {
                // λ_i grows along the ray: the ray enters through face i at λ_i = 0.
                let t = -a[i] / b[i];
                if t > near {
                    near = t;
                    entry_face = i;
                }
            } else {
                let t = -a[i] / b[i];
                if t < far {
                    far = t;
                    exit_face = i;
                }
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
