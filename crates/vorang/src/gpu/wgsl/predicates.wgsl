// Exact screen predicates in f64 (twins: gpu/twin.rs, predicates).
//
// Node positions on screen lie on the 2^-28 px grid (scene::SUBPIXEL), so for screens below
// 2^24 px the coordinate differences are exact and orient2d is the sign of an exact difference
// of two exact products: two_prod (an exact fma where the device has one, else Dekker's split,
// exact because the shader compiler does not contract a*b+c) and Shewchuk's Two_Two_Diff.

struct Dd {
    hi: f64,
    lo: f64,
}

fn two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    let bb = s - a;
    return Dd(s, (a - (s - bb)) + (b - bb));
}

fn two_diff(a: f64, b: f64) -> Dd {
    let x = a - b;
    let bv = a - x;
    let av = x + bv;
    let br = bv - b;
    let ar = a - av;
    return Dd(x, ar + br);
}

// Veltkamp's split: a = hi + lo with 26 bits each.
fn split(a: f64) -> Dd {
    let c = 134217729.0lf * a;
    let big = c - a;
    let hi = c - big;
    return Dd(hi, a - hi);
}

// a*b = hi + lo exactly.
fn two_prod(a: f64, b: f64) -> Dd {
    let p = a * b;
    if (exact_fma()) {
        return Dd(p, fma(a, b, -p));
    }
    let sa = split(a);
    let sb = split(b);
    let err1 = p - sa.hi * sb.hi;
    let err2 = err1 - sa.lo * sb.hi;
    let err3 = err2 - sa.hi * sb.lo;
    return Dd(p, sa.lo * sb.lo - err3);
}

fn sign_of(x: f64) -> i32 {
    return select(select(0, -1, x < 0.0lf), 1, x > 0.0lf);
}

// Sign of (a.x - c.x)(b.y - c.y) - (a.y - c.y)(b.x - c.x), exactly.
fn orient(a: vec2<f64>, b: vec2<f64>, c: vec2<f64>) -> i32 {
    let l = two_prod(a.x - c.x, b.y - c.y);
    let r = two_prod(a.y - c.y, b.x - c.x);
    // (l.hi + l.lo) - (r.hi + r.lo) as the nonoverlapping expansion x3 > x2 > x1 > x0.
    let t0 = two_diff(l.lo, r.lo);
    let t1 = two_sum(l.hi, t0.hi);
    let t2 = two_diff(t1.lo, r.hi);
    let t3 = two_sum(t1.hi, t2.hi);
    if (t3.hi != 0.0lf) {
        return sign_of(t3.hi);
    }
    if (t3.lo != 0.0lf) {
        return sign_of(t3.lo);
    }
    if (t2.lo != 0.0lf) {
        return sign_of(t2.lo);
    }
    return sign_of(t0.lo);
}

// Top-left rule (y down): a positively oriented polygon owns the points on its edge u -> v.
fn owns(u: vec2<f64>, v: vec2<f64>) -> bool {
    let dx = v.x - u.x;
    let dy = v.y - u.y;
    return dy < 0.0lf || (dy == 0.0lf && dx > 0.0lf);
}

fn inside(u: vec2<f64>, v: vec2<f64>, p: vec2<f64>) -> bool {
    let e = orient(u, v, p);
    return e > 0 || (e == 0 && owns(u, v));
}
