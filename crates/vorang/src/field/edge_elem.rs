//! `EdgeElem(@edgedata)`: lowest-order Whitney (Nédélec) edge elements (thesis appendix B, docs/formats.md):
//! `E = Σ_e u_e (λ_a ∇λ_b − λ_b ∇λ_a)` over the cell's six edges, each edge directed
//! `a → b` as its `FromTo` row says. Complex edge values give a complex field; the field's value
//! is its real part (docs/formats.md), the imaginary part is used by `EdgeElemSAR`.

use super::Support;
use super::{InterpolatorInfo, Sources, scalar_edge_values};
use crate::data::{ElementKind, RawData};
use crate::mesh::{EDGE_NODES, barycentric_gradients};

pub const INFO: InterpolatorInfo = InterpolatorInfo {
    interpolator: super::Interpolator::EdgeElem,
    name: "EdgeElem",
    summary: "Whitney edge elements: edge values → vector field (float[3]); complex → real part",
    signature: "EdgeElem(@edgedata)",
    required: &[ElementKind::Edge],
    optional: &[],
    check,
};

fn check(s: &Sources) -> Result<(), String> {
    scalar_edge_values(s.raw[0], "EdgeElem")?;
    if s.ty.components() != 3 {
        return Err(format!(
            "EdgeElem gives a vector field; declare it float[3], not {}",
            s.ty
        ));
    }
    Ok(())
}

/// The field's real and imaginary parts at a point of `cell`.
pub struct Complex3 {
    pub re: [f64; 3],
    pub im: [f64; 3],
}

pub fn eval(on: &Support, raw: &RawData, cell: usize, lambda: &[f64; 4]) -> Complex3 {
    let mut e = Complex3 {
        re: [0.0; 3],
        im: [0.0; 3],
    };
    let (Some(grads), Some(edges)) = (
        barycentric_gradients(&on.mesh.corners(cell)),
        on.tet_edges(cell),
    ) else {
        return e;
    };
    for (k, &[i, j]) in EDGE_NODES.iter().enumerate() {
        let (edge, reversed) = edges[k];
        // Whitney function of the local edge i → j; flipped if the file directs it j → i.
        let sign = if reversed { -1.0 } else { 1.0 };
        let (ur, ui) = (raw.value(edge, 0) * sign, raw.imag(edge, 0) * sign);
        for d in 0..3 {
            let w = lambda[i] * grads[j][d] - lambda[j] * grads[i][d];
            e.re[d] += ur * w;
            e.im[d] += ui * w;
        }
    }
    e
}
