//! An independent reference renderer for tests and the accuracy report: a deliberately simple
//! brute-force ray caster in f64.
//!
//! Every pixel ray is intersected with every cell; the intervals are sorted by depth and each is
//! integrated by adaptive Gauss–Legendre quadrature of the optical model of docs/optics.md — the
//! optical depth by an inner quadrature at every outer node — to a tolerance near machine
//! precision. It shares no code with the projection renderer except the mesh, the fields and the
//! maps: transforms, camera rays and ray–cell intersection are written again here (with 4×4
//! homogeneous matrices and Cramer's rule) from the conventions of docs/camera.md. Only for tiny meshes
//! and images: the cost is pixels × cells.

use rayon::prelude::*;

use crate::framebuffer::Background;
use crate::mapping::Mapping;
use crate::scene::{Camera, LookAt, TransformOp, View};
use crate::volume::Volume;

type M4 = [[f64; 4]; 4];

fn identity() -> M4 {
    let mut m = [[0.0; 4]; 4];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    m
}

fn mul(a: &M4, b: &M4) -> M4 {
    let mut m = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            m[i][j] = (0..4).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

fn point(m: &M4, p: [f64; 3]) -> [f64; 3] {
    let h = [p[0], p[1], p[2], 1.0];
    std::array::from_fn(|i| (0..4).map(|k| m[i][k] * h[k]).sum())
}

fn vector(m: &M4, v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| (0..3).map(|k| m[i][k] * v[k]).sum())
}

fn translate(t: [f64; 3]) -> M4 {
    let mut m = identity();
    for k in 0..3 {
        m[k][3] = t[k];
    }
    m
}

/// Rotation by `deg` about `axis` (right-handed), built from the two-reflection form
/// `v ↦ v cos + (a×v) sin + a (a·v)(1 − cos)` applied to the basis vectors.
fn rotate(axis: [f64; 3], deg: f64) -> M4 {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let a = axis.map(|v| v / n);
    let (s, c) = (deg * std::f64::consts::PI / 180.0).sin_cos();
    let mut m = identity();
    for j in 0..3 {
        let mut e = [0.0; 3];
        e[j] = 1.0;
        let axv = [
            a[1] * e[2] - a[2] * e[1],
            a[2] * e[0] - a[0] * e[2],
            a[0] * e[1] - a[1] * e[0],
        ];
        let adv = a[j];
        for i in 0..3 {
            m[i][j] = e[i] * c + axv[i] * s + a[i] * adv * (1.0 - c);
        }
    }
    m
}

/// File → world, following docs/camera.md literally: centre, then each operation; a rotation is about
/// the image of the file's bounding-box centre under everything before it.
fn model(view: &View, centre: [f64; 3]) -> M4 {
    let mut m = translate(centre.map(|c| -c));
    for op in &view.transforms {
        let step = match *op {
            TransformOp::Scale(s) => {
                let mut k = identity();
                for i in 0..3 {
                    k[i][i] = s[i];
                }
                k
            }
            TransformOp::Translate(t) => translate(t),
            TransformOp::Rotate { axis, degrees } => {
                let pivot = point(&m, centre);
                mul(
                    &translate(pivot),
                    &mul(&rotate(axis, degrees), &translate(pivot.map(|v| -v))),
                )
            }
        };
        m = mul(&step, &m);
    }
    m
}

/// Eye → world for `look_at` (the camera's basis as columns).
fn camera_to_world(l: &LookAt) -> M4 {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let unit = |v: [f64; 3]| {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / n)
    };
    let mut back = sub(l.eye, l.reference);
    if back == [0.0; 3] {
        back = [0.0, 0.0, 1.0];
    }
    let z = unit(back);
    // Gram–Schmidt: the up vector minus its part along z.
    let d = l.up[0] * z[0] + l.up[1] * z[1] + l.up[2] * z[2];
    let mut y = [l.up[0] - d * z[0], l.up[1] - d * z[1], l.up[2] - d * z[2]];
    if (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt() < 1e-12 {
        y = cross(z, cross([0.0, 1.0, 0.0], z));
        if (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt() < 1e-12 {
            y = cross(z, cross([1.0, 0.0, 0.0], z));
        }
    }
    let y = unit(y);
    let x = cross(y, z);
    let mut m = identity();
    for i in 0..3 {
        m[i][0] = x[i];
        m[i][1] = y[i];
        m[i][2] = z[i];
        m[i][3] = l.eye[i];
    }
    m
}

/// Gauss–Legendre nodes and weights on [0, 1] (10 points, exact for degree 19).
pub const GL: [(f64, f64); 10] = {
    // Abscissae and weights on [−1, 1], mapped to [0, 1].
    const X: [f64; 5] = [
        0.148_874_338_981_631_2,
        0.433_395_394_129_247_2,
        0.679_409_568_299_024_4,
        0.865_063_366_688_984_5,
        0.973_906_528_517_171_7,
    ];
    const W: [f64; 5] = [
        0.295_524_224_714_752_9,
        0.269_266_719_309_996_4,
        0.219_086_362_515_982,
        0.149_451_349_150_580_6,
        0.066_671_344_308_688_1,
    ];
    let mut out = [(0.0, 0.0); 10];
    let mut i = 0;
    while i < 5 {
        out[2 * i] = (0.5 - 0.5 * X[i], 0.5 * W[i]);
        out[2 * i + 1] = (0.5 + 0.5 * X[i], 0.5 * W[i]);
        i += 1;
    }
    out
};

/// One cell crossed by a ray, in world space.
struct Crossing {
    cell: usize,
    /// Entry and exit parameter along the ray (the parameter is the eye-space depth).
    t0: f64,
    t1: f64,
    /// λ(t) = l0 + t·dl.
    l0: [f64; 4],
    dl: [f64; 4],
}

/// What to render besides the volume, maps and view.
#[derive(Debug, Clone)]
pub struct Options {
    pub width: usize,
    pub height: usize,
    pub background: Background,
    /// The brightness factor B.
    pub brightness: f64,
    /// The absolute error aimed at per cell interval.
    pub tolerance: f64,
    /// The lights for `LIT_EMITTER` (none: the default light at the camera). The lighting
    /// factor itself is the mapping's ([`crate::scene::Lighting`]), not re-derived here.
    pub lights: Vec<crate::scene::Light>,
}

impl Options {
    /// White background, B = 1, tolerance 1e-13.
    pub fn new(width: usize, height: usize) -> Options {
        Options {
            width,
            height,
            background: Background::default(),
            brightness: 1.0,
            tolerance: 1e-13,
            lights: Vec::new(),
        }
    }
}

/// Barycentric functions of a cell: gradients and constants.
type Bary = ([[f64; 3]; 4], [f64; 4]);

/// Renders `vol` with the optical model, without grid lines: RGBA per pixel, row-major.
pub fn render(vol: &Volume, mapping: &Mapping, view: &View, opts: &Options) -> Vec<[f64; 4]> {
    let (width, height, brightness, tolerance) =
        (opts.width, opts.height, opts.brightness, opts.tolerance);
    let background = &opts.background;
    let mesh = &vol.mesh;
    let bbox = mesh.bbox();
    let lit;
    let mapping = match crate::scene::Lighting::new(&opts.lights, view, bbox.center()) {
        Some(lighting) if mapping.is_lit() => {
            lit = mapping.lit(lighting);
            &lit
        }
        _ => mapping,
    };
    let to_world = model(view, bbox.center());
    let world: Vec<[f64; 3]> = mesh.nodes().iter().map(|&p| point(&to_world, p)).collect();
    let cam = camera_to_world(&view.look_at);
    // Barycentric functions per cell in world space, by Cramer's rule.
    let bary: Vec<Option<Bary>> = mesh
        .tets()
        .iter()
        .map(|t| {
            let p = t.map(|n| world[n as usize]);
            let e = [1, 2, 3].map(|i| [0, 1, 2].map(|k| p[i][k] - p[0][k]));
            let det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1])
                - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
                + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
            if det == 0.0 {
                return None;
            }
            // Rows of the inverse of the matrix with columns e1, e2, e3.
            let cof = |a: [f64; 3], b: [f64; 3]| {
                [
                    a[1] * b[2] - a[2] * b[1],
                    a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0],
                ]
            };
            let g1 = cof(e[1], e[2]).map(|v| v / det);
            let g2 = cof(e[2], e[0]).map(|v| v / det);
            let g3 = cof(e[0], e[1]).map(|v| v / det);
            let g0 = [0, 1, 2].map(|k| -(g1[k] + g2[k] + g3[k]));
            let g = [g0, g1, g2, g3];
            let h = [0, 1, 2, 3].map(|i| 1.0 - (0..3).map(|k| g[i][k] * p[i][k]).sum::<f64>());
            Some((g, h))
        })
        .collect();
    let (size, bg) = (
        bbox.size(),
        background
            .pixels(width, height)
            .expect("the reference renders small images"),
    );
    // Eye-space ray of a pixel per docs/camera.md, and its depth range.
    let eye_ray = |i: usize, j: usize| -> ([f64; 3], [f64; 3], f64, f64) {
        let (u, v) = (
            (i as f64 + 0.5) / width as f64,
            (j as f64 + 0.5) / height as f64,
        );
        match view.camera {
            None => {
                let (l, r, b, t) = (-size[0] / 2.0, size[0] / 2.0, -size[1] / 2.0, size[1] / 2.0);
                (
                    [l + u * (r - l), t - v * (t - b), 0.0],
                    [0.0, 0.0, -1.0],
                    f64::NEG_INFINITY,
                    f64::INFINITY,
                )
            }
            Some(Camera::Ortho {
                left,
                right,
                bottom,
                top,
                front,
                back,
            }) => (
                [left + u * (right - left), top - v * (top - bottom), 0.0],
                [0.0, 0.0, -1.0],
                front,
                back,
            ),
            Some(Camera::Persp {
                fovy,
                aspect,
                near,
                far,
            }) => {
                let ty = (fovy * std::f64::consts::PI / 360.0).tan();
                (
                    [0.0; 3],
                    [(2.0 * u - 1.0) * ty * aspect, (1.0 - 2.0 * v) * ty, -1.0],
                    near,
                    far,
                )
            }
        }
    };
    (0..width * height)
        .into_par_iter()
        .map(|pix| {
            let (i, j) = (pix % width, pix / width);
            let (o, d, dmin, dmax) = eye_ray(i, j);
            let (o, d) = (point(&cam, o), vector(&cam, d));
            let speed = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let mut hits = Vec::new();
            for (cell, b) in bary.iter().enumerate() {
                let Some((g, h)) = b else { continue };
                let l0: [f64; 4] = std::array::from_fn(|k| {
                    g[k][0] * o[0] + g[k][1] * o[1] + g[k][2] * o[2] + h[k]
                });
                let dl: [f64; 4] =
                    std::array::from_fn(|k| g[k][0] * d[0] + g[k][1] * d[1] + g[k][2] * d[2]);
                let (mut t0, mut t1) = (dmin, dmax);
                let mut empty = false;
                for k in 0..4 {
                    if dl[k] == 0.0 {
                        empty |= l0[k] < 0.0;
                    } else if dl[k] > 0.0 {
                        t0 = t0.max(-l0[k] / dl[k]);
                    } else {
                        t1 = t1.min(-l0[k] / dl[k]);
                    }
                }
                if !empty && t0 < t1 {
                    hits.push(Crossing {
                        cell,
                        t0,
                        t1,
                        l0,
                        dl,
                    });
                }
            }
            // Far to near.
            hits.sort_by(|a, b| b.t0.total_cmp(&a.t0));
            let mut intensity = bg[pix];
            let mut transparency = 1.0;
            for h in &hits {
                let (b, theta) = cell_integral(vol, mapping, h, speed, tolerance);
                for c in 0..3 {
                    intensity[c] = intensity[c] * theta + brightness * b[c];
                }
                transparency *= theta;
            }
            [intensity[0], intensity[1], intensity[2], 1.0 - transparency]
        })
        .collect()
}

/// `(b, θ)` of one crossing: b = ∫ η(s)·exp(−∫_near^s χ) ds, θ = exp(−∫χ), s in world units.
fn cell_integral(
    vol: &Volume,
    mapping: &Mapping,
    h: &Crossing,
    speed: f64,
    tol: f64,
) -> ([f64; 3], f64) {
    let mut buf = vec![0.0; mapping.width()];
    let tets = vol.mesh.tets()[h.cell];
    let nodes = vol.mesh.nodes();
    let mut sample = |t: f64| -> ([f64; 3], f64) {
        let l: [f64; 4] = std::array::from_fn(|k| h.l0[k] + t * h.dl[k]);
        let mut pos = [0.0; 3];
        for (k, &n) in tets.iter().enumerate() {
            for c in 0..3 {
                pos[c] += l[k] * nodes[n as usize][c];
            }
        }
        mapping.sample_fields(vol, h.cell, &l, pos, &mut buf);
        mapping.eval(&buf, h.cell, pos)
    };
    // Split at the map's breakpoints (field values at the ends; exact for fields linear along
    // the ray, harmless otherwise), then adapt.
    let mut cuts = vec![0.0, 1.0];
    {
        let mut ends = Vec::new();
        let mut values = [vec![0.0; mapping.width()], vec![0.0; mapping.width()]];
        for (k, t) in [h.t0, h.t1].into_iter().enumerate() {
            let l: [f64; 4] = std::array::from_fn(|q| h.l0[q] + t * h.dl[q]);
            let mut pos = [0.0; 3];
            for (q, &n) in tets.iter().enumerate() {
                for c in 0..3 {
                    pos[c] += l[q] * nodes[n as usize][c];
                }
            }
            mapping.sample_fields(vol, h.cell, &l, pos, &mut values[k]);
        }
        mapping.cuts(&values[0], &values[1], &mut ends);
        cuts.extend(ends.into_iter().filter(|u| *u > 0.0 && *u < 1.0));
        cuts.sort_by(f64::total_cmp);
    }
    // Near to far: accumulate b = Σ b_k·exp(−τ before k), θ = exp(−Σ τ_k).
    let mut b = [0.0; 3];
    let mut tau = 0.0f64;
    for w in cuts.windows(2) {
        let (a, z) = (h.t0 + w[0] * (h.t1 - h.t0), h.t0 + w[1] * (h.t1 - h.t0));
        let (pb, pt) = adaptive(&mut sample, a, z, speed, tol, 0);
        for c in 0..3 {
            b[c] += (-tau).exp() * pb[c];
        }
        tau += pt;
    }
    (b, (-tau).exp())
}

/// On [a, z] (a nearer): (∫ η e^{−∫_a^s χ} ds, ∫ χ ds), by 10-point Gauss–Legendre with the
/// optical depth at each node by an inner 10-point rule, refined by bisection.
fn adaptive(
    f: &mut impl FnMut(f64) -> ([f64; 3], f64),
    a: f64,
    z: f64,
    speed: f64,
    tol: f64,
    depth: u32,
) -> ([f64; 3], f64) {
    let whole = panel(f, a, z, speed);
    let m = 0.5 * (a + z);
    let (left, right) = (panel(f, a, m, speed), panel(f, m, z, speed));
    let split = combine(left, right);
    let err = (0..3)
        .map(|c| (whole.0[c] - split.0[c]).abs())
        .fold((whole.1 - split.1).abs(), f64::max);
    if err <= tol || depth >= 40 || (z - a).abs() <= 1e-14 * (a.abs() + z.abs()) {
        return split;
    }
    let l = adaptive(f, a, m, speed, tol * 0.5, depth + 1);
    let r = adaptive(f, m, z, speed, tol * 0.5, depth + 1);
    combine(l, r)
}

/// A near panel followed by a far one.
fn combine(near: ([f64; 3], f64), far: ([f64; 3], f64)) -> ([f64; 3], f64) {
    let att = (-near.1).exp();
    (
        [0, 1, 2].map(|c| near.0[c] + att * far.0[c]),
        near.1 + far.1,
    )
}

fn panel(
    f: &mut impl FnMut(f64) -> ([f64; 3], f64),
    a: f64,
    z: f64,
    speed: f64,
) -> ([f64; 3], f64) {
    let len = (z - a) * speed;
    let mut b = [0.0; 3];
    let mut tau = 0.0;
    for &(x, w) in &GL {
        let s = a + x * (z - a);
        let (eta, chi) = f(s);
        tau += w * chi * len;
        // Optical depth from a to s.
        let inner: f64 = GL
            .iter()
            .map(|&(y, v)| v * f(a + y * (s - a)).1)
            .sum::<f64>()
            * (s - a)
            * speed;
        for c in 0..3 {
            b[c] += w * eta[c] * (-inner).exp() * len;
        }
    }
    (b, tau)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        for p in 0..20 {
            let s: f64 = GL.iter().map(|&(x, w)| w * x.powi(p)).sum();
            assert!(
                (s - 1.0 / (p as f64 + 1.0)).abs() < 1e-14,
                "degree {p}: {s}"
            );
        }
    }

    #[test]
    fn nested_quadrature_of_a_homogeneous_slab() {
        // η = 2, χ = 3 over length 0.7: b = η/χ (1 − e^{−χL}).
        let mut f = |_t: f64| ([2.0, 2.0, 2.0], 3.0);
        let (b, tau) = adaptive(&mut f, 0.0, 0.7, 1.0, 1e-14, 0);
        assert!((tau - 2.1).abs() < 1e-14);
        assert!((b[0] - 2.0 / 3.0 * (1.0 - (-2.1f64).exp())).abs() < 1e-14);
        // Linear χ = 1 + 4t, η = t on [0, 1]: compare with a fine midpoint sum.
        let mut g = |t: f64| ([t, t, t], 1.0 + 4.0 * t);
        let (b, tau) = adaptive(&mut g, 0.0, 1.0, 1.0, 1e-14, 0);
        assert!((tau - 3.0).abs() < 1e-14);
        let n = 200_000;
        let brute: f64 = (0..n)
            .map(|k| {
                let t = (k as f64 + 0.5) / n as f64;
                t * (-(t + 2.0 * t * t)).exp() / n as f64
            })
            .sum();
        assert!((b[0] - brute).abs() < 1e-10, "{} vs {brute}", b[0]);
    }
}
