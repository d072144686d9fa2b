//! Merging the pieces of one step into one description: the pieces of a `.pvtu`, the
//! unstructured blocks of a `.vtm`, the parts of a `.pvd` step.
//!
//! A solver that writes its grid in pieces writes the points on the faces between two pieces
//! once in each. The renderer finds its way through a mesh by face adjacency (the visibility
//! sort, docs/architecture.md), so such a face must become interior again: points of a later
//! piece with exactly the coordinates of a point of an earlier piece are that point (the first
//! piece's values are kept). Points within one piece are never merged with each other, so that
//! one piece reads exactly as the same file read alone, and the merged grid of pieces cut from
//! one grid is that grid.
//!
//! Ghost cells — the copies of a neighbouring piece's cells that a parallel writer adds around
//! each piece, marked in the `vtkGhostType` cell array with bit 1 (DUPLICATECELL) or 32
//! (HIDDENCELL) — are dropped, and the `vtkGhostType` arrays themselves are VTK's bookkeeping,
//! not data: they do not become fields. Every piece must have the same point and cell arrays
//! (name, components, type) in the same order, so that the fields keep the numbering of a
//! single `.vtu` (point arrays first, then cell arrays).
//!
//! Pieces arrive one at a time ([`Merge::add`]): a step's files are read, merged and freed one
//! after the other, so that only the merged grid and one piece are in memory at once.

use std::collections::HashMap;

use crate::error::{ParseError, Warning};
use crate::formats::{Array, ArrayValues, Cells, MeshDescription};

/// VTK's ghost array and the bits that mark a cell as not this piece's own.
pub const GHOST_ARRAY: &str = "vtkGhostType";
const DUPLICATE_CELL: i64 = 1;
const HIDDEN_CELL: i64 = 32;

/// Where a piece comes from, for messages: its file, and the collection line that lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct PieceLabel {
    /// The piece's file, as shown.
    pub file: String,
    /// The collection file that lists it, and the line.
    pub from: String,
    pub line: usize,
}

/// An array as the pieces must agree on it: name, components, kind of values.
type Signature = (String, usize, &'static str);

/// The merge of a step's pieces so far.
pub struct Merge {
    /// The merged description (after the first piece: that piece as read).
    desc: Option<MeshDescription>,
    pieces: usize,
    /// Coordinates → merged point, filled once a second piece arrives.
    index: HashMap<[u64; 3], u32>,
    /// The first piece and its arrays, which every later piece must match.
    first: Option<(PieceLabel, Vec<Signature>, Vec<Signature>)>,
}

impl Default for Merge {
    fn default() -> Self {
        Merge::new()
    }
}

impl Merge {
    /// An empty merge.
    pub fn new() -> Merge {
        Merge {
            desc: None,
            pieces: 0,
            index: HashMap::new(),
            first: None,
        }
    }

    /// How many pieces were added.
    pub fn pieces(&self) -> usize {
        self.pieces
    }

    /// Adds one piece: its ghost cells dropped, its points merged with those of the pieces
    /// before it, its cells and arrays appended.
    pub fn add(&mut self, mut piece: MeshDescription, label: PieceLabel) -> Result<(), ParseError> {
        drop_ghosts(&mut piece);
        let (points, cells) = (
            signature(&piece.point_arrays),
            signature(&piece.cell_arrays),
        );
        match &self.first {
            None => self.first = Some((label.clone(), points, cells)),
            Some((first, p0, c0)) => {
                check_same_arrays(first, &label, ("point", p0, &points))?;
                check_same_arrays(first, &label, ("cell", c0, &cells))?;
            }
        }
        self.pieces += 1;
        match self.desc.take() {
            None => self.desc = Some(piece),
            Some(mut merged) => {
                if self.pieces == 2 {
                    self.start_merging(&mut merged);
                }
                self.append(&mut merged, piece, &label)?;
                self.desc = Some(merged);
            }
        }
        Ok(())
    }

    /// The merged description (`None` if no piece was added).
    pub fn finish(self) -> Option<MeshDescription> {
        self.desc
    }

    /// Turns the first piece into the merged grid once a second arrives: named after the
    /// collection that lists the first piece, at that piece's line (messages about the merged
    /// grid point there), its points indexed, its dataset-level arrays (which describe that one
    /// file) dropped.
    fn start_merging(&mut self, merged: &mut MeshDescription) {
        let (from, line) = self
            .first
            .as_ref()
            .map_or((String::new(), 1), |f| (f.0.from.clone(), f.0.line));
        merged.source = from;
        merged.field_arrays.clear();
        merged.points_line = line;
        merged.cells_line = line;
        for a in merged
            .point_arrays
            .iter_mut()
            .chain(&mut merged.cell_arrays)
        {
            a.line = line;
        }
        self.index.reserve(merged.nodes.len());
        for (i, p) in merged.nodes.iter().enumerate() {
            self.index.entry(key(p)).or_insert(i as u32);
        }
    }

    fn append(
        &mut self,
        merged: &mut MeshDescription,
        piece: MeshDescription,
        label: &PieceLabel,
    ) -> Result<(), ParseError> {
        let base = merged.nodes.len();
        // Local point → merged point; the piece's new points, in order.
        let mut map: Vec<u32> = Vec::with_capacity(piece.nodes.len());
        let mut new: Vec<usize> = Vec::new();
        for (i, p) in piece.nodes.iter().enumerate() {
            match self.index.get(&key(p)) {
                Some(&g) => map.push(g),
                None => {
                    let g = base + new.len();
                    if g >= u32::MAX as usize {
                        return Err(ParseError::new(
                            &label.from,
                            label.line,
                            format!(
                                "{}: more than {} points in all: VoRANG indexes at most that many",
                                label.file,
                                u32::MAX - 1
                            ),
                        ));
                    }
                    map.push(g as u32);
                    new.push(i);
                }
            }
        }
        for &i in &new {
            let p = piece.nodes[i];
            self.index.entry(key(&p)).or_insert(map[i]);
            merged.nodes.push(p);
        }
        merged.float_coordinates &= piece.float_coordinates;
        append_cells(&mut merged.cells, &piece.cells, &map);
        for (dst, src) in merged.point_arrays.iter_mut().zip(&piece.point_arrays) {
            extend_at(&mut dst.values, &src.values, src.components, &new);
        }
        for (dst, src) in merged.cell_arrays.iter_mut().zip(piece.cell_arrays) {
            append_values(&mut dst.values, src.values);
        }
        merged.warnings.extend(piece.warnings);
        Ok(())
    }
}

/// A point's coordinates as a key: exact, with −0 and +0 the same point.
fn key(p: &[f64; 3]) -> [u64; 3] {
    p.map(|c| (c + 0.0).to_bits())
}

fn kind_name(v: &ArrayValues) -> &'static str {
    match v {
        ArrayValues::Int(_) => "integer",
        ArrayValues::F32(_) => "Float32",
        ArrayValues::F64(_) => "Float64",
    }
}

fn signature(arrays: &[Array]) -> Vec<Signature> {
    arrays
        .iter()
        .map(|a| (a.name.clone(), a.components, kind_name(&a.values)))
        .collect()
}

fn describe(s: Option<&Signature>) -> String {
    match s {
        Some((name, c, kind)) => format!(
            "\"{name}\" ({c} component{}, {kind})",
            if *c == 1 { "" } else { "s" }
        ),
        None => "no array".into(),
    }
}

/// The error for a piece whose `what` (point or cell) arrays are not the first piece's.
fn check_same_arrays(
    first: &PieceLabel,
    this: &PieceLabel,
    (what, want, got): (&str, &[Signature], &[Signature]),
) -> Result<(), ParseError> {
    let n = want.len().max(got.len());
    let Some(k) = (0..n).find(|&k| want.get(k) != got.get(k)) else {
        return Ok(());
    };
    Err(ParseError::new(
        &this.from,
        this.line,
        format!(
            "the pieces' arrays disagree: {what} array {} is {} in {} but {} in {} ({}:{}); every piece needs the same point and cell arrays (name, components, type)",
            k + 1,
            describe(got.get(k)),
            this.file,
            describe(want.get(k)),
            first.file,
            first.from,
            first.line
        ),
    ))
}

/// Removes the ghost cells (with the values of every cell array) and the `vtkGhostType`
/// arrays.
fn drop_ghosts(d: &mut MeshDescription) {
    d.point_arrays.retain(|a| a.name != GHOST_ARRAY);
    let Some(at) = d.cell_arrays.iter().position(|a| a.name == GHOST_ARRAY) else {
        return;
    };
    let ghost = d.cell_arrays.remove(at);
    let n = d.cells.len();
    if ghost.components != 1 || ghost.values.len() != n {
        d.warnings.push(Warning {
            file: d.source.clone(),
            line: Some(ghost.line.max(1)),
            message: format!(
                "{GHOST_ARRAY} has {} values for {n} cells: ignored, no cell is dropped",
                ghost.values.len()
            ),
        });
        return;
    }
    let keep: Vec<bool> = (0..n)
        .map(|i| (ghost.values.get(i) as i64) & (DUPLICATE_CELL | HIDDEN_CELL) == 0)
        .collect();
    if keep.iter().all(|&k| k) {
        return;
    }
    let mut cells = Cells::default();
    cells.offsets.push(0);
    for i in (0..n).filter(|&i| keep[i]) {
        if let Some(faces) = d.cells.faces.of(i) {
            cells.faces.push(cells.types.len(), faces);
        }
        cells.types.push(d.cells.types[i]);
        cells.connectivity.extend_from_slice(d.cells.nodes(i));
        cells.offsets.push(cells.connectivity.len());
    }
    d.cells = cells;
    let kept: Vec<usize> = (0..n).filter(|&i| keep[i]).collect();
    for a in &mut d.cell_arrays {
        let mut v = empty_like(&a.values);
        extend_at(&mut v, &a.values, a.components, &kept);
        a.values = v;
    }
}

/// The piece's cells after the merged ones, its point indices mapped (an index outside the
/// piece stays out of range), the faces of its polyhedra too.
fn append_cells(dst: &mut Cells, src: &Cells, map: &[u32]) {
    if dst.offsets.is_empty() {
        dst.offsets.push(0);
    }
    let to = |n: &u32| map.get(*n as usize).copied().unwrap_or(u32::MAX);
    for &(i, _) in &src.faces.cells {
        let faces: Vec<Vec<u32>> = src
            .faces
            .of(i)
            .into_iter()
            .flatten()
            .map(|f| f.iter().map(to).collect())
            .collect();
        dst.faces
            .push(dst.types.len() + i, faces.iter().map(Vec::as_slice));
    }
    dst.types.extend_from_slice(&src.types);
    let base = dst.connectivity.len();
    dst.connectivity.extend(
        src.connectivity
            .iter()
            .map(|&n| map.get(n as usize).copied().unwrap_or(u32::MAX)),
    );
    dst.offsets
        .extend(src.offsets.iter().skip(1).map(|&o| base + o));
}

fn empty_like(v: &ArrayValues) -> ArrayValues {
    match v {
        ArrayValues::Int(_) => ArrayValues::Int(Vec::new()),
        ArrayValues::F32(_) => ArrayValues::F32(Vec::new()),
        ArrayValues::F64(_) => ArrayValues::F64(Vec::new()),
    }
}

/// Appends the tuples `at` (of `components` values each) of `src` to `dst` (of the same kind,
/// as [`check_same_arrays`] made sure).
fn extend_at(dst: &mut ArrayValues, src: &ArrayValues, components: usize, at: &[usize]) {
    fn tuples<T: Copy>(d: &mut Vec<T>, s: &[T], c: usize, at: &[usize]) {
        d.reserve(at.len() * c);
        for &i in at {
            if let Some(t) = s.get(i * c..i * c + c) {
                d.extend_from_slice(t);
            }
        }
    }
    let c = components.max(1);
    match (dst, src) {
        (ArrayValues::Int(d), ArrayValues::Int(s)) => tuples(d, s, c, at),
        (ArrayValues::F32(d), ArrayValues::F32(s)) => tuples(d, s, c, at),
        (ArrayValues::F64(d), ArrayValues::F64(s)) => tuples(d, s, c, at),
        _ => {}
    }
}

fn append_values(dst: &mut ArrayValues, src: ArrayValues) {
    match (dst, src) {
        (ArrayValues::Int(d), ArrayValues::Int(mut s)) => d.append(&mut s),
        (ArrayValues::F32(d), ArrayValues::F32(mut s)) => d.append(&mut s),
        (ArrayValues::F64(d), ArrayValues::F64(mut s)) => d.append(&mut s),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::cell_type::TETRA;

    /// One tetrahedron on `base` (its four corners), with a point array and a cell array.
    fn tet(base: [[f64; 3]; 4], t: f64, ghost: Option<i64>) -> MeshDescription {
        let mut d = MeshDescription {
            source: "piece.vtu".into(),
            nodes: base.to_vec(),
            float_coordinates: false,
            ..MeshDescription::default()
        };
        d.cells.push(TETRA, &[0, 1, 2, 3]);
        d.point_arrays.push(Array {
            name: "T".into(),
            components: 1,
            values: ArrayValues::F64(vec![t; 4]),
            line: 3,
        });
        d.cell_arrays.push(Array {
            name: "id".into(),
            components: 1,
            values: ArrayValues::Int(vec![t as i64]),
            line: 4,
        });
        if let Some(g) = ghost {
            d.cell_arrays.push(Array {
                name: GHOST_ARRAY.into(),
                components: 1,
                values: ArrayValues::Int(vec![g]),
                line: 5,
            });
        }
        d
    }

    fn label(file: &str, line: usize) -> PieceLabel {
        PieceLabel {
            file: file.into(),
            from: "p.pvtu".into(),
            line,
        }
    }

    const A: [[f64; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
    const B: [[f64; 3]; 4] = [[1., 0., 0.], [0., 1., 0.], [0., 0., 1.], [1., 1., 1.]];

    #[test]
    fn shared_points_are_merged_and_ghosts_dropped() {
        let mut m = Merge::new();
        m.add(tet(A, 1.0, Some(0)), label("a.vtu", 6)).unwrap();
        // A ghost copy of the first cell, then the second piece's own cell.
        m.add(tet(A, 9.0, Some(1)), label("a_ghost.vtu", 7))
            .unwrap();
        m.add(tet(B, 2.0, Some(0)), label("b.vtu", 8)).unwrap();
        assert_eq!(m.pieces(), 3);
        let d = m.finish().unwrap();
        assert_eq!(d.source, "p.pvtu");
        assert_eq!(d.nodes.len(), 5);
        assert_eq!(d.cells.len(), 2);
        assert_eq!(d.cells.nodes(1), &[1, 2, 3, 4]);
        assert_eq!(
            d.point_arrays[0].values,
            ArrayValues::F64(vec![1., 1., 1., 1., 2.])
        );
        assert_eq!(d.cell_arrays.len(), 1);
        assert_eq!(d.cell_arrays[0].values, ArrayValues::Int(vec![1, 2]));
        let (vol, _) = crate::formats::build::volume(d).unwrap();
        // The shared face is interior: each cell has one neighbour.
        assert_eq!(vol.mesh.boundary_face_count(), 6);
    }

    #[test]
    fn a_lone_piece_is_read_as_it_is() {
        let mut m = Merge::new();
        let mut one = tet(A, 1.0, None);
        one.nodes.push([0.0, 0.0, 0.0]);
        m.add(one.clone(), label("a.vtu", 6)).unwrap();
        assert_eq!(m.finish().unwrap(), one);
    }

    #[test]
    fn disagreeing_arrays_name_both_pieces() {
        let mut m = Merge::new();
        m.add(tet(A, 1.0, None), label("a.vtu", 6)).unwrap();
        let mut other = tet(B, 2.0, None);
        other.point_arrays[0].components = 2;
        other.point_arrays[0].values = ArrayValues::F64(vec![0.0; 8]);
        let e = m.add(other, label("b.vtu", 7)).unwrap_err();
        assert_eq!((e.file.as_str(), e.line), ("p.pvtu", 7));
        assert!(
            e.message.contains("point array 1 is \"T\" (2 components, Float64) in b.vtu but \"T\" (1 component, Float64) in a.vtu (p.pvtu:6)"),
            "{e}"
        );
        let mut renamed = tet(B, 2.0, None);
        renamed.cell_arrays[0].values = ArrayValues::F32(vec![2.0]);
        let e = m.add(renamed, label("c.vtu", 8)).unwrap_err();
        assert!(
            e.message
                .contains("cell array 1 is \"id\" (1 component, Float32) in c.vtu"),
            "{e}"
        );
    }
}
