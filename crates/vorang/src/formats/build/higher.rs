//! Lagrange cells (VTK 71–74) to tetrahedra, by degree (docs/formats.md, "Cells"):
//!
//! - **Degree 1** is the linear cell of the same shape: its corners, split as a tetrahedron,
//!   hexahedron, wedge or pyramid is.
//! - **Degree 2**: the corners are split as for degree 1, and every edge of the tetrahedra
//!   so cut has a node of the cell at its middle (a mid-edge node; on a face diagonal the
//!   face's centre node, on a body diagonal the cell's): those are remembered as the
//!   tetrahedra's mid-edge nodes, exactly as for VTK's quadratic tetrahedron, and the point
//!   arrays become `HigherOrder` (P2) fields. A degree-2 Lagrange tetrahedron is a quadratic
//!   tetrahedron (the same ten nodes in the same order).
//! - **Degree 3 and more**: the cell is cut along its lattice into `p³` small cells of its own
//!   shape between neighbouring nodes (hexahedra and wedges split conformingly as linear ones,
//!   a tetrahedron's lattice into upright and inverted tetrahedra and octahedra), so the field
//!   is linear between neighbouring nodes; the builder warns about it. Pyramids of such degree
//!   are skipped: VTK numbers no nodes for them.
//!
//! The node at a lattice point comes from [`crate::formats::lagrange`]; the cut follows the
//! file's global node numbers, so neighbouring cells cut their shared faces alike.

use super::cut::Tetrahedra;
use crate::formats::cell_type;
use crate::formats::lagrange::Shape;

/// The tetrahedra of Lagrange cell `i` of `shape` with nodes `conn` (a node count of some
/// degree, checked before).
pub(super) fn add(out: &mut Tetrahedra, i: u32, shape: Shape, conn: &[u32]) {
    let Some(p) = shape.degree(conn.len()) else {
        return;
    };
    // VTK's 21-node wedge: the 18-node one plus the centres of the triangles (15, 16) and
    // of the cell (20).
    let wedge21: Vec<u32>;
    let conn = if conn.len() == 21 {
        wedge21 = (0..15).chain(17..20).map(|k| conn[k]).collect();
        &wedge21[..]
    } else {
        conn
    };
    let node = |ijk: [usize; 3]| conn[shape.index(p, ijk)];
    match p {
        1 | 2 => {
            let corners: Vec<u32> = (0..shape.vertices())
                .map(|v| node(shape.corner(p, v)))
                .collect();
            let tets = out.split(i, shape.linear(), &corners);
            if p == 2 {
                for t in tets {
                    for a in 0..4 {
                        for b in a + 1..4 {
                            let (ca, cb) = (shape.corner(2, t[a]), shape.corner(2, t[b]));
                            let mid = [0, 1, 2].map(|d| (ca[d] + cb[d]) / 2);
                            out.midpoint(corners[t[a]], corners[t[b]], node(mid));
                        }
                    }
                }
            }
        }
        _ => match shape {
            Shape::Hexahedron => subdivide_hexahedron(out, i, p, &node),
            Shape::Wedge => subdivide_wedge(out, i, p, &node),
            Shape::Tetrahedron => subdivide_tetrahedron(out, i, p, &node),
            Shape::Pyramid => {
                out.unordered += 1;
                return;
            }
        },
    }
    if p > 2 {
        out.subdivided += 1;
    }
}

/// `p³` small hexahedra between neighbouring lattice points, each split as a linear one.
fn subdivide_hexahedron(out: &mut Tetrahedra, i: u32, p: usize, node: &dyn Fn([usize; 3]) -> u32) {
    for k in 0..p {
        for j in 0..p {
            for x in 0..p {
                let at = |di: usize, dj: usize, dk: usize| node([x + di, j + dj, k + dk]);
                let hex = [
                    at(0, 0, 0),
                    at(1, 0, 0),
                    at(1, 1, 0),
                    at(0, 1, 0),
                    at(0, 0, 1),
                    at(1, 0, 1),
                    at(1, 1, 1),
                    at(0, 1, 1),
                ];
                out.split(i, cell_type::HEXAHEDRON, &hex);
            }
        }
    }
}

/// The triangles of a degree-`p` triangle's lattice: `p²` of them, counter-clockwise like the
/// big one (upright ones at every point with `i + j < p`, inverted ones where `i + j < p − 1`).
fn lattice_triangles(p: usize) -> Vec<[(usize, usize); 3]> {
    let mut list = Vec::with_capacity(p * p);
    for j in 0..p {
        for i in 0..p - j {
            list.push([(i, j), (i + 1, j), (i, j + 1)]);
            if i + j + 2 <= p {
                list.push([(i + 1, j), (i + 1, j + 1), (i, j + 1)]);
            }
        }
    }
    list
}

/// `p³` small wedges: the triangle's lattice, layer by layer, each split as a linear wedge.
fn subdivide_wedge(out: &mut Tetrahedra, i: u32, p: usize, node: &dyn Fn([usize; 3]) -> u32) {
    let triangles = lattice_triangles(p);
    for k in 0..p {
        for tri in &triangles {
            let wedge: Vec<u32> = [k, k + 1]
                .iter()
                .flat_map(|&kk| tri.map(|(a, b)| node([a, b, kk])))
                .collect();
            out.split(i, cell_type::WEDGE, &wedge);
        }
    }
}

/// `p³` small tetrahedra of a tetrahedron's lattice: an upright tetrahedron at every point
/// with `i + j + k < p`, an octahedron (four tetrahedra about one diagonal) where
/// `i + j + k < p − 1`, an inverted tetrahedron where `i + j + k < p − 2`. Each is oriented as
/// the cell is (positively in lattice coordinates).
fn subdivide_tetrahedron(out: &mut Tetrahedra, i: u32, p: usize, node: &dyn Fn([usize; 3]) -> u32) {
    let mut emit = |pts: [[usize; 3]; 4]| {
        let d = |a: [usize; 3], b: [usize; 3]| [0, 1, 2].map(|c| b[c] as i64 - a[c] as i64);
        let (u, v, w) = (d(pts[0], pts[1]), d(pts[0], pts[2]), d(pts[0], pts[3]));
        let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]);
        let mut tet = pts.map(node);
        if det < 0 {
            tet.swap(2, 3);
        }
        out.push(i, tet);
    };
    for k in 0..p {
        for j in 0..p - k {
            for x in 0..p - k - j {
                let s = x + j + k;
                let at = |di: usize, dj: usize, dk: usize| [x + di, j + dj, k + dk];
                emit([at(0, 0, 0), at(1, 0, 0), at(0, 1, 0), at(0, 0, 1)]);
                if s + 2 <= p {
                    // The octahedron's diagonal a0–a1; its other vertices in a cycle.
                    let (a0, a1) = (at(1, 0, 0), at(0, 1, 1));
                    let ring = [at(0, 1, 0), at(1, 1, 0), at(1, 0, 1), at(0, 0, 1)];
                    for r in 0..4 {
                        emit([a0, a1, ring[r], ring[(r + 1) % 4]]);
                    }
                }
                if s + 3 <= p {
                    emit([at(1, 1, 0), at(1, 0, 1), at(0, 1, 1), at(1, 1, 1)]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_triangles_tile_the_triangle() {
        for p in 1..6 {
            let tris = lattice_triangles(p);
            assert_eq!(tris.len(), p * p);
            for t in tris {
                let [(a, b), (c, d), (e, f)] = t.map(|(x, y)| (x as i64, y as i64));
                let area2 = (c - a) * (f - b) - (d - b) * (e - a);
                assert_eq!(area2, 1, "{t:?}");
            }
        }
    }
}
