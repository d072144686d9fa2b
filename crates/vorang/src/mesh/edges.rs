//! Edge lists of a tetrahedral mesh: lookup by node pair and the six edges of each cell, for
//! the fields that live on edges (edge elements, quadratic fields).

use std::collections::HashMap;

use super::{EDGE_NODES, TetMesh};

/// Marks "no element" in index lists (a missing neighbour in UpperLower, an edge of a cell that
/// the edge list lacks).
pub const NONE: u32 = u32::MAX;

/// Edge lookup by unordered node pair; `Err((edge, earlier edge))` for a repeated pair.
pub fn edge_index(list: &[[u32; 2]]) -> Result<HashMap<(u32, u32), u32>, (usize, usize)> {
    let mut index: HashMap<(u32, u32), u32> = HashMap::with_capacity(list.len());
    for (e, &[a, b]) in list.iter().enumerate() {
        if let Some(first) = index.insert((a.min(b), a.max(b)), e as u32) {
            return Err((e, first as usize));
        }
    }
    Ok(index)
}

/// For each cell, its six edges as indices into `list` (bit 31 set where the list directs the
/// edge against the local order), [`NONE`] where the list lacks one.
pub fn edges_of_cells(
    mesh: &TetMesh,
    list: &[[u32; 2]],
    index: &HashMap<(u32, u32), u32>,
) -> Vec<[u32; 6]> {
    mesh.tets()
        .iter()
        .map(|tet| {
            EDGE_NODES.map(|[i, j]| {
                let (a, b) = (tet[i], tet[j]);
                match index.get(&(a.min(b), a.max(b))) {
                    Some(&e) if list[e as usize][0] == a => e,
                    Some(&e) => e | 1 << 31,
                    None => NONE,
                }
            })
        })
        .collect()
}
