//! interpolateColor on the GPU (`wgsl/color.wgsl`): what the CPU decides per cell and frame —
//! the Shirley–Tuchman classification of its projection (render::project, thesis 2.2.2.2),
//! with its exact orientation predicates — as one word per cell; the GPU computes the rest
//! (the thick point, θ and η̄ there, the fan) as the CPU does (twins: `twin::color`).

use rayon::prelude::*;

use crate::render::Placed;
use crate::render::cell::EyeCell;
use crate::render::footprint::{Footprint, footprint_into};
use crate::render::gouraud::Fan;
use crate::render::project::{ProjClass, THICK};
use crate::volume::Volume;

/// The fan's word: the number of triangles (bits 0–2), the node at the thick point T (bits
/// 3–4, with bit 6) or T where two edges cross (bit 5), and per triangle `k` at bit `8 + 6k`
/// T's position in it and its two nodes in the triangle's order after T. 0: no fan.
fn encode(fp: &Footprint) -> u32 {
    let Some(proj) = fp.projection else {
        return 0;
    };
    let mut code = fp.count as u32;
    match proj.thick_node {
        Some(i) => code |= (i as u32) << 3 | 64,
        None if proj.class == ProjClass::Two => code |= 32,
        None => {}
    }
    for k in 0..fp.count {
        let c = fp.corners[k];
        let t = c.iter().position(|&v| v == THICK).unwrap_or(0);
        let (i, j) = (u32::from(c[(t + 1) % 3]), u32::from(c[(t + 2) % 3]));
        code |= (t as u32 | i << 2 | j << 4) << (8 + 6 * k);
    }
    code
}

/// Every cell's fan word: 0 where the CPU draws no fan (a flat cell, one reaching in front of
/// a perspective near plane, a fan without area: render::tile's draw_fan).
pub(crate) fn fan_codes(vol: &Volume, placed: &Placed) -> Vec<u32> {
    let tets = vol.mesh.tets();
    (0..vol.mesh.tet_count())
        .into_par_iter()
        .map_init(Footprint::empty, |fp, cell| {
            let ids = tets[cell];
            let eye = ids.map(|n| placed.eye_nodes[n as usize]);
            let screen = ids.map(|n| placed.screen[n as usize]);
            if !EyeCell::is_proper(&eye)
                || !footprint_into(ids, &eye, &screen, &placed.projector, fp)
            {
                return 0;
            }
            // Whether a fan has area does not depend on its values.
            if Fan::new(fp, &[[0.0; 4]; 5]).is_none() {
                return 0;
            }
            encode(fp)
        })
        .collect()
}
