//! The Rust twins of the WGSL functions (`wgsl/*.wgsl`): the same operations in the same
//! order, so that on a device that rounds every f64 operation as IEEE 754 says and contracts
//! nothing (lavapipe) each gives the shader's bits — the GPU tests hold them to it. Where the
//! device has a true fused multiply-add, the exact products use it (`fma`), else Veltkamp's
//! split; both give the same exact product.
//!
//! Each function names its shader twin; the comments on the algorithms are in the shaders.
//! Comparisons keep the shaders' form, NaN behaviour included (`!(x > y)` is not `x <= y`).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::mesh::{FACE_NODES, NO_NEIGHBOR};

pub mod color;

/// `hi + lo`, nonoverlapping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dd {
    pub hi: f64,
    pub lo: f64,
}

/// `two_sum`.
#[inline]
pub fn two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    let bb = s - a;
    Dd {
        hi: s,
        lo: (a - (s - bb)) + (b - bb),
    }
}

/// `two_diff`.
#[inline]
pub fn two_diff(a: f64, b: f64) -> Dd {
    let x = a - b;
    let bv = a - x;
    let av = x + bv;
    let br = bv - b;
    let ar = a - av;
    Dd { hi: x, lo: ar + br }
}

/// `split`.
#[inline]
fn split(a: f64) -> Dd {
    let c = 134217729.0 * a;
    let big = c - a;
    let hi = c - big;
    Dd { hi, lo: a - hi }
}

/// `two_prod`.
#[inline]
pub fn two_prod(a: f64, b: f64, fma: bool) -> Dd {
    let p = a * b;
    if fma {
        return Dd {
            hi: p,
            lo: a.mul_add(b, -p),
        };
    }
    let (sa, sb) = (split(a), split(b));
    let err1 = p - sa.hi * sb.hi;
    let err2 = err1 - sa.lo * sb.hi;
    let err3 = err2 - sa.hi * sb.lo;
    Dd {
        hi: p,
        lo: sa.lo * sb.lo - err3,
    }
}

fn sign_of(x: f64) -> i32 {
    (x > 0.0) as i32 - (x < 0.0) as i32
}

/// `orient`: the exact sign of the orientation of three points on the sub-pixel grid.
pub fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2], fma: bool) -> i32 {
    let l = two_prod(a[0] - c[0], b[1] - c[1], fma);
    let r = two_prod(a[1] - c[1], b[0] - c[0], fma);
    let t0 = two_diff(l.lo, r.lo);
    let t1 = two_sum(l.hi, t0.hi);
    let t2 = two_diff(t1.lo, r.hi);
    let t3 = two_sum(t1.hi, t2.hi);
    for x in [t3.hi, t3.lo, t2.lo] {
        if x != 0.0 {
            return sign_of(x);
        }
    }
    sign_of(t0.lo)
}

/// `owns`: the top-left rule.
fn owns(u: [f64; 2], v: [f64; 2]) -> bool {
    let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
    dy < 0.0 || (dy == 0.0 && dx > 0.0)
}

/// `inside`.
pub fn inside(u: [f64; 2], v: [f64; 2], p: [f64; 2], fma: bool) -> bool {
    let e = orient(u, v, p, fma);
    e > 0 || (e == 0 && owns(u, v))
}

/// `Corner`: a face's node on screen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corner {
    pub p: [f64; 2],
    /// Depth (orthographic) or inverse depth (perspective).
    pub z: f64,
    /// The field at the node.
    pub v: f64,
    pub id: u32,
}

/// `clamp_select`.
fn clamp_select(x: f64, lo: f64, hi: f64) -> f64 {
    let m = if x > lo { x } else { lo };
    if m < hi { m } else { hi }
}

fn dd_add(a: Dd, b: Dd) -> Dd {
    let s = two_sum(a.hi, b.hi);
    let t = s.lo + a.lo + b.lo;
    let q = s.hi + t;
    Dd {
        hi: q,
        lo: t - (q - s.hi),
    }
}

fn dd_mul(a: Dd, b: Dd, fma: bool) -> Dd {
    let p = two_prod(a.hi, b.hi, fma);
    let e = p.lo + (a.hi * b.lo + a.lo * b.hi);
    let q = p.hi + e;
    Dd {
        hi: q,
        lo: e - (q - p.hi),
    }
}

fn dd_neg(a: Dd) -> Dd {
    Dd {
        hi: -a.hi,
        lo: -a.lo,
    }
}

fn dd_cross(u: [f64; 2], v: [f64; 2], p: [f64; 2], fma: bool) -> Dd {
    let l = dd_mul(two_sum(u[0], -p[0]), two_sum(v[1], -p[1]), fma);
    let r = dd_mul(two_sum(u[1], -p[1]), two_sum(v[0], -p[0]), fma);
    dd_add(l, dd_neg(r))
}

fn dd_weight(d: Dd, sign: f64) -> Dd {
    let s = Dd {
        hi: sign * d.hi,
        lo: sign * d.lo,
    };
    if s.hi + s.lo > 0.0 {
        s
    } else {
        Dd { hi: 0.0, lo: 0.0 }
    }
}

/// `face_hit`: `(depth, field value)` on the face through three corners at screen position `p`.
pub fn face_hit(k: [Corner; 3], p: [f64; 2], persp: bool, fma: bool) -> [f64; 2] {
    let mut k = k;
    for (i, j) in [(0, 1), (1, 2), (0, 1)] {
        if k[j].id < k[i].id {
            k.swap(i, j);
        }
    }
    let (a, b, c) = (k[0].p, k[1].p, k[2].p);
    let (z0, z1, z2) = (k[0].z, k[1].z, k[2].z);
    let area = ((a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])).abs();
    let len2 =
        |u: [f64; 2], v: [f64; 2]| (u[0] - v[0]) * (u[0] - v[0]) + (u[1] - v[1]) * (u[1] - v[1]);
    let longest = len2(a, b).max(len2(b, c)).max(len2(c, a));
    let sliver = area.is_nan() || area < 1e-3 * longest;
    let mut f = [k[0].v, k[1].v, k[2].v];
    let vlo = f[0].min(f[1]).min(f[2]);
    let vhi = f[0].max(f[1]).max(f[2]);
    if persp {
        f = [f[0] * z0, f[1] * z1, f[2] * z2];
    }
    if !sliver {
        let zmin = z0.min(z1).min(z2);
        let zmax = z0.max(z1).max(z2);
        let e1 = [b[0] - a[0], b[1] - a[1]];
        let e2 = [c[0] - a[0], c[1] - a[1]];
        let (d1, d2) = (z1 - z0, z2 - z0);
        let det = e1[0] * e2[1] - e1[1] * e2[0];
        let gx = (d1 * e2[1] - d2 * e1[1]) / det;
        let gy = (d2 * e1[0] - d1 * e2[0]) / det;
        let row = (z0 + gy * (p[1] - a[1])) - gx * a[0];
        let z = clamp_select(row + gx * p[0], zmin, zmax);
        let (f1, f2) = (f[1] - f[0], f[2] - f[0]);
        let hx = (f1 * e2[1] - f2 * e1[1]) / det;
        let hy = (f2 * e1[0] - f1 * e2[0]) / det;
        let value = ((f[0] + hy * (p[1] - a[1])) - hx * a[0]) + hx * p[0];
        if persp {
            return [1.0 / z, clamp_select(value / z, vlo, vhi)];
        }
        return [z, clamp_select(value, vlo, vhi)];
    }
    let sign = f64::from(orient(a, b, c, fma));
    let w0 = dd_weight(dd_cross(b, c, p, fma), sign);
    let w1 = dd_weight(dd_cross(c, a, p, fma), sign);
    let w2 = dd_weight(dd_cross(a, b, p, fma), sign);
    let sum = dd_add(dd_add(w0, w1), w2);
    let z_of = |z: f64| Dd { hi: z, lo: 0.0 };
    let num = dd_add(
        dd_add(dd_mul(w0, z_of(z0), fma), dd_mul(w1, z_of(z1), fma)),
        dd_mul(w2, z_of(z2), fma),
    );
    let ws = [w0.hi + w0.lo, w1.hi + w1.lo, w2.hi + w2.lo];
    let wsum = ws[0] + ws[1] + ws[2];
    let (n, d) = if persp { (sum, num) } else { (num, sum) };
    if d.hi + d.lo == 0.0 {
        let mean = (z0 + z1 + z2) / 3.0;
        let vmean = (k[0].v + k[1].v + k[2].v) / 3.0;
        return [if persp { 1.0 / mean } else { mean }, vmean];
    }
    let q = n.hi / d.hi;
    let r = dd_add(n, dd_neg(dd_mul(Dd { hi: q, lo: 0.0 }, d, fma)));
    let depth = q + (r.hi + r.lo) / d.hi;
    let mut value = (ws[0] * f[0] + ws[1] * f[1] + ws[2] * f[2]) / wsum;
    if persp {
        value *= depth;
    }
    if wsum == 0.0 {
        value = (k[0].v + k[1].v + k[2].v) / 3.0;
    }
    [depth, clamp_select(value, vlo, vhi)]
}

/// `exit_face`: the exit face holding `p` of a cell with screen positions `s` (4: none).
pub fn exit_face(s: &[[f64; 2]; 4], entry_sign: i32, p: [f64; 2], fma: bool) -> usize {
    let mut kind = [0i32; 4];
    let mut pos = [[0usize; 3]; 4];
    for f in 0..4 {
        let [l0, l1, l2] = FACE_NODES[f];
        let o = orient(s[l0], s[l1], s[l2], fma);
        kind[f] = o * entry_sign;
        pos[f] = if o >= 0 { [l0, l1, l2] } else { [l0, l2, l1] };
    }
    let last = (0..4).rev().find(|&f| kind[f] < 0).unwrap_or(4);
    for f in 0..4 {
        if kind[f] >= 0 || f == last {
            continue;
        }
        let holds = (0..3).all(|e| {
            let (u, v) = (pos[f][e], pos[f][(e + 1) % 3]);
            let other = 6 - f - u - v;
            kind[other] != kind[f] || inside(s[u], s[v], p, fma)
        });
        if holds {
            return f;
        }
    }
    last
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `NEAR_ENTRY`: a pixel's entry into a near-clipped cell (the cell number with this bit).
pub const NEAR_ENTRY: u32 = 0x8000_0000;
/// `PARALLEL` (render::cell's tolerance for rays parallel to a face plane).
const PARALLEL: f64 = 1e-12;

/// `Line`: a cell's barycentric coordinates `a + τ·b` along a ray, and the tolerances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    pub a: [f64; 4],
    pub b: [f64; 4],
    pub tol: [f64; 4],
}

/// `clip_line`: the near and far depth and the exit face (`render::cell`'s clip).
fn clip_line(line: &Line, infinity: f64) -> Option<(f64, f64, usize)> {
    let (mut near, mut far, mut exit) = (-infinity, infinity, 0);
    for i in 0..4 {
        if line.b[i].abs() <= line.tol[i] {
            if line.a[i] < -1e-9 {
                return None;
            }
            continue;
        }
        let t = -line.a[i] / line.b[i];
        if line.b[i] > 0.0 {
            if t > near {
                near = t;
            }
        } else if t < far {
            far = t;
            exit = i;
        }
    }
    (near < far).then_some((near, far, exit))
}

/// `MAX_DEPTH`: the largest end depth of a segment summed by the series.
pub const MAX_DEPTH: f64 = 0.5;
const MAX_TERMS: u32 = 64;

/// `(b, θ)`.
pub type Contribution = ([f64; 3], f64);

/// `moments`: `(J0, J1, J2, θ)` for end depths `c` (near) and `c + d` (far).
pub fn moments(c: f64, d: f64) -> [f64; 4] {
    let (mut prev, mut q) = (0.0f64, 1.0f64);
    let (mut j0, mut j1, mut j2) = (1.0f64, 0.5f64, 1.0 / 3.0);
    for j in 0..MAX_TERMS {
        let next = (-c * q - d * prev) / f64::from(j + 1);
        j0 += next / f64::from(j + 2);
        j1 += next / f64::from(j + 3);
        j2 += next / f64::from(j + 4);
        prev = q;
        q = next;
        let small = 0.5e-17 * j1;
        if q.abs() <= small && prev.abs() <= small {
            break;
        }
    }
    let theta = (1.0 - (c * j0 + d * j1)).min(1.0);
    [j0, j1, j2, theta]
}

fn thin(near: [f64; 3], p1: [f64; 3], p2: [f64; 3], c: f64, a: f64, l: f64) -> Contribution {
    let m = moments(c, a - c);
    let b = [0, 1, 2].map(|k| l * (near[k] * m[0] + p1[k] * m[1] + p2[k] * m[2]));
    (b, m[3])
}

/// `segment`: the exact linear rule for one segment (η at the far and near end, in the middle
/// where `quadratic`; χ at the far and near end; length `l`).
pub fn segment(
    far: [f64; 3],
    near: [f64; 3],
    mid: [f64; 3],
    quadratic: bool,
    chi_far: f64,
    chi_near: f64,
    l: f64,
) -> Contribution {
    let a = (chi_far * l).max(0.0);
    let c = (chi_near * l).max(0.0);
    let mut p1 = [0, 1, 2].map(|k| far[k] - near[k]);
    let mut p2 = [0.0; 3];
    if quadratic {
        p1 = [0, 1, 2].map(|k| -3.0 * near[k] + 4.0 * mid[k] - far[k]);
        p2 = [0, 1, 2].map(|k| 2.0 * near[k] - 4.0 * mid[k] + 2.0 * far[k]);
    }
    let deepest = a.max(c);
    if !(deepest > MAX_DEPTH) {
        return thin(near, p1, p2, c, a, l);
    }
    let n = (deepest / MAX_DEPTH).ceil();
    let h = 1.0 / n;
    let mut out = ([0.0; 3], 1.0);
    let mut depth = 0.0;
    let count = n as u32;
    for i in 0..count {
        let w0 = f64::from(i) * h;
        let w1 = if i + 1 == count {
            1.0
        } else {
            f64::from(i + 1) * h
        };
        let c0 = (c + (a - c) * w0) * h;
        let c1 = (c + (a - c) * w1) * h;
        let e0 = [0, 1, 2].map(|k| near[k] + p1[k] * w0 + p2[k] * (w0 * w0));
        let s = w1 - w0;
        let q1 = [0, 1, 2].map(|k| (p1[k] + 2.0 * w0 * p2[k]) * s);
        let q2 = [0, 1, 2].map(|k| p2[k] * (s * s));
        let piece = thin(e0, q1, q2, c0, c1, l * h);
        out.0 = [0, 1, 2].map(|k| out.0[k] + out.1 * piece.0[k]);
        out.1 *= piece.1;
        depth += 0.5 * (c0 + c1);
        if depth > 45.0 {
            break;
        }
    }
    out
}

/// The indices into the frame's numbers (`consts` in `march.wgsl`).
pub mod slot {
    pub const WIDTH: usize = 0;
    pub const HEIGHT: usize = 1;
    pub const PERSPECTIVE: usize = 2;
    pub const ENTRY_SIGN: usize = 3;
    pub const FRONT_TO_BACK: usize = 4;
    pub const DMIN: usize = 5;
    pub const DMAX: usize = 6;
    pub const TAN_X: usize = 7;
    pub const TAN_Y: usize = 8;
    pub const BRIGHTNESS: usize = 9;
    pub const WEIGHTED: usize = 10;
    pub const QUADRATIC: usize = 11;
    pub const KNOTS: usize = 12;
    pub const HAS_LINES: usize = 13;
    pub const EXACT_FMA: usize = 14;
    pub const CELLS: usize = 15;
    /// The numbers per node.
    pub const NODE: usize = 16;
    /// 0: `exact linear 0`, 1: `interpolateCoeff linear`, 2: `interpolateColor`.
    pub const METHOD: usize = 17;
    /// The rays' origin rows (9 numbers), then their direction rows (`scene::RayPlanes`).
    pub const PLANES: usize = 18;
    /// `scene::RayPlanes::max_speed`.
    pub const MAX_SPEED: usize = 36;
    /// +∞.
    pub const INFINITY: usize = 37;
    /// The rows of the mesh per binding (set by the device, not read by the twins).
    pub const PART_ROWS: usize = 38;
    /// 1 where some cell reaches in front of the perspective near plane.
    pub const ANY_NEAR: usize = 39;
    /// interpolateColor: where the cells' fans start in the nodes' numbers.
    pub const FANS: usize = 40;
    /// 2: the iterations of `loops_ran`'s loop.
    pub const LOOP_CHECK: usize = 41;
    /// The knots, then per piece `from, base[4], slope[4]`.
    pub const TABLE: usize = 42;
}

/// The cells a pixel's ray passed, as the march writes it where the driver ended its loops
/// early (`loops_ran`): the pixel's colour is then not to be trusted.
pub const LOOPS_CUT: f64 = -1.0;

/// `EARLY_TERMINATION`, `NEGLIGIBLE`.
const EARLY_TERMINATION: f64 = crate::render::EARLY_TERMINATION;
const NEGLIGIBLE: f64 = 1e-20;

/// What one frame's march reads: the buffers of `march.wgsl`.
#[derive(Debug, Clone, Copy)]
pub struct Buffers<'a> {
    /// Per cell: its nodes, then its neighbours.
    pub mesh: &'a [[u32; 4]],
    /// Per node: screen x, y, depth value, field value.
    pub nodes: &'a [f64],
    /// Per pixel offsets, then the boundary entries.
    pub lists: &'a [u32],
    pub lines: &'a [f64],
    pub consts: &'a [f64],
}

impl Buffers<'_> {
    fn flag(&self, i: usize) -> bool {
        self.consts[i] != 0.0
    }

    fn knot_count(&self) -> usize {
        self.consts[slot::KNOTS] as usize
    }

    fn knot(&self, i: usize) -> f64 {
        self.consts[slot::TABLE + i]
    }

    /// `piece_of`: the number of knots `≤ s`, by bisection.
    pub fn piece_of(&self, s: f64) -> usize {
        self.knots_where(|x| x <= s)
    }

    /// `knots_below`: the number of knots `< s`, by bisection.
    pub fn knots_below(&self, s: f64) -> usize {
        self.knots_where(|x| x < s)
    }

    /// How many of the increasing knots have `holds`, which holds for a first stretch of them
    /// (the bisection loop of `piece_of` and `knots_below`, which WGSL writes out twice).
    fn knots_where(&self, holds: impl Fn(f64) -> bool) -> usize {
        let (mut lo, mut hi) = (0, self.knot_count());
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if holds(self.knot(mid)) {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// `eval_in`.
    fn eval_in(&self, p: usize, s: f64) -> [f64; 4] {
        let k = self.knot_count();
        let pieces = if k == 0 { 1 } else { k + 1 };
        let at = slot::TABLE + k + 9 * p.min(pieces - 1);
        let c = self.consts;
        let d = s - c[at];
        let r = [0, 1, 2, 3].map(|i| c[at + 1 + i] + d * c[at + 5 + i]);
        if self.flag(slot::WEIGHTED) {
            [r[0] * r[3], r[1] * r[3], r[2] * r[3], r[3]]
        } else {
            r
        }
    }

    /// `piece`.
    fn piece(
        &self,
        u0: f64,
        u1: f64,
        p: usize,
        s_far: f64,
        s_near: f64,
        length: f64,
    ) -> Contribution {
        let s0 = s_far + u0 * (s_near - s_far);
        let s1 = s_far + u1 * (s_near - s_far);
        let mid = 0.5 * (s0 + s1);
        let far = self.eval_in(p, s0);
        let near = self.eval_in(p, s1);
        let quadratic = self.flag(slot::QUADRATIC);
        let mut eta_mid = [0.0; 3];
        if quadratic {
            let m = self.eval_in(p, mid);
            eta_mid = [m[0], m[1], m[2]];
        }
        segment(
            [far[0], far[1], far[2]],
            [near[0], near[1], near[2]],
            eta_mid,
            quadratic,
            far[3],
            near[3],
            (u1 - u0) * length,
        )
    }

    /// `piece_between`.
    fn piece_between(
        &self,
        u0: f64,
        u1: f64,
        s_far: f64,
        s_near: f64,
        length: f64,
    ) -> Contribution {
        let s0 = s_far + u0 * (s_near - s_far);
        let s1 = s_far + u1 * (s_near - s_far);
        self.piece(
            u0,
            u1,
            self.piece_of(0.5 * (s0 + s1)),
            s_far,
            s_near,
            length,
        )
    }

    /// `cell_contribution`.
    pub fn cell_contribution(&self, s_far: f64, s_near: f64, length: f64) -> Contribution {
        let accumulate = |acc: Contribution, c: Contribution| -> Contribution {
            ([0, 1, 2].map(|k| acc.0[k] * c.1 + c.0[k]), acc.1 * c.1)
        };
        let mut acc = ([0.0; 3], 1.0);
        let p = self.piece_of(s_far);
        if self.piece_of(s_near) == p {
            acc = self.piece(0.0, 1.0, p, s_far, s_near, length);
        } else {
            let rising = s_near > s_far;
            let (lo, hi) = if rising {
                (s_far, s_near)
            } else {
                (s_near, s_far)
            };
            let first = self.piece_of(lo);
            let last = self.knots_below(hi).max(first);
            let mut prev = 0.0;
            for j in 0..last - first {
                let i = if rising { first + j } else { last - 1 - j };
                let u = (self.knot(i) - s_far) / (s_near - s_far);
                if u > prev {
                    acc = accumulate(acc, self.piece_between(prev, u, s_far, s_near, length));
                    prev = u;
                }
            }
            if 1.0 > prev {
                acc = accumulate(acc, self.piece_between(prev, 1.0, s_far, s_near, length));
            }
        }
        let k = self.consts[slot::BRIGHTNESS];
        (acc.0.map(|b| b * k), acc.1)
    }

    /// `node_at`.
    pub(super) fn node_at(&self, n: u32) -> usize {
        self.consts[slot::NODE] as usize * n as usize
    }

    fn corner(&self, n: u32) -> Corner {
        let i = self.node_at(n);
        Corner {
            p: [self.nodes[i], self.nodes[i + 1]],
            z: self.nodes[i + 2],
            v: self.nodes[i + 6],
            id: n,
        }
    }

    /// `eye_of`.
    fn eye_of(&self, n: u32) -> [f64; 3] {
        let i = self.node_at(n);
        [self.nodes[i + 3], self.nodes[i + 4], self.nodes[i + 5]]
    }

    /// `plane`.
    fn plane(&self, at: usize, g: [f64; 3], k: usize) -> f64 {
        let c = self.consts;
        g[0] * c[at + k] + g[1] * c[at + 3 + k] + g[2] * c[at + 6 + k]
    }

    /// `cell_line`: `λ(τ) = a + τ·b` (and the tolerances where `with_tol`), `None` for a flat
    /// cell.
    pub fn cell_line(&self, tet: [u32; 4], p: [f64; 2], with_tol: bool) -> Option<Line> {
        let c = tet.map(|n| self.eye_of(n));
        let sub = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
        let (e1, e2, e3) = (sub(c[1], c[0]), sub(c[2], c[0]), sub(c[3], c[0]));
        let det = dot3(cross3(e1, e2), e3);
        if !(det != 0.0 && det.abs() <= f64::MAX) {
            return None;
        }
        let scaled = |v: [f64; 3]| v.map(|x| x / det);
        let (g1, g2, g3) = (
            scaled(cross3(e2, e3)),
            scaled(cross3(e3, e1)),
            scaled(cross3(e1, e2)),
        );
        let g0 = [0, 1, 2].map(|k| -(g1[k] + g2[k] + g3[k]));
        let g = [g0, g1, g2, g3];
        let (mut a, mut b, mut tol) = ([0.0; 4], [0.0; 4], [0.0; 4]);
        for i in 0..4 {
            let h = 1.0 - dot3(g[i], c[i]);
            let a0 = self.plane(slot::PLANES, g[i], 0) + h;
            let a1 = self.plane(slot::PLANES, g[i], 1);
            let a2 = self.plane(slot::PLANES, g[i], 2);
            let b0 = self.plane(slot::PLANES + 9, g[i], 0);
            let b1 = self.plane(slot::PLANES + 9, g[i], 1);
            let b2 = self.plane(slot::PLANES + 9, g[i], 2);
            a[i] = a0 + a1 * p[0] + a2 * p[1];
            b[i] = b0 + b1 * p[0] + b2 * p[1];
            if with_tol {
                tol[i] = PARALLEL * dot3(g[i], g[i]).sqrt() * self.consts[slot::MAX_SPEED];
            }
        }
        Some(Line { a, b, tol })
    }

    /// `near_clipped`.
    fn near_clipped(&self, tet: [u32; 4]) -> bool {
        if !self.flag(slot::ANY_NEAR) {
            return false;
        }
        let dmin = self.consts[slot::DMIN];
        tet.iter().any(|&n| -self.eye_of(n)[2] < dmin)
    }

    /// `near_step`: `(b, θ)`, then the next cell and its entry depth.
    fn near_step(
        &self,
        cell: u32,
        p: [f64; 2],
        dmax: f64,
        speed: f64,
    ) -> (Contribution, Option<(u32, f64)>) {
        let none = (([0.0; 3], 1.0), None);
        let tet = self.mesh[2 * cell as usize];
        let Some(line) = self.cell_line(tet, p, true) else {
            return none;
        };
        let Some((iv_near, iv_far, exit)) = clip_line(&line, self.consts[slot::INFINITY]) else {
            return none;
        };
        let near = iv_near.max(self.consts[slot::DMIN]);
        let far = iv_far.min(dmax);
        let mut c = ([0.0; 3], 1.0);
        if near < far {
            c = self.contribution(tet, &line, near, far, (far - near) * speed);
        }
        let next = self.mesh[2 * cell as usize + 1][exit];
        if next != NO_NEIGHBOR && !self.near_clipped(self.mesh[2 * next as usize]) {
            return (c, Some((next, self.hit(tet, exit, p)[0])));
        }
        (c, None)
    }

    /// `interpolate`.
    fn interpolate(&self, tet: [u32; 4], l: [f64; 4]) -> [f64; 4] {
        let mut r = [0.0; 4];
        for i in 0..4 {
            let at = self.node_at(tet[i]) + 6;
            let c = if self.consts[slot::METHOD] == 2.0 {
                self.map_field(self.nodes[at])
            } else {
                [0, 1, 2, 3].map(|k| self.nodes[at + k])
            };
            for k in 0..4 {
                r[k] += l[i] * c[k];
            }
        }
        r
    }

    /// `contribution`.
    fn contribution(
        &self,
        tet: [u32; 4],
        line: &Line,
        near: f64,
        far: f64,
        length: f64,
    ) -> Contribution {
        let (a, b) = (line.a, line.b);
        if self.consts[slot::METHOD] == 0.0 {
            let v = tet.map(|n| self.nodes[self.node_at(n) + 6]);
            let s0 = a[0] * v[0] + a[1] * v[1] + a[2] * v[2] + a[3] * v[3];
            let slope = b[0] * v[0] + b[1] * v[1] + b[2] * v[2] + b[3] * v[3];
            return self.cell_contribution(s0 + far * slope, s0 + near * slope, length);
        }
        let at = |t: f64| [0, 1, 2, 3].map(|i| a[i] + t * b[i]);
        let f = self.interpolate(tet, at(far));
        let n = self.interpolate(tet, at(near));
        let k = self.consts[slot::BRIGHTNESS];
        if self.consts[slot::METHOD] == 2.0 {
            let eta = [0, 1, 2].map(|i| 0.5 * (f[i] + n[i]));
            let chi = 0.5 * (f[3] + n[3]);
            let (c, theta) = segment(eta, eta, [0.0; 3], false, chi, chi, length);
            return (c.map(|x| x * k), theta);
        }
        let (c, theta) = segment(
            [f[0], f[1], f[2]],
            [n[0], n[1], n[2]],
            [0.0; 3],
            false,
            f[3],
            n[3],
            length,
        );
        (c.map(|x| x * k), theta)
    }

    /// `hit`.
    fn hit(&self, tet: [u32; 4], f: usize, p: [f64; 2]) -> [f64; 2] {
        let k = FACE_NODES[f].map(|l| self.corner(tet[l]));
        face_hit(
            k,
            p,
            self.flag(slot::PERSPECTIVE),
            self.flag(slot::EXACT_FMA),
        )
    }

    pub(super) fn screen_of(&self, n: u32) -> [f64; 2] {
        let i = self.node_at(n);
        [self.nodes[i], self.nodes[i + 1]]
    }

    /// `loops_ran` (here every loop runs to its end: true).
    fn loops_ran(&self) -> bool {
        let trips = self.consts[slot::LOOP_CHECK] as u32;
        (0..trips).count() as u32 == trips
    }

    /// `march` for pixel (x, y): colour accumulated front to back, transparency, cells passed
    /// (−1 where the driver cut the loops, [`LOOPS_CUT`]).
    pub fn pixel(&self, x: u32, y: u32) -> [f64; 5] {
        let c = self.consts;
        let width = c[slot::WIDTH] as u32;
        let pix = (y * width + x) as usize;
        let p = [f64::from(x) + 0.5, f64::from(y) + 0.5];
        let ftb = self.flag(slot::FRONT_TO_BACK);
        let stop = if ftb { EARLY_TERMINATION } else { NEGLIGIBLE };
        let dmin = c[slot::DMIN];
        let mut dmax = c[slot::DMAX];
        if self.flag(slot::HAS_LINES) {
            dmax = dmax.min(self.lines[pix]);
        }
        let mut speed = 1.0;
        if self.flag(slot::PERSPECTIVE) {
            let xn = 2.0 * p[0] / c[slot::WIDTH] - 1.0;
            let yn = 1.0 - 2.0 * p[1] / c[slot::HEIGHT];
            let (dx, dy) = (xn * c[slot::TAN_X], yn * c[slot::TAN_Y]);
            speed = (dx * dx + dy * dy + 1.0).sqrt();
        }
        let entry_sign = c[slot::ENTRY_SIGN] as i32;
        let fma = self.flag(slot::EXACT_FMA);
        let cells = c[slot::CELLS] as u32;
        let mut color = [0.0; 3];
        let mut t = 1.0;
        let mut steps = 0u32;
        let (first, last) = (self.lists[pix], self.lists[pix + 1]);
        for e in first..last {
            let entry = self.lists[e as usize];
            let (mut cell, mut tet, mut d_in);
            if entry & NEAR_ENTRY != 0 {
                if t < stop || steps > cells {
                    break;
                }
                steps += 1;
                let (c, next) = self.near_step(entry & !NEAR_ENTRY, p, dmax, speed);
                color = [0, 1, 2].map(|k| color[k] + t * c.0[k]);
                t *= c.1;
                let Some((next, d)) = next else {
                    continue;
                };
                cell = next;
                tet = self.mesh[2 * cell as usize];
                d_in = d;
            } else {
                cell = entry >> 2;
                tet = self.mesh[2 * cell as usize];
                d_in = self.hit(tet, (entry & 3) as usize, p)[0];
            }
            loop {
                if t < stop || !(d_in < dmax) || steps > cells {
                    break;
                }
                steps += 1;
                let s = tet.map(|n| self.screen_of(n));
                let x = exit_face(&s, entry_sign, p, fma);
                if x > 3 {
                    break;
                }
                let out = self.hit(tet, x, p);
                let d_out = out[0].max(d_in);
                let near = d_in.max(dmin);
                let far = d_out.min(dmax);
                if near < far && c[slot::METHOD] == 2.0 {
                    let (b, theta) =
                        self.color_contribution(cell, tet, p, [near, far, d_out - d_in]);
                    color = [0, 1, 2].map(|k| color[k] + t * b[k]);
                    t *= theta;
                } else if near < far
                    && let Some(line) = self.cell_line(tet, p, false)
                {
                    let (b, theta) = self.contribution(tet, &line, near, far, (far - near) * speed);
                    color = [0, 1, 2].map(|k| color[k] + t * b[k]);
                    t *= theta;
                }
                let next = self.mesh[2 * cell as usize + 1][x];
                if next == NO_NEIGHBOR || self.near_clipped(self.mesh[2 * next as usize]) {
                    break;
                }
                cell = next;
                tet = self.mesh[2 * cell as usize];
                d_in = out[0];
            }
        }
        let steps = if self.loops_ran() {
            f64::from(steps)
        } else {
            LOOPS_CUT
        };
        [color[0], color[1], color[2], t, steps]
    }
}
