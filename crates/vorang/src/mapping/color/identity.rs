//! `IDENTITY` (no block): a float[3] field is the emission itself.
//!
//! Emission is light added along the ray, so it cannot be negative: a negative component is
//! clamped to 0 where the colour is evaluated (at the rule's sample points), and counted (beyond
//! rounding), so that a render can warn once how many values it clamped
//! ([`ColorShading::take_clamped`]).

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::mapping::block::{BlockError, ParamBlock};
use crate::mapping::{ColorShading, FieldNeed, MethodInfo, Point, Shape};

pub const INFO: MethodInfo<dyn ColorShading> = MethodInfo {
    name: "IDENTITY",
    summary: "a float[3] field used directly as the RGB emission (negative components count as 0, with one warning per render)",
    params: "no block",
    needs_block: false,
    build,
};

/// Negative values smaller than this fraction of the largest component (or of 1) are rounding.
const ROUNDING: f64 = 1e-9;

#[derive(Debug, Default)]
pub struct Identity {
    /// Evaluations with a negative component since the last [`ColorShading::take_clamped`].
    clamped: AtomicU64,
}

fn build(_: Option<&ParamBlock>) -> Result<Arc<dyn ColorShading>, BlockError> {
    Ok(Arc::new(Identity::default()))
}

impl ColorShading for Identity {
    fn color(&self, p: &Point, _: f64) -> [f64; 3] {
        let v = [p.value[0], p.value[1], p.value[2]];
        // Interpolating non-negative node values can round to −10⁻¹⁷: clamped, but not worth
        // a warning. Only values negative beyond rounding are counted.
        let scale = v.iter().fold(1.0f64, |m, c| m.max(c.abs()));
        if v.iter().any(|&c| c < -ROUNDING * scale) {
            self.clamped.fetch_add(1, Ordering::Relaxed);
        }
        v.map(|c| c.max(0.0))
    }
    fn take_clamped(&self) -> u64 {
        self.clamped.swap(0, Ordering::Relaxed)
    }
    fn field_need(&self) -> FieldNeed {
        FieldNeed::Components(3)
    }
    fn shape(&self) -> Shape {
        Shape::Linear
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negative_components_are_clamped_and_counted() {
        let m = Identity::default();
        let color = |v: [f64; 3]| {
            let p = Point {
                value: &v,
                cell: 0,
                pos: [0.0; 3],
            };
            m.color(&p, 0.0)
        };
        assert_eq!(color([0.2, 0.5, 1.5]), [0.2, 0.5, 1.5]);
        assert_eq!(m.take_clamped(), 0);
        assert_eq!(color([-0.2, 0.5, -3.0]), [0.0, 0.5, 0.0]);
        assert_eq!(color([0.1, -1e-6, 0.0]), [0.1, 0.0, 0.0]);
        assert_eq!(m.take_clamped(), 2);
        // Rounding of non-negative data: clamped, not counted.
        assert_eq!(color([0.3, -1e-17, 0.5]), [0.3, 0.0, 0.5]);
        assert_eq!(m.take_clamped(), 0);
        assert_eq!(m.take_clamped(), 0);
    }
}
