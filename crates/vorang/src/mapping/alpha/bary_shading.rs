//! `BARY_SHADING @m` with block `k scale`: absorption from a float[4] field `(v1 … v4)`
//! (barycentric coordinates in the thesis's example, 7.4), by one of five schemes:
//! 1: v1 · 2: v1·v2 · 3: v1·v2·|v1−v2| · 4: v1·v2·v3 · 5: v1²·v2·v3, times `scale`.

use std::sync::Arc;

use crate::mapping::block::{BlockError, ParamBlock, required};
use crate::mapping::{AlphaShading, FieldNeed, MethodInfo, Point, Shape};

pub const INFO: MethodInfo<dyn AlphaShading> = MethodInfo {
    name: "BARY_SHADING",
    summary: "absorption from a float[4] field (v1…v4): scheme k = 1: v1, 2: v1·v2, 3: v1·v2·|v1−v2|, 4: v1·v2·v3, 5: v1²·v2·v3, times scale",
    params: "one row: k scale (k = 1…5)",
    needs_block: true,
    build,
};

#[derive(Debug)]
pub struct BaryShading {
    pub scheme: u8,
    pub scale: f64,
}

fn build(block: Option<&ParamBlock>) -> Result<Arc<dyn AlphaShading>, BlockError> {
    let row = required(block)?.single_row(2, "k scale")?;
    let (k, scale) = (row.numbers[0], row.numbers[1]);
    if k.fract() != 0.0 || !(1.0..=5.0).contains(&k) {
        return Err(BlockError::new(
            row.line,
            format!("BARY_SHADING scheme k must be 1, 2, 3, 4 or 5, found {k}"),
        ));
    }
    if scale < 0.0 {
        return Err(BlockError::new(
            row.line,
            format!("BARY_SHADING scale must be ≥ 0 (it scales an absorption), found {scale}"),
        ));
    }
    Ok(Arc::new(BaryShading {
        scheme: k as u8,
        scale,
    }))
}

impl AlphaShading for BaryShading {
    fn alpha(&self, p: &Point) -> f64 {
        let v = p.value;
        let a = match self.scheme {
            1 => v[0],
            2 => v[0] * v[1],
            3 => v[0] * v[1] * (v[0] - v[1]).abs(),
            4 => v[0] * v[1] * v[2],
            _ => v[0] * v[0] * v[1] * v[2],
        };
        self.scale * a
    }
    fn field_need(&self) -> FieldNeed {
        FieldNeed::Components(4)
    }
    fn shape(&self) -> Shape {
        match self.scheme {
            1 => Shape::Linear,
            2 => Shape::Quadratic,
            _ => Shape::Nonlinear,
        }
    }
    /// Scheme 3 has a kink where v1 = v2.
    fn cuts(&self, v0: &[f64], v1: &[f64], out: &mut Vec<f64>) {
        if self.scheme == 3 {
            let (d0, d1) = (v0[0] - v0[1], v1[0] - v1[1]);
            if (d0 < 0.0 && d1 > 0.0) || (d0 > 0.0 && d1 < 0.0) {
                out.push(d0 / (d0 - d1));
            }
        }
    }
}
