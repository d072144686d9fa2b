//! Visibility ordering of the cells (thesis 2.2.2.2, 5.2.1).
//!
//! Projected-tetrahedra compositing needs the cells back to front (or front to back). For a
//! connected convex mesh MPVO (Williams 1992) orders them exactly: across every interior face
//! the cell on the viewer's side comes later; a topological sort of that relation is a correct
//! order. Meshes with concavities or holes need more: `mpvo` with depth priority is Williams'
//! MPVONC heuristic (the thesis's `VRxConcaveSort`); where it (or a broken cycle) leaves the
//! order wrong along some ray, the renderer settles it per pixel ([`crate::render::runs`]), so
//! the sort only has to be good, not exact. Faces are classified by the same exact screen
//! predicate the renderer uses ([`crate::predicates`]), and a mirroring transform flips them
//! once. Each strategy is one entry in [`SORTS`].

mod farthest;
mod levels;
mod mpvo;

/// Convexity is the mesh's own property ([`crate::mesh::is_convex`], cached by
/// [`TetMesh::is_convex`]); it picks the sort ([`choose`]) and stays reachable here.
pub use crate::mesh::is_convex;

use crate::mesh::TetMesh;

/// What a sort needs: the mesh, node positions in eye space and the kind of projection.
pub struct SortInput<'a> {
    pub mesh: &'a TetMesh,
    /// Node positions in eye space (the camera looks along −z).
    pub eye_nodes: &'a [[f64; 3]],
    /// Node positions on screen (where in front of the eye). Faces whose nodes are all in front
    /// of the eye are classified by the exact orientation of their screen triangle — the same
    /// predicate the renderer uses to pick a pixel's entry and exit faces, so that sort and
    /// rasteriser agree even on faces within rounding of edge-on.
    pub screen: &'a [[f64; 2]],
    /// Perspective: the eye is at the origin; orthographic: the viewer is at +∞ along z.
    pub perspective: bool,
    /// The model transform has a negative determinant (a mirror): every orientation flips.
    pub mirrored: bool,
}

/// A back-to-front order of all cells and how many cells had to be forced out of a visibility
/// cycle (0 for an exact order).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Order {
    pub back_to_front: Vec<u32>,
    pub cycle_cells: usize,
}

/// One registry entry.
pub struct SortInfo {
    pub name: &'static str,
    pub summary: &'static str,
    pub sort: fn(&SortInput) -> Order,
}

/// Every visibility sort.
pub const SORTS: &[SortInfo] = &[mpvo::MPVO, mpvo::MPVONC];

/// The sort for a mesh: MPVO for a connected convex mesh, the MPVONC heuristic otherwise.
pub fn choose(convex: bool) -> &'static SortInfo {
    if convex { &SORTS[0] } else { &SORTS[1] }
}
