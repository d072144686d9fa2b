//! The `linear` rule for optically thin segments in SIMD lanes: the moments `J0`, `J1` and the
//! transparency `θ` of [`super::linear`] for several segments at once, with a series length
//! fixed in advance — no per-lane loop condition, no `exp`, so the compiler keeps every lane busy.
//!
//! With `c = χ_near·Δs`, `a = χ_far·Δs` (both ≥ 0) and `d = a − c = 2k`, the integrand
//! `e^{−(c·w + k·w²)} = Σ q_j wʲ` has `(j+1)·q_{j+1} = −c·q_j − d·q_{j−1}` (`q_0 = 1`), and
//! `J_n = Σ q_j/(n + j + 1)`. The transparency follows from the moments without `exp`:
//! integrating `d/dw e^{−(c·w + k·w²)} = −(c + d·w)·e^{…}` over `[0, 1]` gives
//! `θ = e^{−T} = 1 − (c·J0 + d·J1)`.
//!
//! **How many terms.** If every segment of a batch has `a, c ≤ B`, then `|c| ≤ B` and
//! `|k| ≤ B/2`, so the coefficients are bounded term by term by those of the majorant
//! `e^{B·w + (B/2)·w²}`: `|q_j| ≤ M_j` with `(j+1)·M_{j+1} = B·M_j + B·M_{j−1}`, `M_0 = 1`
//! (the exponential of a series with non-negative coefficients dominates the exponential of any
//! series whose coefficients are smaller in magnitude). [`terms_for`] returns the smallest `N`
//! with `Σ_{j>N} M_j ≤ 2⁻⁵³` (the unit roundoff of f64, against `J0 ≥ e^{−B} > 0.6`), which
//! bounds the truncation error of both moments and of θ by `(1 + 2B)·2⁻⁵³ ≤ 2⁻⁵²` — the size
//! of the rounding the sums make anyway, so more terms would not change the results beyond it
//! (2⁻⁶⁰ before: one to two more terms per segment, about 3.5 % of an `exact` frame, for
//! digits the arithmetic does not keep). The bound is computed once per cell from
//! the cell's largest absorption and depth extent, so lanes never disagree about the loop length.
//! Batches with `B > `[`MAX_DEPTH`] go to the scalar rule. Where the absorption changes little
//! along the segments, a smaller bound `K` on `|k|` gives the majorant `e^{B·w + K·w²}` and a
//! shorter series (often 5–8 terms instead of 10–17).

/// The largest bound `B` on a segment's end optical depths `χ·Δs` handled in lanes (the series
/// then needs at most [`MAX_TERMS`] terms).
pub const MAX_DEPTH: f64 = 0.5;

/// The longest series [`terms_for`] asks for (at `B = MAX_DEPTH`).
pub const MAX_TERMS: usize = 32;

/// `1/m`, so that the series multiplies instead of divides.
const RECIPROCAL: [f64; MAX_TERMS + 4] = {
    let mut r = [0.0; MAX_TERMS + 4];
    let mut m = 1;
    while m < r.len() {
        r[m] = 1.0 / m as f64;
        m += 1;
    }
    r
};

/// The tail bound `Σ_{j>N} M_j` must stay below this.
const TAIL: f64 = 1.0 / (1u64 << 53) as f64;

/// The number of series terms after `q_0` that bounds the truncation error by `2⁻⁵³` for every
/// segment with `a, c ≤ depth` and `|k| = |a − c|/2 ≤ slope` (the change of the optical depth
/// along the segment, often far below `depth/2`); `None` for `depth` above [`MAX_DEPTH`] or NaN.
/// Both bounds are rounded up to powers of two and the count looked up (a per-cell call must be
/// cheap).
pub fn terms_for(depth: f64, slope: f64) -> Option<usize> {
    if depth.is_nan() || slope.is_nan() || depth > MAX_DEPTH {
        return None;
    }
    static TABLE: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    let table = TABLE.get_or_init(|| {
        let mut t = Vec::with_capacity(POWERS * POWERS);
        for ec in 0..POWERS {
            for ek in 0..POWERS {
                let (c, k) = (power(ec), power(ek));
                t.push(terms_exact(c, k.min(0.5 * c)) as u8);
            }
        }
        t
    });
    // Half the depth bounds |k| anyway.
    let slope = slope.min(0.5 * depth);
    Some(table[index(depth) * POWERS + index(slope)] as usize)
}

/// Bounds tabulated by [`terms_for`]: `2⁻ᵉ` for `e = 0 … POWERS − 2`, and 0 as the last entry.
const POWERS: usize = 66;

fn power(e: usize) -> f64 {
    if e + 1 == POWERS {
        0.0
    } else {
        0.5f64.powi(e as i32)
    }
}

/// The entry of the smallest tabulated bound at least `x` (`0 ≤ x ≤ 1`).
fn index(x: f64) -> usize {
    if x <= 0.0 {
        return POWERS - 1;
    }
    let exp = ((x.to_bits() >> 52) & 0x7ff) as i64 - 1023;
    // x ∈ [2^exp, 2^(exp+1)): the bound 2^-e with e = −exp if x is that power, else −exp − 1;
    // below 2^-(POWERS−2) (and subnormals) the smallest nonzero entry, which still bounds x.
    // A power of two has no mantissa bits (read from the bits: `powi` is a library call).
    let e = if x.to_bits() & ((1 << 52) - 1) == 0 {
        -exp
    } else {
        -exp - 1
    };
    e.clamp(0, POWERS as i64 - 2) as usize
}

/// The term count for the majorant `e^{c·w + k·w²}` (`c ≥ 0`, `k ≥ 0`):
/// `(j+1)·M_{j+1} = c·M_j + 2k·M_{j−1}`.
fn terms_exact(c: f64, k: f64) -> usize {
    // Far enough to see the tail: beyond j = 2(c + 2k) + 2 the coefficients fall faster than
    // 2⁻ʲ, so the terms summed here bound the tail up to a factor 2.
    let mut m = [0.0f64; 64];
    m[0] = 1.0;
    for j in 0..63 {
        let prev = if j == 0 { 0.0 } else { m[j - 1] };
        m[j + 1] = (c * m[j] + 2.0 * k * prev) / (j + 1) as f64;
    }
    let mut tail = 2.0 * m[63];
    for n in (0..63).rev() {
        // `tail` is Σ_{j>n} M_j (up to the factor-2 allowance for j ≥ 64).
        tail += m[n + 1];
        if tail > TAIL {
            return (n + 1).min(MAX_TERMS);
        }
    }
    0
}

/// `a·b + c`: one fused multiply-add where `FMA` (the kernels compiled for processors that have
/// it), else a product and a sum (the baseline). The fused form rounds once instead of twice.
#[inline(always)]
pub fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA { a.mul_add(b, c) } else { a * b + c }
}

/// `(J0, J1, θ)` for `L` segments with end optical depths `c` (near) and `a = c + d` (far), using
/// `terms` series terms (from [`terms_for`]).
#[inline(always)]
pub fn moments<const L: usize>(
    c: &[f64; L],
    d: &[f64; L],
    terms: usize,
) -> ([f64; L], [f64; L], [f64; L]) {
    moments_with::<L, false>(c, d, terms)
}

/// [`moments`] with fused multiply-adds where `FMA` (only for code compiled with the `fma`
/// target feature: elsewhere `mul_add` is a slow library call).
#[inline(always)]
pub fn moments_with<const L: usize, const FMA: bool>(
    c: &[f64; L],
    d: &[f64; L],
    terms: usize,
) -> ([f64; L], [f64; L], [f64; L]) {
    let mut prev = [0.0; L];
    let mut q = [1.0; L];
    let mut j0 = [1.0; L];
    let mut j1 = [0.5; L];
    for j in 0..terms.min(MAX_TERMS) {
        let (r, r0, r1) = (RECIPROCAL[j + 1], RECIPROCAL[j + 2], RECIPROCAL[j + 3]);
        for l in 0..L {
            let next = madd::<FMA>(-c[l], q[l], -(d[l] * prev[l])) * r;
            j0[l] = madd::<FMA>(next, r0, j0[l]);
            j1[l] = madd::<FMA>(next, r1, j1[l]);
            prev[l] = q[l];
            q[l] = next;
        }
    }
    let mut theta = [0.0; L];
    for l in 0..L {
        theta[l] = (1.0 - madd::<FMA>(c[l], j0[l], d[l] * j1[l])).min(1.0);
    }
    (j0, j1, theta)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Segment;
    use crate::integrate::linear::rule;

    /// Independent reference: Gauss–Legendre quadrature of the moments in f64 on 64 sub-intervals
    /// (the integrand is entire and varies by at most e^{1.5} here).
    fn quadrature(c: f64, k: f64) -> [f64; 2] {
        const X: [f64; 5] = [
            -0.906_179_845_938_664,
            -0.538_469_310_105_683_1,
            0.0,
            0.538_469_310_105_683_1,
            0.906_179_845_938_664,
        ];
        const W: [f64; 5] = [
            0.236_926_885_056_189_1,
            0.478_628_670_499_366_5,
            128.0 / 225.0,
            0.478_628_670_499_366_5,
            0.236_926_885_056_189_1,
        ];
        let n = 64;
        let mut j = [0.0; 2];
        for i in 0..n {
            let (lo, h) = (i as f64 / n as f64, 1.0 / n as f64);
            for (x, w) in X.iter().zip(W) {
                let t = lo + 0.5 * h * (x + 1.0);
                let f = (-(c * t + k * t * t)).exp() * 0.5 * h * w;
                j[0] += f;
                j[1] += t * f;
            }
        }
        j
    }

    #[test]
    fn the_term_count_grows_with_the_bound() {
        assert_eq!(terms_for(0.0, 0.0), Some(0));
        assert_eq!(terms_for(f64::NAN, 0.0), None);
        assert_eq!(terms_for(2.0 * MAX_DEPTH, 0.0), None);
        let n: Vec<usize> = [1e-12, 1e-6, 1e-3, 0.1, MAX_DEPTH]
            .iter()
            .map(|&b| terms_for(b, b).unwrap())
            .collect();
        assert!(n.windows(2).all(|w| w[0] <= w[1]), "{n:?}");
        assert!(n[4] <= MAX_TERMS && n[0] >= 1, "{n:?}");
        // A small change of the depth along the segment needs fewer terms.
        assert!(terms_for(1e-3, 1e-9).unwrap() < terms_for(1e-3, 5e-4).unwrap());
        // The table lookup never asks for fewer terms than the bounds themselves need.
        for i in 0..1500 {
            let c = 1e-20 * 1.03f64.powi(i);
            if c > MAX_DEPTH {
                break;
            }
            for k in [0.0, 1e-3 * c, 0.1 * c, 0.5 * c] {
                assert!(terms_for(c, k).unwrap() >= terms_exact(c, k), "{c} {k}");
            }
        }
        let worst = terms_exact(MAX_DEPTH, 0.5 * MAX_DEPTH);
        assert_eq!(terms_for(MAX_DEPTH, MAX_DEPTH), Some(worst));
        assert!(worst < MAX_TERMS);
    }

    #[test]
    fn lanes_agree_with_quadrature_and_the_scalar_rule() {
        // Every combination of end depths on a grid up to each bound, including the extremes.
        for bound in [1e-9, 1e-5, 1e-3, 0.05, 0.3, MAX_DEPTH] {
            let terms = terms_for(bound, 0.5 * bound).unwrap();
            let grid: Vec<f64> = (0..=8).map(|i| bound * i as f64 / 8.0).collect();
            for &a in &grid {
                let c = [
                    grid[0], grid[1], grid[3], grid[5], grid[7], grid[8], 0.0, bound,
                ];
                let d = c.map(|c| a - c);
                // Fused multiply-adds (the AVX kernels) round differently, not worse.
                let (j0, j1, theta) = moments(&c, &d, terms);
                let fused = moments_with::<8, true>(&c, &d, terms);
                for l in 0..8 {
                    let q = quadrature(c[l], 0.5 * d[l]);
                    assert!((fused.0[l] - q[0]).abs() < 2e-15, "J0 fused {bound} {a}");
                    assert!((fused.1[l] - q[1]).abs() < 2e-15, "J1 fused {bound} {a}");
                    let t = (-(c[l] + 0.5 * d[l])).exp();
                    assert!((fused.2[l] - t).abs() < 4e-16, "θ fused {bound} {a}");
                }
                for l in 0..8 {
                    let k = 0.5 * d[l];
                    let q = quadrature(c[l], k);
                    assert!((j0[l] - q[0]).abs() < 2e-15, "J0 {bound} {a} {}", c[l]);
                    assert!((j1[l] - q[1]).abs() < 2e-15, "J1 {bound} {a} {}", c[l]);
                    let t = (-(c[l] + k)).exp();
                    assert!((theta[l] - t).abs() < 4e-16, "θ {bound} {a} {}", c[l]);
                    // The scalar rule with ds = 1 and η = (far 0, near 1): b = J0 − J1.
                    let s = Segment {
                        eta: [[0.0; 3], [1.0; 3]],
                        chi: [a, c[l]],
                        ds: 1.0,
                        eta_mid: None,
                    };
                    let (b, th) = rule(&s);
                    assert!(
                        (b[0] - (j0[l] - j1[l])).abs() < 2e-15,
                        "{bound} {a} {}",
                        c[l]
                    );
                    assert!((th - theta[l]).abs() < 1e-15);
                }
            }
        }
    }

    #[test]
    fn a_small_change_along_the_segment_keeps_the_accuracy() {
        for bound in [1e-6, 1e-3, 0.05, MAX_DEPTH] {
            for kb in [1e-12 * bound, 1e-4 * bound, 0.01 * bound] {
                let terms = terms_for(bound, kb).unwrap();
                let c: [f64; 8] =
                    std::array::from_fn(|l| 2.0 * kb + (bound - 4.0 * kb) * l as f64 / 7.0);
                for sign in [-1.0, 1.0] {
                    let d = [2.0 * kb * sign; 8];
                    let (j0, j1, theta) = moments(&c, &d, terms);
                    for l in 0..8 {
                        let q = quadrature(c[l], 0.5 * d[l]);
                        assert!((j0[l] - q[0]).abs() < 2e-15, "{bound} {kb} {}", c[l]);
                        assert!((j1[l] - q[1]).abs() < 2e-15, "{bound} {kb} {}", c[l]);
                        let t = (-(c[l] + 0.5 * d[l])).exp();
                        assert!((theta[l] - t).abs() < 4e-16);
                    }
                }
            }
        }
    }

    #[test]
    fn half_the_terms_are_not_enough_at_the_bound() {
        // The count is not generous by accident: absorption rising away from the eye from 0 to
        // the bound (k = B/2, the slowest series) needs them.
        let bound = MAX_DEPTH;
        let n = terms_for(bound, 0.5 * bound).unwrap();
        let (c, d) = ([0.0; 1], [bound; 1]);
        let q = quadrature(0.0, 0.5 * bound);
        let (j0, ..) = moments(&c, &d, n / 2);
        assert!((j0[0] - q[0]).abs() > 1e-12);
        let (j0, ..) = moments(&c, &d, n);
        assert!((j0[0] - q[0]).abs() < 2e-15);
    }
}
