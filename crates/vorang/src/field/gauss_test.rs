//! `GaussTest(@extradata float[5])`: an analytic test field independent of the mesh (thesis
//! B.2): `f(x) = Σ a·exp(−|x−c|²/ρ²)` over the rows `(cx, cy, cz, ρ, a)`, evaluated in the file's
//! own coordinates (thesis appendix B, docs/formats.md).

use super::{InterpolatorInfo, Sources};
use crate::data::{ElementKind, RawData};

pub const INFO: InterpolatorInfo = InterpolatorInfo {
    interpolator: super::Interpolator::GaussTest,
    name: "GaussTest",
    summary: "sum of Gaussians a·exp(-|x-c|²/ρ²) from ExtraData rows (cx cy cz ρ a)",
    signature: "GaussTest(@extradata)",
    required: &[ElementKind::Extra],
    optional: &[],
    check,
};

fn check(s: &Sources) -> Result<(), String> {
    let raw = s.raw[0];
    if raw.ty.components() != 5
        || raw.ty.scalar.is_integer()
        || raw.ty.scalar == crate::data::ScalarType::Complex
    {
        return Err(format!(
            "GaussTest needs ExtraData float[5] rows (cx cy cz ρ a), found {}",
            raw.ty
        ));
    }
    if s.ty.components() != 1 {
        return Err(format!(
            "GaussTest gives a scalar field; declare it float or double, not {}",
            s.ty
        ));
    }
    for e in 0..raw.elements() {
        if raw.value(e, 3) == 0.0 {
            return Err(format!(
                "GaussTest: row {} has ρ = 0; ρ must be non-zero",
                e + 1
            ));
        }
    }
    Ok(())
}

pub fn eval(raw: &RawData, p: [f64; 3]) -> f64 {
    (0..raw.elements())
        .map(|e| {
            let d2: f64 = (0..3).map(|k| (p[k] - raw.value(e, k)).powi(2)).sum();
            let rho = raw.value(e, 3);
            raw.value(e, 4) * (-d2 / (rho * rho)).exp()
        })
        .sum()
}
