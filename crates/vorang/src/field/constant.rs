//! `Constant(@tetdata)`: one value per cell (thesis B.2), scalar or vector.

use super::{InterpolatorInfo, Sources, same_shape};
use crate::data::{ElementKind, RawData};

pub const INFO: InterpolatorInfo = InterpolatorInfo {
    interpolator: super::Interpolator::Constant,
    name: "Constant",
    summary: "one value per tetrahedron; scalar or vector",
    signature: "Constant(@tetdata)",
    required: &[ElementKind::Tetrahedron],
    optional: &[],
    check,
};

fn check(s: &Sources) -> Result<(), String> {
    same_shape(s.ty, s.raw[0].ty, "Constant")
}

pub fn eval(raw: &RawData, cell: usize, out: &mut [f64]) {
    let n = raw.ty.numbers();
    for (c, o) in out.iter_mut().enumerate().take(n) {
        *o = raw.values.get(cell * n + c);
    }
}
