//! Grid lines (`linedraw`, thesis A.1): opaque black edges, depth-correct. Each pixel keeps the
//! depth of the nearest line through it; compositing then treats that line as an opaque black
//! background at that depth, so the volume in front of a line attenuates it and nothing behind
//! it is seen (docs/scripts.md).

use crate::error::Error;
use crate::field::Interpolator;
use crate::mesh::EDGE_NODES;
use crate::scene::Projector;
use crate::volume::Volume;

/// Which grid lines to draw.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum LineDraw {
    Off,
    /// Every edge of the grid (the default).
    #[default]
    All,
    /// The edges of the cells whose Constant field `field` has one of `values`.
    Cells {
        field: usize,
        values: Vec<f64>,
    },
}

/// The unique edges to draw, as node pairs.
pub fn edges(vol: &Volume, lines: &LineDraw) -> Result<Vec<[u32; 2]>, Error> {
    let cells: Box<dyn Iterator<Item = usize>> = match lines {
        LineDraw::Off => return Ok(Vec::new()),
        LineDraw::All => Box::new(0..vol.mesh.tet_count()),
        LineDraw::Cells { field, values } => {
            let f = vol.field(*field).ok_or_else(|| {
                Error::Invalid(format!(
                    "linedraw: there is no field {field} (the volume has {} fields)",
                    vol.data.fields.len()
                ))
            })?;
            if f.interpolator != Interpolator::Constant || !f.is_scalar() {
                return Err(Error::Invalid(format!(
                    "linedraw: field {field} must be a scalar Constant (per-cell) field, it is {{ {} }} = {}",
                    f.ty,
                    f.interpolator.name()
                )));
            }
            let raw = &vol.data.raw[f.sources[0]];
            let values = values.clone();
            Box::new((0..vol.mesh.tet_count()).filter(move |&c| values.contains(&raw.value(c, 0))))
        }
    };
    let tets = vol.mesh.tets();
    let mut e: Vec<[u32; 2]> = cells
        .flat_map(|c| {
            EDGE_NODES.map(|[i, j]| {
                let (a, b) = (tets[c][i], tets[c][j]);
                [a.min(b), a.max(b)]
            })
        })
        .collect();
    e.sort_unstable();
    e.dedup();
    Ok(e)
}

/// Per pixel: the depth of the nearest line, ∞ where there is none. Lines are clipped to the
/// camera's depth range and drawn one pixel wide (a DDA along the major axis).
pub fn depth_buffer(
    edges: &[[u32; 2]],
    eye: &[[f64; 3]],
    projector: &Projector,
    width: usize,
    height: usize,
) -> Result<Vec<f64>, crate::error::Error> {
    let mut buf = crate::framebuffer::try_pixels(f64::INFINITY, width, height, "the line depths")?;
    let (dmin, dmax) = projector.depth();
    for &[a, b] in edges {
        let (p, q) = (eye[a as usize], eye[b as usize]);
        let (dp, dq) = (-p[2], -q[2]);
        // Clip the segment to dmin ≤ depth ≤ dmax.
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (bound, keep_above) in [(dmin, true), (dmax, false)] {
            if !bound.is_finite() {
                continue;
            }
            let (fp, fq) = if keep_above {
                (dp - bound, dq - bound)
            } else {
                (bound - dp, bound - dq)
            };
            if fp < 0.0 && fq < 0.0 {
                t1 = -1.0;
            } else if fp < 0.0 {
                t0 = t0.max(fp / (fp - fq));
            } else if fq < 0.0 {
                t1 = t1.min(fp / (fp - fq));
            }
        }
        if t0 > t1 {
            continue;
        }
        let at = |t: f64| [0, 1, 2].map(|k| p[k] + t * (q[k] - p[k]));
        let (p0, p1) = (at(t0), at(t1));
        let (s0, s1) = (projector.screen(p0), projector.screen(p1));
        let (d0, d1) = (-p0[2], -p1[2]);
        let (dx, dy) = (s1[0] - s0[0], s1[1] - s0[1]);
        let steps = dx.abs().max(dy.abs()).ceil().max(1.0);
        if !steps.is_finite() || steps > 1e7 {
            continue;
        }
        let n = steps as usize;
        for k in 0..=n {
            let u = k as f64 / steps;
            let (x, y) = (s0[0] + u * dx, s0[1] + u * dy);
            if x < 0.0 || y < 0.0 || x >= width as f64 || y >= height as f64 {
                continue;
            }
            // Depth is linear on screen for orthographic views; its inverse for perspective.
            let d = if projector.is_perspective() {
                1.0 / ((1.0 - u) / d0 + u / d1)
            } else {
                d0 + u * (d1 - d0)
            };
            let i = y as usize * width + x as usize;
            if d < buf[i] {
                buf[i] = d;
            }
        }
    }
    Ok(buf)
}
