//! Cameras and pixel rays (docs/camera.md). Pixel (i, j) has its centre at screen position
//! (i + ½, j + ½), i left → right, j top → bottom.

use crate::error::Error;

/// `ortho_camera` or `persp_camera` as given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Camera {
    /// `ortho_camera l r b t front back`: x_eye ∈ [l, r], y_eye ∈ [b, t], depth ∈ [front, back].
    Ortho {
        left: f64,
        right: f64,
        bottom: f64,
        top: f64,
        front: f64,
        back: f64,
    },
    /// `persp_camera fovy aspect near far`: vertical field of view in degrees, width/height of
    /// the view, depth ∈ [near, far].
    Persp {
        fovy: f64,
        aspect: f64,
        near: f64,
        far: f64,
    },
}

impl Camera {
    /// Checks the parameters; the message names what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            Camera::Ortho {
                left,
                right,
                bottom,
                top,
                front,
                back,
            } => {
                if [left, right, bottom, top, front, back]
                    .iter()
                    .any(|v| !v.is_finite())
                {
                    return Err("ortho_camera: all six values must be finite numbers".into());
                }
                if left >= right || bottom >= top {
                    return Err(format!(
                        "ortho_camera: expected left < right and bottom < top, found {left} {right} {bottom} {top}"
                    ));
                }
                if front >= back {
                    return Err(format!(
                        "ortho_camera: expected front < back, found front {front}, back {back}"
                    ));
                }
                Ok(())
            }
            Camera::Persp {
                fovy,
                aspect,
                near,
                far,
            } => {
                if !(fovy > 0.0 && fovy < 180.0) {
                    return Err(format!(
                        "persp_camera: the field of view must lie between 0 and 180 degrees, found {fovy}"
                    ));
                }
                if !(aspect > 0.0 && aspect.is_finite()) {
                    return Err(format!(
                        "persp_camera: the aspect ratio must be positive, found {aspect}"
                    ));
                }
                if !(near > 0.0 && near.is_finite()) {
                    return Err(format!(
                        "persp_camera: near must be > 0 (a distance in front of the eye), found {near}"
                    ));
                }
                if far.is_nan() || far <= near {
                    return Err(format!(
                        "persp_camera: far must be greater than near, found near {near}, far {far}"
                    ));
                }
                Ok(())
            }
        }
    }
}

/// Node positions on screen are rounded to multiples of this (in pixels): 2⁻²⁸ px (4·10⁻⁹ px),
/// far finer than anything an image shows and still ~10⁴ times coarser than what rounding in a
/// chain of transforms moves a node (~10⁻¹³ px per rotation at 1000 px). A view
/// that is degenerate up to rounding — an axis view after `vol_rotate 0 1 0 90`, an animation
/// turned a full circle in steps — then puts the nodes at exactly the positions of the exactly
/// degenerate view, and every method renders it as that one: the edge-on faces of a structured
/// mesh stay edge-on instead of becoming slivers whose crossing depth is pure rounding. Moving a
/// node by at most 2⁻²⁹ px keeps every accuracy-report scene within 6·10⁻⁸ of the reference
/// (with 2⁻²⁰ px a grazing perspective silhouette was off by 2·10⁻⁶).
pub const SUBPIXEL: f64 = 1.0 / 268435456.0;

/// `v` rounded to the nearest multiple of [`SUBPIXEL`] (unchanged where the float grid is
/// already coarser, or not finite).
#[inline]
pub fn snap(v: f64) -> f64 {
    let scaled = v * (1.0 / SUBPIXEL);
    if scaled.abs() < 4503599627370496.0 {
        // Round half away from zero without a library call: exact for |scaled| < 2⁵².
        let t = scaled as i64 as f64;
        let r = scaled - t;
        let t = if r >= 0.5 {
            t + 1.0
        } else if r <= -0.5 {
            t - 1.0
        } else {
            t
        };
        t * SUBPIXEL
    } else {
        v
    }
}

/// A ray in eye space: `origin + τ·dir`, with `dir.z = −1` so that τ is the depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: [f64; 3],
    pub dir: [f64; 3],
}

impl Ray {
    /// World length of a unit of τ.
    pub fn speed(&self) -> f64 {
        (self.dir[0] * self.dir[0] + self.dir[1] * self.dir[1] + 1.0).sqrt()
    }
}

/// The rays of a [`Projector`] as affine functions of the screen position: component `k` of
/// the ray through (x, y) is `c[k][0] + c[k][1]·x + c[k][2]·y` for origin and direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayPlanes {
    pub origin: [[f64; 3]; 3],
    pub dir: [[f64; 3]; 3],
    /// The largest `|dir|` over the image (at its corners).
    pub max_speed: f64,
}

/// The camera resolved for an image size: rays of pixels and projection of eye points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projector {
    Ortho {
        left: f64,
        right: f64,
        bottom: f64,
        top: f64,
        depth: (f64, f64),
        width: f64,
        height: f64,
    },
    Persp {
        tan_x: f64,
        tan_y: f64,
        depth: (f64, f64),
        width: f64,
        height: f64,
    },
}

impl Projector {
    /// `camera` = `None` is the default orthographic camera: the x/y extents of the centred,
    /// untransformed grid's bounding box (`size`), and no depth clipping — the ray is the whole
    /// line (docs/camera.md).
    pub fn new(
        camera: Option<&Camera>,
        size: [f64; 3],
        width: usize,
        height: usize,
    ) -> Result<Projector, Error> {
        let (w, h) = (width as f64, height as f64);
        Ok(match camera {
            None => Projector::Ortho {
                left: -0.5 * size[0],
                right: 0.5 * size[0],
                bottom: -0.5 * size[1],
                top: 0.5 * size[1],
                depth: (f64::NEG_INFINITY, f64::INFINITY),
                width: w,
                height: h,
            },
            Some(c) => {
                c.validate().map_err(Error::Invalid)?;
                match *c {
                    Camera::Ortho {
                        left,
                        right,
                        bottom,
                        top,
                        front,
                        back,
                    } => Projector::Ortho {
                        left,
                        right,
                        bottom,
                        top,
                        depth: (front, back),
                        width: w,
                        height: h,
                    },
                    Camera::Persp {
                        fovy,
                        aspect,
                        near,
                        far,
                    } => {
                        let tan_y = (0.5 * fovy).to_radians().tan();
                        Projector::Persp {
                            tan_x: tan_y * aspect,
                            tan_y,
                            depth: (near, far),
                            width: w,
                            height: h,
                        }
                    }
                }
            }
        })
    }

    pub fn is_perspective(&self) -> bool {
        matches!(self, Projector::Persp { .. })
    }

    /// The depth range rays are clipped to.
    pub fn depth(&self) -> (f64, f64) {
        match *self {
            Projector::Ortho { depth, .. } | Projector::Persp { depth, .. } => depth,
        }
    }

    /// The ray through screen position `(x, y)` (pixel centres at `i + ½`).
    #[inline]
    pub fn ray_at(&self, x: f64, y: f64) -> Ray {
        match *self {
            Projector::Ortho {
                left,
                right,
                bottom,
                top,
                width,
                height,
                ..
            } => Ray {
                origin: [
                    left + x * (right - left) / width,
                    top - y * (top - bottom) / height,
                    0.0,
                ],
                dir: [0.0, 0.0, -1.0],
            },
            Projector::Persp {
                tan_x,
                tan_y,
                width,
                height,
                ..
            } => {
                let xn = 2.0 * x / width - 1.0;
                let yn = 1.0 - 2.0 * y / height;
                Ray {
                    origin: [0.0; 3],
                    dir: [xn * tan_x, yn * tan_y, -1.0],
                }
            }
        }
    }

    /// The rays of all screen positions at once: the origin and direction of the ray through
    /// (x, y) (as in [`Projector::ray_at`]) are affine functions of x and y. Lets a cell compute
    /// where every pixel's ray meets it from a few coefficients.
    pub fn ray_planes(&self) -> RayPlanes {
        match *self {
            Projector::Ortho {
                left,
                right,
                bottom,
                top,
                width,
                height,
                ..
            } => {
                let (sx, sy) = ((right - left) / width, (top - bottom) / height);
                RayPlanes {
                    origin: [[left, sx, 0.0], [top, 0.0, -sy], [0.0; 3]],
                    dir: [[0.0; 3], [0.0; 3], [-1.0, 0.0, 0.0]],
                    max_speed: 1.0,
                }
            }
            Projector::Persp {
                tan_x,
                tan_y,
                width,
                height,
                ..
            } => RayPlanes {
                origin: [[0.0; 3]; 3],
                dir: [
                    [-tan_x, 2.0 * tan_x / width, 0.0],
                    [tan_y, 0.0, -2.0 * tan_y / height],
                    [-1.0, 0.0, 0.0],
                ],
                max_speed: (1.0 + tan_x * tan_x + tan_y * tan_y).sqrt(),
            },
        }
    }

    /// The ray of pixel (i, j).
    #[inline]
    pub fn ray(&self, i: usize, j: usize) -> Ray {
        self.ray_at(i as f64 + 0.5, j as f64 + 0.5)
    }

    /// Screen position of an eye-space point (for perspective it must lie in front of the eye,
    /// depth > 0), on the sub-pixel grid [`SUBPIXEL`].
    #[inline]
    pub fn screen(&self, p: [f64; 3]) -> [f64; 2] {
        self.screen_exact(p).map(snap)
    }

    /// [`Projector::screen`] before snapping to the sub-pixel grid.
    #[inline]
    pub fn screen_exact(&self, p: [f64; 3]) -> [f64; 2] {
        match *self {
            Projector::Ortho {
                left,
                right,
                bottom,
                top,
                width,
                height,
                ..
            } => [
                (p[0] - left) / (right - left) * width,
                (top - p[1]) / (top - bottom) * height,
            ],
            Projector::Persp {
                tan_x,
                tan_y,
                width,
                height,
                ..
            } => {
                let d = -p[2];
                [
                    (p[0] / (d * tan_x) + 1.0) * 0.5 * width,
                    (1.0 - p[1] / (d * tan_y)) * 0.5 * height,
                ]
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapping_removes_rounding_and_nothing_else() {
        assert_eq!(snap(5.999999999999998), 6.0);
        assert_eq!(snap(-3.0000000000000004), -3.0);
        assert_eq!(snap(0.5 + 3.0 * SUBPIXEL + 1e-13), 0.5 + 3.0 * SUBPIXEL);
        assert!((snap(10.0 / 3.0) - 10.0 / 3.0).abs() <= 0.5 * SUBPIXEL);
        assert_eq!(snap(1e30), 1e30);
        assert!(snap(f64::NAN).is_nan());
        assert_eq!(snap(f64::INFINITY), f64::INFINITY);
    }

    #[test]
    fn ray_planes_are_the_rays() {
        for cam in [
            Camera::Ortho {
                left: -2.0,
                right: 1.5,
                bottom: -1.0,
                top: 1.3,
                front: 0.0,
                back: 9.0,
            },
            Camera::Persp {
                fovy: 50.0,
                aspect: 1.4,
                near: 0.1,
                far: 9.0,
            },
        ] {
            let p = Projector::new(Some(&cam), [1.0; 3], 40, 30).unwrap();
            let planes = p.ray_planes();
            let mut fastest = 0.0f64;
            for (x, y) in [
                (0.0, 0.0),
                (40.0, 0.0),
                (0.0, 30.0),
                (40.0, 30.0),
                (13.5, 7.25),
            ] {
                let r = p.ray_at(x, y);
                let at = |c: &[[f64; 3]; 3], k: usize| c[k][0] + c[k][1] * x + c[k][2] * y;
                for k in 0..3 {
                    assert!((at(&planes.origin, k) - r.origin[k]).abs() < 1e-14);
                    assert!((at(&planes.dir, k) - r.dir[k]).abs() < 1e-14);
                }
                fastest = fastest.max(r.speed());
            }
            assert!((planes.max_speed - fastest).abs() < 1e-14);
        }
    }

    #[test]
    fn pixel_centres_follow_the_spec() {
        let p = Projector::new(
            Some(&Camera::Ortho {
                left: -2.0,
                right: 2.0,
                bottom: -1.0,
                top: 1.0,
                front: 0.0,
                back: 9.0,
            }),
            [0.0; 3],
            4,
            2,
        )
        .unwrap();
        let r = p.ray(0, 0);
        assert_eq!(r.origin, [-1.5, 0.5, 0.0]);
        assert_eq!(p.ray(3, 1).origin, [1.5, -0.5, 0.0]);
        assert_eq!(p.screen([-1.5, 0.5, -3.0]), [0.5, 0.5]);
        let q = Projector::new(
            Some(&Camera::Persp {
                fovy: 90.0,
                aspect: 2.0,
                near: 1.0,
                far: 10.0,
            }),
            [0.0; 3],
            4,
            2,
        )
        .unwrap();
        let r = q.ray(0, 0);
        // x_n = −1 + 2·0.5/4 = −0.75, y_n = 1 − 2·0.5/2 = 0.5; tan 45° = 1.
        assert!(
            (r.dir[0] + 1.5).abs() < 1e-12 && (r.dir[1] - 0.5).abs() < 1e-12 && r.dir[2] == -1.0
        );
        let s = q.screen([r.dir[0] * 3.0, r.dir[1] * 3.0, -3.0]);
        assert!((s[0] - 0.5).abs() < 1e-12 && (s[1] - 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_default_camera_sees_the_whole_line() {
        let p = Projector::new(None, [2.0, 1.0, 1.0], 512, 256).unwrap();
        assert_eq!(p.depth(), (f64::NEG_INFINITY, f64::INFINITY));
        assert_eq!(p.ray(0, 0).origin[0], -1.0 + 0.5 * 2.0 / 512.0);
    }

    #[test]
    fn bad_cameras_are_refused() {
        assert!(
            Camera::Persp {
                fovy: 40.0,
                aspect: 1.0,
                near: 0.0,
                far: 1.0
            }
            .validate()
            .is_err()
        );
        assert!(
            Camera::Persp {
                fovy: 40.0,
                aspect: 1.0,
                near: 2.0,
                far: 1.0
            }
            .validate()
            .is_err()
        );
        assert!(
            Camera::Persp {
                fovy: 180.0,
                aspect: 1.0,
                near: 1.0,
                far: 2.0
            }
            .validate()
            .is_err()
        );
        assert!(
            Camera::Ortho {
                left: 1.0,
                right: 0.0,
                bottom: 0.0,
                top: 1.0,
                front: 0.0,
                back: 1.0
            }
            .validate()
            .is_err()
        );
    }
}
