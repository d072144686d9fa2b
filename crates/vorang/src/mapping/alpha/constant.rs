//! `CONSTANT @m` with block `a`: the same absorption everywhere.

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock, non_negative, required};
use crate::mapping::{AlphaShading, FieldNeed, MethodInfo, Point, ScalarAlpha, Shape};

pub const INFO: MethodInfo<dyn AlphaShading> = MethodInfo {
    name: "CONSTANT",
    summary: "the same absorption everywhere",
    params: "one row: a",
    needs_block: true,
    build,
};

#[derive(Debug)]
pub struct Constant(pub f64);

fn build(block: Option<&ParamBlock>) -> Result<Arc<dyn AlphaShading>, BlockError> {
    let row = required(block)?.single_row(1, "a")?;
    non_negative(row, &row.numbers, "absorption")?;
    Ok(Arc::new(Constant(row.numbers[0])))
}

impl AlphaShading for Constant {
    fn alpha(&self, _: &Point) -> f64 {
        self.0
    }
    fn field_need(&self) -> FieldNeed {
        FieldNeed::Any
    }
    fn shape(&self) -> Shape {
        Shape::Constant
    }
    fn scalar_form(&self) -> Option<ScalarAlpha<'_>> {
        Some(ScalarAlpha::Constant(self.0))
    }
}
