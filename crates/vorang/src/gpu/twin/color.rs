//! The Rust twins of `wgsl/color.wgsl` (interpolateColor's fans, see [`crate::gpu::color`])
//! and of `linear.wgsl`'s `pow_frac`, `soft_ln` and `soft_exp`: the same operations in the same
//! order.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{Buffers, Contribution, slot};
use crate::gpu::color::{FAN, FAN_SPLIT};
use crate::render::project::THICK;

const THICK_V: u32 = THICK as u32;

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

fn fan_base(b: &Buffers, cell: u32) -> usize {
    b.consts[slot::FANS] as usize + FAN * cell as usize
}

/// `fan_code`.
fn fan_code(b: &Buffers, cell: u32) -> [u32; 2] {
    let code = b.nodes[fan_base(b, cell) + 6];
    let hi = (code / FAN_SPLIT).floor();
    [(code - hi * FAN_SPLIT) as u32, hi as u32]
}

/// `fan_corner`.
fn fan_corner(code: [u32; 2], k: u32, m: u32) -> u32 {
    if k < 3 {
        return (code[0] >> (9 * k + 3 * m)) & 7;
    }
    (code[1] >> (3 * m)) & 7
}

/// `fan_pos`.
fn fan_pos(b: &Buffers, cell: u32, tet: [u32; 4], v: u32) -> [f64; 2] {
    if v == THICK_V {
        let i = fan_base(b, cell);
        return [b.nodes[i + 4], b.nodes[i + 5]];
    }
    b.screen_of(tet[v as usize])
}

/// `fan_value`.
fn fan_value(b: &Buffers, cell: u32, tet: [u32; 4], v: u32) -> [f64; 4] {
    if v == THICK_V {
        let i = fan_base(b, cell);
        return [b.nodes[i], b.nodes[i + 1], b.nodes[i + 2], b.nodes[i + 3]];
    }
    let at = b.node_at(tet[v as usize]) + 6;
    [1.0, b.nodes[at], b.nodes[at + 1], b.nodes[at + 2]]
}

/// `Sector`: T's weight and the second node's as `(c, x, y)`, the nodes `i`, `j`.
struct Sector {
    thick: [f64; 3],
    second: [f64; 3],
    i: u32,
    j: u32,
}

/// `sector`; `None` where it is not ok.
fn sector(b: &Buffers, cell: u32, tet: [u32; 4], code: [u32; 2], k: u32) -> Option<Sector> {
    let t = if fan_corner(code, k, 0) == THICK_V {
        0
    } else if fan_corner(code, k, 1) == THICK_V {
        1
    } else {
        2
    };
    let i = fan_corner(code, k, (t + 1) % 3);
    let j = fan_corner(code, k, (t + 2) % 3);
    let pi = fan_pos(b, cell, tet, i);
    let pj = fan_pos(b, cell, tet, j);
    let pt = fan_pos(b, cell, tet, THICK_V);
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

/// `plane_at`.
fn plane_at(q: [f64; 3], p: [f64; 2]) -> f64 {
    q[0] + q[1] * p[0] + q[2] * p[1]
}

/// `fan_at`: `[θ, η̄]` at pixel `p`.
pub fn fan_at(b: &Buffers, cell: u32, tet: [u32; 4], p: [f64; 2]) -> [f64; 4] {
    let code = fan_code(b, cell);
    let mut which = [0u32; 4];
    let inf = b.consts[slot::INFINITY];
    let mut l = [inf; 4];
    let mut used = 0;
    for k in 0..code[1] >> 9 {
        let Some(s) = sector(b, cell, tet, code, k) else {
            continue;
        };
        which[used] = k;
        l[used] = plane_at(s.thick, p);
        used += 1;
    }
    let (a, la) = if l[1] < l[0] { (1, l[1]) } else { (0, l[0]) };
    let (bb, lb) = if l[3] < l[2] { (3, l[3]) } else { (2, l[2]) };
    let best = if lb < la { bb } else { a };
    let mut out = [0.0; 4];
    if best >= used {
        return out;
    }
    let Some(s) = sector(b, cell, tet, code, which[best]) else {
        return out;
    };
    let vi = fan_value(b, cell, tet, s.i);
    let vj = fan_value(b, cell, tet, s.j);
    let vt = fan_value(b, cell, tet, THICK_V);
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
    b: &Buffers,
    cell: u32,
    tet: [u32; 4],
    p: [f64; 2],
    [near, far, full]: [f64; 3],
) -> Contribution {
    if fan_code(b, cell)[1] >> 9 == 0 {
        return ([0.0; 3], 1.0);
    }
    let v = fan_at(b, cell, tet, p);
    let mut theta = v[0];
    if far - near < full {
        theta = pow_frac(theta, (far - near) / full);
    }
    let k = b.consts[slot::BRIGHTNESS] * (1.0 - theta);
    ([v[1] * k, v[2] * k, v[3] * k], theta)
}
