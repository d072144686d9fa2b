//! `IDENTITY` (no block): a float[3] field is the emission itself.

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock};
use crate::mapping::{ColorShading, FieldNeed, MethodInfo, Point, Shape};

pub const INFO: MethodInfo<dyn ColorShading> = MethodInfo {
    name: "IDENTITY",
    summary: "a float[3] field used directly as the RGB emission",
    params: "no block",
    needs_block: false,
    build,
};

#[derive(Debug)]
pub struct Identity;

fn build(_: Option<&ParamBlock>) -> Result<Arc<dyn ColorShading>, BlockError> {
    Ok(Arc::new(Identity))
}

impl ColorShading for Identity {
    fn color(&self, p: &Point, _: f64) -> [f64; 3] {
        [p.value[0], p.value[1], p.value[2]]
    }
    fn field_need(&self) -> FieldNeed {
        FieldNeed::Components(3)
    }
    fn shape(&self) -> Shape {
        Shape::Linear
    }
}
