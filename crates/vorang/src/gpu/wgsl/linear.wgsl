// The `linear` rule without exp (twins: gpu/twin.rs, linear). With c = χ_near·Δs,
// a = χ_far·Δs, d = a − c: e^{−(c·w + d/2·w²)} = Σ q_j wʲ, (j+1)·q_{j+1} = −c·q_j − d·q_{j−1},
// J_n = Σ q_j/(n + j + 1) and θ = 1 − (c·J0 + d·J1) (integrate::linear_lanes). Segments whose
// end depths exceed MAX_DEPTH are cut into equal sub-segments that do not, composited front to
// back; as integrate::linear's pieces, the light beyond an optical depth of 45 is dropped.

const MAX_DEPTH: f64 = 0.5lf;
const MAX_TERMS: u32 = 64u;

struct Contribution {
    b: vec3<f64>,
    theta: f64,
}

// (J0, J1, J2, θ) for end depths c (near) and c + d (far), both in [0, MAX_DEPTH].
fn moments(c: f64, d: f64) -> vec4<f64> {
    var prev = 0.0lf;
    var q = 1.0lf;
    var j0 = 1.0lf;
    var j1 = 0.5lf;
    var j2 = 1.0lf / 3.0lf;
    for (var j = 0u; j < MAX_TERMS; j++) {
        let next = (-c * q - d * prev) / f64(j + 1u);
        j0 = j0 + next / f64(j + 2u);
        j1 = j1 + next / f64(j + 3u);
        j2 = j2 + next / f64(j + 4u);
        prev = q;
        q = next;
        let small = 0.5e-17lf * j1;
        if (abs(q) <= small && abs(prev) <= small) {
            break;
        }
    }
    let theta = min(1.0lf - (c * j0 + d * j1), 1.0lf);
    return vec4<f64>(j0, j1, j2, theta);
}

// A thin segment: η(w) = near + p1·w + p2·w² (w from the near end), depths c, a.
fn thin(near: vec3<f64>, p1: vec3<f64>, p2: vec3<f64>, c: f64, a: f64, l: f64) -> Contribution {
    let m = moments(c, a - c);
    let b = l * (near * m.x + p1 * m.y + p2 * m.z);
    return Contribution(b, m.w);
}

// The segment's (b, θ): η at the far and near end (and in the middle if quadratic), χ at the
// far and near end, length l.
fn segment(far: vec3<f64>, near: vec3<f64>, mid: vec3<f64>, quadratic: bool, chi_far: f64, chi_near: f64, l: f64) -> Contribution {
    let a = max(chi_far * l, 0.0lf);
    let c = max(chi_near * l, 0.0lf);
    var p1 = far - near;
    var p2 = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    if (quadratic) {
        p1 = -3.0lf * near + 4.0lf * mid - far;
        p2 = 2.0lf * near - 4.0lf * mid + 2.0lf * far;
    }
    let deepest = max(a, c);
    if (!(deepest > MAX_DEPTH)) {
        return thin(near, p1, p2, c, a, l);
    }
    // Optically thick: n sub-segments of end depths ≤ MAX_DEPTH, near to far.
    let n = ceil(deepest / MAX_DEPTH);
    let h = 1.0lf / n;
    var out = Contribution(vec3<f64>(0.0lf, 0.0lf, 0.0lf), 1.0lf);
    var depth = 0.0lf;
    let count = u32(n);
    for (var i = 0u; i < count; i++) {
        let w0 = f64(i) * h;
        let w1 = select(f64(i + 1u) * h, 1.0lf, i + 1u == count);
        let c0 = (c + (a - c) * w0) * h;
        let c1 = (c + (a - c) * w1) * h;
        // η over the sub-segment as a polynomial in its own w ∈ [0, 1].
        let e0 = near + p1 * w0 + p2 * (w0 * w0);
        let s = w1 - w0;
        let q1 = (p1 + 2.0lf * w0 * p2) * s;
        let q2 = p2 * (s * s);
        let piece = thin(e0, q1, q2, c0, c1, l * h);
        out.b = out.b + out.theta * piece.b;
        out.theta = out.theta * piece.theta;
        depth = depth + 0.5lf * (c0 + c1);
        if (depth > 45.0lf) {
            break;
        }
    }
    return out;
}

// θ^f without pow (approx::interpolate_color raises the interpolated θ to the kept fraction f of
// a clipped interval): e^{f·ln θ}, ln by halving to m ∈ [√½, √2) and the series
// ln m = 2·atanh((m − 1)/(m + 1)), e^y by y = k·ln 2 + r, |r| ≤ ½ln 2, and Taylor's series,
// ln 2 split in two (fdlibm's) so that k·ln 2 keeps its bits. A few units in the last place of
// the CPU's powf. Twins: gpu/twin.rs, soft_ln, soft_exp, pow_frac.
const LN2_HI: f64 = 6.93147180369123816490e-01lf;
const LN2_LO: f64 = 1.90821492927058770002e-10lf;
const INV_LN2: f64 = 1.44269504088896338700e+00lf;
const SQRT_HALF: f64 = 0.70710678118654752440lf;
const TWO_64: f64 = 18446744073709551616.0lf;
const FINITE_MAX: f64 = 1.7976931348623157e308lf;

// ln x for a finite x > 0.
fn soft_ln(x: f64) -> f64 {
    var m = x;
    var e = 0.0lf;
    while (m < 1.0lf / TWO_64) {
        m = m * TWO_64;
        e = e - 64.0lf;
    }
    while (m < 0.5lf) {
        m = m * 2.0lf;
        e = e - 1.0lf;
    }
    while (m >= 1.0lf) {
        m = m * 0.5lf;
        e = e + 1.0lf;
    }
    if (m < SQRT_HALF) {
        m = m * 2.0lf;
        e = e - 1.0lf;
    }
    let z = (m - 1.0lf) / (m + 1.0lf);
    let z2 = z * z;
    var s = 1.0lf / 29.0lf;
    for (var j = 0u; j < 14u; j++) {
        s = s * z2 + 1.0lf / f64(27u - 2u * j);
    }
    return e * LN2_HI + (e * LN2_LO + 2.0lf * z * s);
}

// e^y (0 below −746).
fn soft_exp(y: f64) -> f64 {
    if (y < -746.0lf) {
        return 0.0lf;
    }
    let k = floor(y * INV_LN2 + 0.5lf);
    let r = (y - k * LN2_HI) - k * LN2_LO;
    var s = 1.0lf;
    for (var j = 0u; j < 20u; j++) {
        s = 1.0lf + s * r / f64(20u - j);
    }
    var kk = k;
    while (kk <= -64.0lf) {
        s = s * (1.0lf / TWO_64);
        kk = kk + 64.0lf;
    }
    while (kk < 0.0lf) {
        s = s * 0.5lf;
        kk = kk + 1.0lf;
    }
    while (kk > 0.0lf) {
        s = s * 2.0lf;
        kk = kk - 1.0lf;
    }
    return s;
}

// θ^f for f in (0, 1]: 0 where θ is not positive (the CPU's θ.max(0).powf(f)).
fn pow_frac(theta: f64, f: f64) -> f64 {
    if (!(theta > 0.0lf)) {
        return 0.0lf;
    }
    if (!(theta <= FINITE_MAX)) {
        return theta;
    }
    return soft_exp(f * soft_ln(theta));
}
