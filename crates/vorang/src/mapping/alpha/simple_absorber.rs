//! `SIMPLE_ABSORBER @m` with rows `a value`: piecewise-linear absorption over a scalar field,
//! values strictly increasing, clamped outside the table.

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock, required};
use crate::mapping::{AlphaShading, FieldNeed, MethodInfo, Point, ScalarAlpha, Shape, Table};

pub const INFO: MethodInfo<dyn AlphaShading> = MethodInfo {
    name: "SIMPLE_ABSORBER",
    summary: "piecewise-linear absorption over a scalar field, clamped outside the table",
    params: "rows: a value (values strictly increasing)",
    needs_block: true,
    build,
};

#[derive(Debug)]
pub struct SimpleAbsorber(pub Table<1>);

fn build(block: Option<&ParamBlock>) -> Result<Arc<dyn AlphaShading>, BlockError> {
    let rows = required(block)?.rows_of(2, "a value")?;
    Ok(Arc::new(SimpleAbsorber(Table::from_rows(
        rows,
        "absorption",
    )?)))
}

impl AlphaShading for SimpleAbsorber {
    fn alpha(&self, p: &Point) -> f64 {
        self.0.eval(p.value[0])[0]
    }
    fn field_need(&self) -> FieldNeed {
        FieldNeed::Scalar
    }
    fn shape(&self) -> Shape {
        Shape::Linear
    }
    fn breakpoints(&self) -> &[f64] {
        self.0.values()
    }
    fn scalar_form(&self) -> Option<ScalarAlpha<'_>> {
        Some(ScalarAlpha::Table(&self.0))
    }
}
