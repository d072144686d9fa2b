//! The Rust twins of `wgsl/color.wgsl` (interpolateColor's fans, see [`crate::gpu::color`])
//! and of `linear.wgsl`'s `pow_frac`, `soft_ln` and `soft_exp`: the same operations in the same
//! order.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{Buffers, Contribution, segment, slot};

const LN2_HI: f64 = 6.931_471_803_691_238e-1;
const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
const INV_LN2: f64 = std::f64::consts::LOG2_E;
const SQRT_HALF: f64 = std::f64::consts::FRAC_1_SQRT_2;
const TWO_64: f64 = 18_446_744_073_709_551_616.0;

/// `soft_ln`: ln x for a finite x > 0.
pub fn soft_ln(x: f64) -> f64 {
    let (mut m, mut e) = (x, 0.0f64);
    while m < 1.0 / TWO_64 {
        m *= TWO_64;
        e -= 64.0;
    }
    while m < 0.5 {
        m *= 2.0;
        e -= 1.0;
    }
    while m >= 1.0 {
        m *= 0.5;
        e += 1.0;
    }
    if m < SQRT_HALF {
        m *= 2.0;
        e -= 1.0;
    }
    let z = (m - 1.0) / (m + 1.0);
    let z2 = z * z;
    let mut s = 1.0 / 29.0;
    for j in 0..14u32 {
        s = s * z2 + 1.0 / f64::from(27 - 2 * j);
    }
    e * LN2_HI + (e * LN2_LO + 2.0 * z * s)
}

/// `soft_exp`: e^y (0 below −746).
pub fn soft_exp(y: f64) -> f64 {
    if y < -746.0 {
        return 0.0;
    }
    let k = (y * INV_LN2 + 0.5).floor();
    let r = (y - k * LN2_HI) - k * LN2_LO;
    let mut s = 1.0;
    for j in 0..20u32 {
        s = 1.0 + s * r / f64::from(20 - j);
    }
    let mut kk = k;
    while kk <= -64.0 {
        s *= 1.0 / TWO_64;
        kk += 64.0;
    }
    while kk < 0.0 {
        s *= 0.5;
        kk += 1.0;
    }
    while kk > 0.0 {
        s *= 2.0;
        kk -= 1.0;
    }
    s
}

/// `pow_frac`: θ^f, 0 where θ is not positive.
pub fn pow_frac(theta: f64, f: f64) -> f64 {
    if !(theta > 0.0) {
        return 0.0;
    }
    if !(theta <= f64::MAX) {
        return theta;
    }
    soft_exp(f * soft_ln(theta))
}

/// `End`: barycentric coordinates and depth.
#[derive(Debug, Clone, Copy)]
struct End {
    lambda: [f64; 4],
    d: f64,
}

fn cross2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn sub2(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// `scalar4`.
fn scalar4(v: [f64; 4], l: [f64; 4]) -> f64 {
    l[0] * v[0] + l[1] * v[1] + l[2] * v[2] + l[3] * v[3]
}

impl Buffers<'_> {
    /// `fan_code`.
    pub(crate) fn fan_code(&self, cell: u32) -> u32 {
        self.lists[self.consts[slot::FANS] as usize + cell as usize]
    }

    /// `field_of`.
    fn field_of(&self, n: u32) -> f64 {
        self.nodes[self.node_at(n) + 6]
    }

    /// `map_field`.
    pub(super) fn map_field(&self, s: f64) -> [f64; 4] {
        self.eval_in(self.piece_of(s), s)
    }

    /// `node_value`.
    fn node_value(&self, n: u32) -> [f64; 4] {
        let m = self.map_field(self.field_of(n));
        [1.0, m[0], m[1], m[2]]
    }

    /// `thick_point`.
    pub(crate) fn thick_point(&self, tet: [u32; 4], code: u32) -> [f64; 2] {
        if code & 32 == 0 {
            return self.screen_of(tet[((code >> 3) & 3) as usize]);
        }
        let at = |k: u32, m: u32| self.screen_of(tet[fan_node(code, k, m) as usize]);
        let p = at(0, 0);
        let q = at(0, 1);
        let r = sub2(at(1, 1), p);
        let u = sub2(at(2, 1), q);
        let denom = r[0] * u[1] - r[1] * u[0];
        let t = ((q[0] - p[0]) * u[1] - (q[1] - p[1]) * u[0]) / denom;
        [p[0] + t * r[0], p[1] + t * r[1]]
    }

    /// `thick_end`.
    fn thick_end(&self, at: [usize; 3], mu: [f64; 3], n: usize, depth: [f64; 4]) -> End {
        let mut e = End {
            lambda: [0.0; 4],
            d: 0.0,
        };
        if self.consts[slot::PERSPECTIVE] != 0.0 {
            let mut total = 0.0;
            for m in 0..n {
                total += mu[m] / depth[at[m]];
            }
            for m in 0..n {
                e.lambda[at[m]] = mu[m] / depth[at[m]] / total;
            }
        } else {
            for m in 0..n {
                e.lambda[at[m]] = mu[m];
            }
        }
        for m in 0..n {
            e.d += e.lambda[at[m]] * depth[at[m]];
        }
        e
    }

    /// `thick_value`: `[θ, η̄]` at T.
    pub(crate) fn thick_value(&self, tet: [u32; 4], code: u32, tp: [f64; 2]) -> [f64; 4] {
        let s = tet.map(|n| self.screen_of(n));
        let depth = tet.map(|n| -self.eye_of(n)[2]);
        let (a, b);
        if code & 32 != 0 {
            let node = |k: u32, m: u32| fan_node(code, k, m) as usize;
            let (na, nc, nb, nd) = (node(0, 0), node(0, 1), node(1, 1), node(2, 1));
            let (p, r, q, w) = (s[na], sub2(s[nb], s[na]), s[nc], sub2(s[nd], s[nc]));
            let denom = cross2(r, w);
            if denom == 0.0 {
                return [1.0, 0.0, 0.0, 0.0];
            }
            let t = cross2(sub2(q, p), w) / denom;
            let u = cross2(sub2(q, p), r) / denom;
            a = self.thick_end([na, nb, 0], [1.0 - t, t, 0.0], 2, depth);
            b = self.thick_end([nc, nd, 0], [1.0 - u, u, 0.0], 2, depth);
        } else if code & 64 != 0 {
            let i = ((code >> 3) & 3) as usize;
            let j = if i == 0 { 1 } else { 0 };
            let k = if i == j + 1 { j + 2 } else { j + 1 };
            let l = if i == k + 1 { k + 2 } else { k + 1 };
            let area = cross2(sub2(s[k], s[j]), sub2(s[l], s[j]));
            if area == 0.0 {
                return self.node_value(tet[i]);
            }
            let mj = cross2(sub2(s[k], tp), sub2(s[l], tp)) / area;
            let mk = cross2(sub2(s[l], tp), sub2(s[j], tp)) / area;
            a = self.thick_end([i, 0, 0], [1.0, 0.0, 0.0], 1, depth);
            b = self.thick_end([j, k, l], [mj, mk, 1.0 - mj - mk], 3, depth);
        } else {
            return [1.0, 0.0, 0.0, 0.0];
        }
        let (near, far) = if !(a.d <= b.d) { (b, a) } else { (a, b) };
        let v = tet.map(|n| self.field_of(n));
        let front = self.map_field(scalar4(v, near.lambda));
        let back = self.map_field(scalar4(v, far.lambda));
        let l = (far.d - near.d) * self.ray_speed(tp);
        let theta = segment([0.0; 3], [0.0; 3], [0.0; 3], false, back[3], front[3], l).1;
        [
            theta,
            back[0] * theta + front[0] * (1.0 - theta),
            back[1] * theta + front[1] * (1.0 - theta),
            back[2] * theta + front[2] * (1.0 - theta),
        ]
    }

    /// `ray_speed`.
    fn ray_speed(&self, p: [f64; 2]) -> f64 {
        let c = self.consts;
        if c[slot::PERSPECTIVE] == 0.0 {
            return 1.0;
        }
        let xn = 2.0 * p[0] / c[slot::WIDTH] - 1.0;
        let yn = 1.0 - 2.0 * p[1] / c[slot::HEIGHT];
        let (dx, dy) = (xn * c[slot::TAN_X], yn * c[slot::TAN_Y]);
        (dx * dx + dy * dy + 1.0).sqrt()
    }

    /// `sector`; `None` where it is not ok.
    fn sector(&self, tet: [u32; 4], code: u32, k: u32, pt: [f64; 2]) -> Option<Sector> {
        let (i, j) = (fan_node(code, k, 0), fan_node(code, k, 1));
        let pi = self.screen_of(tet[i as usize]);
        let pj = self.screen_of(tet[j as usize]);
        let d = [pj[0] - pi[0], pj[1] - pi[1]];
        let e = [pt[0] - pi[0], pt[1] - pi[1]];
        let area = d[0] * e[1] - d[1] * e[0];
        if !(area != 0.0 && area.abs() <= f64::MAX) {
            return None;
        }
        Some(Sector {
            thick: [
                (d[1] * pi[0] - d[0] * pi[1]) / area,
                -d[1] / area,
                d[0] / area,
            ],
            second: [
                (e[0] * pi[1] - e[1] * pi[0]) / area,
                e[1] / area,
                -e[0] / area,
            ],
            i,
            j,
        })
    }

    /// `fan_at`: `[θ, η̄]` at pixel `p`.
    pub fn fan_at(&self, tet: [u32; 4], code: u32, p: [f64; 2]) -> [f64; 4] {
        let pt = self.thick_point(tet, code);
        let mut which = [0u32; 4];
        let mut l = [self.consts[slot::INFINITY]; 4];
        let mut used = 0;
        for k in 0..code & 7 {
            let Some(s) = self.sector(tet, code, k, pt) else {
                continue;
            };
            which[used] = k;
            l[used] = plane_at(s.thick, p);
            used += 1;
        }
        let (a, la) = if l[1] < l[0] { (1, l[1]) } else { (0, l[0]) };
        let (b, lb) = if l[3] < l[2] { (3, l[3]) } else { (2, l[2]) };
        let best = if lb < la { b } else { a };
        let mut out = [0.0; 4];
        if best >= used {
            return out;
        }
        let Some(s) = self.sector(tet, code, which[best], pt) else {
            return out;
        };
        let vi = self.node_value(tet[s.i as usize]);
        let vj = self.node_value(tet[s.j as usize]);
        let vt = self.thick_value(tet, code, pt);
        for (c, o) in out.iter_mut().enumerate() {
            let dt = vt[c] - vi[c];
            let dj = vj[c] - vi[c];
            let q = [
                vi[c] + s.thick[0] * dt + s.second[0] * dj,
                s.thick[1] * dt + s.second[1] * dj,
                s.thick[2] * dt + s.second[2] * dj,
            ];
            *o = plane_at(q, p);
        }
        out
    }

    /// `color_contribution` over `[near, far, full]`.
    pub fn color_contribution(
        &self,
        cell: u32,
        tet: [u32; 4],
        p: [f64; 2],
        [near, far, full]: [f64; 3],
    ) -> Contribution {
        let code = self.fan_code(cell);
        if code & 7 == 0 {
            return ([0.0; 3], 1.0);
        }
        let v = self.fan_at(tet, code, p);
        let mut theta = v[0];
        if far - near < full {
            theta = pow_frac(theta, (far - near) / full);
        }
        let k = self.consts[slot::BRIGHTNESS] * (1.0 - theta);
        ([v[1] * k, v[2] * k, v[3] * k], theta)
    }
}

/// `fan_node`: node `m` (0: the first after T, 1: the second) of fan triangle `k`.
fn fan_node(code: u32, k: u32, m: u32) -> u32 {
    (code >> (10 + 6 * k + 2 * m)) & 3
}

/// `Sector`: T's weight and the second node's as `(c, x, y)`, the nodes `i`, `j`.
struct Sector {
    thick: [f64; 3],
    second: [f64; 3],
    i: u32,
    j: u32,
}

/// `plane_at`.
fn plane_at(q: [f64; 3], p: [f64; 2]) -> f64 {
    q[0] + q[1] * p[0] + q[2] * p[1]
}
