//! `ABSORPTION_WEIGHTED @m` with rows `r g b value`: the SIMPLE_EMITTER table times the
//! absorption χ the alphamap gives at the same point — emission coupled to absorption
//! (thesis 7.2; the two maps may use different fields).

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock, required};
use crate::mapping::{ColorShading, FieldNeed, MethodInfo, Point, ScalarColor, Shape, Table};

pub const INFO: MethodInfo<dyn ColorShading> = MethodInfo {
    name: "ABSORPTION_WEIGHTED",
    summary: "SIMPLE_EMITTER's table times the absorption χ at the same point",
    params: "rows: r g b value (values strictly increasing)",
    needs_block: true,
    build,
};

#[derive(Debug)]
pub struct AbsorptionWeighted(pub Table<3>);

fn build(block: Option<&ParamBlock>) -> Result<Arc<dyn ColorShading>, BlockError> {
    let rows = required(block)?.rows_of(4, "r g b value")?;
    Ok(Arc::new(AbsorptionWeighted(Table::from_rows(
        rows, "emission",
    )?)))
}

impl ColorShading for AbsorptionWeighted {
    fn color(&self, p: &Point, chi: f64) -> [f64; 3] {
        self.0.eval(p.value[0]).map(|c| c * chi)
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
    fn uses_absorption(&self) -> bool {
        true
    }
    fn scalar_form(&self) -> Option<ScalarColor<'_>> {
        Some(ScalarColor::Table(&self.0))
    }
}
