//! `SIMPLE_EMITTER @m` with rows `r g b value`: piecewise-linear emission over a scalar field,
//! values strictly increasing, clamped outside the table.

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock, required};
use crate::mapping::{ColorShading, FieldNeed, MethodInfo, Point, ScalarColor, Shape, Table};

pub const INFO: MethodInfo<dyn ColorShading> = MethodInfo {
    name: "SIMPLE_EMITTER",
    summary: "piecewise-linear RGB emission over a scalar field, clamped outside the table",
    params: "rows: r g b value (values strictly increasing)",
    needs_block: true,
    build,
};

#[derive(Debug)]
pub struct SimpleEmitter(pub Table<3>);

fn build(block: Option<&ParamBlock>) -> Result<Arc<dyn ColorShading>, BlockError> {
    let rows = required(block)?.rows_of(4, "r g b value")?;
    Ok(Arc::new(SimpleEmitter(Table::from_rows(rows, "emission")?)))
}

impl ColorShading for SimpleEmitter {
    fn color(&self, p: &Point, _: f64) -> [f64; 3] {
        self.0.eval(p.value[0])
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
    fn scalar_form(&self) -> Option<ScalarColor<'_>> {
        Some(ScalarColor::Table(&self.0))
    }
}
