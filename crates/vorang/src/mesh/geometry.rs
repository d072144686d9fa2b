//! Small geometric predicates and measures on tetrahedra.

use robust::Coord3D;

/// Sign of `((b−a)×(c−a))·(d−a)`: positive for a right-handed (positively oriented) cell,
/// exactly zero only when the four points are coplanar. Computed with Shewchuk's adaptive exact
/// predicate, so that "degenerate" means degenerate and not "lost to rounding".
pub fn orientation(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    let p = |v: [f64; 3]| Coord3D {
        x: v[0],
        y: v[1],
        z: v[2],
    };
    // Shewchuk's orient3d is positive when d lies below the plane abc (abc counter-clockwise seen
    // from above), i.e. it has the opposite sign of our right-handed determinant.
    -robust::orient3d(p(a), p(b), p(c), p(d))
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Volume of the tetrahedron (always ≥ 0).
pub fn tet_volume(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    dot(cross(sub(b, a), sub(c, a)), sub(d, a)).abs() / 6.0
}

/// Barycentric coordinates of `p` in the tetrahedron `corners`, and their constant gradients
/// `∇λ_i` (the rows of the inverse Jacobian). Returns `None` for a degenerate cell.
pub fn barycentric(corners: &[[f64; 3]; 4], p: [f64; 3]) -> Option<([f64; 4], [[f64; 3]; 4])> {
    let grads = barycentric_gradients(corners)?;
    let mut l = [0.0; 4];
    for i in 1..4 {
        l[i] = dot(grads[i], sub(p, corners[0]));
    }
    l[0] = 1.0 - l[1] - l[2] - l[3];
    Some((l, grads))
}

/// The edges from node 0 and the determinant of the Jacobian they form.
#[inline(always)]
fn jacobian(c: &[[f64; 3]; 4]) -> ([[f64; 3]; 3], f64) {
    let e1 = sub(c[1], c[0]);
    let e2 = sub(c[2], c[0]);
    let e3 = sub(c[3], c[0]);
    ([e1, e2, e3], dot(cross(e1, e2), e3))
}

/// Whether [`barycentric_gradients`] has an answer: a nonzero, finite Jacobian determinant.
#[inline]
pub fn is_proper(c: &[[f64; 3]; 4]) -> bool {
    proper_det(jacobian(c).1)
}

#[inline(always)]
fn proper_det(det: f64) -> bool {
    det != 0.0 && det.is_finite()
}

/// `∇λ_i` for the four barycentric coordinates of a cell.
pub fn barycentric_gradients(c: &[[f64; 3]; 4]) -> Option<[[f64; 3]; 4]> {
    let ([e1, e2, e3], det) = jacobian(c);
    if !proper_det(det) {
        return None;
    }
    // Rows of the inverse of [e1 e2 e3] (columns): ∇λ1 = (e2×e3)/det, etc.
    let scaled = |v: [f64; 3]| [v[0] / det, v[1] / det, v[2] / det];
    let g1 = scaled(cross(e2, e3));
    let g2 = scaled(cross(e3, e1));
    let g3 = scaled(cross(e1, e2));
    let g0 = [
        -(g1[0] + g2[0] + g3[0]),
        -(g1[1] + g2[1] + g3[1]),
        -(g1[2] + g2[2] + g3[2]),
    ];
    Some([g0, g1, g2, g3])
}

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Aabb {
    /// The smallest box holding all points; an "empty" box (min > max) for no points.
    pub fn of_points(points: &[[f64; 3]]) -> Aabb {
        let mut b = Aabb {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
        };
        for p in points {
            for k in 0..3 {
                b.min[k] = b.min[k].min(p[k]);
                b.max[k] = b.max[k].max(p[k]);
            }
        }
        b
    }

    /// The smallest box holding both boxes (exact: minima and maxima round nothing).
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: [0, 1, 2].map(|k| self.min[k].min(other.min[k])),
            max: [0, 1, 2].map(|k| self.max[k].max(other.max[k])),
        }
    }

    pub fn center(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| 0.5 * (self.min[k] + self.max[k]))
    }

    pub fn size(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| self.max[k] - self.min[k])
    }

    pub fn is_empty(&self) -> bool {
        (0..3).any(|k| self.min[k] > self.max[k])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentric_coordinates_reproduce_the_point() {
        let c = [
            [0.1, 0.2, 0.3],
            [2.0, 0.0, 0.5],
            [0.3, 1.7, 0.0],
            [0.2, 0.4, 3.0],
        ];
        let p = [0.5, 0.5, 0.7];
        let (l, g) = barycentric(&c, p).unwrap();
        assert!((l.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        for k in 0..3 {
            let q: f64 = (0..4).map(|i| l[i] * c[i][k]).sum();
            assert!((q - p[k]).abs() < 1e-14);
        }
        // ∇λ_i · (c_j − c_0) = δ_ij − δ_i0
        for i in 0..4 {
            for j in 1..4 {
                let v = dot(g[i], sub(c[j], c[0]));
                let expect = f64::from(u8::from(i == j)) - f64::from(u8::from(i == 0));
                assert!((v - expect).abs() < 1e-13, "{i} {j} {v}");
            }
        }
    }

    #[test]
    fn volume_of_unit_corner() {
        let v = tet_volume([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert!((v - 1.0 / 6.0).abs() < 1e-16);
    }
}
