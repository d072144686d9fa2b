//! Affine transforms in f64: the model transform built from `vol_scale`, `vol_translate`,
//! `vol_rotate` (docs/camera.md) and the rigid view transform of `look_at`.

/// `x ↦ M·x + t`, stored as a 3×4 matrix `[M | t]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Affine(pub [[f64; 4]; 3]);

impl Affine {
    pub const IDENTITY: Affine = Affine([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ]);

    pub fn translation(t: [f64; 3]) -> Affine {
        let mut a = Affine::IDENTITY;
        for k in 0..3 {
            a.0[k][3] = t[k];
        }
        a
    }

    pub fn scale(s: [f64; 3]) -> Affine {
        let mut a = Affine::IDENTITY;
        for k in 0..3 {
            a.0[k][k] = s[k];
        }
        a
    }

    /// Right-handed rotation by `degrees` about `axis` through the origin (Rodrigues). `None`
    /// for a zero axis.
    pub fn rotation(axis: [f64; 3], degrees: f64) -> Option<Affine> {
        let len = norm(axis);
        if len == 0.0 || !len.is_finite() {
            return None;
        }
        let [x, y, z] = axis.map(|v| v / len);
        let (s, c) = degrees.to_radians().sin_cos();
        let t = 1.0 - c;
        Some(Affine([
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0.0],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0.0],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0.0],
        ]))
    }

    /// `self ∘ other`: apply `other` first, then `self`.
    pub fn after(&self, other: &Affine) -> Affine {
        let (a, b) = (&self.0, &other.0);
        let mut m = [[0.0; 4]; 3];
        for i in 0..3 {
            for j in 0..4 {
                m[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum::<f64>()
                    + if j == 3 { a[i][3] } else { 0.0 };
            }
        }
        Affine(m)
    }

    #[inline]
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let m = &self.0;
        [0, 1, 2].map(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3])
    }

    /// The linear part applied to a direction.
    #[inline]
    pub fn apply_vector(&self, v: [f64; 3]) -> [f64; 3] {
        let m = &self.0;
        [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
    }

    /// The inverse transform (`None` if singular, e.g. a zero scale).
    pub fn inverse(&self) -> Option<Affine> {
        let m = &self.0;
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = |r: usize, c: usize| {
            let (r1, r2) = ((c + 1) % 3, (c + 2) % 3);
            let (c1, c2) = ((r + 1) % 3, (r + 2) % 3);
            (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det
        };
        let mut out = [[0.0; 4]; 3];
        for i in 0..3 {
            for j in 0..3 {
                out[i][j] = inv(i, j);
            }
        }
        for i in 0..3 {
            out[i][3] = -(0..3).map(|k| out[i][k] * m[k][3]).sum::<f64>();
        }
        Some(Affine(out))
    }

    /// The determinant of the linear part.
    pub fn determinant(&self) -> f64 {
        let m = &self.0;
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    }
}

pub fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12)
    }

    #[test]
    fn rotation_is_right_handed() {
        let r = Affine::rotation([0.0, 0.0, 1.0], 90.0).unwrap();
        assert!(close(r.apply([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0]));
        let r = Affine::rotation([1.0, 0.0, 0.0], 90.0).unwrap();
        assert!(close(r.apply([0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]));
        assert!(Affine::rotation([0.0; 3], 10.0).is_none());
    }

    #[test]
    fn composition_and_inverse() {
        let a = Affine::rotation([1.0, 2.0, 3.0], 37.0).unwrap();
        let b = Affine::translation([1.0, -2.0, 0.5]).after(&Affine::scale([2.0, 3.0, 0.5]));
        let ab = a.after(&b);
        let p = [0.3, -0.7, 1.1];
        assert!(close(ab.apply(p), a.apply(b.apply(p))));
        assert!(close(ab.inverse().unwrap().apply(ab.apply(p)), p));
        assert!(Affine::scale([1.0, 0.0, 1.0]).inverse().is_none());
    }
}
