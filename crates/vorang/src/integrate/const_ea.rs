//! `constEA`: η and χ taken constant at their means, `b = η̄·(1−θ)/χ̄` (thesis 6.3.2, eq. 2.12).
//! Exact when η and χ are proportional along the segment. For `χ̄·Δs → 0` the limit
//! `b → η̄·Δs` is used (docs/optics.md).

use super::{Contribution, RuleInfo, Segment, one_minus_exp_over, theta_trapezoid};

pub const INFO: RuleInfo = RuleInfo {
    name: "constEA",
    summary: "constant emission/absorption at their means: b = η̄·(1−θ)/χ̄",
    rule,
    exact_for_linear: false,
};

pub fn rule(s: &Segment) -> Contribution {
    let theta = theta_trapezoid(s);
    let chi = 0.5 * (s.chi[0] + s.chi[1]);
    // η̄·(1−θ)/χ̄ = η̄·Δs·(1 − e^{−χ̄Δs})/(χ̄Δs)
    let f = s.ds * one_minus_exp_over(chi * s.ds);
    let b = [0, 1, 2].map(|c| 0.5 * (s.eta[0][c] + s.eta[1][c]) * f);
    (b, theta)
}
