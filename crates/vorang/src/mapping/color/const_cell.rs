//! `CONST_CELL @m` with rows `r g b value`: one emission per byte value of a per-cell (Constant)
//! byte field, e.g. a material per tissue (thesis C.2). Values the table lacks emit nothing.

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock, required};
use crate::mapping::{ByteTable, ColorShading, FieldNeed, MethodInfo, Point, Shape};

pub const INFO: MethodInfo<dyn ColorShading> = MethodInfo {
    name: "CONST_CELL",
    summary: "one RGB emission per byte value of a per-cell byte field",
    params: "rows: r g b value (value a byte 0…255)",
    needs_block: true,
    build,
};

#[derive(Debug)]
pub struct ConstCell(pub ByteTable<3>);

fn build(block: Option<&ParamBlock>) -> Result<Arc<dyn ColorShading>, BlockError> {
    let rows = required(block)?.rows_of(4, "r g b value")?;
    Ok(Arc::new(ConstCell(ByteTable::from_rows(rows, "emission")?)))
}

impl ColorShading for ConstCell {
    fn color(&self, p: &Point, _: f64) -> [f64; 3] {
        self.0.eval(p.value[0])
    }
    fn field_need(&self) -> FieldNeed {
        FieldNeed::ByteConstant
    }
    fn shape(&self) -> Shape {
        Shape::Constant
    }
    fn defined_bytes(&self) -> Option<[bool; 256]> {
        Some(self.0.defined())
    }
}
