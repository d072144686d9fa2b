//! `LIT_EMITTER @m`: a SIMPLE_EMITTER table lit by the scene's lights.
//! The block's first row is `ka kd ks shininess`, the rows after it are the table `r g b value`.
//! The method gives the table's colour; the mapping multiplies it by the lighting factor of
//! [`crate::scene::Lighting`], which needs the data field's gradient at the point — something a
//! method alone does not see (see [`crate::mapping::Mapping`]).

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock, non_negative, required};
use crate::mapping::{ColorShading, FieldNeed, Point, ScalarColor, Shape, Table};
use crate::scene::Phong;

pub const INFO: crate::mapping::MethodInfo<dyn ColorShading> = crate::mapping::MethodInfo {
    name: "LIT_EMITTER",
    summary: "SIMPLE_EMITTER emission shaded by the lights (addlight) through the field's gradient: table × (ka + Σ light × (kd·max(0,n·l) + ks·max(0,n·h)^shininess)), n = −∇f/|∇f|",
    params: "first row: ka kd ks shininess; then rows: r g b value (values strictly increasing)",
    needs_block: true,
    build,
};

#[derive(Debug)]
pub struct LitEmitter {
    pub phong: Phong,
    pub table: Table<3>,
}

fn build(block: Option<&ParamBlock>) -> Result<Arc<dyn ColorShading>, BlockError> {
    let block = required(block)?;
    let rows = block.rows_of(4, "ka kd ks shininess, then r g b value")?;
    let (first, table) = rows.split_first().expect("rows_of rejects an empty block");
    non_negative(first, &first.numbers, "ka, kd, ks and shininess")?;
    if let Some(v) = first.numbers.iter().find(|v| !v.is_finite()) {
        return Err(BlockError::new(
            first.line,
            format!("ka kd ks shininess must be finite, found {v}"),
        ));
    }
    if table.is_empty() {
        return Err(BlockError::new(
            block.line,
            format!(
                "block @{} has only the lighting row 'ka kd ks shininess': expected rows of 'r g b value' after it",
                block.marker
            ),
        ));
    }
    let [ka, kd, ks, shininess] = [0, 1, 2, 3].map(|k| first.numbers[k]);
    Ok(Arc::new(LitEmitter {
        phong: Phong {
            ka,
            kd,
            ks,
            shininess,
        },
        table: Table::from_rows(table, "emission")?,
    }))
}

impl ColorShading for LitEmitter {
    /// The unlit table colour; [`crate::mapping::Mapping`] applies the lighting factor.
    fn color(&self, p: &Point, _: f64) -> [f64; 3] {
        self.table.eval(p.value[0])
    }
    fn field_need(&self) -> FieldNeed {
        FieldNeed::Scalar
    }
    /// Linear in the value; the lighting factor is constant per cell only for Linear and
    /// Constant fields, which the mapping accounts for.
    fn shape(&self) -> Shape {
        Shape::Linear
    }
    fn breakpoints(&self) -> &[f64] {
        self.table.values()
    }
    /// The legend shows the table's colours; the lights only scale them.
    fn legend_form(&self) -> Option<ScalarColor<'_>> {
        Some(ScalarColor::Table(&self.table))
    }
    fn phong(&self) -> Option<&Phong> {
        Some(&self.phong)
    }
}
