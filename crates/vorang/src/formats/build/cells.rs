//! Cells to tetrahedra. Tetrahedra stay, quadratic tetrahedra keep their corners (their
//! mid-edge nodes are remembered for the `HigherOrder` fields), hexahedra, wedges and pyramids
//! are split conformingly ([`split_cell`]), everything else is counted and skipped. A rule of
//! its own, with its own tests, hence its own module: every tetrahedron remembers the cell it
//! was cut from, which is all the field step needs to know about the split.

use std::collections::HashMap;

use crate::error::{ParseError, Warning};
use crate::formats::{Cells, cell_type};

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
    /// Whether any cell is a quadratic tetrahedron.
    pub(super) quadratic: bool,
}

/// Cells → tetrahedra, each remembering the cell it came from. A volume cell needs its number
/// of nodes, each one of the `n_nodes` points.
pub(super) fn tetrahedra(
    source: &str,
    cells: &Cells,
    n_nodes: usize,
    cells_line: usize,
) -> Result<Tetrahedra, ParseError> {
    let err = |line: usize, msg: String| ParseError::new(source, line.max(1), msg);
    let mut out = Tetrahedra {
        tets: Vec::new(),
        parent: Vec::new(),
        skipped: HashMap::new(),
        midpoints: HashMap::new(),
        quadratic: false,
    };
    for i in 0..cells.len() {
        let ty = cells.types[i];
        let conn = cells.nodes(i);
        let Some(need) = cell_type::volume_nodes(ty) else {
            *out.skipped.entry(ty).or_default() += 1;
            continue;
        };
        if conn.len() != need {
            return Err(err(
                cells_line,
                format!(
                    "cell {} is a {} and needs {need} nodes, but the connectivity gives it {}",
                    i + 1,
                    cell_type::name(ty),
                    conn.len()
                ),
            ));
        }
        if let Some(&bad) = conn.iter().find(|&&n| n as usize >= n_nodes) {
            return Err(err(
                cells_line,
                format!(
                    "cell {} refers to point {bad} (0-based), but there are only {n_nodes} points",
                    i + 1
                ),
            ));
        }
        if i >= u32::MAX as usize {
            return Err(err(cells_line, "too many cells".into()));
        }
        out.add_cell(i as u32, ty, conn);
    }
    Ok(out)
}

impl Tetrahedra {
    /// The tetrahedra of volume cell `i` of type `ty` with nodes `conn`.
    fn add_cell(&mut self, i: u32, ty: u8, conn: &[u32]) {
        let g = |k: usize| conn[k];
        match ty {
            cell_type::TETRA => {
                self.tets.push([g(0), g(1), g(2), g(3)]);
                self.parent.push(i);
            }
            cell_type::QUADRATIC_TETRA => {
                self.quadratic = true;
                self.tets.push([g(0), g(1), g(2), g(3)]);
                self.parent.push(i);
                // VTK order of the mid-edge nodes 4…9.
                const EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
                for (k, [a, b]) in EDGES.iter().enumerate() {
                    let (a, b) = (g(*a), g(*b));
                    self.midpoints.insert((a.min(b), a.max(b)), g(4 + k));
                }
            }
            _ => {
                for t in split_cell(ty, conn) {
                    let tet = t.map(g);
                    // Collapsed cells (repeated nodes) give empty pieces; drop those.
                    let distinct = (0..4).all(|a| (0..a).all(|b| tet[a] != tet[b]));
                    if distinct {
                        self.tets.push(tet);
                        self.parent.push(i);
                    }
                }
            }
        }
    }
}

/// One warning that counts the skipped cells by type, if there are any.
pub(super) fn skipped_warning(
    source: &str,
    cells_line: usize,
    skipped: HashMap<u8, usize>,
) -> Option<Warning> {
    if skipped.is_empty() {
        return None;
    }
    let mut kinds: Vec<(u8, usize)> = skipped.into_iter().collect();
    kinds.sort_unstable();
    let total: usize = kinds.iter().map(|k| k.1).sum();
    let list: Vec<String> = kinds
        .iter()
        .map(|(t, n)| format!("{n} × {}", cell_type::name(*t)))
        .collect();
    Some(Warning {
        file: source.to_string(),
        line: Some(cells_line.max(1)),
        message: format!(
            "skipped {total} cell{} that VoRANG does not render ({}); only tetrahedra, hexahedra, wedges, pyramids and quadratic tetrahedra are volume cells",
            if total == 1 { "" } else { "s" },
            list.join(", ")
        ),
    })
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
