//! Shirley–Tuchman classification of a projected tetrahedron (thesis 2.2.2.2, fig. 2.8).
//!
//! | class | projection | triangles | thick point T |
//! |---|---|---|---|
//! | 1a, 1b | a triangle with the fourth vertex inside (1a: that vertex is in front of the opposite face, 1b: behind) | 3 | the inner vertex |
//! | 2 | a convex quadrilateral: two edges cross | 4 | the crossing |
//! | 3a, 3b | a triangle with the fourth vertex on an edge (a face seen edge-on) | 2 | that vertex |
//! | 4 | two vertices coincide (an edge along the view) | 1 | the coinciding vertices |
//!
//! The projection is split into triangles that all share T, where the depth of the cell is
//! largest. Orientation tests are exact (Shewchuk's predicates), so the class is decided
//! consistently even for degenerate views.

use crate::mesh::orientation;
use crate::predicates::orient_sign as sign;

/// The projection class.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ProjClass {
    OneA,
    OneB,
    Two,
    ThreeA,
    ThreeB,
    Four,
    /// All four vertices on a line: the projection has no area.
    Flat,
}

impl ProjClass {
    pub fn name(self) -> &'static str {
        match self {
            ProjClass::OneA => "1a",
            ProjClass::OneB => "1b",
            ProjClass::Two => "2",
            ProjClass::ThreeA => "3a",
            ProjClass::ThreeB => "3b",
            ProjClass::Four => "4",
            ProjClass::Flat => "flat",
        }
    }
}

/// For each node, the other three in increasing order (the face opposite it).
const OTHERS: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];

/// Marks the thick point T as a triangle vertex (0…3 are the cell's nodes).
pub const THICK: u8 = 4;

/// A classified projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    pub class: ProjClass,
    /// Screen position of the thick point T.
    pub thick: [f64; 2],
    /// The node that T coincides with (classes 1, 3, 4).
    pub thick_node: Option<usize>,
    /// Triangles over the projection, vertices 0…3 (nodes) or [`THICK`].
    pub triangles: [[u8; 3]; 4],
    pub count: usize,
}

/// Where the ray through the thick point T enters and leaves the cell: each end's barycentric
/// coordinates and depth, the nearer end first ([`Projection::thick_ends`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThickEnds {
    pub near: ([f64; 4], f64),
    pub far: ([f64; 4], f64),
}

impl Projection {
    /// The ends of the cell's thickest ray, from the classification itself: T is a node (classes
    /// 1, 3, 4), whose ray leaves through the opposite face at T's barycentric coordinates in
    /// that face's projection; or the crossing of two edges (class 2), at their parameters
    /// there. Screen-space weights become the cell's own by the perspective correction
    /// `(μ_n/d_n) / Σ μ_m/d_m` (d the nodes' depths). The same points as intersecting that ray
    /// with the cell's four face planes (as [`crate::render::cell::EyeCell::interval`] does, up
    /// to rounding; tested), at a fraction of the cost: no inverse of the cell's Jacobian, no
    /// divisions per face. `s` and `eye`: the nodes' screen and eye positions the projection
    /// was classified from. `None` for a flat projection, or a zero area in floating point.
    pub fn thick_ends(
        &self,
        s: &[[f64; 2]; 4],
        eye: &[[f64; 3]; 4],
        perspective: bool,
    ) -> Option<ThickEnds> {
        let depth = eye.map(|p| -p[2]);
        let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
        let sub = |a: [f64; 2], b: [f64; 2]| [a[0] - b[0], a[1] - b[1]];
        // Screen-affine weights `mu` of nodes `at` as the cell's barycentric coordinates, and
        // the depth there.
        let end = |at: &[usize], mu: &[f64]| -> ([f64; 4], f64) {
            let mut lambda = [0.0; 4];
            if perspective {
                let total: f64 = at.iter().zip(mu).map(|(&n, &m)| m / depth[n]).sum();
                for (&n, &m) in at.iter().zip(mu) {
                    lambda[n] = m / depth[n] / total;
                }
            } else {
                for (&n, &m) in at.iter().zip(mu) {
                    lambda[n] = m;
                }
            }
            let d = at.iter().map(|&n| lambda[n] * depth[n]).sum();
            (lambda, d)
        };
        let (a, b) = match (self.class, self.thick_node) {
            (ProjClass::Flat, _) => return None,
            (ProjClass::Two, _) => {
                // Triangles [a, c, T], [c, b, T], [b, d, T], [d, a, T]: edges ab and cd cross.
                let t = &self.triangles;
                let node = |v: u8| usize::from(v);
                let (a, c, b, d) = (node(t[0][0]), node(t[0][1]), node(t[1][1]), node(t[2][1]));
                let (p, r) = (s[a], sub(s[b], s[a]));
                let (q, w) = (s[c], sub(s[d], s[c]));
                let denom = cross(r, w);
                if denom == 0.0 {
                    return None;
                }
                let t = cross(sub(q, p), w) / denom;
                let u = cross(sub(q, p), r) / denom;
                (end(&[a, b], &[1.0 - t, t]), end(&[c, d], &[1.0 - u, u]))
            }
            (_, Some(i)) => {
                let [j, k, l] = OTHERS[i];
                let tp = s[i];
                let area = cross(sub(s[k], s[j]), sub(s[l], s[j]));
                if area == 0.0 {
                    return None;
                }
                let mj = cross(sub(s[k], tp), sub(s[l], tp)) / area;
                let mk = cross(sub(s[l], tp), sub(s[j], tp)) / area;
                (end(&[i], &[1.0]), end(&[j, k, l], &[mj, mk, 1.0 - mj - mk]))
            }
            (_, None) => return None,
        };
        Some(if a.1 <= b.1 {
            ThickEnds { near: a, far: b }
        } else {
            ThickEnds { near: b, far: a }
        })
    }
}

/// Is node `i` nearer to the viewer than the plane of the other three? (`eye` in eye space.)
fn in_front(eye: &[[f64; 3]; 4], i: usize, others: [usize; 3], perspective: bool) -> bool {
    let [j, k, l] = others.map(|n| eye[n]);
    let node_side = orientation(j, k, l, eye[i]);
    let viewer_side = if perspective {
        orientation(j, k, l, [0.0; 3])
    } else {
        // The viewer at +∞ z: the side is the sign of the plane normal's z component.
        (k[0] - j[0]) * (l[1] - j[1]) - (k[1] - j[1]) * (l[0] - j[0])
    };
    node_side * viewer_side > 0.0
}

/// Classifies the projection of a cell with screen positions `s` and eye positions `eye`.
///
/// Every decision is the sign of the orientation of three of the four screen positions. There
/// are only four such triples; each is computed once ([`Orientations`]) and every other order of
/// its points is a permutation of it (the sign is exact, so it flips exactly with an odd
/// permutation). Deciding from those four instead of asking the predicate for every triple
/// again (up to 28 calls) gives the same classes for less work.
pub fn classify(s: &[[f64; 2]; 4], eye: &[[f64; 3]; 4], perspective: bool) -> Projection {
    let o = Orientations::new(s);
    classify_with(|a, b, c| o.sign(a, b, c), s, eye, perspective)
}

/// The signs of the orientations of the four triples of a cell's screen positions.
struct Orientations {
    /// `omit[m]`: the sign for the three nodes other than `m`, in increasing order.
    omit: [i8; 4],
}

impl Orientations {
    fn new(s: &[[f64; 2]; 4]) -> Orientations {
        Orientations {
            omit: [
                sign(s[1], s[2], s[3]),
                sign(s[0], s[2], s[3]),
                sign(s[0], s[1], s[3]),
                sign(s[0], s[1], s[2]),
            ],
        }
    }

    /// The sign for the distinct nodes `a`, `b`, `c` in that order: the increasing order's,
    /// flipped by an odd permutation.
    #[inline]
    fn sign(&self, a: usize, b: usize, c: usize) -> i8 {
        let s = self.omit[6 - a - b - c];
        let inversions = (a > b) as u8 + (a > c) as u8 + (b > c) as u8;
        if inversions.is_multiple_of(2) { s } else { -s }
    }
}

/// [`classify`] with `sign(a, b, c)` the sign of the orientation of the screen positions of
/// nodes `a`, `b`, `c`.
fn classify_with(
    sign: impl Fn(usize, usize, usize) -> i8,
    s: &[[f64; 2]; 4],
    eye: &[[f64; 3]; 4],
    perspective: bool,
) -> Projection {
    let mut out = Projection {
        class: ProjClass::Flat,
        thick: s[0],
        thick_node: None,
        triangles: [[0; 3]; 4],
        count: 0,
    };
    // A vertex inside, on an edge of, or on a vertex of the triangle of the other three.
    for i in 0..4 {
        let [j, k, l] = OTHERS[i];
        let area = sign(j, k, l);
        if area == 0 {
            continue;
        }
        let e = [sign(j, k, i), sign(k, l, i), sign(l, j, i)];
        if e.contains(&-area) {
            continue;
        }
        let zeros = e.iter().filter(|&&x| x == 0).count();
        let (jj, kk, ll) = (j as u8, k as u8, l as u8);
        out.thick = s[i];
        out.thick_node = Some(i);
        let front = in_front(eye, i, [j, k, l], perspective);
        match zeros {
            0 => {
                out.class = if front {
                    ProjClass::OneA
                } else {
                    ProjClass::OneB
                };
                out.triangles = [[jj, kk, THICK], [kk, ll, THICK], [ll, jj, THICK], [0; 3]];
                out.count = 3;
            }
            1 => {
                // On the edge whose orientation is zero: (j,k), (k,l) or (l,j).
                let (a, b, c) = match e.iter().position(|&x| x == 0) {
                    Some(0) => (jj, kk, ll),
                    Some(1) => (kk, ll, jj),
                    _ => (ll, jj, kk),
                };
                out.class = if front {
                    ProjClass::ThreeA
                } else {
                    ProjClass::ThreeB
                };
                out.triangles = [[a, THICK, c], [THICK, b, c], [0; 3], [0; 3]];
                out.count = 2;
            }
            _ => {
                // Coincides with one of j, k, l: the triangle of the three distinct points.
                let same = match e {
                    [0, _, 0] => jj,
                    [0, 0, _] => kk,
                    _ => ll,
                };
                let rest: Vec<u8> = [jj, kk, ll].into_iter().filter(|&v| v != same).collect();
                out.class = ProjClass::Four;
                out.triangles = [[THICK, rest[0], rest[1]], [0; 3], [0; 3], [0; 3]];
                out.count = 1;
            }
        }
        return out;
    }
    // A convex quadrilateral: find the two crossing edges (the diagonals).
    for (a, b, c, d) in [(0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2)] {
        let crosses = sign(a, b, c) * sign(a, b, d) < 0 && sign(c, d, a) * sign(c, d, b) < 0;
        if !crosses {
            continue;
        }
        let (p, r) = (s[a], [s[b][0] - s[a][0], s[b][1] - s[a][1]]);
        let (q, u) = (s[c], [s[d][0] - s[c][0], s[d][1] - s[c][1]]);
        let denom = r[0] * u[1] - r[1] * u[0];
        let t = ((q[0] - p[0]) * u[1] - (q[1] - p[1]) * u[0]) / denom;
        out.class = ProjClass::Two;
        out.thick = [p[0] + t * r[0], p[1] + t * r[1]];
        let (a, b, c, d) = (a as u8, b as u8, c as u8, d as u8);
        // Around the hull: a, c, b, d.
        out.triangles = [[a, c, THICK], [c, b, THICK], [b, d, THICK], [d, a, THICK]];
        out.count = 4;
        return out;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The thick point's ray ends from the classification against intersecting the ray through
    /// T with the cell's face planes ([`crate::render::cell::EyeCell::interval`]): the same
    /// depths and barycentric coordinates, for random cells of every class with a thick point,
    /// orthographic and perspective.
    #[test]
    fn thick_ends_are_where_the_ray_through_t_crosses_the_faces() {
        use crate::render::cell::EyeCell;
        use crate::scene::Ray;
        let mut rng = crate::mesh::generate::SplitMix64(0x1234_5678_9abc_def1);
        let mut next = || rng.next_f64();
        let mut compared = std::collections::HashMap::new();
        for round in 0..20_000 {
            let perspective = round % 2 == 1;
            let eye: [[f64; 3]; 4] =
                std::array::from_fn(|_| [next() * 2.0 - 1.0, next() * 2.0 - 1.0, -3.0 - next()]);
            let s = if perspective {
                eye.map(|p| [p[0] / -p[2], -p[1] / -p[2]])
            } else {
                eye.map(|p| [p[0], -p[1]])
            };
            let proj = classify(&s, &eye, perspective);
            let (Some(ends), Some(cell)) =
                (proj.thick_ends(&s, &eye, perspective), EyeCell::new(&eye))
            else {
                continue;
            };
            let [x, y] = proj.thick;
            let ray = if perspective {
                Ray {
                    origin: [0.0; 3],
                    dir: [x, -y, -1.0],
                }
            } else {
                Ray {
                    origin: [x, -y, 0.0],
                    dir: [0.0, 0.0, -1.0],
                }
            };
            // Skip the rays the face planes settle badly (a face almost along the ray).
            let Some(iv) = cell.interval(&ray) else {
                continue;
            };
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + a.abs());
            assert!(close(ends.near.1, iv.near), "{eye:?}: {ends:?} vs {iv:?}");
            assert!(close(ends.far.1, iv.far), "{eye:?}: {ends:?} vs {iv:?}");
            let (ln, lf) = (iv.lambda(iv.near), iv.lambda(iv.far));
            for n in 0..4 {
                assert!(close(ends.near.0[n], ln[n]), "{eye:?}: {ends:?} vs {ln:?}");
                assert!(close(ends.far.0[n], lf[n]), "{eye:?}: {ends:?} vs {lf:?}");
            }
            *compared.entry((proj.class, perspective)).or_insert(0) += 1;
        }
        for class in [ProjClass::OneA, ProjClass::OneB, ProjClass::Two] {
            for perspective in [false, true] {
                let n = compared.get(&(class, perspective)).copied().unwrap_or(0);
                assert!(
                    n > 1000,
                    "{class:?} perspective {perspective}: {n} compared"
                );
            }
        }
    }

    /// Every class decided with the predicate asked afresh for each triple, as before the four
    /// orientations were shared: the same projection, bit for bit, on random cells and on cells
    /// whose nodes lie on a coarse grid (collinear and coinciding points: every degenerate
    /// class).
    #[test]
    fn shared_orientations_decide_as_the_predicate_per_triple() {
        let mut rng = crate::mesh::generate::SplitMix64(0x9e37_79b9_7f4a_7c15);
        let mut next = || rng.next_f64();
        let mut classes = std::collections::HashSet::new();
        for round in 0..100_000 {
            let eye: [[f64; 3]; 4] = std::array::from_fn(|_| {
                std::array::from_fn(|k| {
                    let r = next();
                    let v = if round % 2 == 0 {
                        (r * 3.0).floor()
                    } else {
                        r * 4.0 - 2.0
                    };
                    if k == 2 { v - 5.0 } else { v }
                })
            });
            for perspective in [false, true] {
                let s = if perspective {
                    eye.map(|p| [p[0] / -p[2], -p[1] / -p[2]])
                } else {
                    eye.map(|p| [p[0], -p[1]])
                };
                let per_triple = |a: usize, b: usize, c: usize| sign(s[a], s[b], s[c]);
                let want = classify_with(per_triple, &s, &eye, perspective);
                let got = classify(&s, &eye, perspective);
                assert_eq!(got, want, "{eye:?} perspective {perspective}");
                classes.insert(got.class);
            }
        }
        assert_eq!(classes.len(), 7, "every class met: {classes:?}");
    }

    /// Orthographic: screen = (x, −y) of eye space (any fixed affine map would do).
    fn ortho(eye: [[f64; 3]; 4]) -> Projection {
        let s = eye.map(|p| [p[0], -p[1]]);
        classify(&s, &eye, false)
    }

    #[test]
    fn every_class_is_recognised() {
        // A vertex straight in front of / behind the centre of a face.
        let base = [[0.0, 0.0, -5.0], [3.0, 0.0, -5.0], [0.0, 3.0, -5.0]];
        let c = ortho([base[0], base[1], base[2], [1.0, 1.0, -4.0]]);
        assert_eq!(
            (c.class, c.count, c.thick_node),
            (ProjClass::OneA, 3, Some(3))
        );
        let c = ortho([base[0], base[1], base[2], [1.0, 1.0, -6.0]]);
        assert_eq!(c.class, ProjClass::OneB);
        // Two crossing edges.
        let c = ortho([
            [0.0, 0.0, -5.0],
            [2.0, 2.0, -5.0],
            [2.0, 0.0, -4.0],
            [0.0, 2.0, -4.0],
        ]);
        assert_eq!((c.class, c.count), (ProjClass::Two, 4));
        assert!((c.thick[0] - 1.0).abs() < 1e-15 && (c.thick[1] + 1.0).abs() < 1e-15);
        // A vertex over an edge.
        let c = ortho([base[0], base[1], base[2], [1.5, 0.0, -4.0]]);
        assert_eq!((c.class, c.count), (ProjClass::ThreeA, 2));
        let c = ortho([base[0], base[1], base[2], [1.5, 0.0, -6.0]]);
        assert_eq!(c.class, ProjClass::ThreeB);
        // An edge along the view direction.
        let c = ortho([base[0], base[1], base[2], [0.0, 0.0, -7.0]]);
        assert_eq!((c.class, c.count), (ProjClass::Four, 1));
        // Everything on one line.
        let c = ortho([
            [0.0, 0.0, -1.0],
            [1.0, 0.0, -2.0],
            [2.0, 0.0, -3.0],
            [3.0, 0.0, -1.0],
        ]);
        assert_eq!((c.class, c.count), (ProjClass::Flat, 0));
    }

    #[test]
    fn perspective_front_and_back_use_the_eye() {
        // Eye at the origin looking down −z: the inner vertex nearer to the eye is class 1a.
        let base = [[-1.0, -1.0, -5.0], [2.0, -1.0, -5.0], [-1.0, 2.0, -5.0]];
        let near = [0.0, 0.0, -3.0];
        let eye = [base[0], base[1], base[2], near];
        let s = eye.map(|p| [p[0] / -p[2], -p[1] / -p[2]]);
        assert_eq!(classify(&s, &eye, true).class, ProjClass::OneA);
        let far = [0.0, 0.0, -8.0];
        let eye = [base[0], base[1], base[2], far];
        let s = eye.map(|p| [p[0] / -p[2], -p[1] / -p[2]]);
        assert_eq!(classify(&s, &eye, true).class, ProjClass::OneB);
    }
}
