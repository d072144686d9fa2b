//! Building the cells once every keyword is read: `CELL_TYPES` gives each cell's type, and
//! either the classic `CELLS` list or 5.1's `OFFSETS`/`CONNECTIVITY` its nodes. Kept apart from
//! the keywords because the two may come in any order and are only checked against each other
//! (counts, node indices against the points) here.

use super::Sections;
use crate::error::ParseError;
use crate::formats::{Cells, MeshDescription, cell_type, lagrange};

/// Checks and adds cells by their index in `CELL_TYPES`.
struct CellSink<'a> {
    name: &'a str,
    types: &'a [i64],
    types_line: usize,
    n_nodes: i64,
    cells: &'a mut Cells,
}

impl CellSink<'_> {
    /// Cell `i` with `nodes` (given on `line`); a volume cell must name existing points.
    fn push(&mut self, i: usize, nodes: &[i64], line: usize) -> Result<(), ParseError> {
        let (name, n_nodes) = (self.name, self.n_nodes);
        let t = self.types[i];
        if !(0..=255).contains(&t) {
            return Err(ParseError::new(
                name,
                self.types_line,
                format!("cell {}: type {t} is not a VTK cell type", i + 1),
            ));
        }
        if t == i64::from(cell_type::POLYHEDRON) {
            // A polyhedron's entry is its face stream.
            let bad = |m: String| ParseError::new(name, line, format!("cell {}: {m}", i + 1));
            let before = self.cells.faces.nodes.len();
            self.cells.push_face_stream(nodes).map_err(bad)?;
            if let Some(&n) = self.cells.faces.nodes[before..]
                .iter()
                .find(|&&n| i64::from(n) >= n_nodes)
            {
                return Err(bad(format!(
                    "a face refers to point {n}, but there are {n_nodes} points (0-based)"
                )));
            }
            return Ok(());
        }
        if cell_type::is_volume(t as u8)
            && let Some(&bad) = nodes.iter().find(|&&n| n < 0 || n >= n_nodes)
        {
            return Err(ParseError::new(
                name,
                line,
                format!(
                    "cell {} refers to point {bad}, but there are {n_nodes} points (0-based)",
                    i + 1
                ),
            ));
        }
        let nodes: Vec<u64> = nodes.iter().map(|&n| n.max(0) as u64).collect();
        self.cells.push(t as u8, &nodes);
        Ok(())
    }
}

impl Sections {
    /// The description, once the file is read: points and cell types are required, and the
    /// cells are built from whichever list the file has.
    pub(super) fn finish(self, name: &str, end_line: usize) -> Result<MeshDescription, ParseError> {
        if !self.have_points {
            return Err(ParseError::new(
                name,
                end_line,
                "no POINTS section in this file",
            ));
        }
        let Some((types, types_line)) = self.types else {
            return Err(ParseError::new(
                name,
                end_line,
                "no CELL_TYPES section in this file",
            ));
        };
        let mut desc = self.desc;
        let mut sink = CellSink {
            name,
            types: &types,
            types_line,
            n_nodes: desc.nodes.len() as i64,
            cells: &mut desc.cells,
        };
        if let Some((list, n, line)) = self.legacy_cells {
            cell_list(&mut sink, &list, n, line)?;
        } else if let (Some(off), Some(conn)) = (self.offsets, self.connectivity) {
            offsets_and_connectivity(&mut sink, &off, &conn, desc.cells_line)?;
        } else {
            return Err(ParseError::new(
                name,
                types_line,
                "no CELLS section in this file",
            ));
        }
        if desc.cells.offsets.is_empty() {
            desc.cells.offsets.push(0);
        }
        // Lagrange hexahedra of files before 5.1 are in VTK 8's node order, as VTK reads them.
        if self.version < 5.1 {
            let cells = &mut desc.cells;
            for i in 0..cells.len() {
                if cells.types[i] == cell_type::LAGRANGE_HEXAHEDRON {
                    let (a, b) = (cells.offsets[i], cells.offsets[i + 1]);
                    lagrange::hexahedron_from_vtk8(&mut cells.connectivity[a..b]);
                }
            }
        }
        Ok(desc)
    }
}

/// The classic list: `n` cells, each its node count and nodes, filling the list exactly.
fn cell_list(sink: &mut CellSink, list: &[i64], n: usize, line: usize) -> Result<(), ParseError> {
    let name = sink.name;
    if sink.types.len() != n {
        return Err(ParseError::new(
            name,
            sink.types_line,
            format!(
                "CELL_TYPES lists {} cells, but CELLS has {n}",
                sink.types.len()
            ),
        ));
    }
    let mut p = 0usize;
    for i in 0..n {
        let k = list.get(p).copied().unwrap_or(-1);
        let end = usize::try_from(k)
            .ok()
            .and_then(|k| p.checked_add(1)?.checked_add(k));
        if k < 0 || end.is_none_or(|e| e > list.len()) {
            return Err(ParseError::new(
                name,
                line,
                format!(
                    "CELLS: cell {} has a node count {k} that runs past the list of {} numbers",
                    i + 1,
                    list.len()
                ),
            ));
        }
        let nodes = &list[p + 1..p + 1 + k as usize];
        sink.push(i, nodes, line)?;
        p += 1 + k as usize;
    }
    if p != list.len() {
        return Err(ParseError::new(
            name,
            line,
            format!(
                "CELLS: the {n} cells use {p} numbers, but the size given is {}",
                list.len()
            ),
        ));
    }
    Ok(())
}

/// 5.1: cell `i` is `conn[off[i]..off[i + 1]]`.
fn offsets_and_connectivity(
    sink: &mut CellSink,
    off: &[i64],
    conn: &[i64],
    line: usize,
) -> Result<(), ParseError> {
    let (name, n) = (sink.name, sink.types.len());
    if off.len() != n + 1 {
        return Err(ParseError::new(
            name,
            sink.types_line,
            format!(
                "CELL_TYPES lists {n} cells, but OFFSETS has {} entries (cells + 1)",
                off.len()
            ),
        ));
    }
    for i in 0..n {
        let (a, b) = (off[i], off[i + 1]);
        if a < 0 || b < a || b as usize > conn.len() {
            return Err(ParseError::new(
                name,
                line,
                format!(
                    "OFFSETS: cell {} spans {a}…{b}, outside the connectivity of {} entries",
                    i + 1,
                    conn.len()
                ),
            ));
        }
        sink.push(i, &conn[a as usize..b as usize], line)?;
    }
    Ok(())
}
