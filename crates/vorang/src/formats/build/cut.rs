//! What the cells are cut into: the tetrahedra, each with the file's cell it came from, the
//! mid-edge nodes of quadratic cells, and the points the polyhedra add — one place that the
//! rules for each kind of cell (`cells`, `higher`, `polyhedra`) write into and the builder
//! reads from, so that the rules need not know each other. The smallest-node split of
//! hexahedra, wedges and pyramids ([`split_cell`]) lives here because every rule that cuts a
//! cell of those shapes (linear cells, Lagrange cells and their lattices) uses it.

use std::collections::HashMap;

use crate::formats::{Array, ArrayValues, cell_type};

/// The tetrahedra of a hexahedron, wedge or pyramid (VTK node order) under the smallest-node
/// rule, as local node indices. `global` are the cell's global node numbers.
pub fn split_cell(ty: u8, global: &[u32]) -> Vec<[usize; 4]> {
    // Faces in VTK order, each listed so that consecutive entries are neighbours on the face.
    const HEX_FACES: [&[usize]; 6] = [
        &[0, 3, 2, 1],
        &[4, 5, 6, 7],
        &[0, 1, 5, 4],
        &[1, 2, 6, 5],
        &[2, 3, 7, 6],
        &[3, 0, 4, 7],
    ];
    const WEDGE_FACES: [&[usize]; 5] = [
        &[0, 1, 2],
        &[3, 5, 4],
        &[0, 3, 4, 1],
        &[1, 4, 5, 2],
        &[2, 5, 3, 0],
    ];
    const PYRAMID_FACES: [&[usize]; 5] = [
        &[0, 3, 2, 1],
        &[0, 1, 4],
        &[1, 2, 4],
        &[2, 3, 4],
        &[3, 0, 4],
    ];
    let faces: &[&[usize]] = match ty {
        cell_type::HEXAHEDRON => &HEX_FACES,
        cell_type::WEDGE => &WEDGE_FACES,
        cell_type::PYRAMID => &PYRAMID_FACES,
        _ => return vec![[0, 1, 2, 3]],
    };
    let v = (0..global.len())
        .min_by_key(|&i| global[i])
        .unwrap_or_default();
    let mut tets = Vec::with_capacity(6);
    for f in faces {
        if f.contains(&v) {
            continue;
        }
        match f.len() {
            3 => tets.push([v, f[0], f[1], f[2]]),
            _ => {
                // The quad's smallest node and its opposite corner form the diagonal.
                let k = (0..4).min_by_key(|&k| global[f[k]]).unwrap_or_default();
                let (a, b, c, d) = (f[k], f[(k + 1) % 4], f[(k + 2) % 4], f[(k + 3) % 4]);
                tets.push([v, a, b, c]);
                tets.push([v, a, c, d]);
            }
        }
    }
    tets
}

/// The tetrahedra cut from a file's cells.
pub(super) struct Tetrahedra {
    pub(super) tets: Vec<[u32; 4]>,
    /// The file's cell each tetrahedron was cut from.
    pub(super) parent: Vec<u32>,
    /// Cells that are not volume cells, counted by type.
    pub(super) skipped: HashMap<u8, usize>,
    /// Mid-edge node of each (sorted) corner pair, from quadratic cells.
    pub(super) midpoints: HashMap<(u32, u32), u32>,
    /// Whether any cell is quadratic (a quadratic tetrahedron, a Lagrange cell of degree 2).
    pub(super) quadratic: bool,
    /// Lagrange cells of degree 3 or more, subdivided along their lattice.
    pub(super) subdivided: usize,
    /// Lagrange pyramids of degree 3 or more (skipped: VTK numbers no such nodes).
    pub(super) unordered: usize,
    /// The points the polyhedra and the serendipity cells added.
    pub(super) added: Added,
    /// The face centres added for serendipity cells, by the face's sorted corners.
    pub(super) serendipity_faces: HashMap<Vec<u32>, u32>,
}

impl Tetrahedra {
    /// One tetrahedron of cell `i`.
    pub(super) fn push(&mut self, i: u32, tet: [u32; 4]) {
        self.tets.push(tet);
        self.parent.push(i);
    }

    /// Remembers `m` as the node halfway between nodes `a` and `b` (a quadratic cell's).
    pub(super) fn midpoint(&mut self, a: u32, b: u32, m: u32) {
        self.quadratic = true;
        self.midpoints.insert((a.min(b), a.max(b)), m);
    }

    /// The tetrahedra of a hexahedron, wedge or pyramid `global` (VTK order) of cell `i`, by
    /// [`split_cell`]; returns them as local node indices. Collapsed cells (repeated nodes)
    /// give empty pieces, which are dropped.
    pub(super) fn split(&mut self, i: u32, ty: u8, global: &[u32]) -> Vec<[usize; 4]> {
        let mut kept = Vec::new();
        for t in split_cell(ty, global) {
            let tet = t.map(|k| global[k]);
            let distinct = (0..4).all(|a| (0..a).all(|b| tet[a] != tet[b]));
            if distinct {
                self.push(i, tet);
                kept.push(t);
            }
        }
        kept
    }
}

/// The points the builder adds: the polyhedra's centres, each the mean of some of the file's
/// points, and the face and cell centres of serendipity cells, each a weighted sum of the
/// cell's points (`serendipity`).
#[derive(Debug, Clone)]
pub(super) struct Added {
    /// The number of the file's points (added point `k` is point `base + k`).
    pub(super) base: usize,
    /// Whether every coordinate of the file is a `float`: the added points are rounded to one.
    float32: bool,
    /// Added point `k` stands for `members[offsets[k]..offsets[k + 1]]` (sorted): their mean,
    /// or where `weighted[k]` their sum with the `weights` at the same places.
    offsets: Vec<usize>,
    members: Vec<u32>,
    weights: Vec<f64>,
    weighted: Vec<bool>,
    positions: Vec<[f64; 3]>,
    /// Face centres by the face's sorted points.
    pub(super) face_centres: HashMap<Vec<u32>, u32>,
}

impl Added {
    pub(super) fn new(base: usize, float32: bool) -> Added {
        Added {
            base,
            float32,
            offsets: vec![0],
            members: Vec::new(),
            weights: Vec::new(),
            weighted: Vec::new(),
            positions: Vec::new(),
            face_centres: HashMap::new(),
        }
    }

    /// A new point at the mean of `members` (sorted, distinct).
    pub(super) fn mean_point(&mut self, members: &[u32], nodes: &[[f64; 3]]) -> u32 {
        let mut sum = [0.0f64; 3];
        for &m in members {
            for (s, c) in sum.iter_mut().zip(nodes[m as usize]) {
                *s += c;
            }
        }
        let n = members.len() as f64;
        // A volume whose coordinates are all `float` keeps them so (and is written so).
        let round = |x: f64| if self.float32 { f64::from(x as f32) } else { x };
        self.positions.push(sum.map(|s| round(s / n)));
        self.members.extend_from_slice(members);
        self.weights.extend(members.iter().map(|_| 1.0));
        self.weighted.push(false);
        self.offsets.push(self.members.len());
        (self.base + self.positions.len() - 1) as u32
    }

    /// A new point at `Σ weight · point` over `terms` (point, weight), summed in the order of
    /// the points (sorted here), so that the same terms give the same bits whoever asks.
    pub(super) fn weighted_point(&mut self, terms: &mut [(u32, f64)], nodes: &[[f64; 3]]) -> u32 {
        terms.sort_unstable_by_key(|t| t.0);
        let mut sum = [0.0f64; 3];
        for &(m, w) in terms.iter() {
            for (s, c) in sum.iter_mut().zip(nodes[m as usize]) {
                *s += w * c;
            }
        }
        let round = |x: f64| if self.float32 { f64::from(x as f32) } else { x };
        self.positions.push(sum.map(round));
        self.members.extend(terms.iter().map(|t| t.0));
        self.weights.extend(terms.iter().map(|t| t.1));
        self.weighted.push(true);
        self.offsets.push(self.members.len());
        (self.base + self.positions.len() - 1) as u32
    }

    /// The position of point `id`, of the file or added.
    pub(super) fn position(&self, id: u32, nodes: &[[f64; 3]]) -> [f64; 3] {
        match (id as usize).checked_sub(self.base) {
            Some(k) => self.positions[k],
            None => nodes[id as usize],
        }
    }

    /// How many points were added.
    pub(super) fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Appends the added points to the file's points.
    pub(super) fn extend_points(&self, nodes: &mut Vec<[f64; 3]>) {
        nodes.extend_from_slice(&self.positions);
    }

    /// What a later time step with the same points and cells needs: the means, not the
    /// positions nor the faces' index.
    pub(super) fn means_only(mut self) -> Added {
        self.positions = Vec::new();
        self.face_centres = HashMap::new();
        self
    }

    /// Appends to every point array the mean (or weighted sum) of its values at the points
    /// each added point stands for (integer arrays become Float64: a mean is seldom whole).
    pub(super) fn extend_arrays(&self, point_arrays: &mut [Array]) {
        let added = self.len();
        if added == 0 {
            return;
        }
        for a in point_arrays {
            let n = a.components;
            let mut means = Vec::with_capacity(added * n);
            for (k, w) in self.offsets.windows(2).enumerate() {
                let members = &self.members[w[0]..w[1]];
                let weights = &self.weights[w[0]..w[1]];
                for c in 0..n {
                    let value = |m: u32| a.values.get(m as usize * n + c);
                    means.push(if self.weighted[k] {
                        members
                            .iter()
                            .zip(weights)
                            .map(|(&m, &wt)| wt * value(m))
                            .sum()
                    } else {
                        members.iter().map(|&m| value(m)).sum::<f64>() / members.len() as f64
                    });
                }
            }
            match &mut a.values {
                ArrayValues::F64(v) => v.extend(means),
                ArrayValues::F32(v) => v.extend(means.into_iter().map(|x| x as f32)),
                ArrayValues::Int(v) => {
                    let mut all: Vec<f64> = v.iter().map(|&x| x as f64).collect();
                    all.extend(means);
                    a.values = ArrayValues::F64(all);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::cell_type;
    use crate::mesh::tet_volume;

    fn cube() -> Vec<[f64; 3]> {
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ]
    }

    fn volume_of(p: &[[f64; 3]], tets: &[[usize; 4]]) -> f64 {
        tets.iter()
            .map(|t| tet_volume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]).abs())
            .sum()
    }

    #[test]
    fn every_numbering_of_a_hexahedron_fills_it() {
        let p = cube();
        // Each rotation of the global numbering puts the smallest node at another corner.
        for shift in 0..8u32 {
            let global: Vec<u32> = (0..8).map(|i| (i + shift) % 8).collect();
            let tets = split_cell(cell_type::HEXAHEDRON, &global);
            assert_eq!(tets.len(), 6);
            assert!((volume_of(&p, &tets) - 1.0).abs() < 1e-12, "shift {shift}");
            for t in &tets {
                assert!(tet_volume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]).abs() > 1e-9);
            }
        }
    }

    #[test]
    fn wedges_and_pyramids_fill_themselves() {
        let w = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 1.0],
        ];
        for shift in 0..6u32 {
            let global: Vec<u32> = (0..6).map(|i| (i * 5 + shift) % 6).collect();
            let tets = split_cell(cell_type::WEDGE, &global);
            assert_eq!(tets.len(), 3);
            assert!((volume_of(&w, &tets) - 0.5).abs() < 1e-12);
        }
        let py = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1.0],
        ];
        for shift in 0..5u32 {
            let global: Vec<u32> = (0..5).map(|i| (i + shift) % 5).collect();
            let tets = split_cell(cell_type::PYRAMID, &global);
            assert_eq!(tets.len(), 2);
            assert!((volume_of(&py, &tets) - 1.0 / 3.0).abs() < 1e-12);
        }
    }

    #[test]
    fn a_shared_quad_face_is_cut_the_same_way_from_both_sides() {
        // Two hexahedra stacked along z share the face 4 5 6 7 (global numbers).
        let lower: Vec<u32> = (0..8).collect();
        let upper: Vec<u32> = (4..12).collect();
        let face_tris = |ty: u8, g: &[u32]| -> Vec<[u32; 3]> {
            let mut out = Vec::new();
            for t in split_cell(ty, g) {
                let nodes = t.map(|k| g[k]);
                for skip in 0..4 {
                    let mut tri: Vec<u32> =
                        (0..4).filter(|&k| k != skip).map(|k| nodes[k]).collect();
                    if tri.iter().all(|n| (4..8).contains(n)) {
                        tri.sort_unstable();
                        out.push([tri[0], tri[1], tri[2]]);
                    }
                }
            }
            out.sort_unstable();
            out
        };
        let a = face_tris(cell_type::HEXAHEDRON, &lower);
        let b = face_tris(cell_type::HEXAHEDRON, &upper);
        assert_eq!(a.len(), 2);
        assert_eq!(a, b);
    }
}
