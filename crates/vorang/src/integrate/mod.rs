//! Integration rules for one ray segment (thesis 6.3.2, docs/optics.md): the segment transparency
//! `θ = exp(−∫χ)` and intensity `b = ∫ η(s)·exp(−∫_s^{s_k} χ) ds` from the values of η and χ at
//! the segment's ends. `s_{k−1}` (index 0) is the far end, `s_k` (index 1) the near end.
//!
//! Every rule is a pure function listed once in [`RULES`]; the `method` command, help texts and
//! the tests that run over every rule read that table.

pub mod const_ea;
pub mod linear;
pub mod linear_lanes;
mod trapez;
mod weighted_const_ea;

/// η and χ at the two ends of a segment of length `ds` (world units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// η at the far end `s_{k−1}` and the near end `s_k`.
    pub eta: [[f64; 3]; 2],
    /// χ at the far and near end.
    pub chi: [f64; 2],
    pub ds: f64,
    /// η in the middle, where it varies quadratically (emission weighted by a varying
    /// absorption); only the `linear` rule uses it, the others treat η as linear.
    pub eta_mid: Option<[f64; 3]>,
}

/// `(b, θ)`: the segment's intensity (RGB, before the brightness factor) and transparency.
pub type Contribution = ([f64; 3], f64);

/// A rule: segment → contribution.
pub type Rule = fn(&Segment) -> Contribution;

/// One registry entry.
pub struct RuleInfo {
    pub name: &'static str,
    pub summary: &'static str,
    pub rule: Rule,
    /// Exact for η (up to quadratic) and χ linear along the segment: the `exact` method then
    /// cuts the ray at the maps' breakpoints and samples η in the middle of each piece.
    pub exact_for_linear: bool,
}

impl std::fmt::Debug for RuleInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name)
    }
}

impl RuleInfo {
    /// The rule applied to a segment. The closed-form `linear` rule is called directly rather
    /// than through the function pointer, so that it is inlined into the per-pixel loops that
    /// spend most of their time in it.
    #[inline]
    pub fn apply(&self, s: &Segment) -> Contribution {
        if self.name == linear::INFO.name {
            linear::rule(s)
        } else {
            (self.rule)(s)
        }
    }
}

/// Registry entries are the same rule when they have the same name.
impl PartialEq for RuleInfo {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

/// Every integration rule, in the thesis's order.
pub const RULES: &[RuleInfo] = &[
    trapez::INFO,
    const_ea::INFO,
    weighted_const_ea::INFO,
    linear::INFO,
];

/// The rule called `name`.
pub fn find(name: &str) -> Option<&'static RuleInfo> {
    RULES.iter().find(|r| r.name == name)
}

/// "trapez, constEA, …" for messages.
pub fn names() -> String {
    RULES.iter().map(|r| r.name).collect::<Vec<_>>().join(", ")
}

/// `θ = exp(−½(χ_{k−1}+χ_k)·Δs)`: the trapezoid rule on χ, shared by the thesis's three rules
/// (exact for χ linear along the segment, eq. 2.14).
#[inline]
pub fn theta_trapezoid(s: &Segment) -> f64 {
    (-0.5 * (s.chi[0] + s.chi[1]) * s.ds).exp()
}

/// `(1 − e^{−x})/x`, accurate for every `x ≥ 0` including `x → 0` (where it tends to 1).
///
/// For tiny `x` the quotient is evaluated by its series, not as `0/0` — the thesis replaced χ
/// by 1e-7 there, which wrongly gives zero emission in absorption-free regions
/// (docs/optics.md).
#[inline]
pub fn one_minus_exp_over(x: f64) -> f64 {
    if x.abs() < 1e-5 {
        // 1 − x/2 + x²/6 − x³/24: error below x⁴/120 < 1e-22.
        1.0 - x * (0.5 - x * (1.0 / 6.0 - x / 24.0))
    } else {
        -f64::exp_m1(-x) / x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact contribution of a segment with constant η and χ.
    fn exact_constant(eta: f64, chi: f64, ds: f64) -> (f64, f64) {
        let theta = (-chi * ds).exp();
        (eta * ds * one_minus_exp_over(chi * ds), theta)
    }

    #[test]
    fn every_rule_is_exact_for_constant_coefficients_up_to_its_order() {
        for info in RULES {
            for (eta, chi, ds) in [
                (1.0, 0.0, 0.5),
                (0.3, 2.0, 0.01),
                (2.0, 1.0, 1e-9),
                (0.7, 0.0, 3.0),
            ] {
                let s = Segment {
                    eta: [[eta; 3]; 2],
                    chi: [chi; 2],
                    ds,
                    eta_mid: None,
                };
                let (b, theta) = (info.rule)(&s);
                let (eb, et) = exact_constant(eta, chi, ds);
                assert!((theta - et).abs() < 1e-15, "{} θ", info.name);
                if info.name != "trapez" || chi * ds < 1e-6 || chi == 0.0 {
                    assert!(
                        (b[0] - eb).abs() <= 1e-14 * eb.max(1e-300),
                        "{}: {} vs {eb}",
                        info.name,
                        b[0]
                    );
                }
            }
        }
    }

    #[test]
    fn series_and_closed_form_agree_where_they_meet() {
        for x in [1e-6, 9.9e-6, 1.01e-5, 1e-4] {
            let closed = -f64::exp_m1(-x) / x;
            assert!((one_minus_exp_over(x) - closed).abs() < 1e-15, "{x}");
        }
        assert_eq!(one_minus_exp_over(0.0), 1.0);
        assert!((one_minus_exp_over(50.0) - 0.02).abs() < 1e-15);
    }

    #[test]
    fn registry_names_are_unique_and_found() {
        for r in RULES {
            assert_eq!(find(r.name).map(|f| f.name), Some(r.name));
        }
        assert!(find("simpson").is_none());
    }
}
