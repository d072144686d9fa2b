//! `EdgeElemSAR(@edgedata, @tetmaterials)`: the specific absorption rate `½·σ·|E|²/ρ` of an
//! edge-element field `E` (thesis appendix B, docs/formats.md), with `σ` (`sigma`) and `ρ` (`rho`, 1 if absent) taken
//! from the cell's material; for complex `E`, `|E|² = |Re E|² + |Im E|²`.

use super::Support;
use super::{InterpolatorInfo, Sources, edge_elem, scalar_edge_values};
use crate::data::{ElementKind, RawData};

pub const INFO: InterpolatorInfo = InterpolatorInfo {
    interpolator: super::Interpolator::EdgeElemSar,
    name: "EdgeElemSAR",
    summary: "specific absorption rate ½·σ·|E|²/ρ of an edge-element field, σ and ρ from the cell's material",
    signature: "EdgeElemSAR(@edgedata, @tetmaterials)",
    required: &[ElementKind::Edge, ElementKind::Tetrahedron],
    optional: &[],
    check,
};

fn check(s: &Sources) -> Result<(), String> {
    scalar_edge_values(s.raw[0], "EdgeElemSAR")?;
    if !s.raw[1].is_byte_scalar() {
        return Err(format!(
            "EdgeElemSAR needs the cells' materials as TetrahedronData {{ byte Materials }}, found {}",
            s.raw[1].ty
        ));
    }
    if s.ty.components() != 1 {
        return Err(format!(
            "EdgeElemSAR gives a scalar field; declare it float or double, not {}",
            s.ty
        ));
    }
    let Some(materials) = s.materials else {
        return Err(
            "EdgeElemSAR needs a Materials block with sigma (and optionally rho) per material"
                .into(),
        );
    };
    let mat = s.raw[1];
    let mut seen = [false; 256];
    for cell in 0..mat.elements() {
        let id = mat.value(cell, 0) as u8;
        if std::mem::replace(&mut seen[id as usize], true) {
            continue;
        }
        let Some(m) = materials.get(id) else {
            return Err(format!(
                "EdgeElemSAR: tetrahedron {} has material {id}, which the Materials block does not define",
                cell + 1
            ));
        };
        if m.prop("sigma").is_none() {
            return Err(format!(
                "EdgeElemSAR: material {id} (\"{}\") has no numeric sigma",
                m.name
            ));
        }
        if m.prop("rho") == Some(0.0) {
            return Err(format!(
                "EdgeElemSAR: material {id} (\"{}\") has rho = 0",
                m.name
            ));
        }
    }
    Ok(())
}

pub fn eval(
    on: &Support,
    edges: &RawData,
    materials: &RawData,
    cell: usize,
    lambda: &[f64; 4],
) -> f64 {
    let e = edge_elem::eval(on, edges, cell, lambda);
    let e2: f64 = (0..3).map(|d| e.re[d] * e.re[d] + e.im[d] * e.im[d]).sum();
    let id = materials.value(cell, 0) as u8;
    let m = on.materials.and_then(|m| m.get(id));
    let sigma = m.and_then(|m| m.prop("sigma")).unwrap_or(0.0);
    let rho = m.and_then(|m| m.prop("rho")).unwrap_or(1.0);
    0.5 * sigma * e2 / rho
}
