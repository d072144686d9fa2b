//! The tetrahedral mesh (thesis 2.2.1.1): node positions, positively oriented cells,
//! face adjacency (face `i` is opposite node `i`), boundary faces and bounding box.
//!
//! This is the structure every later stage traverses, so it is kept flat: three arrays indexed by
//! node or cell, `u32` indices, no per-cell allocation.

mod adjacency;
mod convex;
pub mod edges;
pub mod generate;
mod geometry;
pub mod overlap;

pub use convex::is_convex;
pub use geometry::{Aabb, barycentric, barycentric_gradients, is_proper, orientation, tet_volume};

/// Marks a face without a neighbouring cell (a boundary face).
pub const NO_NEIGHBOR: u32 = u32::MAX;

/// The nodes of face `i` (opposite node `i`), ordered so that the face normal by the right-hand
/// rule points out of a positively oriented cell.
pub const FACE_NODES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

/// The six edges of a cell in the HyperMesh coding order (n0n1, n0n2, n0n3, n1n2, n1n3, n2n3).
pub const EDGE_NODES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// Why a set of nodes and cells is not a valid tetrahedral mesh. Cell and node numbers are
/// 0-based; readers translate them into file lines.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MeshError {
    NodeOutOfRange {
        tet: usize,
        node: usize,
        nodes: usize,
    },
    RepeatedNode {
        tet: usize,
        node: usize,
    },
    Degenerate {
        tet: usize,
    },
    NonManifold {
        tet: usize,
        face: usize,
        others: [usize; 2],
    },
    NonFinite {
        node: usize,
    },
    TooLarge {
        tets: usize,
    },
}

impl MeshError {
    /// The cell the error is about, if any.
    pub fn tet(&self) -> Option<usize> {
        match *self {
            MeshError::NodeOutOfRange { tet, .. }
            | MeshError::RepeatedNode { tet, .. }
            | MeshError::Degenerate { tet }
            | MeshError::NonManifold { tet, .. } => Some(tet),
            MeshError::NonFinite { .. } | MeshError::TooLarge { .. } => None,
        }
    }

    /// What is wrong, without naming the cell (for messages that name it already).
    pub fn detail(&self) -> String {
        match *self {
            MeshError::NodeOutOfRange { node, nodes, .. } => {
                format!(
                    "refers to node {}, but there are only {nodes} nodes",
                    node + 1
                )
            }
            MeshError::RepeatedNode { node, .. } => format!("uses node {} twice", node + 1),
            MeshError::Degenerate { .. } => {
                "degenerate: its four nodes lie in one plane (zero volume)".into()
            }
            MeshError::NonManifold { face, others, .. } => format!(
                "its face opposite node {face} is shared by more than two tetrahedra (also by {} and {})",
                others[0] + 1,
                others[1] + 1
            ),
            MeshError::NonFinite { node } => {
                format!("node {} has a non-finite coordinate", node + 1)
            }
            MeshError::TooLarge { tets } => {
                format!("{tets} tetrahedra are more than this build supports (at most 2^30)")
            }
        }
    }
}

impl std::fmt::Display for MeshError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.tet() {
            Some(t) => write!(f, "tetrahedron {}: {}", t + 1, self.detail()),
            None => f.write_str(&self.detail()),
        }
    }
}

impl std::error::Error for MeshError {}

/// A validated tetrahedral mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct TetMesh {
    nodes: Vec<[f64; 3]>,
    tets: Vec<[u32; 4]>,
    neighbors: Vec<[u32; 4]>,
    bbox: Aabb,
    reoriented: usize,
    boundary_faces: usize,
    /// Whether the mesh is convex, decided on first use (it picks the visibility sort and costs
    /// a pass over the boundary — worth doing once, not every frame).
    convex: ConvexCache,
}

/// A lazily computed property that takes no part in comparisons.
#[derive(Debug, Clone, Default)]
struct ConvexCache(std::sync::OnceLock<bool>);

impl PartialEq for ConvexCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// Cells per parallel task of [`orient_cells`].
const CELLS_PER_TASK: usize = 1 << 14;

/// Checks every cell's node indices and turns negatively oriented cells (exact predicate) the
/// positive way; returns how many were turned. In parallel, by chunks of cells that come back
/// in order, so the error reported is the first cell's a single thread would find.
fn orient_cells(nodes: &[[f64; 3]], tets: &mut [[u32; 4]]) -> Result<usize, MeshError> {
    use rayon::prelude::*;
    let counts: Vec<Result<usize, MeshError>> = tets
        .par_chunks_mut(CELLS_PER_TASK)
        .enumerate()
        .map(|(chunk, cells)| {
            let mut reoriented = 0;
            for (i, tet) in cells.iter_mut().enumerate() {
                let t = chunk * CELLS_PER_TASK + i;
                for (k, &n) in tet.iter().enumerate() {
                    if n as usize >= nodes.len() {
                        return Err(MeshError::NodeOutOfRange {
                            tet: t,
                            node: n as usize,
                            nodes: nodes.len(),
                        });
                    }
                    if tet[..k].contains(&n) {
                        return Err(MeshError::RepeatedNode {
                            tet: t,
                            node: n as usize,
                        });
                    }
                }
                let p = tet.map(|n| nodes[n as usize]);
                let sign = orientation(p[0], p[1], p[2], p[3]);
                if sign == 0.0 {
                    return Err(MeshError::Degenerate { tet: t });
                }
                if sign < 0.0 {
                    tet.swap(2, 3);
                    reoriented += 1;
                }
            }
            Ok(reoriented)
        })
        .collect();
    let mut total = 0;
    for count in counts {
        total += count?;
    }
    Ok(total)
}

impl TetMesh {
    /// Validates and builds a mesh. Negatively oriented cells are re-oriented in place (their
    /// index is kept, so cell data stays attached); [`TetMesh::reoriented`] says how many.
    pub fn new(nodes: Vec<[f64; 3]>, mut tets: Vec<[u32; 4]>) -> Result<TetMesh, MeshError> {
        if tets.len() >= 1 << 30 {
            return Err(MeshError::TooLarge { tets: tets.len() });
        }
        use rayon::prelude::*;
        if let Some(node) = nodes
            .par_iter()
            .with_min_len(CELLS_PER_TASK)
            .position_first(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(MeshError::NonFinite { node });
        }
        let reoriented = orient_cells(&nodes, &mut tets)?;
        let neighbors = adjacency::face_neighbors(nodes.len(), &tets)?;
        let boundary_faces = neighbors
            .par_iter()
            .with_min_len(CELLS_PER_TASK)
            .map(|nb| nb.iter().filter(|&&n| n == NO_NEIGHBOR).count())
            .sum();
        // Minima and maxima are exact, so the chunks' boxes merge to the serial box.
        let bbox = nodes
            .par_chunks(CELLS_PER_TASK)
            .map(Aabb::of_points)
            .reduce(|| Aabb::of_points(&[]), |a, b| a.union(&b));
        Ok(TetMesh {
            nodes,
            tets,
            neighbors,
            bbox,
            reoriented,
            boundary_faces,
            convex: ConvexCache::default(),
        })
    }

    /// Node positions in the file's coordinates.
    pub fn nodes(&self) -> &[[f64; 3]] {
        &self.nodes
    }

    /// Cells as four node indices, positively oriented:
    /// `((n1−n0)×(n2−n0))·(n3−n0) > 0`.
    pub fn tets(&self) -> &[[u32; 4]] {
        &self.tets
    }

    /// For each cell and face `i` (opposite node `i`): the neighbouring cell or [`NO_NEIGHBOR`].
    pub fn neighbors(&self) -> &[[u32; 4]] {
        &self.neighbors
    }

    pub fn neighbor(&self, tet: usize, face: usize) -> Option<usize> {
        let n = self.neighbors[tet][face];
        (n != NO_NEIGHBOR).then_some(n as usize)
    }

    /// The faces without neighbour, as `(cell, face)`.
    pub fn boundary_faces(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.neighbors.iter().enumerate().flat_map(|(t, nb)| {
            (0..4)
                .filter(move |&f| nb[f] == NO_NEIGHBOR)
                .map(move |f| (t, f))
        })
    }

    pub fn boundary_face_count(&self) -> usize {
        self.boundary_faces
    }

    /// The axis-aligned bounding box of all nodes.
    pub fn bbox(&self) -> Aabb {
        self.bbox
    }

    /// Gives the mesh another bounding box: a piece of a larger mesh (one rank's cells of a
    /// distributed frame) is centred, framed and lit as the whole it belongs to, so it carries
    /// the whole's box (docs/distributed.md).
    pub fn set_bbox(&mut self, bbox: Aabb) {
        self.bbox = bbox;
    }

    /// How many cells were negatively oriented in the input and have been re-oriented.
    pub fn reoriented(&self) -> usize {
        self.reoriented
    }

    /// The four corner positions of a cell.
    #[inline]
    pub fn corners(&self, tet: usize) -> [[f64; 3]; 4] {
        self.gather(tet, &self.nodes)
    }

    /// A per-node quantity (positions in eye space, on screen, field values …) at the four
    /// corners of a cell. Written out rather than with `array::map`, which does not always
    /// inline — this runs for every cell of every frame.
    #[inline]
    pub fn gather<T: Copy>(&self, tet: usize, per_node: &[T]) -> [T; 4] {
        let n = self.tets[tet];
        [
            per_node[n[0] as usize],
            per_node[n[1] as usize],
            per_node[n[2] as usize],
            per_node[n[3] as usize],
        ]
    }

    /// Volume of a cell (positive).
    pub fn tet_volume(&self, tet: usize) -> f64 {
        let p = self.corners(tet);
        tet_volume(p[0], p[1], p[2], p[3])
    }

    /// The three node indices of face `face` of `tet`, outward-oriented.
    pub fn face_nodes(&self, tet: usize, face: usize) -> [u32; 3] {
        FACE_NODES[face].map(|k| self.tets[tet][k])
    }

    /// Whether the mesh is convex (its boundary faces all bound one convex region), computed
    /// once.
    pub fn is_convex(&self) -> bool {
        *self.convex.0.get_or_init(|| convex::is_convex(self))
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn tet_count(&self) -> usize {
        self.tets.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two cubes side by side, each split into 6 tetrahedra (the thesis's farbraum layout).
    pub(crate) fn two_cubes() -> (Vec<[f64; 3]>, Vec<[u32; 4]>) {
        let mut nodes = Vec::new();
        for z in 0..2 {
            for y in 0..2 {
                for x in 0..3 {
                    nodes.push([x as f64, y as f64, z as f64]);
                }
            }
        }
        let id = |x: u32, y: u32, z: u32| x + 3 * y + 6 * z;
        let mut tets = Vec::new();
        for cx in 0..2 {
            let c = |i: u32| {
                let (x, y, z) = (i & 1, (i >> 1) & 1, (i >> 2) & 1);
                id(cx + x, y, z)
            };
            // Kuhn subdivision: 6 tets around the diagonal 0–7.
            for perm in [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]] {
                let a = perm[0];
                let b = perm[1];
                tets.push([c(0), c(a), c(b), c(7)]);
            }
        }
        (nodes, tets)
    }

    #[test]
    fn orientation_convention_matches_the_spec() {
        let o = [0.0; 3];
        let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert!(orientation(o, x, y, z) > 0.0);
        assert!(orientation(o, y, x, z) < 0.0);
        assert_eq!(orientation(o, x, y, [1.0, 1.0, 0.0]), 0.0);
    }

    #[test]
    fn kuhn_cubes_build_with_adjacency_and_reorientation() {
        let (nodes, tets) = two_cubes();
        let mesh = TetMesh::new(nodes, tets).unwrap();
        assert_eq!(mesh.tet_count(), 12);
        // Half of the Kuhn tets come out negative in this construction.
        assert!(mesh.reoriented() > 0);
        for t in 0..12 {
            let p = mesh.corners(t);
            assert!(orientation(p[0], p[1], p[2], p[3]) > 0.0);
            assert!((mesh.tet_volume(t) - 1.0 / 6.0).abs() < 1e-15);
        }
        // A 2×1×1 box has 2·(2+1+2)·2 = 20 boundary triangles.
        assert_eq!(mesh.boundary_face_count(), 20);
        // Adjacency is symmetric and neighbours share the face's nodes.
        for t in 0..12 {
            for f in 0..4 {
                if let Some(n) = mesh.neighbor(t, f) {
                    let back = (0..4).find(|&g| mesh.neighbor(n, g) == Some(t)).unwrap();
                    let mut a = mesh.face_nodes(t, f);
                    let mut b = mesh.face_nodes(n, back);
                    a.sort();
                    b.sort();
                    assert_eq!(a, b);
                }
            }
        }
        assert_eq!(mesh.bbox().max, [2.0, 1.0, 1.0]);
    }

    #[test]
    fn outward_faces_point_away_from_the_opposite_node() {
        let (nodes, tets) = two_cubes();
        let mesh = TetMesh::new(nodes, tets).unwrap();
        for t in 0..mesh.tet_count() {
            for f in 0..4 {
                let [a, b, c] = mesh.face_nodes(t, f).map(|n| mesh.nodes()[n as usize]);
                let opp = mesh.nodes()[mesh.tets()[t][f] as usize];
                assert!(orientation(a, b, c, opp) < 0.0, "face {f} of {t}");
            }
        }
    }

    #[test]
    fn invalid_meshes_name_the_cell() {
        let (nodes, mut tets) = two_cubes();
        tets[3] = [0, 1, 2, 5]; // 0,1,2 collinear → zero volume
        assert_eq!(
            TetMesh::new(nodes.clone(), tets).unwrap_err(),
            MeshError::Degenerate { tet: 3 }
        );
        let (_, mut tets) = two_cubes();
        tets[2][1] = tets[2][0];
        assert!(matches!(
            TetMesh::new(nodes.clone(), tets),
            Err(MeshError::RepeatedNode { tet: 2, .. })
        ));
        let (_, mut tets) = two_cubes();
        tets.push(tets[0]);
        tets.push(tets[0]);
        assert!(matches!(
            TetMesh::new(nodes.clone(), tets),
            Err(MeshError::NonManifold { .. })
        ));
        let (_, mut tets) = two_cubes();
        tets[0][0] = 99;
        assert!(matches!(
            TetMesh::new(nodes.clone(), tets),
            Err(MeshError::NodeOutOfRange { tet: 0, .. })
        ));
        let (mut nodes, tets) = two_cubes();
        nodes[1][0] = f64::NAN;
        assert_eq!(
            TetMesh::new(nodes, tets).unwrap_err(),
            MeshError::NonFinite { node: 1 }
        );
    }
}
