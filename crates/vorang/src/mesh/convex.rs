//! Is a mesh a single convex body? Then MPVO alone orders it exactly (thesis 5.2.1), and the
//! renderer composites in the sort's order without per-pixel runs.
//!
//! A property of the mesh alone — its adjacency and its boundary, decided by the exact 3D
//! orientation predicate — so it lives with the mesh and is cached there
//! ([`TetMesh::is_convex`]); the visibility sort only reads it.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use rayon::prelude::*;

use super::{TetMesh, orientation};

/// Cells per parallel task.
const CELLS_PER_TASK: usize = 1 << 14;

/// True if the mesh is connected and its boundary is a closed surface that never folds inward
/// (every boundary edge joins exactly two boundary faces at a convex or flat angle, decided by
/// exact predicates). Such a surface bounds a convex body.
pub fn is_convex(mesh: &TetMesh) -> bool {
    if mesh.tet_count() == 0 {
        return true;
    }
    if !connected(mesh) {
        return false;
    }
    // Boundary edges: each must have two boundary faces; the far vertex of one face must not lie
    // outside the other's plane.
    let mut edges: HashMap<(u32, u32), Vec<[u32; 3]>> = HashMap::new();
    let boundary: Vec<(usize, usize)> = (0..mesh.tet_count())
        .into_par_iter()
        .with_min_len(CELLS_PER_TASK)
        .flat_map_iter(|c| {
            (0..4)
                .filter(move |&f| mesh.neighbor(c, f).is_none())
                .map(move |f| (c, f))
        })
        .collect();
    for (c, f) in boundary {
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

/// Whether every cell can be reached from every other across faces: a union–find over the
/// face adjacency, built in parallel (lock-free: a root is linked under the smaller root by a
/// compare-and-swap, so concurrent unions never lose a link), then one check that every cell's
/// root is cell 0's.
fn connected(mesh: &TetMesh) -> bool {
    let n = mesh.tet_count();
    let parent: Vec<AtomicU32> = (0..n as u32).into_par_iter().map(AtomicU32::new).collect();
    let find = |mut x: u32| loop {
        let p = parent[x as usize].load(Relaxed);
        if p == x {
            return x;
        }
        let grand = parent[p as usize].load(Relaxed);
        // Path halving; a lost race only leaves a longer path.
        let _ = parent[x as usize].compare_exchange(p, grand, Relaxed, Relaxed);
        x = grand;
    };
    (0..n)
        .into_par_iter()
        .with_min_len(CELLS_PER_TASK)
        .for_each(|c| {
            for f in 0..4 {
                let Some(m) = mesh.neighbor(c, f) else {
                    continue;
                };
                if m < c {
                    continue;
                }
                let (mut a, mut b) = (c as u32, m as u32);
                loop {
                    (a, b) = (find(a), find(b));
                    if a == b {
                        break;
                    }
                    let (high, low) = if a > b { (a, b) } else { (b, a) };
                    if parent[high as usize]
                        .compare_exchange(high, low, Relaxed, Relaxed)
                        .is_ok()
                    {
                        break;
                    }
                }
            }
        });
    let root = find(0);
    (1..n as u32)
        .into_par_iter()
        .with_min_len(CELLS_PER_TASK)
        .all(|c| find(c) == root)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{SplitMix64, kuhn_box};

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

    /// Connected by a plain depth-first search, the reference of the union–find.
    fn connected_by_search(mesh: &TetMesh) -> bool {
        let mut seen = vec![false; mesh.tet_count()];
        let mut stack = vec![0];
        seen[0] = true;
        let mut count = 1;
        while let Some(c) = stack.pop() {
            for f in 0..4 {
                if let Some(m) = mesh.neighbor(c, f)
                    && !seen[m]
                {
                    seen[m] = true;
                    count += 1;
                    stack.push(m);
                }
            }
        }
        count == mesh.tet_count()
    }

    /// Boxes thinned at random until they fall apart: the parallel union–find agrees with a
    /// depth-first search, in pools of 1 to 3 threads.
    #[test]
    fn union_find_agrees_with_a_search() {
        let (nodes, tets) = kuhn_box([12, 10, 3], [1.0; 3], 0.1, 2);
        let mut rng = SplitMix64(11);
        let pools = [1, 2, 3].map(|t| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .unwrap()
        });
        let mut outcomes = [0, 0];
        for keep in [1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.45, 0.4] {
            let kept: Vec<[u32; 4]> = tets
                .iter()
                .copied()
                .filter(|_| rng.next_f64() < keep)
                .collect();
            let mesh = TetMesh::new(nodes.clone(), kept).unwrap();
            let expected = connected_by_search(&mesh);
            outcomes[usize::from(expected)] += 1;
            for pool in &pools {
                assert_eq!(pool.install(|| connected(&mesh)), expected, "keep {keep}");
            }
        }
        assert!(
            outcomes[0] > 0 && outcomes[1] > 0,
            "both outcomes tested: {outcomes:?}"
        );
    }
}
