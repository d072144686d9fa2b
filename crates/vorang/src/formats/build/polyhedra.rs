//! Polyhedra (VTK 42) to tetrahedra (docs/formats.md, "Cells"). A polyhedron gets a point at
//! its centre, and each face of more than three points a point at the face's centre; the
//! polyhedron is then the union of the tetrahedra (cell centre, face centre, two neighbouring
//! points of the face), and (cell centre, triangle) for triangular faces. Each added point is
//! the mean of the points it stands for — the cell's distinct points, or the face's — summed
//! in the order of their indices, so that the centre of a face depends on nothing but the
//! face: the two cells that share a face add the same point, bit for bit, and it is added
//! once (merged by the face's sorted points). The split therefore needs nothing of a cell's
//! neighbours and is conforming between polyhedra. It is exact for cells that are star-shaped
//! about their centre with faces star-shaped about theirs (every convex cell); a point array's
//! value at an added point is the mean of its values at the points it stands for, which keeps
//! a linear field linear.

use super::cut::Tetrahedra;
use crate::formats::Cells;
use crate::mesh::orientation;

/// The faces of polyhedron `i`, checked: at least four, each of three or more distinct points,
/// every point one of the cell's own (and so of the `n_nodes` points). The error completes
/// "cell N is a polyhedron, but …".
pub(super) fn faces_of(cells: &Cells, i: usize, n_nodes: usize) -> Result<Vec<&[u32]>, String> {
    let faces: Vec<&[u32]> = match cells.faces.of(i) {
        Some(f) => f.collect(),
        None => return Err("the file gives no faces for it".into()),
    };
    if faces.len() < 4 {
        return Err(format!(
            "it has {} faces; a polyhedron has at least 4",
            faces.len()
        ));
    }
    let mut points = cells.nodes(i).to_vec();
    points.sort_unstable();
    for (f, face) in faces.iter().enumerate() {
        if face.len() < 3 {
            return Err(format!(
                "its face {} has {} points; a face has at least 3",
                f + 1,
                face.len()
            ));
        }
        for (k, &n) in face.iter().enumerate() {
            if n as usize >= n_nodes {
                return Err(format!(
                    "its face {} refers to point {n} (0-based), but there are only {n_nodes} points",
                    f + 1
                ));
            }
            if face[..k].contains(&n) {
                return Err(format!("its face {} lists point {n} twice", f + 1));
            }
            if points.binary_search(&n).is_err() {
                return Err(format!(
                    "its face {} uses point {n}, which is not among the cell's points",
                    f + 1
                ));
            }
        }
    }
    Ok(faces)
}

/// The tetrahedra of polyhedron `i` with (checked) `faces`, each positively oriented.
pub(super) fn split(out: &mut Tetrahedra, i: u32, faces: &[&[u32]], nodes: &[[f64; 3]]) {
    let mut points: Vec<u32> = faces.iter().flat_map(|f| f.iter().copied()).collect();
    points.sort_unstable();
    points.dedup();
    let centre = out.added.mean_point(&points, nodes);
    for face in faces {
        if face.len() == 3 {
            emit(out, i, [centre, face[0], face[1], face[2]], nodes);
            continue;
        }
        let mut key = face.to_vec();
        key.sort_unstable();
        let middle = match out.added.face_centres.get(&key) {
            Some(&m) => m,
            None => {
                let m = out.added.mean_point(&key, nodes);
                out.added.face_centres.insert(key, m);
                m
            }
        };
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            emit(out, i, [centre, middle, a, b], nodes);
        }
    }
}

/// Adds a tetrahedron of cell `i`, turned round if it is negatively oriented (a flat one is
/// left to the mesh, which reports it).
fn emit(out: &mut Tetrahedra, i: u32, mut tet: [u32; 4], nodes: &[[f64; 3]]) {
    let p = tet.map(|n| out.added.position(n, nodes));
    if orientation(p[0], p[1], p[2], p[3]) < 0.0 {
        tet.swap(2, 3);
    }
    out.push(i, tet);
}
