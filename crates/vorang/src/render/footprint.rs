//! The screen footprint of one cell: the triangles to scan-convert.
//!
//! Normally the Shirley–Tuchman split of the projection. For a perspective camera, a cell that
//! reaches in front of the near plane cannot be projected as a whole (points at or behind the
//! eye have no screen position): its footprint is the projection of the part beyond the near
//! plane, a convex polygon fanned into triangles.

use super::project::{ProjClass, Projection, THICK, classify};
use super::raster::ScreenTriangle;
use crate::scene::Projector;

/// At most five triangles (a fan over the 7-gon a near plane can cut from a tetrahedron).
#[derive(Debug, Clone, Copy)]
pub struct Footprint {
    pub tris: [ScreenTriangle; 5],
    /// For each triangle vertex: 0…3 a node, [`THICK`] the thick point (unclipped footprints).
    pub corners: [[u8; 3]; 5],
    pub count: usize,
    /// The Shirley–Tuchman projection (`None` for a near-clipped cell).
    pub projection: Option<Projection>,
}

impl Footprint {
    /// No triangles yet (to be filled by [`footprint_into`]).
    pub fn empty() -> Footprint {
        let empty = ScreenTriangle { v: [[0.0; 2]; 3] };
        Footprint {
            tris: [empty; 5],
            corners: [[0; 3]; 5],
            count: 0,
            projection: None,
        }
    }

    /// The outline of an unclipped footprint: its three or four node positions in order around
    /// it (the Shirley–Tuchman triangles without the thick point). Methods that need no
    /// Gouraud weights scan-convert this instead of the 3–4 triangles: fewer, longer rows.
    pub fn hull(&self) -> Option<([[f64; 2]; 4], usize)> {
        let p = self.projection.as_ref()?;
        let at = |t: usize, k: usize| self.tris[t].v[k];
        Some(match p.class {
            // Fans around T: [[j, k, T], [k, l, T], [l, j, T]] and [[a, c, T], [c, b, T], …].
            ProjClass::OneA | ProjClass::OneB => ([at(0, 0), at(1, 0), at(2, 0), [0.0; 2]], 3),
            ProjClass::Two => ([at(0, 0), at(1, 0), at(2, 0), at(3, 0)], 4),
            // [[a, T, c], [T, b, c]]: T lies on the edge a–b.
            ProjClass::ThreeA | ProjClass::ThreeB => ([at(0, 0), at(1, 1), at(0, 2), [0.0; 2]], 3),
            // [[T, r0, r1]]: T is a node.
            ProjClass::Four => ([at(0, 0), at(0, 1), at(0, 2), [0.0; 2]], 3),
            ProjClass::Flat => return None,
        })
    }

    /// Pixel bounding box `[x0, x1) × [y0, y1)` (unclamped).
    pub fn bbox(&self) -> Option<[f64; 4]> {
        if self.count == 0 {
            return None;
        }
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for t in &self.tris[..self.count] {
            for v in t.v {
                b[0] = b[0].min(v[0]);
                b[1] = b[1].min(v[1]);
                b[2] = b[2].max(v[0]);
                b[3] = b[3].max(v[1]);
            }
        }
        Some(b)
    }
}

/// The footprint of a cell with nodes `ids` at eye positions `eye` and screen positions
/// `screen` (valid where the depth is ≥ the near plane). `None` if nothing of the cell lies
/// beyond the near plane.
pub fn footprint(
    ids: [u32; 4],
    eye: &[[f64; 3]; 4],
    screen: &[[f64; 2]; 4],
    projector: &Projector,
) -> Option<Footprint> {
    let mut fp = Footprint::empty();
    footprint_into(ids, eye, screen, projector, &mut fp).then_some(fp)
}

/// [`footprint`] written into `fp`, which the tile loop reuses from cell to cell: returned,
/// the 320 bytes were copied once more per cell (about 1 % of an `interpolateColor` frame).
/// `false` where [`footprint`] gives `None`. Triangles past the new count keep stale values.
pub fn footprint_into(
    ids: [u32; 4],
    eye: &[[f64; 3]; 4],
    screen: &[[f64; 2]; 4],
    projector: &Projector,
    fp: &mut Footprint,
) -> bool {
    fp.count = 0;
    fp.projection = None;
    let near = match projector {
        Projector::Persp { depth, .. } => Some(depth.0),
        Projector::Ortho { .. } => None,
    };
    let depth = [-eye[0][2], -eye[1][2], -eye[2][2], -eye[3][2]];
    if let Some(near) = near.filter(|&n| depth.iter().any(|&d| d < n)) {
        if depth.iter().all(|&d| d < near) {
            return false;
        }
        clipped(ids, eye, &depth, near, projector, fp);
        return true;
    }
    let proj = classify(screen, eye, projector.is_perspective());
    let pos = |v: u8| {
        if v == THICK {
            proj.thick
        } else {
            screen[v as usize]
        }
    };
    for k in 0..proj.count {
        let c = proj.triangles[k];
        fp.tris[k] = ScreenTriangle { v: c.map(pos) };
        fp.corners[k] = c;
    }
    fp.count = proj.count;
    fp.projection = Some(proj);
    true
}

/// The projection of cell ∩ {depth ≥ near}: the kept nodes and the edge crossings, hull-ordered
/// and fanned.
fn clipped(
    ids: [u32; 4],
    eye: &[[f64; 3]; 4],
    depth: &[f64; 4],
    near: f64,
    projector: &Projector,
    fp: &mut Footprint,
) {
    let mut pts: Vec<([f64; 2], u64)> = Vec::with_capacity(7);
    for i in 0..4 {
        if depth[i] >= near {
            pts.push((projector.screen(eye[i]), u64::from(ids[i])));
        }
    }
    // Crossings are labelled past the node ids, only to tell points apart in the hull.
    const CLIP: u64 = 1 << 62;
    for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        if (depth[i] < near) != (depth[j] < near) {
            // Canonical order (smaller node id first) so that neighbouring cells compute the
            // same point bit for bit.
            let (a, b) = if ids[i] < ids[j] { (i, j) } else { (j, i) };
            let t = (near - depth[a]) / (depth[b] - depth[a]);
            let p = [0, 1, 2].map(|k| eye[a][k] + t * (eye[b][k] - eye[a][k]));
            let p = [p[0], p[1], -near];
            let id = CLIP | (u64::from(ids[a]) << 31) | u64::from(ids[b]);
            pts.push((projector.screen(p), id));
        }
    }
    let hull = convex_hull(&mut pts);
    for k in 1..hull.len().saturating_sub(1) {
        let tri = [hull[0], hull[k], hull[k + 1]];
        fp.tris[fp.count] = ScreenTriangle {
            v: tri.map(|p| p.0),
        };
        fp.corners[fp.count] = [u8::MAX; 3];
        fp.count += 1;
        if fp.count == 5 {
            break;
        }
    }
}

/// Andrew's monotone chain; collinear points dropped.
fn convex_hull(pts: &mut [([f64; 2], u64)]) -> Vec<([f64; 2], u64)> {
    pts.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]).then(a.0[1].total_cmp(&b.0[1])));
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<([f64; 2], u64)> = Vec::with_capacity(pts.len() * 2);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &([f64; 2], u64)>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2].0, hull[hull.len() - 1].0, p.0) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_of_a_square_with_an_inner_point() {
        let mut pts = vec![
            ([0.0, 0.0], 0),
            ([1.0, 0.0], 1),
            ([0.5, 0.5], 9),
            ([1.0, 1.0], 2),
            ([0.0, 1.0], 3),
        ];
        let h = convex_hull(&mut pts);
        assert_eq!(h.len(), 4);
        assert!(!h.iter().any(|p| p.1 == 9));
    }

    #[test]
    fn a_cell_through_the_near_plane_keeps_the_part_beyond_it() {
        let p = Projector::new(
            Some(&crate::scene::Camera::Persp {
                fovy: 90.0,
                aspect: 1.0,
                near: 1.0,
                far: 10.0,
            }),
            [1.0; 3],
            100,
            100,
        )
        .unwrap();
        let eye = [
            [0.0, 0.0, -0.5],
            [1.0, 0.0, -3.0],
            [0.0, 1.0, -3.0],
            [-1.0, -1.0, -3.0],
        ];
        let screen = eye.map(|q| {
            if -q[2] >= 1.0 {
                p.screen(q)
            } else {
                [f64::NAN; 2]
            }
        });
        let fp = footprint([0, 1, 2, 3], &eye, &screen, &p).unwrap();
        assert!(fp.projection.is_none());
        // The crossings of the near plane project inside the triangle of the far nodes here, so
        // the hull is that triangle.
        assert_eq!(fp.count, 1);
        let mut v = fp.tris[0].v.to_vec();
        v.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let mut nodes: Vec<[f64; 2]> = [1, 2, 3].iter().map(|&i| p.screen(eye[i])).collect();
        nodes.sort_by(|a, b| a[0].total_cmp(&b[0]));
        assert_eq!(v, nodes);
        let b = fp.bbox().unwrap();
        assert!(b.iter().all(|v| v.is_finite()));
        let all_behind = [
            [0.0, 0.0, -0.5],
            [1.0, 0.0, -0.6],
            [0.0, 1.0, -0.2],
            [0.0, 0.0, 1.0],
        ];
        assert!(footprint([0, 1, 2, 3], &all_behind, &screen, &p).is_none());
    }
}
