//! Is a mesh a single convex body? Then MPVO alone orders it exactly (thesis 5.2.1), and the
//! renderer composites in the sort's order without per-pixel runs.
//!
//! A property of the mesh alone — its adjacency and its boundary, decided by the exact 3D
//! orientation predicate — so it lives with the mesh and is cached there
//! ([`TetMesh::is_convex`]); the visibility sort only reads it.

use std::collections::HashMap;

use super::{TetMesh, orientation};

/// True if the mesh is connected and its boundary is a closed surface that never folds inward
/// (every boundary edge joins exactly two boundary faces at a convex or flat angle, decided by
/// exact predicates). Such a surface bounds a convex body.
pub fn is_convex(mesh: &TetMesh) -> bool {
    if mesh.tet_count() == 0 {
        return true;
    }
    // Connected?
    let mut seen = vec![false; mesh.tet_count()];
    let mut stack = vec![0usize];
    seen[0] = true;
    let mut count = 1;
    while let Some(c) = stack.pop() {
        for f in 0..4 {
            if let Some(n) = mesh.neighbor(c, f)
                && !seen[n]
            {
                seen[n] = true;
                count += 1;
                stack.push(n);
            }
        }
    }
    if count != mesh.tet_count() {
        return false;
    }
    // Boundary edges: each must have two boundary faces; the far vertex of one face must not lie
    // outside the other's plane.
    let mut edges: HashMap<(u32, u32), Vec<[u32; 3]>> = HashMap::new();
    for (c, f) in mesh.boundary_faces() {
        let face = mesh.face_nodes(c, f);
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(face);
        }
    }
    let p = |n: u32| mesh.nodes()[n as usize];
    edges.iter().all(|(&(a, b), faces)| {
        if faces.len() != 2 {
            return false;
        }
        let other = |face: &[u32; 3]| *face.iter().find(|&&n| n != a && n != b).unwrap_or(&a);
        let [f1, f2] = [&faces[0], &faces[1]];
        // Outward-oriented face: a point outside it has positive orientation.
        orientation(p(f1[0]), p(f1[1]), p(f1[2]), p(other(f2))) <= 0.0
            && orientation(p(f2[0]), p(f2[1]), p(f2[2]), p(other(f1))) <= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::kuhn_box;

    #[test]
    fn boxes_are_convex_and_an_l_shape_is_not() {
        let (nodes, tets) = kuhn_box([3, 2, 2], [1.0; 3], 0.0, 0);
        assert!(is_convex(
            &TetMesh::new(nodes.clone(), tets.clone()).unwrap()
        ));
        // Remove the cubes of one corner column: an L-shaped (non-convex) body.
        let keep: Vec<[u32; 4]> = tets
            .iter()
            .filter(|t| {
                let c =
                    [0, 1, 2].map(|k| t.iter().map(|&n| nodes[n as usize][k]).sum::<f64>() / 4.0);
                !(c[0] > 2.0 / 3.0 && c[1] > 0.5)
            })
            .copied()
            .collect();
        assert!(!is_convex(&TetMesh::new(nodes.clone(), keep).unwrap()));
        // Two separate cubes.
        let (n2, t2) = kuhn_box([3, 1, 1], [3.0, 1.0, 1.0], 0.0, 0);
        let apart: Vec<[u32; 4]> = t2
            .iter()
            .filter(|t| {
                t.iter().map(|&n| n2[n as usize][0]).sum::<f64>() / 4.0 < 1.0
                    || t.iter().map(|&n| n2[n as usize][0]).sum::<f64>() / 4.0 > 2.0
            })
            .copied()
            .collect();
        assert!(!is_convex(&TetMesh::new(n2, apart).unwrap()));
    }
}
