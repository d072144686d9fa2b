//! VTK's quadratic hexahedron, wedge and pyramid (types 25, 26, 27: the serendipity cells of
//! 20, 15 and 13 nodes that Exodus calls `HEX20`, `WEDGE15`, `PYRAMID13` and XDMF
//! `Hexahedron_20`, `Wedge_15`, `Pyramid_13`), and the triquadratic hexahedron and
//! biquadratic-quadratic wedge (29, 32), as degree-2 Lagrange cells (docs/formats.md,
//! "Cells").
//!
//! A serendipity cell lacks the Lagrange cell's face centres (and the hexahedron its centre).
//! Each is added as a point: the serendipity interpolation at that place, a weighted sum of
//! the cell's nodes. On a quadrilateral face it depends on the face's nodes only —
//! `−¼ Σ corners + ½ Σ mid-edge nodes` — so two cells sharing the face share the point (one
//! per face, by its corners); the hexahedron's centre is `−¼ Σ corners + ¼ Σ mid-edge nodes`.
//! The serendipity space lies inside the Lagrange cell's (every function of the 20-node
//! hexahedron is a triquadratic one, and so on), so the Lagrange cell through these points
//! is the serendipity cell itself: its field exactly, not from its corners only (the cells
//! are cut into straight-sided tetrahedra between the corners, as Lagrange cells are:
//! `higher`). The same weights give every point array's values there, in every time step.
//!
//! The nodes' places come from VTK's parametric coordinates of each type (doubled: the
//! degree-2 lattice of [`crate::formats::lagrange`]); the pyramid's apex edges, which VTK
//! does not place at lattice midpoints, keep their order (VoRANG's degree-2 Lagrange pyramid
//! lists its nodes as VTK's quadratic pyramid does, then the base's centre).

use super::cut::Tetrahedra;
use crate::formats::cell_type;
use crate::formats::lagrange::Shape;

/// VTK's quadratic hexahedron's nodes on the degree-2 lattice (the triquadratic hexahedron
/// adds the centres of the faces x = 0, x = 2, y = 0, y = 2, z = 0, z = 2 and of the cell).
const HEX: [[usize; 3]; 27] = [
    [0, 0, 0],
    [2, 0, 0],
    [2, 2, 0],
    [0, 2, 0],
    [0, 0, 2],
    [2, 0, 2],
    [2, 2, 2],
    [0, 2, 2],
    [1, 0, 0],
    [2, 1, 0],
    [1, 2, 0],
    [0, 1, 0],
    [1, 0, 2],
    [2, 1, 2],
    [1, 2, 2],
    [0, 1, 2],
    [0, 0, 1],
    [2, 0, 1],
    [2, 2, 1],
    [0, 2, 1],
    [0, 1, 1],
    [2, 1, 1],
    [1, 0, 1],
    [1, 2, 1],
    [1, 1, 0],
    [1, 1, 2],
    [1, 1, 1],
];

/// VTK's quadratic wedge's nodes on the degree-2 lattice (the biquadratic-quadratic wedge adds
/// the centres of its quadrilateral faces).
const WEDGE: [[usize; 3]; 18] = [
    [0, 0, 0],
    [2, 0, 0],
    [0, 2, 0],
    [0, 0, 2],
    [2, 0, 2],
    [0, 2, 2],
    [1, 0, 0],
    [1, 1, 0],
    [0, 1, 0],
    [1, 0, 2],
    [1, 1, 2],
    [0, 1, 2],
    [0, 0, 1],
    [2, 0, 1],
    [0, 2, 1],
    [1, 0, 1],
    [1, 1, 1],
    [0, 1, 1],
];

/// A quadrilateral face by local node numbers: its corners, then its mid-edge nodes.
type LocalFace = ([usize; 4], [usize; 4]);

/// The quadrilateral faces of VTK's quadratic hexahedron whose centres are its nodes 20–25
/// (`HEX`'s places): corners, then mid-edge nodes, as local node numbers.
const HEX_FACES: [LocalFace; 6] = [
    ([0, 3, 7, 4], [11, 19, 15, 16]),
    ([1, 2, 6, 5], [9, 18, 13, 17]),
    ([0, 1, 5, 4], [8, 17, 12, 16]),
    ([3, 2, 6, 7], [10, 18, 14, 19]),
    ([0, 1, 2, 3], [8, 9, 10, 11]),
    ([4, 5, 6, 7], [12, 13, 14, 15]),
];

/// The quadrilateral faces of VTK's quadratic wedge whose centres are its nodes 15–17.
const WEDGE_FACES: [LocalFace; 3] = [
    ([0, 1, 4, 3], [6, 13, 9, 12]),
    ([1, 2, 5, 4], [7, 14, 10, 13]),
    ([2, 0, 3, 5], [8, 12, 11, 14]),
];

/// The pyramid's base: corners 0–3, mid-edge nodes 5–8.
const PYRAMID_BASE: LocalFace = ([0, 1, 2, 3], [5, 6, 7, 8]);

/// Whether `ty` is one of the cells read here.
pub(super) fn handles(ty: u8) -> bool {
    matches!(
        ty,
        cell_type::QUADRATIC_HEXAHEDRON
            | cell_type::QUADRATIC_WEDGE
            | cell_type::QUADRATIC_PYRAMID
            | cell_type::TRIQUADRATIC_HEXAHEDRON
            | cell_type::BIQUADRATIC_QUADRATIC_WEDGE
    )
}

/// The tetrahedra of cell `i` of type `ty` (one [`handles`]) with nodes `conn` (VTK order,
/// their count checked): its degree-2 Lagrange cell, with the missing centres added.
pub(super) fn add(out: &mut Tetrahedra, i: u32, ty: u8, conn: &[u32], nodes: &[[f64; 3]]) {
    let face = |f: &LocalFace| -> Face { (f.0.map(|k| conn[k]), f.1.map(|k| conn[k])) };
    let (shape, places, faces): (Shape, &[[usize; 3]], &[LocalFace]) = match ty {
        cell_type::QUADRATIC_HEXAHEDRON | cell_type::TRIQUADRATIC_HEXAHEDRON => {
            (Shape::Hexahedron, &HEX, &HEX_FACES)
        }
        cell_type::QUADRATIC_WEDGE | cell_type::BIQUADRATIC_QUADRATIC_WEDGE => {
            (Shape::Wedge, &WEDGE, &WEDGE_FACES)
        }
        _ => {
            // The pyramid: VTK's 13 nodes are the degree-2 Lagrange pyramid's first 13.
            let mut lagrange = conn.to_vec();
            lagrange.push(face_centre(out, face(&PYRAMID_BASE), nodes));
            super::higher::add(out, i, Shape::Pyramid, &lagrange);
            return;
        }
    };
    // The places of the face centres follow the corners and mid-edge nodes.
    let first_face = places.len() - faces.len() - usize::from(shape == Shape::Hexahedron);
    let mut lagrange = vec![u32::MAX; shape.nodes(2)];
    for (k, &at) in places.iter().enumerate() {
        let n = match conn.get(k) {
            Some(&n) => n,
            None if k - first_face < faces.len() => {
                face_centre(out, face(&faces[k - first_face]), nodes)
            }
            None => cell_centre(out, &conn[..20], nodes),
        };
        lagrange[shape.index(2, at)] = n;
    }
    super::higher::add(out, i, shape, &lagrange);
}

/// A quadrilateral face of a serendipity cell: its corners, then its mid-edge nodes.
type Face = ([u32; 4], [u32; 4]);

/// The point at the centre of `face`: the serendipity quadrilateral there,
/// `−¼ Σ corners + ½ Σ mid-edge nodes`, one point per face (by its sorted corners).
fn face_centre(out: &mut Tetrahedra, (corners, mids): Face, nodes: &[[f64; 3]]) -> u32 {
    let mut key = corners.to_vec();
    key.sort_unstable();
    if let Some(&c) = out.serendipity_faces.get(&key) {
        return c;
    }
    let mut terms: Vec<(u32, f64)> = corners
        .iter()
        .map(|&n| (n, -0.25))
        .chain(mids.iter().map(|&n| (n, 0.5)))
        .collect();
    let c = out.added.weighted_point(&mut terms, nodes);
    out.serendipity_faces.insert(key, c);
    c
}

/// The point at the centre of a 20-node hexahedron (`conn`: its nodes, VTK order):
/// `−¼ Σ corners + ¼ Σ mid-edge nodes`.
fn cell_centre(out: &mut Tetrahedra, conn: &[u32], nodes: &[[f64; 3]]) -> u32 {
    let mut terms: Vec<(u32, f64)> = conn
        .iter()
        .enumerate()
        .map(|(k, &n)| (n, if k < 8 { -0.25 } else { 0.25 }))
        .collect();
    out.added.weighted_point(&mut terms, nodes)
}
