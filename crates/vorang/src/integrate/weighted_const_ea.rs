//! `weightedConstEA`: as constEA, but the emission mean weighs the far end by θ:
//! `η̄ = η_{k−1}·θ + η_k·(1−θ)` (thesis 6.3.2). Better for coherent opaque regions, where only
//! the front emission is seen; loses constEA's exactness for proportional η and χ.

use super::{Contribution, RuleInfo, Segment, one_minus_exp_over, theta_trapezoid};

pub const INFO: RuleInfo = RuleInfo {
    name: "weightedConstEA",
    summary: "as constEA with η̄ = η_far·θ + η_near·(1−θ)",
    rule,
    exact_for_linear: false,
};

pub fn rule(s: &Segment) -> Contribution {
    let theta = theta_trapezoid(s);
    let chi = 0.5 * (s.chi[0] + s.chi[1]);
    let f = s.ds * one_minus_exp_over(chi * s.ds);
    let b = [0, 1, 2].map(|c| (s.eta[0][c] * theta + s.eta[1][c] * (1.0 - theta)) * f);
    (b, theta)
}
