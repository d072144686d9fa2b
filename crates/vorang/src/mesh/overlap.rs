//! Finding cells that interpenetrate without sharing a face (`vorang info --check`): broken
//! input such as overlapping parts exported together or a bad merge. A volume check cannot see
//! it (each cell encloses its own volume); two cells' interiors meet exactly when a node of one
//! lies strictly inside the other, or an edge of one strictly crosses a face of the other (for
//! cells in general position), which exact orientation predicates decide. Identical cells under
//! other node numbers are caught by their centroids.
//!
//! Candidate pairs come from a uniform grid over the mesh's bounding box (about one grid cell per
//! mesh cell); the work is bounded by a budget of pair tests, and the report says when it ran out.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rayon::prelude::*;

use super::{FACE_NODES, TetMesh, orientation};

/// What the check found.
#[derive(Debug, Clone, PartialEq)]
pub struct OverlapReport {
    /// Pairs of interpenetrating cells (0-based, smaller first), at most `limit` of them.
    pub pairs: Vec<(u32, u32)>,
    /// How many pairs were found in all (may exceed `pairs.len()`).
    pub found: usize,
    /// Candidate pairs tested exactly.
    pub tested: usize,
    /// Whether every candidate pair was tested (the budget did not run out).
    pub complete: bool,
}

/// Looks for interpenetrating cells, testing at most `budget` candidate pairs and listing at
/// most `limit` of the pairs found.
pub fn find_overlaps(mesh: &TetMesh, budget: usize, limit: usize) -> OverlapReport {
    let n = mesh.tet_count();
    let boxes: Vec<[[f64; 3]; 2]> = (0..n)
        .map(|c| {
            let p = mesh.corners(c);
            let mut b = [p[0], p[0]];
            for q in &p[1..] {
                for k in 0..3 {
                    b[0][k] = b[0][k].min(q[k]);
                    b[1][k] = b[1][k].max(q[k]);
                }
            }
            b
        })
        .collect();
    let mut report = OverlapReport {
        pairs: Vec::new(),
        found: 0,
        tested: 0,
        complete: true,
    };
    if n < 2 {
        return report;
    }
    let bbox = mesh.bbox();
    let (lo, size) = (bbox.min, bbox.size());
    let g = ((n as f64).cbrt().ceil() as usize).clamp(1, 256);
    let cell_of = |v: f64, k: usize| -> usize {
        if size[k] <= 0.0 {
            return 0;
        }
        (((v - lo[k]) / size[k] * g as f64) as usize).min(g - 1)
    };
    let span = |b: &[[f64; 3]; 2]| [0, 1, 2].map(|k| (cell_of(b[0][k], k), cell_of(b[1][k], k)));
    // The grid: each cell lists the mesh cells whose box reaches it (bounded insertions).
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); g * g * g];
    let mut insertions = 0usize;
    for (c, b) in boxes.iter().enumerate() {
        let s = span(b);
        let count = (s[0].1 - s[0].0 + 1) * (s[1].1 - s[1].0 + 1) * (s[2].1 - s[2].0 + 1);
        insertions += count;
        // Memory stays within 64 entries per cell (boxes spanning many grid cells are rare).
        if insertions > n.saturating_mul(64) {
            report.complete = false;
            break;
        }
        for z in s[2].0..=s[2].1 {
            for y in s[1].0..=s[1].1 {
                for x in s[0].0..=s[0].1 {
                    grid[(z * g + y) * g + x].push(c as u32);
                }
            }
        }
    }
    let neighbors = mesh.neighbors();
    let tested = AtomicUsize::new(0);
    let exhausted = AtomicBool::new(false);
    // Grid cells in parallel; each finds the pairs whose boxes' overlap starts in it.
    let found: Vec<(u32, u32)> = grid
        .par_iter()
        .enumerate()
        .flat_map_iter(|(index, list)| {
            let here = [index % g, (index / g) % g, index / (g * g)];
            let mut out = Vec::new();
            'list: for (i, &a) in list.iter().enumerate() {
                for &b in &list[i + 1..] {
                    let (ba, bb) = (&boxes[a as usize], &boxes[b as usize]);
                    if (0..3).any(|k| ba[1][k] <= bb[0][k] || bb[1][k] <= ba[0][k]) {
                        continue;
                    }
                    // Each pair once: in the grid cell holding the corner of the boxes' overlap.
                    if [0, 1, 2].map(|k| cell_of(ba[0][k].max(bb[0][k]), k)) != here {
                        continue;
                    }
                    // Face neighbours touch along their shared face only.
                    if neighbors[a as usize].contains(&b) {
                        continue;
                    }
                    if tested.fetch_add(1, Ordering::Relaxed) >= budget {
                        exhausted.store(true, Ordering::Relaxed);
                        break 'list;
                    }
                    if interpenetrate(&mesh.corners(a as usize), &mesh.corners(b as usize)) {
                        out.push((a.min(b), a.max(b)));
                    }
                }
            }
            out
        })
        .collect();
    report.tested = tested.load(Ordering::Relaxed).min(budget);
    report.complete &= !exhausted.load(Ordering::Relaxed);
    report.found = found.len();
    report.pairs = found;
    report.pairs.sort_unstable();
    report.pairs.truncate(limit);
    report
}

/// Whether `p` lies strictly inside the positively oriented cell `t`.
fn strictly_inside(t: &[[f64; 3]; 4], p: [f64; 3]) -> bool {
    (0..4).all(|i| {
        let mut q = *t;
        q[i] = p;
        orientation(q[0], q[1], q[2], q[3]) > 0.0
    })
}

/// Whether segment `p`–`q` crosses the interior of triangle `a b c` (strictly, both ways).
fn crosses(p: [f64; 3], q: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> bool {
    let s = |v: f64| (v > 0.0) as i8 - (v < 0.0) as i8;
    let (s1, s2) = (s(orientation(a, b, c, p)), s(orientation(a, b, c, q)));
    if s1 == 0 || s2 == 0 || s1 == s2 {
        return false;
    }
    let t = [
        s(orientation(p, q, a, b)),
        s(orientation(p, q, b, c)),
        s(orientation(p, q, c, a)),
    ];
    t[0] != 0 && t[0] == t[1] && t[1] == t[2]
}

/// Whether a face plane of `s` has all of `t` on its outer side (or on it): then their interiors
/// are apart. Most touching neighbours are told apart by this alone.
fn separated(s: &[[f64; 3]; 4], t: &[[f64; 3]; 4]) -> bool {
    FACE_NODES.iter().any(|f| {
        let [p, q, r] = f.map(|k| s[k]);
        // FACE_NODES lists a face counter-clockwise from outside: the cell's inside is negative.
        t.iter().all(|&x| orientation(p, q, r, x) >= 0.0)
    })
}

/// Whether the interiors of two positively oriented cells meet.
pub fn interpenetrate(a: &[[f64; 3]; 4], b: &[[f64; 3]; 4]) -> bool {
    if separated(a, b) || separated(b, a) {
        return false;
    }
    let centroid =
        |t: &[[f64; 3]; 4]| [0, 1, 2].map(|k| (t[0][k] + t[1][k] + t[2][k] + t[3][k]) / 4.0);
    if b.iter().any(|&p| strictly_inside(a, p))
        || a.iter().any(|&p| strictly_inside(b, p))
        || strictly_inside(a, centroid(b))
        || strictly_inside(b, centroid(a))
    {
        return true;
    }
    const EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];
    let pierces = |s: &[[f64; 3]; 4], t: &[[f64; 3]; 4]| {
        EDGES.iter().any(|&[i, j]| {
            FACE_NODES
                .iter()
                .any(|f| crosses(s[i], s[j], f.map(|k| t[k])))
        })
    };
    pierces(a, b) || pierces(b, a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::kuhn_box;

    fn unit(shift: [f64; 3]) -> [[f64; 3]; 4] {
        [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ]
        .map(|p| [p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]])
    }

    #[test]
    fn overlapping_touching_and_identical_cells() {
        assert!(interpenetrate(&unit([0.0; 3]), &unit([0.2, 0.2, 0.2])));
        assert!(
            interpenetrate(&unit([0.0; 3]), &unit([0.0; 3])),
            "duplicates"
        );
        // Edges crossing without a node inside: a thin tet piercing a face.
        let needle = [
            [0.2, 0.2, -1.0],
            [0.25, 0.2, -1.0],
            [0.2, 0.25, -1.0],
            [0.2, 0.2, 2.0],
        ];
        assert!(interpenetrate(&unit([0.0; 3]), &needle));
        // Sharing a face, an edge, a node, or apart.
        let below = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, -1.0],
        ];
        assert!(!interpenetrate(&unit([0.0; 3]), &below));
        assert!(!interpenetrate(&unit([0.0; 3]), &unit([1.0, 0.0, 0.0])));
        assert!(!interpenetrate(&unit([0.0; 3]), &unit([3.0, 0.0, 0.0])));
    }

    #[test]
    fn a_valid_mesh_has_no_overlaps_and_a_bad_merge_is_found() {
        let (nodes, tets) = kuhn_box([4, 4, 4], [1.0; 3], 0.1, 3);
        let mesh = TetMesh::new(nodes.clone(), tets.clone()).unwrap();
        let r = find_overlaps(&mesh, 1 << 20, 10);
        assert!(r.complete && r.found == 0 && r.tested > 100, "{r:?}");
        // The same box again, shifted by a third of a cube: every cell of one meets cells of the
        // other.
        let mut all = nodes.clone();
        all.extend(nodes.iter().map(|p| [p[0] + 0.08, p[1] + 0.05, p[2]]));
        let base = nodes.len() as u32;
        let mut cells = tets.clone();
        cells.extend(tets.iter().map(|t| t.map(|v| v + base)));
        let merged = TetMesh::new(all, cells).unwrap();
        let r = find_overlaps(&merged, 1 << 20, 5);
        assert!(r.complete && r.found > 300 && r.pairs.len() == 5, "{r:?}");
        // A budget too small says so.
        let r = find_overlaps(&merged, 10, 5);
        assert!(!r.complete && r.tested == 10);
    }
}
