//! Generated meshes for tests, benchmarks and examples, so that no large file needs to be kept.
//!
//! [`kuhn_box`] splits a box into `nx·ny·nz` cubes and each cube into the 6 tetrahedra around
//! its main diagonal (Kuhn/Freudenthal subdivision). All cubes use the same diagonal, so the
//! tetrahedra of neighbouring cubes meet face to face and the mesh is conforming. Interior nodes
//! can be jittered to make the mesh irregular.

/// A small, fast, deterministic pseudo-random generator (SplitMix64), so generated meshes are
/// identical on every machine and run.
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// The six Kuhn tetrahedra of the unit cube, as corner numbers `x + 2y + 4z`: each is a path
/// 0 → one axis → two axes → 7 along the cube's edges.
pub const KUHN_TETS: [[usize; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 1, 5, 7],
    [0, 2, 3, 7],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 6, 7],
];

/// A box `[0, size]` split into `cells` cubes per axis, 6 tetrahedra per cube. Interior nodes are
/// moved by up to `jitter` times the cube size along each axis (keep `jitter` ≤ 0.15 so that no
/// cell flips). Returns nodes and cells (not yet oriented; see [`super::TetMesh::new`]).
pub fn kuhn_box(
    cells: [usize; 3],
    size: [f64; 3],
    jitter: f64,
    seed: u64,
) -> (Vec<[f64; 3]>, Vec<[u32; 4]>) {
    let [nx, ny, nz] = cells;
    let h = [
        size[0] / nx as f64,
        size[1] / ny as f64,
        size[2] / nz as f64,
    ];
    let mut rng = SplitMix64(seed);
    let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let interior = [i > 0 && i < nx, j > 0 && j < ny, k > 0 && k < nz];
                let idx = [i, j, k];
                let mut p = [0.0; 3];
                for d in 0..3 {
                    let shake = if interior[d] {
                        (2.0 * rng.next_f64() - 1.0) * jitter * h[d]
                    } else {
                        0.0
                    };
                    p[d] = idx[d] as f64 * h[d] + shake;
                }
                nodes.push(p);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (i + (nx + 1) * (j + (ny + 1) * k)) as u32;
    let mut tets = Vec::with_capacity(6 * nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let corner = |c: usize| id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                for t in KUHN_TETS {
                    tets.push(t.map(corner));
                }
            }
        }
    }
    (nodes, tets)
}

/// The number of cubes per axis that gives about `tets` tetrahedra in a cube-shaped box.
pub fn cubes_for(tets: usize) -> usize {
    ((tets as f64 / 6.0).cbrt().round() as usize).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::TetMesh;

    #[test]
    fn jittered_boxes_are_valid_meshes_with_the_right_volume() {
        let (nodes, tets) = kuhn_box([4, 3, 5], [2.0, 1.5, 1.0], 0.15, 7);
        let mesh = TetMesh::new(nodes, tets).unwrap();
        assert_eq!(mesh.tet_count(), 6 * 60);
        let total: f64 = (0..mesh.tet_count()).map(|t| mesh.tet_volume(t)).sum();
        assert!((total - 3.0).abs() < 1e-12, "{total}");
        // Boundary: 2·(4·3 + 3·5 + 4·5) squares, 2 triangles each.
        assert_eq!(mesh.boundary_face_count(), 2 * 2 * (12 + 15 + 20));
    }

    #[test]
    fn generation_is_deterministic() {
        assert_eq!(
            kuhn_box([2, 2, 2], [1.0; 3], 0.1, 3),
            kuhn_box([2, 2, 2], [1.0; 3], 0.1, 3)
        );
        assert_ne!(
            kuhn_box([2, 2, 2], [1.0; 3], 0.1, 3).0,
            kuhn_box([2, 2, 2], [1.0; 3], 0.1, 4).0
        );
    }
}
