//! VTK's Lagrange cells (types 71–74): which degree a cell's node count gives, and where the
//! node at a lattice point sits in the cell's connectivity. A cell of degree `p` carries a node
//! at every point of a lattice with `p` steps along each edge; VTK lists the cell's vertices
//! first, then the nodes inside each edge, inside each face and inside the cell
//! (docs/formats.md, "Cells"). The readers need this to put a file's nodes where they belong,
//! the builder to cut a cell along its lattice; neither needs to know how VTK arrived at its
//! numbering, so it sits here, apart from both, checked node for node against files VTK wrote
//! (`tests/cells.rs`).
//!
//! Lattice points are `(i, j, k)`, the parametric coordinates times `p`: a tetrahedron has
//! its vertices at (0,0,0), (p,0,0), (0,p,0), (0,0,p) and holds the points with
//! `i + j + k ≤ p`; a hexahedron holds `0 ≤ i, j, k ≤ p` (vertices in VTK's hexahedron order);
//! a wedge `i + j ≤ p, 0 ≤ k ≤ p` (vertices (0,0), (p,0), (0,p) at k = 0, then at k = p).
//! VTK defines no numbering for Lagrange pyramids beyond the corners; degree 2 (14 nodes) is
//! read as vertices, the mid-edge nodes in the edge order of VTK's quadratic pyramid, then
//! the base's centre — the same scheme as every other Lagrange cell.

use super::cell_type;

/// The shape of a Lagrange cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    Tetrahedron,
    Hexahedron,
    Wedge,
    Pyramid,
}

impl Shape {
    /// The shape of a Lagrange cell type, `None` for other types.
    pub fn of(ty: u8) -> Option<Shape> {
        Some(match ty {
            cell_type::LAGRANGE_TETRAHEDRON => Shape::Tetrahedron,
            cell_type::LAGRANGE_HEXAHEDRON => Shape::Hexahedron,
            cell_type::LAGRANGE_WEDGE => Shape::Wedge,
            cell_type::LAGRANGE_PYRAMID => Shape::Pyramid,
            _ => return None,
        })
    }

    /// The linear VTK cell of the same shape (its corners).
    pub fn linear(self) -> u8 {
        match self {
            Shape::Tetrahedron => cell_type::TETRA,
            Shape::Hexahedron => cell_type::HEXAHEDRON,
            Shape::Wedge => cell_type::WEDGE,
            Shape::Pyramid => cell_type::PYRAMID,
        }
    }

    /// Number of nodes of a cell of degree `p`.
    pub fn nodes(self, p: usize) -> usize {
        match self {
            Shape::Tetrahedron => tet_count(p as isize),
            Shape::Hexahedron => (p + 1).pow(3),
            Shape::Wedge => (p + 1) * (p + 1) * (p + 2) / 2,
            Shape::Pyramid => (p + 1) * (p + 2) * (2 * p + 3) / 6,
        }
    }

    /// The degree a cell of `n` nodes has, `None` if no degree gives `n` nodes. VTK's 21-node
    /// wedge (a degree-2 wedge with a node at the centre of each triangle and of the cell) is
    /// degree 2.
    pub fn degree(self, n: usize) -> Option<usize> {
        if self == Shape::Wedge && n == 21 {
            return Some(2);
        }
        let mut p = 1;
        while self.nodes(p) < n {
            p += 1;
        }
        (self.nodes(p) == n).then_some(p)
    }

    /// The node counts of degrees 1, 2 and 3, for messages.
    pub fn counts(self) -> String {
        let n: Vec<String> = (1..=3).map(|p| self.nodes(p).to_string()).collect();
        format!("{}, …", n.join(", "))
    }

    /// The lattice point of vertex `v` of a cell of degree `p`.
    pub fn corner(self, p: usize, v: usize) -> [usize; 3] {
        let k = |up: bool| if up { p } else { 0 };
        match self {
            Shape::Tetrahedron => [[0, 0, 0], [p, 0, 0], [0, p, 0], [0, 0, p]][v],
            Shape::Hexahedron => {
                let (i, j) = [(0, 0), (p, 0), (p, p), (0, p)][v % 4];
                [i, j, k(v >= 4)]
            }
            Shape::Wedge => {
                let (i, j) = [(0, 0), (p, 0), (0, p)][v % 3];
                [i, j, k(v >= 3)]
            }
            // The apex is placed at (0, 0, p): only its index matters (see `index`).
            Shape::Pyramid => [[0, 0, 0], [p, 0, 0], [p, p, 0], [0, p, 0], [0, 0, p]][v],
        }
    }

    /// The number of vertices.
    pub fn vertices(self) -> usize {
        match self {
            Shape::Tetrahedron => 4,
            Shape::Hexahedron => 8,
            Shape::Wedge => 6,
            Shape::Pyramid => 5,
        }
    }

    /// Where the node at lattice point `ijk` sits in a degree-`p` cell's connectivity.
    /// Pyramids: degree 1 or 2 only, lattice points as [`Shape::corner`] places them and the
    /// midpoints between two of those.
    pub fn index(self, p: usize, ijk: [usize; 3]) -> usize {
        match self {
            Shape::Tetrahedron => {
                let [i, j, k] = ijk;
                tet_index(p, [p - i - j - k, i, j, k])
            }
            Shape::Hexahedron => hex_index(p, ijk),
            Shape::Wedge => wedge_index(p, ijk),
            Shape::Pyramid => pyramid_index(p, ijk),
        }
    }
}

fn tet_count(q: isize) -> usize {
    if q < 0 {
        0
    } else {
        let q = q as usize;
        (q + 1) * (q + 2) * (q + 3) / 6
    }
}

fn triangle_count(q: isize) -> usize {
    if q < 0 {
        0
    } else {
        let q = q as usize;
        (q + 1) * (q + 2) / 2
    }
}

/// A triangle of degree `q` (VTK's Lagrange triangle, as the faces of a tetrahedron use it):
/// `b` are the lattice weights of its three vertices (summing to `q`). Vertices, then the
/// edges 0→1, 1→2, 2→0 (each from its first vertex on), then the inside: a triangle of degree
/// `q − 3`, numbered the same way.
fn triangle_index(mut q: usize, mut b: [usize; 3]) -> usize {
    let mut offset = 0;
    while q > 0 && b.iter().all(|&x| x > 0) {
        offset += 3 * q;
        b = b.map(|x| x - 1);
        q -= 3;
    }
    if q == 0 {
        return offset;
    }
    if let Some(v) = (0..3).find(|&v| b[v] == q) {
        return offset + v;
    }
    let e = (0..3).find(|&e| b[(e + 2) % 3] == 0).unwrap_or_default();
    offset + 3 + e * (q - 1) + b[(e + 1) % 3] - 1
}

/// The edges of a tetrahedron in VTK's order (each counted from its first vertex).
const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
/// The faces of a tetrahedron in VTK's order, each with the vertex order its inside is
/// numbered in.
const TET_FACES: [[usize; 3]; 4] = [[0, 1, 3], [2, 3, 1], [0, 3, 2], [0, 2, 1]];

/// A tetrahedron of degree `p`, `b` the lattice weights of its four vertices (summing to
/// `p`): vertices, edges, faces (each a triangle of degree `p − 3`), then the inside, a
/// tetrahedron of degree `p − 4` numbered the same way.
fn tet_index(mut p: usize, mut b: [usize; 4]) -> usize {
    let mut offset = 0;
    while p > 0 && b.iter().all(|&x| x > 0) {
        offset += tet_count(p as isize) - tet_count(p as isize - 4);
        b = b.map(|x| x - 1);
        p -= 4;
    }
    if p == 0 {
        return offset;
    }
    if let Some(v) = (0..4).find(|&v| b[v] == p) {
        return offset + v;
    }
    for (e, [a, c]) in TET_EDGES.iter().enumerate() {
        if (0..4).all(|x| x == *a || x == *c || b[x] == 0) {
            return offset + 4 + e * (p - 1) + b[*c] - 1;
        }
    }
    let f = (0..4)
        .find(|&f| b[6 - TET_FACES[f].iter().sum::<usize>()] == 0)
        .unwrap_or_default();
    let face = TET_FACES[f].map(|v| b[v] - 1);
    offset + 4 + 6 * (p - 1) + f * triangle_count(p as isize - 3) + triangle_index(p - 3, face)
}

/// A hexahedron of degree `p`: vertices, the edges (bottom 0-1, 1-2, 3-2, 0-3, the same on top,
/// then the vertical ones from vertices 0, 1, 2, 3), the faces i = 0, i = p, j = 0, j = p,
/// k = 0, k = p, then the inside; every edge, face and the inside counted with `i` fastest,
/// then `j`, then `k`.
fn hex_index(p: usize, [i, j, k]: [usize; 3]) -> usize {
    let on = |x: usize| x == 0 || x == p;
    let (bi, bj, bk) = (on(i), on(j), on(k));
    let corner = |i: usize, j: usize| match (i > 0, j > 0) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    };
    let e = p - 1;
    let top = |x: usize, n: usize| if x > 0 { n } else { 0 };
    match (bi, bj, bk) {
        (true, true, true) => corner(i, j) + top(k, 4),
        (false, true, true) => 8 + (i - 1) + top(j, 2 * e) + top(k, 4 * e),
        (true, false, true) => 8 + (j - 1) + if i > 0 { e } else { 3 * e } + top(k, 4 * e),
        (true, true, false) => 8 + 8 * e + corner(i, j) * e + (k - 1),
        _ => {
            let f = e * e;
            let faces = 8 + 12 * e;
            match (bi, bj, bk) {
                (true, _, _) => faces + top(i, f) + (j - 1) + e * (k - 1),
                (_, true, _) => faces + 2 * f + top(j, f) + (i - 1) + e * (k - 1),
                (_, _, true) => faces + 4 * f + top(k, f) + (i - 1) + e * (j - 1),
                _ => faces + 6 * f + (i - 1) + e * (j - 1) + f * (k - 1),
            }
        }
    }
}

/// A wedge of degree `p`: vertices, the triangle edges 0-1, 1-2, 2-0 at the bottom and at the
/// top (each from its first vertex on), the vertical edges, the two triangles' insides (row by
/// row: `i` fastest), the quadrilateral faces j = 0, i + j = p, i = 0 (along the triangle's
/// edge direction, then up), then the inside (triangle rows, then up).
fn wedge_index(p: usize, [i, j, k]: [usize; 3]) -> usize {
    let (bi, bj, bij, bk) = (i == 0, j == 0, i + j == p, k == 0 || k == p);
    let e = p - 1;
    let corner = || {
        if bi && bj {
            0
        } else if bj && bij {
            1
        } else {
            2
        }
    };
    let ntf = e * e.saturating_sub(1) / 2;
    let nqf = e * e;
    // Interior points of a triangle row by row: rows 1 … j−1 hold p − 1 − row points each.
    let row_major = |i: usize, j: usize| (1..j).map(|r| p - 1 - r).sum::<usize>() + (i - 1);
    let top = |n: usize| if k == p { n } else { 0 };
    match [bi, bj, bij, bk].iter().filter(|&&b| b).count() {
        3 => corner() + top(3),
        2 if !bk => 6 + 6 * e + corner() * e + (k - 1),
        2 => {
            let base = 6 + top(3 * e);
            if bj {
                base + i - 1
            } else if bij {
                base + e + j - 1
            } else {
                base + 2 * e + (p - j - 1)
            }
        }
        1 => {
            let faces = 6 + 9 * e;
            if bk {
                faces + top(ntf) + row_major(i, j)
            } else if bj {
                faces + 2 * ntf + (i - 1) + e * (k - 1)
            } else if bij {
                faces + 2 * ntf + nqf + (j - 1) + e * (k - 1)
            } else {
                faces + 2 * ntf + 2 * nqf + (p - j - 1) + e * (k - 1)
            }
        }
        _ => 6 + 9 * e + 2 * ntf + 3 * nqf + row_major(i, j) + ntf * (k - 1),
    }
}

/// A pyramid of degree 1 or 2: vertices, mid-edge nodes (edges 0-1, 1-2, 2-3, 3-0, then 0-4,
/// 1-4, 2-4, 3-4), the base's centre. `ijk` is a corner or the midpoint of two corners as
/// [`Shape::corner`] places them (the apex at (0, 0, p)).
fn pyramid_index(p: usize, ijk: [usize; 3]) -> usize {
    let corners: Vec<[usize; 3]> = (0..5).map(|v| Shape::Pyramid.corner(p, v)).collect();
    if let Some(v) = corners.iter().position(|&c| c == ijk) {
        return v;
    }
    const EDGES: [[usize; 2]; 8] = [
        [0, 1],
        [1, 2],
        [2, 3],
        [3, 0],
        [0, 4],
        [1, 4],
        [2, 4],
        [3, 4],
    ];
    let mid = |[a, b]: [usize; 2]| [0, 1, 2].map(|d| (corners[a][d] + corners[b][d]) / 2);
    match EDGES.iter().position(|&e| mid(e) == ijk) {
        Some(e) => 5 + e,
        None => 13,
    }
}

/// Lagrange hexahedra as VTK wrote them before version 9 (`.vtu` files of version < 2.1,
/// legacy files of version < 5.1): the nodes of the vertical edges from vertices 2 and 3 come
/// in the other order. Puts them into today's order (an exchange, so it also undoes itself).
pub fn hexahedron_from_vtk8(conn: &mut [u32]) {
    let Some(p) = Shape::Hexahedron.degree(conn.len()) else {
        return;
    };
    let e = p - 1;
    let start = 8 + 8 * e + 2 * e;
    for x in 0..e {
        conn.swap(start + x, start + e + x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every lattice point gets its own index, and the indices are 0 … n − 1.
    fn check_bijective(shape: Shape, p: usize) {
        let mut seen = vec![false; shape.nodes(p)];
        for k in 0..=p {
            for j in 0..=p {
                for i in 0..=p {
                    let inside = match shape {
                        Shape::Tetrahedron => i + j + k <= p,
                        Shape::Hexahedron => true,
                        Shape::Wedge => i + j <= p,
                        Shape::Pyramid => false,
                    };
                    if inside {
                        let n = shape.index(p, [i, j, k]);
                        assert!(!seen[n], "{shape:?} p={p}: {i} {j} {k} again at {n}");
                        seen[n] = true;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&s| s), "{shape:?} p={p}");
    }

    #[test]
    fn every_lattice_point_has_its_own_node() {
        for p in 1..=7 {
            check_bijective(Shape::Tetrahedron, p);
            check_bijective(Shape::Hexahedron, p);
            check_bijective(Shape::Wedge, p);
        }
    }

    #[test]
    fn vtk_orders_of_degree_3() {
        // As VTK 9.7 lists them (vtkLagrangeTetra, vtkLagrangeWedge parametric coordinates).
        let tet: [[usize; 3]; 20] = [
            [0, 0, 0],
            [3, 0, 0],
            [0, 3, 0],
            [0, 0, 3],
            [1, 0, 0],
            [2, 0, 0],
            [2, 1, 0],
            [1, 2, 0],
            [0, 2, 0],
            [0, 1, 0],
            [0, 0, 1],
            [0, 0, 2],
            [2, 0, 1],
            [1, 0, 2],
            [0, 2, 1],
            [0, 1, 2],
            [1, 0, 1],
            [1, 1, 1],
            [0, 1, 1],
            [1, 1, 0],
        ];
        for (n, ijk) in tet.iter().enumerate() {
            assert_eq!(Shape::Tetrahedron.index(3, *ijk), n, "{ijk:?}");
        }
        let wedge_faces: [[usize; 3]; 16] = [
            [1, 1, 0],
            [1, 1, 3],
            [1, 0, 1],
            [2, 0, 1],
            [1, 0, 2],
            [2, 0, 2],
            [2, 1, 1],
            [1, 2, 1],
            [2, 1, 2],
            [1, 2, 2],
            [0, 2, 1],
            [0, 1, 1],
            [0, 2, 2],
            [0, 1, 2],
            [1, 1, 1],
            [1, 1, 2],
        ];
        for (n, ijk) in wedge_faces.iter().enumerate() {
            assert_eq!(Shape::Wedge.index(3, *ijk), 24 + n, "{ijk:?}");
        }
    }

    #[test]
    fn degrees_from_node_counts() {
        assert_eq!(Shape::Tetrahedron.degree(4), Some(1));
        assert_eq!(Shape::Tetrahedron.degree(10), Some(2));
        assert_eq!(Shape::Tetrahedron.degree(35), Some(4));
        assert_eq!(Shape::Tetrahedron.degree(11), None);
        assert_eq!(Shape::Hexahedron.degree(27), Some(2));
        assert_eq!(Shape::Wedge.degree(18), Some(2));
        assert_eq!(Shape::Wedge.degree(21), Some(2));
        assert_eq!(Shape::Wedge.degree(40), Some(3));
        assert_eq!(Shape::Pyramid.degree(14), Some(2));
        assert_eq!(Shape::Pyramid.degree(13), None);
        assert_eq!(Shape::Hexahedron.degree(0), None);
    }

    #[test]
    fn vtk8_hexahedra_swap_two_vertical_edges() {
        let mut conn: Vec<u32> = (0..64).collect();
        hexahedron_from_vtk8(&mut conn);
        // Degree 3: the vertical edges start at 8 + 8 × 2 = 24, two nodes each; those from
        // vertices 2 and 3 change places.
        assert_eq!(&conn[24..32], &[24, 25, 26, 27, 30, 31, 28, 29]);
        let mut linear: Vec<u32> = (0..8).collect();
        hexahedron_from_vtk8(&mut linear);
        assert_eq!(linear, (0..8).collect::<Vec<u32>>());
    }
}
