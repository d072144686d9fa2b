//! The viewer's camera: what dragging, the wheel and shift-dragging do to the view,
//! kept as plain numbers so that the view is always an ordinary [`View`] — the one the script
//! commands printed by `p` build again, bit for bit.
//!
//! - Dragging turns the volume about its centre (the pivot `vol_rotate` uses: the file's
//!   bounding-box centre carried along by the transforms), about the screen's up axis for a
//!   horizontal drag and its right axis for a vertical one. The turns accumulate in a unit
//!   quaternion and reach the view as one `vol_rotate axis angle` after the session's own
//!   transforms.
//! - The wheel zooms: an orthographic window shrinks about its centre, a perspective field of
//!   view narrows.
//! - Shift-drag pans: eye and reference point move together in the screen plane, by the
//!   pixels dragged at the depth of the volume's centre.
//!
//! Without a camera of the session's own, the viewer starts with an orthographic camera around
//! the volume's bounding sphere, so no turn moves any part out of the window or the depth range.
//! The commands that build the view again: [`super::commands`].

use vorang::scene::transform::{cross, dot, norm};
use vorang::scene::{Camera, LookAt, TransformOp, View};
use vorang::volume::Volume;

/// Degrees of turn per pixel dragged.
pub const DEGREES_PER_PIXEL: f64 = 0.5;
/// Zoom factor per wheel notch.
pub const ZOOM_STEP: f64 = 1.1;

/// The viewer's view: the session's view at the start, and what the mouse did since.
#[derive(Debug, Clone, PartialEq)]
pub struct Orbit {
    start: View,
    /// Unit quaternion `[w, x, y, z]` of the accumulated turn (world coordinates).
    turn: [f64; 4],
    zoom: f64,
    /// World offset of eye and reference point.
    pan: [f64; 3],
    /// Eye-space depth of the volume's centre at the start (for the pan's scale in perspective).
    centre_depth: f64,
    height: usize,
}

impl Orbit {
    /// Starts from `view` (given a camera if it has none) for an image of `width × height`.
    pub fn new(view: &View, vol: &Volume, width: usize, height: usize) -> Result<Orbit, String> {
        let bbox = vol.mesh.bbox();
        let model = view
            .model(bbox.center())
            .ok_or("view: the volume transform is singular")?;
        let to_eye = view.view_matrix().after(&model);
        let centre = to_eye.apply(bbox.center());
        let mut start = view.clone();
        if start.camera.is_none() {
            let radius = vol
                .mesh
                .nodes()
                .iter()
                .map(|&p| norm(sub(to_eye.apply(p), centre)))
                .fold(0.0f64, f64::max)
                .max(1e-300);
            let aspect = width as f64 / height as f64;
            let half_h = 1.05 * radius * if aspect >= 1.0 { 1.0 } else { 1.0 / aspect };
            let half_w = half_h * aspect;
            start.camera = Some(Camera::Ortho {
                left: centre[0] - half_w,
                right: centre[0] + half_w,
                bottom: centre[1] - half_h,
                top: centre[1] + half_h,
                front: -centre[2] - 1.01 * radius,
                back: -centre[2] + 1.01 * radius,
            });
        }
        Ok(Orbit {
            start,
            turn: [1.0, 0.0, 0.0, 0.0],
            zoom: 1.0,
            pan: [0.0; 3],
            centre_depth: -centre[2],
            height,
        })
    }

    /// The camera's right and up axes in world coordinates.
    fn axes(&self) -> ([f64; 3], [f64; 3]) {
        let m = self.start.view_matrix().0;
        ([m[0][0], m[0][1], m[0][2]], [m[1][0], m[1][1], m[1][2]])
    }

    /// A drag by `(dx, dy)` pixels (x right, y down): the volume's near side follows the mouse.
    pub fn rotate(&mut self, dx: f64, dy: f64) {
        let (right, up) = self.axes();
        let axis = [0, 1, 2].map(|k| up[k] * dx + right[k] * dy);
        let length = norm(axis);
        if length == 0.0 {
            return;
        }
        let half = 0.5 * (length * DEGREES_PER_PIXEL).to_radians();
        let (s, c) = half.sin_cos();
        let d = [
            c,
            s * axis[0] / length,
            s * axis[1] / length,
            s * axis[2] / length,
        ];
        self.turn = normalize(mul(d, self.turn));
    }

    /// Zooms in by `factor` (> 1) or out (< 1).
    pub fn zoom_by(&mut self, factor: f64) {
        if factor.is_finite() && factor > 0.0 {
            self.zoom = (self.zoom * factor).clamp(1e-3, 1e4);
        }
    }

    /// A shift-drag by `(dx, dy)` pixels: the picture follows the mouse.
    pub fn pan(&mut self, dx: f64, dy: f64) {
        let per_pixel = match self.start.camera {
            Some(Camera::Ortho { bottom, top, .. }) => (top - bottom) / self.zoom,
            Some(Camera::Persp { fovy, .. }) => {
                2.0 * self.centre_depth.abs() * (0.5 * fovy.to_radians()).tan() / self.zoom
            }
            None => 0.0,
        } / self.height as f64;
        let (right, up) = self.axes();
        for k in 0..3 {
            self.pan[k] += per_pixel * (-dx * right[k] + dy * up[k]);
        }
    }

    /// Back to the view the viewer started with.
    pub fn reset(&mut self) {
        self.turn = [1.0, 0.0, 0.0, 0.0];
        self.zoom = 1.0;
        self.pan = [0.0; 3];
    }

    /// The accumulated turn as `vol_rotate`'s axis and degrees (`None`: no turn).
    pub fn rotation(&self) -> Option<([f64; 3], f64)> {
        let [w, x, y, z] = self.turn;
        let s = (x * x + y * y + z * z).sqrt();
        if s == 0.0 {
            return None;
        }
        Some(([x, y, z], 2.0 * s.atan2(w).to_degrees()))
    }

    /// The view to render.
    pub fn view(&self) -> View {
        let mut v = self.start.clone();
        if let Some((axis, degrees)) = self.rotation() {
            v.transforms.push(TransformOp::Rotate { axis, degrees });
        }
        let LookAt { eye, reference, up } = v.look_at;
        v.look_at = LookAt {
            eye: [0, 1, 2].map(|k| eye[k] + self.pan[k]),
            reference: [0, 1, 2].map(|k| reference[k] + self.pan[k]),
            up,
        };
        v.camera = match v.camera {
            Some(Camera::Ortho {
                left,
                right,
                bottom,
                top,
                front,
                back,
            }) => {
                let (cx, cy) = (0.5 * (left + right), 0.5 * (bottom + top));
                let (hw, hh) = (
                    0.5 * (right - left) / self.zoom,
                    0.5 * (top - bottom) / self.zoom,
                );
                Some(Camera::Ortho {
                    left: cx - hw,
                    right: cx + hw,
                    bottom: cy - hh,
                    top: cy + hh,
                    front,
                    back,
                })
            }
            Some(Camera::Persp {
                fovy,
                aspect,
                near,
                far,
            }) => Some(Camera::Persp {
                fovy: 2.0
                    * ((0.5 * fovy.to_radians()).tan() / self.zoom)
                        .atan()
                        .to_degrees(),
                aspect,
                near,
                far,
            }),
            None => None,
        };
        v
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Quaternion product `a ⊗ b` (b's turn first, then a's).
fn mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let (av, bv) = ([a[1], a[2], a[3]], [b[1], b[2], b[3]]);
    let c = cross(av, bv);
    [
        a[0] * b[0] - dot(av, bv),
        a[0] * bv[0] + b[0] * av[0] + c[0],
        a[0] * bv[1] + b[0] * av[1] + c[1],
        a[0] * bv[2] + b[0] * av[2] + c[2],
    ]
}

fn normalize(q: [f64; 4]) -> [f64; 4] {
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    q.map(|v| v / n)
}
#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Volume {
        vorang::volume::jittered_box(48, 0.0, 1)
    }

    #[test]
    fn a_drag_turns_the_near_side_with_the_mouse_about_the_centre() {
        let vol = unit_box();
        let mut o = Orbit::new(&View::default(), &vol, 100, 100).unwrap();
        assert_eq!(o.rotation(), None);
        o.rotate(180.0, 0.0); // 90° about the screen's up axis (y)
        let (axis, deg) = o.rotation().unwrap();
        assert!((deg - 90.0).abs() < 1e-9, "{deg}");
        assert!(axis[0].abs() < 1e-12 && axis[1] > 0.0 && axis[2].abs() < 1e-12);
        // The near side (+z, towards the default eye looking along −z) moves to the right.
        let r = vorang::scene::Affine::rotation(axis, deg).unwrap();
        let p = r.apply([0.0, 0.0, 1.0]);
        assert!((p[0] - 1.0).abs() < 1e-9, "{p:?}");
        // Two turns compose; reset forgets them.
        o.rotate(0.0, 180.0);
        assert!(o.rotation().unwrap().1 > 90.0);
        o.reset();
        assert_eq!(o.rotation(), None);
    }

    #[test]
    fn zoom_and_pan_change_the_camera_window_and_the_eye() {
        let vol = unit_box();
        let mut o = Orbit::new(&View::default(), &vol, 200, 100).unwrap();
        let Some(Camera::Ortho {
            left,
            right,
            top,
            bottom,
            ..
        }) = o.view().camera
        else {
            panic!("an orthographic camera")
        };
        assert!(
            ((right - left) / (top - bottom) - 2.0).abs() < 1e-12,
            "the image's aspect"
        );
        o.zoom_by(2.0);
        let Some(Camera::Ortho {
            left: l2,
            right: r2,
            ..
        }) = o.view().camera
        else {
            panic!()
        };
        assert!(((r2 - l2) * 2.0 - (right - left)).abs() < 1e-12);
        o.pan(10.0, 0.0);
        let v = o.view();
        // Dragging right moves the picture right: the eye moves left.
        assert!(v.look_at.eye[0] < 0.0 && v.look_at.reference[0] < 0.0);
        assert!(((top - bottom) / 2.0 / 100.0 * 10.0 + v.look_at.eye[0]).abs() < 1e-12);
    }

    #[test]
    fn a_perspective_camera_zooms_by_its_field_of_view_and_pans_at_the_centre_depth() {
        let vol = unit_box();
        let view = View {
            look_at: LookAt {
                eye: [0.0, 0.0, 4.0],
                reference: [0.0; 3],
                up: [0.0, 1.0, 0.0],
            },
            camera: Some(Camera::Persp {
                fovy: 40.0,
                aspect: 1.0,
                near: 1.0,
                far: 10.0,
            }),
            ..View::default()
        };
        let mut o = Orbit::new(&view, &vol, 100, 100).unwrap();
        assert_eq!(o.view(), view, "no input: the session's view");
        o.zoom_by(2.0);
        let Some(Camera::Persp { fovy, .. }) = o.view().camera else {
            panic!()
        };
        let t = (20f64.to_radians().tan() / 2.0).atan().to_degrees() * 2.0;
        assert!((fovy - t).abs() < 1e-12, "{fovy} {t}");
        o.pan(0.0, 100.0);
        // A drag over the whole height moves the eye up by the height seen at the centre's
        // depth (4): 2·4·tan(fovy/2).
        let up = o.view().look_at.eye[1];
        assert!(
            (up - 8.0 * (0.5 * t.to_radians()).tan()).abs() < 1e-9,
            "{up}"
        );
    }
}
