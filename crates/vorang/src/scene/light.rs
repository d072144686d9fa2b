//! Lights (`addlight`, `removelight`; thesis 1.1, 2.2.1.5, appendix A) and the shading they give
//! the colour method `LIT_EMITTER`.
//!
//! The thesis reserved lights — a default light at the camera until the user adds one — for a
//! colormap shading method it never wrote. The Decision fixes that method: the emission of a
//! SIMPLE_EMITTER table is scaled per channel by a Phong-like factor
//!
//! ```text
//! η = table(f) × (ka + Σ_lights colour × (kd·max(0, n·l) + ks·max(0, n·h)^shininess))
//! ```
//!
//! with `n = −∇f/|∇f|` the unit normal of the data field's level sets, pointing towards falling
//! values; `l` the unit vector towards the light (lights sit at infinity, so `l` is the same
//! everywhere); `h = (l + v)/|l + v|` the half vector with the unit vector `v` towards the
//! viewer. A zero gradient leaves `ka` alone.
//!
//! Everything is in world coordinates (docs/camera.md: after centring and the `vol_*` operations): a
//! gradient computed in the file's coordinates is carried over by the inverse transpose of the
//! model transform's linear part, so that normals stay normal to level sets under non-uniform
//! scales and mirrors. `v` is the camera's viewing direction turned towards the viewer, the
//! same for every point (a viewer at infinity, as OpenGL's default light model), so for a
//! Linear field the factor is one constant per cell and `exact linear 0` stays exact.

use super::transform::{cross, dot, norm, sub};
use super::{Affine, View};

/// A light from `addlight r g b rx ry rz`: colour and the direction from the origin towards
/// the light, which sits at infinity (world coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    pub color: [f64; 3],
    pub direction: [f64; 3],
}

/// The parameter line of `LIT_EMITTER`: `ka kd ks shininess`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phong {
    pub ka: f64,
    pub kd: f64,
    pub ks: f64,
    pub shininess: f64,
}

/// One light as the shading uses it: colour, unit vector `l` towards it, half vector `h`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Beam {
    color: [f64; 3],
    l: [f64; 3],
    /// `None` where the light shines straight at the viewer from behind the volume (`l = −v`):
    /// the half vector is undefined and the highlight is dropped.
    h: Option<[f64; 3]>,
}

/// The lights of one frame in world coordinates, with the transform that carries gradients
/// from file to world coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Lighting {
    beams: Vec<Beam>,
    /// `(A⁻¹)ᵀ` for the model transform's linear part `A` (row-major): maps a gradient in file
    /// coordinates to the gradient in world coordinates.
    normal_matrix: [[f64; 3]; 3],
}

fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(v);
    (n > 0.0 && n.is_finite()).then(|| v.map(|x| x / n))
}

impl Lighting {
    /// The lighting of a frame: the user's lights, or — when there are none — one white light
    /// at the camera, shining from the eye towards the volume's centre (`bbox_centre` is the
    /// file's bounding-box centre). Where the eye sits at the centre (the default `look_at`
    /// with an orthographic camera), the light comes from the viewer's side along the viewing
    /// direction. `None` if the model transform is singular.
    pub fn new(lights: &[Light], view: &View, bbox_centre: [f64; 3]) -> Option<Lighting> {
        let model = view.model(bbox_centre)?;
        let towards_viewer = view.view_matrix().0[2];
        let v = [towards_viewer[0], towards_viewer[1], towards_viewer[2]];
        let default;
        let lights = if lights.is_empty() {
            let centre = model.apply(bbox_centre);
            let from_eye = sub(view.look_at.eye, centre);
            let scale = norm(centre).max(norm(view.look_at.eye)).max(1.0);
            let direction = if norm(from_eye) > 1e-12 * scale {
                from_eye
            } else {
                v
            };
            default = [Light {
                color: [1.0; 3],
                direction,
            }];
            &default[..]
        } else {
            lights
        };
        let beams = lights
            .iter()
            .filter_map(|light| {
                let l = unit(light.direction)?;
                Some(Beam {
                    color: light.color,
                    l,
                    h: unit([l[0] + v[0], l[1] + v[1], l[2] + v[2]]),
                })
            })
            .collect();
        Some(Lighting {
            beams,
            normal_matrix: normal_matrix(&model)?,
        })
    }

    /// The factor `ka + Σ colour × (kd·max(0, n·l) + ks·max(0, n·h)^shininess)` per channel for
    /// a field whose gradient at the point is `gradient` (file coordinates); `ka` alone where
    /// the gradient is zero (or not finite).
    pub fn factor(&self, phong: &Phong, gradient: [f64; 3]) -> [f64; 3] {
        let g = [0, 1, 2].map(|i| dot(self.normal_matrix[i], gradient));
        let mut f = [phong.ka; 3];
        let Some(n) = unit(g.map(|x| -x)) else {
            return f;
        };
        for b in &self.beams {
            let diffuse = phong.kd * dot(n, b.l).max(0.0);
            let specular = match b.h {
                Some(h) if phong.ks != 0.0 => phong.ks * dot(n, h).max(0.0).powf(phong.shininess),
                _ => 0.0,
            };
            for c in 0..3 {
                f[c] += b.color[c] * (diffuse + specular);
            }
        }
        f
    }
}

/// `(A⁻¹)ᵀ` of the linear part of `m`, or `None` if it is singular.
fn normal_matrix(m: &Affine) -> Option<[[f64; 3]; 3]> {
    let rows = m.0.map(|r| [r[0], r[1], r[2]]);
    let det = dot(rows[0], cross(rows[1], rows[2]));
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    // The inverse's columns are the cross products of the rows over det, so the transpose of
    // the inverse has them as rows.
    let c = [
        cross(rows[1], rows[2]),
        cross(rows[2], rows[0]),
        cross(rows[0], rows[1]),
    ];
    Some(c.map(|r| r.map(|x| x / det)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{LookAt, TransformOp};

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12)
    }

    #[test]
    fn the_normal_matrix_keeps_normals_normal_to_level_sets() {
        // f = x + 2y in file coordinates; after a non-uniform scale and a rotation, the world
        // gradient must be orthogonal to every world vector that f does not change along.
        let view = View {
            transforms: vec![
                TransformOp::Scale([2.0, 0.5, 3.0]),
                TransformOp::Rotate {
                    axis: [1.0, 1.0, 0.0],
                    degrees: 30.0,
                },
                TransformOp::Scale([-1.0, 1.0, 1.0]),
            ],
            ..View::default()
        };
        let model = view.model([0.0; 3]).unwrap();
        let nm = normal_matrix(&model).unwrap();
        let g = [1.0, 2.0, 0.0];
        let gw = [0, 1, 2].map(|i| dot(nm[i], g));
        for along in [[2.0, -1.0, 0.0], [0.0, 0.0, 1.0]] {
            assert!(dot(gw, model.apply_vector(along)).abs() < 1e-12);
        }
        // And it measures the change: f(p + d) − f(p) = ∇f·d in both coordinate systems.
        let d = [0.3, -0.2, 0.7];
        assert!((dot(gw, model.apply_vector(d)) - dot(g, d)).abs() < 1e-12);
    }

    #[test]
    fn the_default_light_sits_at_the_camera() {
        let mut view = View::default();
        let lit = Lighting::new(&[], &view, [5.0, 5.0, 5.0]).unwrap();
        // Default look_at: eye at the (centred) volume's centre, looking along −z: the light
        // comes from +z, and with the viewer there too the half vector is +z.
        assert_eq!(lit.beams.len(), 1);
        assert!(close(lit.beams[0].l, [0.0, 0.0, 1.0]));
        assert!(close(lit.beams[0].h.unwrap(), [0.0, 0.0, 1.0]));
        view.look_at = LookAt {
            eye: [3.0, 0.0, 4.0],
            reference: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
        };
        let lit = Lighting::new(&[], &view, [5.0, 5.0, 5.0]).unwrap();
        assert!(close(lit.beams[0].l, [0.6, 0.0, 0.8]));
        // A user light replaces it.
        let red = Light {
            color: [1.0, 0.0, 0.0],
            direction: [0.0, 2.0, 0.0],
        };
        let lit = Lighting::new(&[red], &view, [5.0, 5.0, 5.0]).unwrap();
        assert_eq!(lit.beams.len(), 1);
        assert!(close(lit.beams[0].l, [0.0, 1.0, 0.0]));
    }

    #[test]
    fn the_factor_is_phong_of_the_falling_gradient() {
        let view = View::default();
        let light = Light {
            color: [1.0, 0.5, 0.25],
            direction: [-1.0, 0.0, 0.0],
        };
        let lit = Lighting::new(&[light], &view, [0.0; 3]).unwrap();
        let p = Phong {
            ka: 0.1,
            kd: 0.6,
            ks: 0.3,
            shininess: 4.0,
        };
        // f rises along +x: n = −x̂ points at the light (n·l = 1); h = (−1, 0, 1)/√2, n·h = 1/√2.
        let s = 0.6 + 0.3 * 0.25;
        let want = [0.1 + s, 0.1 + 0.5 * s, 0.1 + 0.25 * s];
        assert!(close(lit.factor(&p, [2.0, 0.0, 0.0]), want));
        // Falling along +x: the light is behind the surface, no diffuse, no highlight.
        assert!(close(lit.factor(&p, [-2.0, 0.0, 0.0]), [0.1; 3]));
        // Across the light: n·l = 0, n·h = 0.
        assert!(close(lit.factor(&p, [0.0, 3.0, 0.0]), [0.1; 3]));
        // No gradient: ambient only.
        assert!(close(lit.factor(&p, [0.0; 3]), [0.1; 3]));
    }
}
