//! The scene: how the volume is placed (`vol_scale`, `vol_translate`, `vol_rotate`), where the
//! eye is (`look_at`) and what the camera sees (`ortho_camera`, `persp_camera`), with the exact
//! conventions of SPEC §5.
//!
//! Coordinates: *file* (as in the HyperMesh file) → *world* (centred on the file's bounding-box
//! centre, then the `vol_*` operations) → *eye* (rigid `look_at` view: the camera looks along
//! −z, x right, y up; depth d = −z). Arc length along a ray is measured in world units, which the
//! rigid view preserves.

mod camera;
pub mod transform;

pub use camera::{Camera, Projector, Ray, RayPlanes, SUBPIXEL, snap};
pub use transform::Affine;

use transform::{cross, dot, norm, sub};

/// One `vol_*` operation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TransformOp {
    /// `vol_scale x y z`: about the world origin.
    Scale([f64; 3]),
    /// `vol_translate x y z`.
    Translate([f64; 3]),
    /// `vol_rotate x y z deg`: right-handed about the axis through the bounding-box centre at
    /// its current position.
    Rotate { axis: [f64; 3], degrees: f64 },
}

/// `look_at ex ey ez rx ry rz ux uy uz`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LookAt {
    pub eye: [f64; 3],
    pub reference: [f64; 3],
    pub up: [f64; 3],
}

impl Default for LookAt {
    /// `0 0 0  0 0 −1  0 1 0` (thesis A.1).
    fn default() -> Self {
        LookAt {
            eye: [0.0; 3],
            reference: [0.0, 0.0, -1.0],
            up: [0.0, 1.0, 0.0],
        }
    }
}

/// Placement of the volume and of the camera.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct View {
    pub transforms: Vec<TransformOp>,
    pub look_at: LookAt,
    /// `None`: the default orthographic camera (bounding box of the centred, untransformed grid;
    /// no depth clipping).
    pub camera: Option<Camera>,
}

impl View {
    /// File → world: centre the file's bounding box at the origin, then apply the operations in
    /// order. A rotation pivots about the file's bounding-box centre carried along by the
    /// operations before it (SPEC §5 **Decision**). `None` if an operation is singular (zero
    /// scale or rotation axis).
    pub fn model(&self, bbox_centre: [f64; 3]) -> Option<Affine> {
        let mut m = Affine::translation(bbox_centre.map(|c| -c));
        let mut centre = [0.0; 3];
        for op in &self.transforms {
            match *op {
                TransformOp::Scale(s) => {
                    if s.contains(&0.0) {
                        return None;
                    }
                    let s = Affine::scale(s);
                    m = s.after(&m);
                    centre = s.apply(centre);
                }
                TransformOp::Translate(t) => {
                    m = Affine::translation(t).after(&m);
                    centre = [0, 1, 2].map(|k| centre[k] + t[k]);
                }
                TransformOp::Rotate { axis, degrees } => {
                    let r = Affine::rotation(axis, degrees)?;
                    let about = Affine::translation(centre)
                        .after(&r)
                        .after(&Affine::translation(centre.map(|c| -c)));
                    m = about.after(&m);
                }
            }
        }
        Some(m)
    }

    /// World → eye (rigid). If eye and reference coincide, the eye keeps its place and looks
    /// along −z; an up vector not orthogonal to the view direction is orthogonalised; an up
    /// vector parallel to it is replaced by the y (or, failing that, the x) axis.
    pub fn view_matrix(&self) -> Affine {
        let LookAt { eye, reference, up } = self.look_at;
        let mut f = sub(reference, eye);
        if norm(f) == 0.0 {
            f = [0.0, 0.0, -1.0];
        }
        let f = f.map(|v| v / norm(f));
        let mut s = cross(f, up);
        for fallback in [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]] {
            if norm(s) > 1e-12 * norm(up).max(1e-300) {
                break;
            }
            s = cross(f, fallback);
        }
        let s = s.map(|v| v / norm(s));
        let u = cross(s, f);
        // Rows: x = s (right), y = u (up), z = −f (backwards).
        let rows = [s, u, f.map(|v| -v)];
        let mut m = [[0.0; 4]; 3];
        for i in 0..3 {
            m[i][..3].copy_from_slice(&rows[i]);
            m[i][3] = -dot(rows[i], eye);
        }
        Affine(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12)
    }

    #[test]
    fn loading_centres_the_bounding_box() {
        let v = View::default();
        let m = v.model([1.0, 2.0, 3.0]).unwrap();
        assert!(close(m.apply([1.0, 2.0, 3.0]), [0.0; 3]));
    }

    #[test]
    fn rotation_pivots_about_the_carried_centre() {
        // Translate by (2,0,0), then rotate 90° about z: the centre stays at (2,0,0), so a point
        // one unit right of the centre moves one unit above it.
        let v = View {
            transforms: vec![
                TransformOp::Translate([2.0, 0.0, 0.0]),
                TransformOp::Rotate {
                    axis: [0.0, 0.0, 1.0],
                    degrees: 90.0,
                },
            ],
            ..View::default()
        };
        let m = v.model([0.0; 3]).unwrap();
        assert!(close(m.apply([0.0; 3]), [2.0, 0.0, 0.0]));
        assert!(close(m.apply([1.0, 0.0, 0.0]), [2.0, 1.0, 0.0]));
        // Scaling about the world origin moves the carried centre too.
        let v = View {
            transforms: vec![
                TransformOp::Translate([1.0, 0.0, 0.0]),
                TransformOp::Scale([3.0, 1.0, 1.0]),
                TransformOp::Rotate {
                    axis: [0.0, 0.0, 1.0],
                    degrees: 180.0,
                },
            ],
            ..View::default()
        };
        let m = v.model([0.0; 3]).unwrap();
        assert!(close(m.apply([0.0; 3]), [3.0, 0.0, 0.0]));
        assert!(close(m.apply([1.0, 0.0, 0.0]), [0.0, 0.0, 0.0]));
    }

    #[test]
    fn look_at_conventions() {
        let v = View::default();
        assert!(close(
            v.view_matrix().apply([1.0, 2.0, -3.0]),
            [1.0, 2.0, -3.0]
        ));
        let v = View {
            look_at: LookAt {
                eye: [0.0, 0.0, 5.0],
                reference: [0.0; 3],
                up: [0.0, 1.0, 0.0],
            },
            ..View::default()
        };
        assert!(close(v.view_matrix().apply([0.0; 3]), [0.0, 0.0, -5.0]));
        // Looking down −x from +x: world +z is to the right? eye at (5,0,0) looking at origin,
        // up y: right = f × up = (−1,0,0) × (0,1,0) = (0,0,−1).
        let v = View {
            look_at: LookAt {
                eye: [5.0, 0.0, 0.0],
                reference: [0.0; 3],
                up: [0.3, 2.0, 0.0],
            },
            ..View::default()
        };
        let m = v.view_matrix();
        assert!(close(m.apply([0.0, 0.0, -1.0]), [1.0, 0.0, -5.0]));
        assert!(close(m.apply([0.0, 1.0, 0.0]), [0.0, 1.0, -5.0]));
        // Eye = reference: keep the eye, look along −z.
        let v = View {
            look_at: LookAt {
                eye: [1.0, 1.0, 1.0],
                reference: [1.0, 1.0, 1.0],
                up: [0.0, 1.0, 0.0],
            },
            ..View::default()
        };
        assert!(close(
            v.view_matrix().apply([1.0, 1.0, 0.0]),
            [0.0, 0.0, -1.0]
        ));
        assert!((v.view_matrix().determinant() - 1.0).abs() < 1e-12);
    }
}
