//! `CONSTANT @m` with block `r g b`: the same emission everywhere.

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock, non_negative, required};
use crate::mapping::{ColorShading, FieldNeed, MethodInfo, Point, ScalarColor, Shape};

pub const INFO: MethodInfo<dyn ColorShading> = MethodInfo {
    name: "CONSTANT",
    summary: "the same emission everywhere",
    params: "one row: r g b",
    needs_block: true,
    build,
};

#[derive(Debug)]
pub struct Constant(pub [f64; 3]);

fn build(block: Option<&ParamBlock>) -> Result<Arc<dyn ColorShading>, BlockError> {
    let row = required(block)?.single_row(3, "r g b")?;
    non_negative(row, &row.numbers, "emission")?;
    Ok(Arc::new(Constant([
        row.numbers[0],
        row.numbers[1],
        row.numbers[2],
    ])))
}

impl ColorShading for Constant {
    fn color(&self, _: &Point, _: f64) -> [f64; 3] {
        self.0
    }
    fn field_need(&self) -> FieldNeed {
        FieldNeed::Any
    }
    fn shape(&self) -> Shape {
        Shape::Constant
    }
    fn scalar_form(&self) -> Option<ScalarColor<'_>> {
        Some(ScalarColor::Constant(self.0))
    }
}
