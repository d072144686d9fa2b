//! interpolateColor on the GPU (`wgsl/color.wgsl`): the fans the CPU prepares per frame with
//! its own code (their Rust twins: `twin::color`).
//!
//! Per cell the CPU classifies the projection (render::project, Shirley–Tuchman, thesis
//! 2.2.2.2) and computes θ and η̄ at the thick point T exactly as its renderer does
//! (approx::interpolate_color's `prepare`: T's ray through the cell, `exp` of its optical
//! depth), so the only exponential of the method is the CPU's own. The GPU builds the fan's
//! sectors from those and the nodes' screen positions and evaluates the winning one per pixel
//! (render::gouraud's `Fan::build` and `Fan::at`, operation for operation).

use rayon::prelude::*;

use crate::mapping::{Mapping, Transfer1D};
use crate::predicates::entry_sign;
use crate::render::Placed;
use crate::render::approx::{Approx, InterpolateColor, Scratch};
use crate::render::cell::EyeCell;
use crate::render::footprint::{Footprint, footprint_into};
use crate::render::frame::{Backdrop, Frame};
use crate::render::gouraud::Fan;
use crate::render::project::THICK;
use crate::volume::Volume;

/// `FAN`: the numbers per cell: θ_T, η̄_T (r, g, b), T on screen, the code of the triangles.
pub const FAN: usize = 7;
/// `FAN_SPLIT`: triangles 0…2 of the code below it, triangle 3 and the count above.
pub const FAN_SPLIT: f64 = 134_217_728.0;

/// The fan's triangles as one number (an integer below 2³⁹): corner `m` of triangle `k` in
/// bits `9k + 3m` (triangles 0…2), triangle 3 and the count times [`FAN_SPLIT`].
fn encode(fp: &Footprint) -> f64 {
    // Only the fan's own triangles: the rest may hold an earlier footprint's corners.
    let tri = |k: usize| -> u32 {
        if k >= fp.count {
            return 0;
        }
        (0..3)
            .map(|m| u32::from(fp.corners[k][m] & 7) << (3 * m))
            .sum()
    };
    let lo = tri(0) | tri(1) << 9 | tri(2) << 18;
    let hi = tri(3) | (fp.count as u32) << 9;
    f64::from(lo) + FAN_SPLIT * f64::from(hi)
}

/// Every cell's fan (`FAN` numbers each): zeros where the CPU draws no fan (a flat cell, one
/// reaching in front of a perspective near plane, a fan without area).
pub(crate) fn fan_data(
    vol: &Volume,
    mapping: &Mapping,
    transfer: &Transfer1D,
    placed: &Placed,
    size: [usize; 2],
    brightness: f64,
) -> Vec<f64> {
    // The CPU's frame for these numbers (render::schedule's map_once and build_frame).
    let frame = Frame {
        vol,
        mapping,
        transfer: Some(transfer.clone()),
        category_transfers: None,
        node_mapped: transfer.map_nodes(vol.mesh.node_count()),
        projector: placed.projector,
        width: size[0],
        height: size[1],
        eye_nodes: placed.eye_nodes.clone(),
        screen: placed.screen.clone(),
        background: Backdrop::Uniform([0.0; 3]),
        line_depth: None,
        entry_sign: entry_sign(placed.mirrored),
        rank: Vec::new(),
        span_kernels: false,
    };
    let method = InterpolateColor { brightness };
    let tets = vol.mesh.tets();
    let mut out = vec![0.0; FAN * vol.mesh.tet_count()];
    out.par_chunks_mut(FAN).enumerate().for_each_init(
        || (Scratch::default(), Footprint::empty()),
        |(scratch, fp), (cell, o)| {
            let eye = frame.eye_corners(cell);
            let screen = frame.screen_corners(cell);
            if !EyeCell::is_proper(&eye)
                || !footprint_into(tets[cell], &eye, &screen, &frame.projector, fp)
            {
                return;
            }
            let Some(proj) = fp.projection else {
                return;
            };
            let prepared = method.prepare(&frame, cell, fp, scratch);
            let Some(values) = method.fan_values(&prepared) else {
                return;
            };
            if Fan::new(fp, &values).is_none() {
                return;
            }
            let t = values[THICK as usize];
            o.copy_from_slice(&[
                t[0],
                t[1],
                t[2],
                t[3],
                proj.thick[0],
                proj.thick[1],
                encode(fp),
            ]);
        },
    );
    out
}
