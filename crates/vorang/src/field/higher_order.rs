//! `HigherOrder(@nodedata, @edgedata[, @tetdata])`: quadratic (P2) Lagrange interpolation from
//! node values and edge-midpoint values, plus an optional cell bubble `256·b·λ0λ1λ2λ3`
//! (thesis appendix B, docs/formats.md).

use super::Support;
use super::{InterpolatorInfo, Sources, same_shape};
use crate::data::{ElementKind, RawData};
use crate::mesh::EDGE_NODES;

pub const INFO: InterpolatorInfo = InterpolatorInfo {
    interpolator: super::Interpolator::HigherOrder,
    name: "HigherOrder",
    summary: "quadratic (P2) from node and edge-midpoint values, optional cell bubble",
    signature: "HigherOrder(@nodedata, @edgedata[, @tetdata])",
    required: &[ElementKind::Node, ElementKind::Edge],
    optional: &[ElementKind::Tetrahedron],
    check,
};

fn check(s: &Sources) -> Result<(), String> {
    for raw in &s.raw {
        same_shape(s.ty, raw.ty, "HigherOrder")?;
    }
    Ok(())
}

pub fn eval(
    on: &Support,
    nodes: &RawData,
    edges: &RawData,
    bubble: Option<&RawData>,
    cell: usize,
    l: &[f64; 4],
    out: &mut [f64],
) {
    let n = nodes.ty.numbers();
    let tet = on.mesh.tets()[cell];
    let cell_edges = on.tet_edges(cell);
    let b = 256.0 * l[0] * l[1] * l[2] * l[3];
    for (c, o) in out.iter_mut().enumerate().take(n) {
        let mut v = 0.0;
        for i in 0..4 {
            v += nodes.values.get(tet[i] as usize * n + c) * l[i] * (2.0 * l[i] - 1.0);
        }
        if let Some(ce) = cell_edges {
            for (k, &[i, j]) in EDGE_NODES.iter().enumerate() {
                v += 4.0 * edges.values.get(ce[k].0 * n + c) * l[i] * l[j];
            }
        }
        if let Some(bub) = bubble {
            v += b * bub.values.get(cell * n + c);
        }
        *o = v;
    }
}
