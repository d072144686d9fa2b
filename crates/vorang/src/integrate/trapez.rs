//! `trapez`: `b = ½(η_{k−1}·θ + η_k)·Δs` (thesis eq. 2.15). Cheap, but for opaque regions and
//! long segments it darkens cell borders, where Δs → 0 while the opacity stays large (6.3.2).

use super::{Contribution, RuleInfo, Segment, theta_trapezoid};

pub const INFO: RuleInfo = RuleInfo {
    name: "trapez",
    summary: "trapezoid rule: b = ½(η_far·θ + η_near)·Δs",
    rule,
    exact_for_linear: false,
};

pub fn rule(s: &Segment) -> Contribution {
    let theta = theta_trapezoid(s);
    let b = [0, 1, 2].map(|c| 0.5 * (s.eta[0][c] * theta + s.eta[1][c]) * s.ds);
    (b, theta)
}
