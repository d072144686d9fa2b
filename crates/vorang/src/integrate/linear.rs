//! `linear`: the exact segment integral for η and χ varying linearly along the segment
//! (thesis 6.3.3, derived there but never implemented; docs/optics.md: beyond the thesis), and for η varying
//! quadratically (ABSORPTION_WEIGHTED: a linear table times a linear χ).
//!
//! With `w ∈ [0, 1]` running from the near end (w = 0) to the far end, `c = χ_near·Δs`,
//! `a = χ_far·Δs` and `k = (a − c)/2`, the optical depth from the near end is
//! `τ(w) = c·w + k·w²` and, for `η(w) = p0 + p1·w + p2·w²`,
//!
//! ```text
//! b = Δs · (p0·J0 + p1·J1 + p2·J2),   J_n = ∫₀¹ wⁿ e^{−(c·w + k·w²)} dw,   θ = e^{−(a+c)/2}.
//! ```
//!
//! The moments `J_n` are computed in one of four ways, chosen so that nothing cancels:
//!
//! 1. **Optically thin** (total depth T = c + k ≤ 1): the Taylor series of the integrand in `w`,
//!    summed term by term — no special function at all (the fast path).
//! 2. **Quadratic term negligible where the integrand lives** (`κ = |k|/max(1, c)² ≤ 10⁻³`):
//!    the series in `k` over `E_j(c) = ∫₀¹ wʲ e^{−c·w} dw`.
//! 3. **Quadratic term dominant** (`κ ≥ 0.1`): the closed form of thesis eq. 6.3 for `J0`
//!    rewritten without overflow — `erfcx` for `k > 0` (absorption rising away from the eye),
//!    Dawson's function for `k < 0` — and the recurrences `c·J0 + 2k·J1 = 1 − e^{−T}`,
//!    `c·J1 + 2k·J2 = J0 − e^{−T}`, which lose at most about a digit there.
//! 4. **In between**: the segment is cut into pieces of optical depth ≤ 1 and each is summed as in
//!    1 (all terms positive), stopping where the remaining light is below 10⁻¹⁹ of the total.

use errorfunctions::RealErrorFunctions;

use super::{Contribution, RuleInfo, Segment};

pub const INFO: RuleInfo = RuleInfo {
    name: "linear",
    summary: "exact for η and χ linear along the segment (η may be quadratic): closed form with erfcx/Dawson",
    rule,
    exact_for_linear: true,
};

const SQRT_PI: f64 = 1.772_453_850_905_516;

/// The segment's contribution. `s.eta_mid`, if given, makes η quadratic through the middle value.
/// Negative absorption (unphysical) is treated as zero.
pub fn rule(s: &Segment) -> Contribution {
    let l = s.ds;
    let a = (s.chi[0] * l).max(0.0);
    let c = (s.chi[1] * l).max(0.0);
    let theta = (-0.5 * (a + c)).exp();
    let (far, near) = (s.eta[0], s.eta[1]);
    let b = match s.eta_mid {
        None => {
            // η linear: only J0 and J1 are needed.
            let j = if c + 0.5 * (a - c) <= 1.0 {
                taylor::<false>(c, 0.5 * (a - c))
            } else {
                moments(c, 0.5 * (a - c))
            };
            let ch = |ch: usize| l * (near[ch] * j[0] + (far[ch] - near[ch]) * j[1]);
            [ch(0), ch(1), ch(2)]
        }
        Some(mid) => {
            let j = moments(c, 0.5 * (a - c));
            let ch = |ch: usize| {
                let p1 = -3.0 * near[ch] + 4.0 * mid[ch] - far[ch];
                let p2 = 2.0 * near[ch] - 4.0 * mid[ch] + 2.0 * far[ch];
                l * (near[ch] * j[0] + p1 * j[1] + p2 * j[2])
            };
            [ch(0), ch(1), ch(2)]
        }
    };
    (b, theta)
}

/// `[J0, J1, J2]` with `J_n = ∫₀¹ wⁿ exp(−(c·w + k·w²)) dw`, for `c ≥ 0` and `c + 2k ≥ 0`.
pub fn moments(c: f64, k: f64) -> [f64; 3] {
    let total = c + k;
    if total <= 1.0 {
        return taylor::<true>(c, k);
    }
    let kappa = k.abs() / c.max(1.0).powi(2);
    if kappa <= 1e-3 {
        k_series(c, k, kappa)
    } else if kappa >= 0.01 {
        closed(c, k)
    } else {
        pieces(c, k)
    }
}

/// `1/m` for the series' denominators, so that the loops multiply instead of divide.
const RECIPROCAL: [f64; 96] = {
    let mut r = [0.0; 96];
    let mut m = 1;
    while m < 96 {
        r[m] = 1.0 / m as f64;
        m += 1;
    }
    r
};

/// Regime 1: `e^{−(c·w + k·w²)} = Σ q_j wʲ` with `(j+1)·q_{j+1} = −c·q_j − 2k·q_{j−1}`, so
/// `J_n = Σ q_j/(n + j + 1)`. For `|c| + |k| ≲ 2` the terms fall like `2ʲ/j!`.
/// Without `J2`, the sums for it are skipped (and it is returned as 0).
#[inline]
fn taylor<const J2: bool>(c: f64, k: f64) -> [f64; 3] {
    // The series is a chain and its latency is the cost, so it advances two terms per step:
    // with α_n = −c/(n+1) and β_n = −2k/(n+1),
    //   q_{n+1} = α_n·q_n + β_n·q_{n−1},
    //   q_{n+2} = (α_{n+1}·α_n + β_{n+1})·q_n + α_{n+1}·β_n·q_{n−1},
    // both from the same pair, with coefficients that do not wait for the chain. Odd and even
    // terms go to separate sums for the same reason.
    let (c2, ck) = (c * c, c * k);
    let (mut prev, mut q) = (0.0, 1.0); // q_{n−1}, q_n
    let mut even = [1.0, 0.5, 1.0 / 3.0];
    let mut odd = [0.0; 3];
    let mut n = 0;
    while n < 88 {
        let (r1, r2) = (RECIPROCAL[n + 1], RECIPROCAL[n + 2]);
        let (a0, b0) = (-c * r1, -2.0 * k * r1);
        let a = c2 * r1 * r2 - 2.0 * k * r2;
        let b = 2.0 * ck * r1 * r2;
        let q1 = a0 * q + b0 * prev;
        let q2 = a * q + b * prev;
        odd[0] += q1 * RECIPROCAL[n + 2];
        odd[1] += q1 * RECIPROCAL[n + 3];
        even[0] += q2 * RECIPROCAL[n + 3];
        even[1] += q2 * RECIPROCAL[n + 4];
        if J2 {
            odd[2] += q1 * RECIPROCAL[n + 4];
            even[2] += q2 * RECIPROCAL[n + 5];
        }
        prev = q1;
        q = q2;
        n += 2;
        // Two small coefficients in a row end it (one alone may be zero, e.g. q₁ = −c = 0).
        // J2 ≤ J1, and within a small factor of J1/2 for these thin segments: as good a
        // scale, and there also without J2.
        let small = 0.5e-17 * (even[1] + odd[1]).abs();
        if q.abs() <= small && prev.abs() <= small {
            break;
        }
    }
    let j2 = if J2 { even[2] + odd[2] } else { 0.0 };
    [even[0] + odd[0], even[1] + odd[1], j2]
}

/// `E_j(c) = ∫₀¹ wʲ e^{−c·w} dw` for `j = 0 ..= jmax` (`c ≥ 0`).
fn exp_moments(c: f64, jmax: usize, out: &mut [f64]) {
    let e = (-c).exp();
    if c > jmax as f64 + 1.0 {
        // Upward recurrence E_j = (j·E_{j−1} − e^{−c})/c: errors shrink by j/c < 1 per step.
        out[0] = -f64::exp_m1(-c) / c;
        for j in 1..=jmax {
            out[j] = (j as f64 * out[j - 1] - e) / c;
        }
    } else {
        // E_jmax = e^{−c} Σ cⁱ / ((jmax+1)…(jmax+i+1)) (positive terms), then downward
        // E_{j−1} = (c·E_j + e^{−c})/j, stable for c < j.
        let mut term = 1.0 / (jmax as f64 + 1.0);
        let mut sum = term;
        let mut i = 0.0;
        while term > 1e-19 * sum {
            i += 1.0;
            term *= c / (jmax as f64 + 1.0 + i);
            sum += term;
        }
        out[jmax] = e * sum;
        for j in (1..=jmax).rev() {
            out[j - 1] = (c * out[j] + e) / j as f64;
        }
    }
}

/// Regime 2: `J_n = Σ_m (−k)^m/m! · E_{n+2m}(c)`. The terms fall at least like
/// `κ^m·(2m)!/m!`, which fixes how many are needed.
fn k_series(c: f64, k: f64, kappa: f64) -> [f64; 3] {
    let terms_needed = match kappa {
        0.0 => 0,
        x if x < 1e-12 => 2,
        x if x < 1e-8 => 3,
        x if x < 1e-6 => 5,
        x if x < 1e-5 => 6,
        x if x < 1e-4 => 8,
        _ => 11,
    };
    let mut e = [0.0; 27];
    exp_moments(c, 2 * terms_needed + 2, &mut e);
    let mut j = [0.0; 3];
    let mut factor = 1.0;
    for m in 0..=terms_needed {
        if m > 0 {
            factor *= -k / m as f64;
        }
        let terms = [
            factor * e[2 * m],
            factor * e[2 * m + 1],
            factor * e[2 * m + 2],
        ];
        for n in 0..3 {
            j[n] += terms[n];
        }
        if terms
            .iter()
            .zip(&j)
            .all(|(t, s)| t.abs() <= 1e-19 * s.abs())
        {
            break;
        }
    }
    j
}

/// Regime 3: the closed form. For k > 0, with s = √k, z₀ = c/(2s), z₁ = z₀ + s:
/// `J0 = √π/(2s) · (erfcx(z₀) − e^{−T}·erfcx(z₁))`; for k < 0, with s = √−k, x₀ = c/(2s),
/// x₁ = x₀ − s ≥ 0: `J0 = (D(x₀) − e^{−T}·D(x₁))/s` (D: Dawson's function). J1, J2 follow from
/// integrating `(c + 2k·w)·wⁿ·e^{−τ}` by parts.
fn closed(c: f64, k: f64) -> [f64; 3] {
    let total = c + k;
    let e = (-total).exp();
    let j0 = if k > 0.0 {
        let s = k.sqrt();
        let z0 = c / (2.0 * s);
        let z1 = z0 + s;
        SQRT_PI / (2.0 * s) * (z0.erfcx() - e * z1.erfcx())
    } else {
        let s = (-k).sqrt();
        let x0 = c / (2.0 * s);
        let x1 = (x0 - s).max(0.0);
        (x0.dawson() - e * x1.dawson()) / s
    };
    let j1 = (-f64::exp_m1(-total) - c * j0) / (2.0 * k);
    let j2 = (j0 - e - c * j1) / (2.0 * k);
    [j0, j1, j2]
}

/// Regime 4: pieces of optical depth ≤ 1, each summed by the Taylor series. With the piece
/// `[w_i, w_i + H]`, `τ(w_i + H·x) = τ_i + b·x + q·x²` (`b = τ'(w_i)·H`, `q = k·H²`) and
/// `(w_i + H·x)ⁿ` expanded binomially, every term is positive.
fn pieces(c: f64, k: f64) -> [f64; 3] {
    let mut j = [0.0; 3];
    let mut w = 0.0f64;
    let mut tau = 0.0f64;
    while w < 1.0 && tau < 45.0 {
        let slope = c + 2.0 * k * w;
        let rest = 1.0 - w;
        // The largest H whose optical depth slope·H + k·H² stays ≤ 1.
        let h = if k > 0.0 {
            2.0 / (slope + (slope * slope + 4.0 * k).sqrt())
        } else {
            (1.0 / slope.max(1e-300)).min(1.0 / (-k).sqrt().max(1e-300))
        }
        .min(rest);
        let m = taylor::<true>(slope * h, k * h * h);
        let weight = (-tau).exp() * h;
        j[0] += weight * m[0];
        j[1] += weight * (w * m[0] + h * m[1]);
        j[2] += weight * (w * w * m[0] + 2.0 * w * h * m[1] + h * h * m[2]);
        tau += slope * h + k * h * h;
        w += h;
    }
    j
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::SplitMix64;

    /// ∫₀¹ f(w)·e^{−(c·w + k·w²)} dw by 10-point Gauss–Legendre on panels of optical depth
    /// ≤ 0.25 (where the rule's error is far below f64 rounding), up to depth 60 (beyond which
    /// less than e⁻⁶⁰ of the light is left).
    fn panels(f: &dyn Fn(f64) -> f64, c: f64, k: f64) -> f64 {
        let tau = |w: f64| c * w + k * w * w;
        let mut total = 0.0;
        let mut w = 0.0f64;
        while w < 1.0 && tau(w) < 60.0 {
            // Depth over the panel ≤ τ'(w)·h + |k|·h² ≤ 0.5.
            let slope = (c + 2.0 * k * w).max(0.0);
            let h = (0.25 / slope.max(1e-300))
                .min((0.25 / k.abs().max(1e-300)).sqrt())
                .min(1.0 - w);
            total += crate::reference::GL
                .iter()
                .map(|&(x, wt)| wt * f(w + x * h) * (-tau(w + x * h)).exp())
                .sum::<f64>()
                * h;
            w += h;
        }
        total
    }

    /// The segment integral straight from its definition, by composite quadrature in f64.
    fn reference(s: &Segment) -> ([f64; 3], f64) {
        let l = s.ds;
        let (a, c) = (s.chi[0] * l, s.chi[1] * l);
        let k = 0.5 * (a - c);
        let eta = |w: f64, ch: usize| {
            let (n, f) = (s.eta[1][ch], s.eta[0][ch]);
            match s.eta_mid {
                None => n + (f - n) * w,
                Some(m) => {
                    let m = m[ch];
                    // Lagrange through w = 0, ½, 1.
                    n * 2.0 * (w - 0.5) * (w - 1.0) - m * 4.0 * w * (w - 1.0)
                        + f * 2.0 * w * (w - 0.5)
                }
            }
        };
        let b = std::array::from_fn(|ch| l * panels(&|w| eta(w, ch), c, k));
        (b, (-0.5 * (a + c)).exp())
    }

    fn check(s: &Segment) -> f64 {
        let (b, theta) = rule(s);
        let (rb, rt) = reference(s);
        assert!(
            (theta - rt).abs() <= 1e-15 * rt.max(1e-300) + 1e-300,
            "θ {theta} vs {rt} for {s:?}"
        );
        let mut worst = 0.0f64;
        for ch in 0..3 {
            let err = (b[ch] - rb[ch]).abs() / rb[ch].abs().max(1e-300);
            worst = worst.max(if rb[ch] == 0.0 && b[ch].abs() < 1e-300 {
                0.0
            } else {
                err
            });
        }
        worst
    }

    #[test]
    fn matches_adaptive_quadrature_over_ten_thousand_random_segments() {
        let mut rng = SplitMix64(2024);
        let mut worst = (0.0, None);
        let mut n = 0;
        for i in 0..12_000 {
            // χ from 0 to 10³ per unit length (log-uniform above 1e-6), with exact zeros and equal
            // ends; lengths from 1e-9 to 10.
            let mut chi = || match rng.next_u64() % 8 {
                0 => 0.0,
                _ => 10f64.powf(rng.next_f64() * 9.0 - 6.0),
            };
            let (mut c0, c1) = (chi(), chi());
            if i % 10 == 0 {
                c0 = c1;
            }
            let ds = 10f64.powf(rng.next_f64() * 10.0 - 9.0);
            let mut eta = || [rng.next_f64(), rng.next_f64() * 2.0, 0.0];
            let (mut far, near) = (eta(), eta());
            if i % 7 == 0 {
                far = near;
            }
            let eta_mid = (i % 3 == 0).then(|| {
                [0, 1, 2]
                    .map(|ch| 0.5 * (far[ch] + near[ch]) + 0.2 * (rng.next_f64() - 0.3))
                    .map(|v: f64| v.max(0.0))
            });
            let s = Segment {
                eta: [far, near],
                chi: [c0, c1],
                ds,
                eta_mid,
            };
            let err = check(&s);
            if err > worst.0 {
                worst = (err, Some(s));
            }
            n += 1;
        }
        assert!(n >= 10_000);
        eprintln!(
            "linear rule vs quadrature, {n} segments: worst relative error {:e}",
            worst.0
        );
        assert!(
            worst.0 <= 1e-12,
            "worst relative error {:e} for {:?}",
            worst.0,
            worst.1
        );
    }

    #[test]
    fn every_regime_and_its_borders() {
        // (χ_far·Δs, χ_near·Δs) picked to land in each regime and next to each switch.
        let cases = [
            (0.0, 0.0),
            (1e-300, 0.0),
            (0.0, 2.0),
            (2.0, 0.0),
            (1.0, 1.0),
            (0.99, 1.01),
            (2.0000001, 1.9999999),
            (50.0, 50.0),
            (1e4, 1e4),
            (1e4, 1.001e4),
            (1.2e4, 1e4),
            (3e4, 1e4),
            (2e6, 1e4),
            (1e4, 1e6),
            (0.0, 1e4),
            (1e4, 0.0),
            (30.0, 0.0),
            (0.0, 30.0),
            (5.0, 3.0),
            (3.0, 5.0),
            (8.0, 2.0),
            (200.0, 10.0),
            (20.5, 10.0),
            (10.0, 30.0),
        ];
        for (a, c) in cases {
            for mid in [None, Some([0.3, 0.0, 1.7])] {
                let s = Segment {
                    eta: [[1.0, 0.5, 2.0], [0.2, 1.5, 0.0]],
                    chi: [a, c],
                    ds: 1.0,
                    eta_mid: mid,
                };
                let err = check(&s);
                assert!(
                    err <= 1e-12,
                    "χΔs far {a}, near {c}: relative error {err:e}"
                );
            }
        }
    }

    #[test]
    fn limits_are_the_analytic_ones() {
        // No absorption: b = Δs·(η_far + η_near)/2.
        let s = Segment {
            eta: [[1.0; 3], [3.0; 3]],
            chi: [0.0; 2],
            ds: 0.5,
            eta_mid: None,
        };
        assert_eq!(rule(&s).0, [1.0; 3]);
        // Constant χ and η: η/χ·(1 − e^{−χΔs}).
        let s = Segment {
            eta: [[2.0; 3], [2.0; 3]],
            chi: [4.0; 2],
            ds: 0.3,
            eta_mid: None,
        };
        assert!((rule(&s).0[0] - 0.5 * (1.0 - (-1.2f64).exp())).abs() < 1e-15);
        // Zero length.
        let s = Segment {
            eta: [[2.0; 3], [2.0; 3]],
            chi: [4.0; 2],
            ds: 0.0,
            eta_mid: None,
        };
        assert_eq!(rule(&s), ([0.0; 3], 1.0));
        // Huge depth: only the first 1/χ near the eye counts: b → η_near/χ + (η_far − η_near)/χ².
        let s = Segment {
            eta: [[9.0; 3], [2.0; 3]],
            chi: [1e6, 1e6],
            ds: 1.0,
            eta_mid: None,
        };
        let b = rule(&s).0[0];
        assert!((b - (2e-6 + 7e-12)).abs() < 1e-20, "{b}");
    }
}
