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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::frame;
    use crate::gpu::twin::Buffers;
    use crate::predicates::entry_sign;
    use crate::render::approx::{Approx, InterpolateColor, Scratch};
    use crate::render::frame::{Backdrop, Frame};
    use crate::render::{Method, Settings, place_nodes};
    use crate::scene::{Camera, LookAt, TransformOp, View};

    /// The march's thick point and its θ and η̄ (twins of `color.wgsl`) against the CPU's own
    /// (render::project's classification, `InterpolateColor::prepare` with `exp`): T bit for
    /// bit, the values within 1e-14, on every cell with a fan, orthographic and perspective.
    #[test]
    fn the_thick_points_values_are_the_cpus() {
        let (nodes, tets) = crate::mesh::generate::kuhn_box([4, 3, 3], [1.0; 3], 0.2, 7);
        let s: Vec<f64> = nodes.iter().map(|p| 1.3 * p[0] - p[1] * p[2]).collect();
        let vol = crate::accuracy::scalar_volume(nodes, tets, s);
        let mapping = crate::accuracy::scalar_maps(&vol);
        let settings = Settings {
            width: 64,
            height: 64,
            method: Method::parse(&["interpolateColor", "1.5"]).unwrap(),
            ..Settings::default()
        };
        let ortho = View {
            transforms: vec![TransformOp::Rotate {
                axis: [1.0, 2.0, 0.5],
                degrees: 35.0,
            }],
            ..View::default()
        };
        let persp = View {
            look_at: LookAt {
                eye: [2.5, 1.9, 3.1],
                reference: [0.5, 0.5, 0.5],
                up: [0.0, 1.0, 0.0],
            },
            camera: Some(Camera::Persp {
                fovy: 40.0,
                aspect: 1.0,
                near: 0.5,
                far: 9.0,
            }),
            ..View::default()
        };
        let method = InterpolateColor { brightness: 1.5 };
        let mut compared = 0;
        for view in [ortho, persp] {
            let data = frame::prepare(&vol, &mapping, &view, &settings, false).unwrap();
            let placed = place_nodes(&vol, &view, &settings).unwrap();
            let transfer = mapping.transfer(&vol).unwrap();
            // The CPU's frame (render::schedule's map_once and build_frame).
            let f = Frame {
                vol: &vol,
                mapping: &mapping,
                node_mapped: transfer.map_nodes(vol.mesh.node_count()),
                transfer: Some(transfer),
                category_transfers: None,
                projector: placed.projector,
                width: 64,
                height: 64,
                eye_nodes: placed.eye_nodes.clone(),
                screen: placed.screen.clone(),
                background: Backdrop::Uniform([0.0; 3]),
                line_depth: None,
                entry_sign: entry_sign(placed.mirrored),
                rank: Vec::new(),
                span_kernels: false,
            };
            let mut cells = Vec::new();
            for (t, nb) in vol.mesh.tets().iter().zip(vol.mesh.neighbors()) {
                cells.push(*t);
                cells.push(*nb);
            }
            let b = Buffers {
                mesh: &cells,
                nodes: &data.nodes,
                lists: &data.lists,
                lines: &[],
                consts: &data.consts,
            };
            let mut fp = Footprint::empty();
            let mut scratch = Scratch::default();
            for (cell, &tet) in vol.mesh.tets().iter().enumerate() {
                let code = b.fan_code(cell as u32);
                if code & 7 == 0 {
                    continue;
                }
                let (eye, screen) = (f.eye_corners(cell), f.screen_corners(cell));
                assert!(footprint_into(tet, &eye, &screen, &f.projector, &mut fp));
                let proj = fp.projection.unwrap();
                let tp = b.thick_point(tet, code);
                assert_eq!(tp, proj.thick, "cell {cell}");
                let prepared = method.prepare(&f, cell, &fp, &mut scratch);
                let want = method.fan_values(&prepared).unwrap()[THICK as usize];
                let got = b.thick_value(tet, code, tp);
                for k in 0..4 {
                    let d = (got[k] - want[k]).abs();
                    assert!(
                        d <= 1e-14 * want[k].abs().max(1.0),
                        "cell {cell}: {got:?} vs {want:?}"
                    );
                }
                compared += 1;
            }
        }
        assert!(compared > 300, "{compared} cells compared");
    }
}
