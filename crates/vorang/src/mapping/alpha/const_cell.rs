//! `CONST_CELL @m` with rows `a value`: one absorption per byte value of a per-cell (Constant)
//! byte field. Values the table lacks absorb nothing.

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock, required};
use crate::mapping::{AlphaShading, ByteTable, FieldNeed, MethodInfo, Point, Shape};

pub const INFO: MethodInfo<dyn AlphaShading> = MethodInfo {
    name: "CONST_CELL",
    summary: "one absorption per byte value of a per-cell byte field",
    params: "rows: a value (value a byte 0…255)",
    needs_block: true,
    build,
};

#[derive(Debug)]
pub struct ConstCell(pub ByteTable<1>);

fn build(block: Option<&ParamBlock>) -> Result<Arc<dyn AlphaShading>, BlockError> {
    let rows = required(block)?.rows_of(2, "a value")?;
    Ok(Arc::new(ConstCell(ByteTable::from_rows(
        rows,
        "absorption",
    )?)))
}

impl AlphaShading for ConstCell {
    fn alpha(&self, p: &Point) -> f64 {
        self.0.eval(p.value[0])[0]
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
