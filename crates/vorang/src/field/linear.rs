//! `Linear(@nodedata)`: barycentric interpolation of node values inside each cell (thesis B.2),
//! for scalar and vector data. The gradient is constant per cell.

use super::Support;
use super::{InterpolatorInfo, Sources, same_shape};
use crate::data::{ElementKind, RawData};
use crate::mesh::barycentric_gradients;

pub const INFO: InterpolatorInfo = InterpolatorInfo {
    interpolator: super::Interpolator::Linear,
    name: "Linear",
    summary: "node values, linear (barycentric) inside each tetrahedron; scalar or vector",
    signature: "Linear(@nodedata)",
    required: &[ElementKind::Node],
    optional: &[],
    check,
};

fn check(s: &Sources) -> Result<(), String> {
    same_shape(s.ty, s.raw[0].ty, "Linear")
}

pub fn eval(on: &Support, raw: &RawData, cell: usize, lambda: &[f64; 4], out: &mut [f64]) {
    let nodes = on.mesh.tets()[cell];
    let n = raw.ty.numbers();
    for (c, o) in out.iter_mut().enumerate().take(n) {
        *o = (0..4)
            .map(|i| lambda[i] * raw.values.get(nodes[i] as usize * n + c))
            .sum();
    }
}

/// `∇f = Σ v_i ∇λ_i` for number `c` of each node value, summed as `Σ_{i≥1} (v_i − v_0) ∇λ_i`
/// (the same, as `Σ ∇λ_i = 0`) so that equal node values give exactly zero, not rounding
/// noise whose direction would light a flat field at random.
pub fn gradient(on: &Support, raw: &RawData, cell: usize, c: usize) -> Option<[f64; 3]> {
    let n = raw.ty.numbers();
    if c >= n {
        return None;
    }
    let grads = barycentric_gradients(&on.mesh.corners(cell))?;
    let nodes = on.mesh.tets()[cell];
    let v0 = raw.values.get(nodes[0] as usize * n + c);
    let mut g = [0.0; 3];
    for i in 1..4 {
        let d = raw.values.get(nodes[i] as usize * n + c) - v0;
        for k in 0..3 {
            g[k] += d * grads[i][k];
        }
    }
    Some(g)
}
