//! The faces of a piece's polyhedra (VTK 42), in either of the two layouts VTK has written:
//!
//! - VTK ≥ 9.4: `face_connectivity` and `face_offsets` (each face's points, and where each
//!   face ends), `polyhedron_to_faces` and `polyhedron_offsets` (each cell's faces, and where
//!   each cell's list ends; empty for other cells). Faces may be shared between cells.
//! - Before: `faces`, each polyhedron's face stream (its number of faces, then each face as
//!   its number of points and its points), and `faceoffsets`, per cell where its stream ends,
//!   or −1 for cells that are not polyhedra.
//!
//! Both become the same [`crate::formats::Faces`]. Kept apart from the other cell arrays
//! because neither layout says how long its arrays are: the lengths follow from one array to
//! the next, and each is checked against the next before use, with an error at the line of the
//! array that does not fit.

use super::arrays::{decode, decode_indices};
use super::xml::{Decl, NumType, Piece, Section, Settings};
use crate::error::ParseError;
use crate::formats::{ArrayValues, Cells, cell_type, parse_face_stream};

/// Where the piece's cells and points start among those of the pieces before it.
pub(super) struct PieceStart {
    pub(super) cell: usize,
    pub(super) node: u32,
}

/// Reads the faces of the polyhedra among the piece's cells (those from `start.cell` on).
pub(super) fn read(
    s: &Settings,
    piece: &Piece,
    here: &[&Decl],
    cells: &mut Cells,
    start: PieceStart,
) -> Result<(), ParseError> {
    let find = |n: &str| {
        here.iter()
            .find(|d| d.section == Section::Cells && d.name == n)
            .copied()
    };
    let new = [
        "face_connectivity",
        "face_offsets",
        "polyhedron_to_faces",
        "polyhedron_offsets",
    ]
    .map(find);
    if let [
        Some(conn),
        Some(offsets),
        Some(to_faces),
        Some(poly_offsets),
    ] = new
    {
        let layout = NewLayout {
            conn,
            offsets,
            to_faces,
            poly_offsets,
        };
        return layout.read(s, piece, cells, start);
    }
    if let (Some(faces), Some(offsets)) = (find("faces"), find("faceoffsets")) {
        return old_layout(s, piece, faces, offsets, cells, start);
    }
    match (start.cell..cells.len()).find(|&i| cells.types[i] == cell_type::POLYHEDRON) {
        Some(i) => Err(ParseError::new(
            s.name,
            piece.line,
            format!(
                "cell {} is a polyhedron (type 42), but this <Piece> has no face arrays: face_connectivity, face_offsets, polyhedron_to_faces and polyhedron_offsets (VTK 9.4 and later), or faces and faceoffsets (before)",
                i - start.cell + 1
            ),
        )),
        None => Ok(()),
    }
}

/// `count` integers of array `d`.
fn integers(s: &Settings, d: &Decl, count: usize) -> Result<Vec<i64>, ParseError> {
    if matches!(d.ty, NumType::F32 | NumType::F64) {
        return Err(ParseError::new(
            s.name,
            d.line,
            format!("{} must be an integer array", d.name),
        ));
    }
    match decode(s, d, count)? {
        ArrayValues::Int(v) => Ok(v),
        _ => Err(ParseError::new(
            s.name,
            d.line,
            format!("{} must be an integer array", d.name),
        )),
    }
}

/// End offsets `v` (one per entry) as ranges: each at least the one before, none negative
/// (`skip_negative`: −1 marks an entry without a range, as in `faceoffsets`).
fn ranges(
    s: &Settings,
    d: &Decl,
    v: &[i64],
    skip_negative: bool,
) -> Result<Vec<Option<(usize, usize)>>, ParseError> {
    let mut prev = 0i64;
    let mut out = Vec::with_capacity(v.len());
    for (k, &end) in v.iter().enumerate() {
        if skip_negative && end == -1 {
            out.push(None);
            continue;
        }
        if end < prev {
            return Err(ParseError::new(
                s.name,
                d.line,
                format!(
                    "{}: entry {} ends at {end}, before the previous entry's end {prev}",
                    d.name,
                    k + 1
                ),
            ));
        }
        out.push(Some((prev as usize, end as usize)));
        prev = end;
    }
    Ok(out)
}

/// The arrays of VTK ≥ 9.4's layout.
struct NewLayout<'d> {
    conn: &'d Decl,
    offsets: &'d Decl,
    to_faces: &'d Decl,
    poly_offsets: &'d Decl,
}

impl NewLayout<'_> {
    fn read(
        &self,
        s: &Settings,
        piece: &Piece,
        cells: &mut Cells,
        start: PieceStart,
    ) -> Result<(), ParseError> {
        let err = |d: &Decl, msg: String| ParseError::new(s.name, d.line, msg);
        let per_cell = integers(s, self.poly_offsets, piece.cells)?;
        let per_cell = ranges(s, self.poly_offsets, &per_cell, false)?;
        let listed = per_cell.last().and_then(|r| *r).map_or(0, |r| r.1);
        let to_faces = integers(s, self.to_faces, listed)?;
        let mut n_faces = 0usize;
        for &f in &to_faces {
            let f = usize::try_from(f)
                .ok()
                .filter(|&f| f < u32::MAX as usize)
                .ok_or_else(|| err(self.to_faces, format!("polyhedron_to_faces: face {f}")))?;
            n_faces = n_faces.max(f + 1);
        }
        let ends = integers(s, self.offsets, n_faces)?;
        let faces = ranges(s, self.offsets, &ends, false)?;
        let used = faces.last().and_then(|r| *r).map_or(0, |r| r.1);
        let (conn, outside) = decode_indices(s, self.conn, used, piece.points)?;
        if let Some(&(at, v)) = outside.first() {
            return Err(err(
                self.conn,
                format!(
                    "face_connectivity: entry {} refers to point {v}, but the piece has {} points",
                    at + 1,
                    piece.points
                ),
            ));
        }
        for (k, range) in per_cell.iter().enumerate() {
            let i = start.cell + k;
            let Some((a, b)) = *range else { continue };
            if cells.types.get(i) != Some(&cell_type::POLYHEDRON) {
                continue;
            }
            if a == b {
                return Err(err(
                    self.poly_offsets,
                    format!(
                        "polyhedron_offsets: cell {} is a polyhedron, but no faces are listed for it",
                        k + 1
                    ),
                ));
            }
            let list: Vec<Vec<u32>> = to_faces[a..b]
                .iter()
                .map(|&f| {
                    let (fa, fb) = faces[f as usize].unwrap_or_default();
                    conn[fa..fb].iter().map(|&n| n + start.node).collect()
                })
                .collect();
            cells.faces.push(i, list.iter().map(Vec::as_slice));
        }
        Ok(())
    }
}

/// The layout before VTK 9.4: `faces` holds each polyhedron's face stream, `faceoffsets`
/// where it ends (−1 for other cells).
fn old_layout(
    s: &Settings,
    piece: &Piece,
    faces_d: &Decl,
    offsets_d: &Decl,
    cells: &mut Cells,
    start: PieceStart,
) -> Result<(), ParseError> {
    let err = |d: &Decl, msg: String| ParseError::new(s.name, d.line, msg);
    let ends = integers(s, offsets_d, piece.cells)?;
    if let Some(&bad) = ends.iter().find(|&&e| e < -1) {
        return Err(err(
            offsets_d,
            format!("faceoffsets: {bad} is neither −1 (no faces) nor where a cell's faces end"),
        ));
    }
    let per_cell = ranges(s, offsets_d, &ends, true)?;
    let total = ends.iter().copied().max().unwrap_or(0).max(0) as usize;
    let stream = integers(s, faces_d, total)?;
    for (k, range) in per_cell.iter().enumerate() {
        let i = start.cell + k;
        let polyhedron = cells.types.get(i) == Some(&cell_type::POLYHEDRON);
        let Some((a, b)) = *range else {
            if polyhedron {
                return Err(err(
                    offsets_d,
                    format!(
                        "faceoffsets: cell {} is a polyhedron, but its offset is −1 (no faces)",
                        k + 1
                    ),
                ));
            }
            continue;
        };
        let faces = parse_face_stream(&stream[a..b]).map_err(|m| {
            err(
                faces_d,
                format!("faces: the face stream of cell {}: {m}", k + 1),
            )
        })?;
        if let Some(&n) = faces
            .iter()
            .flatten()
            .find(|&&n| n as usize >= piece.points)
        {
            return Err(err(
                faces_d,
                format!(
                    "faces: cell {} refers to point {n}, but the piece has {} points",
                    k + 1,
                    piece.points
                ),
            ));
        }
        if polyhedron {
            let faces: Vec<Vec<u32>> = faces
                .into_iter()
                .map(|f| f.into_iter().map(|n| n + start.node).collect())
                .collect();
            cells.faces.push(i, faces.iter().map(Vec::as_slice));
        }
    }
    Ok(())
}
