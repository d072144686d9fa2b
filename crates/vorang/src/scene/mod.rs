//! The scene: how the volume is placed (`vol_scale`, `vol_translate`, `vol_rotate`), where the
//! eye is (`look_at`) and what the camera sees (`ortho_camera`, `persp_camera`), with the exact
//! conventions of docs/camera.md.
//!
//! Coordinates: *file* (as in the HyperMesh file) → *world* (centred on the file's bounding-box
//! centre, then the `vol_*` operations) → *eye* (rigid `look_at` view: the camera looks along
//! −z, x right, y up; depth d = −z). Arc length along a ray is measured in world units, which the
//! rigid view preserves.

mod camera;
pub mod light;
pub mod transform;

pub use camera::{Camera, Projector, Ray, RayPlanes, SUBPIXEL, snap};
pub use light::{Light, Lighting, Phong};
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
    /// operations before it (docs/camera.md). `None` if an operation is singular (zero
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

/// The fraction of the image `view_all` leaves free on each side of the volume.
pub const FIT_MARGIN: f64 = 0.05;

impl View {
    /// `view_all`: a camera of the current kind (orthographic when none
    /// is set) looking in the current direction, such that every node of the transformed volume
    /// lies inside the image of `width × height` pixels with a margin of [`FIT_MARGIN`] on each
    /// side, touching it on at least one side. Orthographic: the window is centred on the
    /// volume's eye-space extent and widened to the image's aspect ratio, the depth range covers
    /// the volume. Perspective: the field of view and aspect are kept and the eye moves along the
    /// viewing direction (reference point at the volume's bounding-box centre, same up vector);
    /// near and far enclose the volume. `nodes` are in file coordinates.
    pub fn fit(
        &mut self,
        nodes: &[[f64; 3]],
        bbox_centre: [f64; 3],
        width: usize,
        height: usize,
    ) -> Result<(), String> {
        let extremes = self.fit_extremes(nodes, bbox_centre)?;
        if nodes.is_empty() {
            return Err("view_all: the volume has no nodes".into());
        }
        self.fit_to(&extremes, bbox_centre, width, height)
    }

    /// What [`View::fit`] needs of the nodes, as minima only (maxima negated), so that the
    /// extremes of several sets of nodes — the ranks of a distributed session, each holding
    /// some of them — combine by an elementwise minimum: orthographic, the eye-space box
    /// (`lo`, then `−hi`); perspective, `−d` and the depth extent along the view (`min z`,
    /// `−max z`). Without nodes, the neutral element.
    pub fn fit_extremes(
        &self,
        nodes: &[[f64; 3]],
        bbox_centre: [f64; 3],
    ) -> Result<[f64; FIT_EXTREMES], String> {
        let model = self
            .model(bbox_centre)
            .ok_or("view_all: the transforms are singular")?;
        let mut out = [f64::INFINITY; FIT_EXTREMES];
        match self.camera {
            None | Some(Camera::Ortho { .. }) => {
                let eye = self.view_matrix();
                for &p in nodes {
                    let q = eye.apply(model.apply(p));
                    for k in 0..3 {
                        out[k] = out[k].min(q[k]);
                        out[3 + k] = out[3 + k].min(-q[k]);
                    }
                }
            }
            Some(Camera::Persp {
                fovy,
                aspect: cam_aspect,
                ..
            }) => {
                let f = self.view_direction();
                let centre = model.apply(bbox_centre);
                let axes = self.view_matrix();
                let rows = [0, 1, 2].map(|i| [axes.0[i][0], axes.0[i][1], axes.0[i][2]]);
                let ty = (0.5 * fovy.to_radians()).tan() * (1.0 - 2.0 * FIT_MARGIN);
                let tx = ty * cam_aspect;
                // With the eye at centre − d·f, a node at offset (x, y) from the axis and z
                // along f from the centre is at depth d + z: it fits if |x| ≤ tx·(d + z) and
                // |y| ≤ ty·(d + z).
                let mut d: f64 = 0.0;
                for &p in nodes {
                    let o = transform::sub(model.apply(p), centre);
                    let (x, y) = (transform::dot(o, rows[0]), transform::dot(o, rows[1]));
                    let z = transform::dot(o, f);
                    d = d.max(x.abs() / tx - z).max(y.abs() / ty - z);
                    out[1] = out[1].min(z);
                    out[2] = out[2].min(-z);
                }
                out[0] = -d;
            }
        }
        Ok(out)
    }

    /// The unit viewing direction of the look-at (−z when the eye is at the reference point).
    fn view_direction(&self) -> [f64; 3] {
        let LookAt { eye, reference, .. } = self.look_at;
        let mut f = transform::sub(reference, eye);
        if transform::norm(f) == 0.0 {
            f = [0.0, 0.0, -1.0];
        }
        f.map(|v| v / transform::norm(f))
    }

    /// [`View::fit`] from the nodes' [`View::fit_extremes`] (of every rank).
    pub fn fit_to(
        &mut self,
        extremes: &[f64; FIT_EXTREMES],
        bbox_centre: [f64; 3],
        width: usize,
        height: usize,
    ) -> Result<(), String> {
        let model = self
            .model(bbox_centre)
            .ok_or("view_all: the transforms are singular")?;
        let aspect = width as f64 / height as f64;
        let keep = 1.0 - 2.0 * FIT_MARGIN;
        match self.camera {
            None | Some(Camera::Ortho { .. }) => {
                let lo = [extremes[0], extremes[1], extremes[2]];
                let hi = [-extremes[3], -extremes[4], -extremes[5]];
                let (cx, cy) = (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]));
                let mut hx = 0.5 * (hi[0] - lo[0]) / keep;
                let mut hy = 0.5 * (hi[1] - lo[1]) / keep;
                if hx <= 0.0 && hy <= 0.0 {
                    return Err("view_all: the volume has no extent on screen".into());
                }
                if hx < hy * aspect {
                    hx = hy * aspect;
                } else {
                    hy = hx / aspect;
                }
                // Depth is −z in eye space; a little room in front and behind.
                let (near, far) = (-hi[2], -lo[2]);
                let pad = 0.05 * (far - near) + 1e-9 * near.abs().max(far.abs()).max(1.0);
                self.camera = Some(Camera::Ortho {
                    left: cx - hx,
                    right: cx + hx,
                    bottom: cy - hy,
                    top: cy + hy,
                    front: near - pad,
                    back: far + pad,
                });
            }
            Some(Camera::Persp {
                fovy,
                aspect: cam_aspect,
                ..
            }) => {
                let f = self.view_direction();
                // The world centre of the bounding box; the eye keeps its direction.
                let centre = model.apply(bbox_centre);
                let mut d = -extremes[0];
                let zs = (extremes[1], -extremes[2]);
                // In front of every node, whatever the field of view.
                let depth_span = zs.1 - zs.0;
                d = d.max(-zs.0 + 0.05 * depth_span.max(1e-9));
                if !d.is_finite() {
                    return Err("view_all: no camera position fits the volume".into());
                }
                let new_eye = [0, 1, 2].map(|k| centre[k] - d * f[k]);
                self.look_at = LookAt {
                    eye: new_eye,
                    reference: centre,
                    up: self.look_at.up,
                };
                let (near, far) = (d + zs.0, d + zs.1);
                self.camera = Some(Camera::Persp {
                    fovy,
                    aspect: cam_aspect,
                    near: (0.5 * near).max(1e-6 * far),
                    far: far * 1.05 + 1e-9,
                });
            }
        }
        Ok(())
    }
}

/// How many numbers [`View::fit_extremes`] gives.
pub const FIT_EXTREMES: usize = 6;

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
