//! Assembling the description: the last phase of reading a `.vtu` file. The pieces the XML walk
//! found ([`super::xml`]) are decoded one after the other ([`super::arrays`]) and concatenated:
//! points, cells (checked as they arrive, the connectivity last and straight into 32-bit
//! indices), point and cell arrays matched by name across pieces, then VoRANG's own FieldData
//! arrays. It is separate from the walk so that the checks between arrays (offsets against
//! types, indices against the piece's points, the same arrays in every piece) sit in one place
//! and read in the order a file is built.

use super::arrays::{append_values, decode, decode_indices};
use super::faces::PieceStart;
use super::sink::Outside;
use super::xml::{Decl, Document, NumType, Piece, Section, Settings};
use crate::error::ParseError;
use crate::formats::{Array, Cells, MeshDescription, cell_type, lagrange};

/// The name, components and type of each point or cell array of the first piece.
type ArrayNames = Vec<(String, usize, NumType)>;

/// Decodes every piece and concatenates them into one description.
pub(super) fn assemble(doc: &Document) -> Result<MeshDescription, ParseError> {
    let s = &doc.settings;
    let mut a = Assembly {
        s,
        desc: MeshDescription {
            source: s.name.to_string(),
            format: "VTK XML UnstructuredGrid".into(),
            float_coordinates: true,
            ..MeshDescription::default()
        },
        multi: doc.pieces.len() > 1,
        point_names: Vec::new(),
        cell_names: Vec::new(),
    };
    a.desc.cells.offsets.push(0);
    // The arrays of each piece (one pass: a file with many pieces stays linear).
    let mut by_piece: Vec<Vec<&Decl>> = vec![Vec::new(); doc.pieces.len()];
    for d in &doc.decls {
        if let Some(list) = by_piece.get_mut(d.piece) {
            list.push(d);
        }
    }
    for (pi, (piece, here)) in doc.pieces.iter().zip(by_piece).enumerate() {
        a.piece(pi, piece, &here)?;
    }
    a.field_arrays(&doc.decls)?;
    let mut desc = a.desc;
    if s.version < (2, 1) {
        vtk8_hexahedra(&mut desc.cells);
    }
    for (i, a) in desc
        .point_arrays
        .iter_mut()
        .chain(desc.cell_arrays.iter_mut())
        .enumerate()
    {
        if a.name.is_empty() {
            a.name = format!("array{i}");
        }
    }
    Ok(desc)
}

/// Lagrange hexahedra as files before version 2.1 list them (VTK 8's order) put into today's
/// order, as VTK itself reads such files.
fn vtk8_hexahedra(cells: &mut Cells) {
    for i in 0..cells.len() {
        if cells.types[i] == cell_type::LAGRANGE_HEXAHEDRON {
            let (a, b) = (cells.offsets[i], cells.offsets[i + 1]);
            lagrange::hexahedron_from_vtk8(&mut cells.connectivity[a..b]);
        }
    }
}

/// The description as it grows, piece by piece.
struct Assembly<'s> {
    s: &'s Settings<'s>,
    desc: MeshDescription,
    /// Whether the file has several pieces (whose arrays must then match the first's).
    multi: bool,
    point_names: ArrayNames,
    cell_names: ArrayNames,
}

/// Where a piece's cells, connectivity entries and points start in the description.
#[derive(Clone, Copy)]
struct Start {
    cell: usize,
    conn: usize,
    node: u64,
}

/// The three `<Cells>` arrays of a piece.
struct CellDecls<'d> {
    conn: &'d Decl,
    offsets: &'d Decl,
    types: &'d Decl,
}

impl Assembly<'_> {
    fn piece(&mut self, pi: usize, piece: &Piece, here: &[&Decl]) -> Result<(), ParseError> {
        let node_base = self.desc.nodes.len() as u64;
        self.points(piece, here)?;
        if piece.cells > 0 || here.iter().any(|d| d.section == Section::Cells) {
            let start = Start {
                cell: self.desc.cells.types.len(),
                conn: self.desc.cells.connectivity.len(),
                node: node_base,
            };
            self.cells(piece, here, start)?;
        }
        self.arrays(pi, piece, here, Section::PointData)?;
        self.arrays(pi, piece, here, Section::CellData)
    }

    fn points(&mut self, piece: &Piece, here: &[&Decl]) -> Result<(), ParseError> {
        let name = self.s.name;
        let pts = here
            .iter()
            .find(|d| d.section == Section::Points)
            .ok_or_else(|| {
                ParseError::new(
                    name,
                    piece.line,
                    "this <Piece> has no <Points><DataArray …/></Points>",
                )
            })?;
        if self.desc.points_line == 0 {
            self.desc.points_line = pts.line;
        }
        if pts.components != 3 {
            return Err(ParseError::new(
                name,
                pts.line,
                format!(
                    "Points need NumberOfComponents=\"3\", found {}",
                    pts.components
                ),
            ));
        }
        let coords = decode(self.s, pts, piece.points.saturating_mul(3))?;
        if pts.ty != NumType::F32 {
            self.desc.float_coordinates = false;
        }
        self.desc
            .nodes
            .extend((0..piece.points).map(|i| [0, 1, 2].map(|c| coords.get(i * 3 + c))));
        Ok(())
    }

    /// The piece's cells: types and offsets first, so that they are checked and stored
    /// compactly before the connectivity, the largest array, is decoded.
    fn cells(&mut self, piece: &Piece, here: &[&Decl], start: Start) -> Result<(), ParseError> {
        let decls = cell_decls(self.s.name, piece, here)?;
        if self.desc.cells_line == 0 {
            self.desc.cells_line = decls.conn.line;
        }
        // Decoded as 32-bit numbers (values that do not fit are kept aside for the messages):
        // no 64-bit copy of the two per-cell arrays.
        let integers = |d: &Decl| {
            if matches!(d.ty, NumType::F32 | NumType::F64) {
                Err(ParseError::new(
                    self.s.name,
                    decls.offsets.line,
                    "offsets and types must be integer arrays",
                ))
            } else {
                Ok(())
            }
        };
        integers(decls.types)?;
        integers(decls.offsets)?;
        let conn_len = self.types_and_offsets(piece, &decls, start.conn)?;
        self.connectivity(piece, decls.conn, conn_len, start)?;
        let at = PieceStart {
            cell: start.cell,
            node: start.node as u32,
        };
        super::faces::read(self.s, piece, here, &mut self.desc.cells, at)
    }

    /// Decodes, checks and stores the piece's cell types and offsets; returns the length of
    /// its connectivity (the last offset).
    fn types_and_offsets(
        &mut self,
        piece: &Piece,
        decls: &CellDecls,
        conn_base: usize,
    ) -> Result<i64, ParseError> {
        let name = self.s.name;
        let (types_d, off_d) = (decls.types, decls.offsets);
        let (types, types_outside) = decode_indices(self.s, types_d, piece.cells, 256)?;
        let (offs, offs_outside) = decode_indices(self.s, off_d, piece.cells, u32::MAX as usize)?;
        let original = |v: &[u32], outside: &Outside, i: usize| -> i64 {
            match outside.iter().find(|(at, _)| *at == i) {
                Some(&(_, x)) => x,
                None => i64::from(v[i]),
            }
        };
        let cells = &mut self.desc.cells;
        let mut prev = 0i64;
        cells.types.reserve(types.len());
        cells.offsets.reserve(offs.len());
        for i in 0..offs.len().min(types.len()) {
            let o = original(&offs, &offs_outside, i);
            let t = original(&types, &types_outside, i);
            if o < prev || o >= i64::from(u32::MAX) {
                return Err(ParseError::new(
                    name,
                    off_d.line,
                    format!(
                        "offsets: cell {} ends at {o}, before the previous cell's end {prev}",
                        i + 1
                    ),
                ));
            }
            if !(0..=255).contains(&t) {
                return Err(ParseError::new(
                    name,
                    types_d.line,
                    format!(
                        "types: cell {} has type {t}, expected a VTK cell type 0…255",
                        i + 1
                    ),
                ));
            }
            if let Some(need) = cell_type::node_count_problem(t as u8, (o - prev) as usize) {
                return Err(ParseError::new(
                    name,
                    off_d.line,
                    format!(
                        "offsets: cell {} is a {} (type {t}) and {need}, but its offsets give it {}",
                        i + 1,
                        cell_type::name(t as u8),
                        o - prev
                    ),
                ));
            }
            cells.types.push(t as u8);
            cells.offsets.push(conn_base + o as usize);
            prev = o;
        }
        Ok(prev)
    }

    /// The connectivity, `len` entries as the last offset says: decoded straight into 32-bit
    /// indices, an index outside the piece's points kept aside for the message, then shifted
    /// past the points of the pieces before.
    fn connectivity(
        &mut self,
        piece: &Piece,
        conn_d: &Decl,
        len: i64,
        start: Start,
    ) -> Result<(), ParseError> {
        let name = self.s.name;
        if self.desc.nodes.len() >= u32::MAX as usize {
            return Err(ParseError::new(
                name,
                piece.line,
                format!(
                    "{} points in all: VoRANG indexes at most {} points",
                    self.desc.nodes.len(),
                    u32::MAX - 1
                ),
            ));
        }
        let (conn, outside) = decode_indices(self.s, conn_d, len as usize, piece.points)?;
        check_connectivity(
            name,
            &self.desc.cells,
            piece,
            conn_d,
            start,
            &conn,
            &outside,
        )?;
        // Validated: the piece's indices follow the points of the pieces before it (in
        // place, no second copy of the largest array of the file).
        let cells = &mut self.desc.cells;
        let base = start.node as u32;
        if cells.connectivity.is_empty() && base == 0 {
            cells.connectivity = conn;
        } else {
            cells
                .connectivity
                .extend(conn.into_iter().map(|n| n.saturating_add(base)));
        }
        Ok(())
    }

    /// The piece's point (`sec` = PointData) or cell arrays, appended by position to those of
    /// the pieces before it; every piece needs the same arrays as the first.
    fn arrays(
        &mut self,
        pi: usize,
        piece: &Piece,
        here: &[&Decl],
        sec: Section,
    ) -> Result<(), ParseError> {
        let (list, want, dest) = if sec == Section::PointData {
            (
                &mut self.point_names,
                piece.points,
                &mut self.desc.point_arrays,
            )
        } else {
            (
                &mut self.cell_names,
                piece.cells,
                &mut self.desc.cell_arrays,
            )
        };
        let arrays: Vec<&&Decl> = here.iter().filter(|d| d.section == sec).collect();
        if pi == 0 {
            for d in &arrays {
                list.push((d.name.clone(), d.components, d.ty));
            }
        } else if self.multi
            && (arrays.len() != list.len()
                || arrays
                    .iter()
                    .zip(list.iter())
                    .any(|(d, l)| d.name != l.0 || d.components != l.1))
        {
            return Err(ParseError::new(
                self.s.name,
                piece.line,
                "this <Piece> has other point or cell arrays than the first one; every piece needs the same arrays",
            ));
        }
        for (k, d) in arrays.iter().enumerate() {
            let v = decode(self.s, d, want.saturating_mul(d.components))?;
            if pi == 0 {
                dest.push(Array {
                    name: d.name.clone(),
                    components: d.components,
                    values: v,
                    line: d.line,
                });
            } else {
                append_values(&mut dest[k].values, v);
            }
        }
        Ok(())
    }

    /// VoRANG's own FieldData arrays (its layout, edges, triangles, data on them); other
    /// FieldData (time values, provenance) are not per point or cell and are not read.
    fn field_arrays(&mut self, decls: &[Decl]) -> Result<(), ParseError> {
        for d in decls
            .iter()
            .filter(|d| d.section == Section::FieldData && d.name.starts_with("VoRANG_"))
        {
            let tuples = d.tuples.ok_or_else(|| {
                ParseError::new(
                    self.s.name,
                    d.line,
                    format!("FieldData array \"{}\" needs NumberOfTuples", d.name),
                )
            })?;
            let v = decode(self.s, d, tuples.saturating_mul(d.components))?;
            self.desc.field_arrays.push(Array {
                name: d.name.clone(),
                components: d.components,
                values: v,
                line: d.line,
            });
        }
        Ok(())
    }
}

/// The piece's `connectivity`, `offsets` and `types` arrays, each required.
fn cell_decls<'d>(
    name: &str,
    piece: &Piece,
    here: &[&'d Decl],
) -> Result<CellDecls<'d>, ParseError> {
    let find = |n: &str| -> Result<&'d Decl, ParseError> {
        here.iter()
            .find(|d| d.section == Section::Cells && d.name == n)
            .copied()
            .ok_or_else(|| {
                ParseError::new(
                    name,
                    piece.line,
                    format!("this <Piece> has no <Cells> DataArray Name=\"{n}\""),
                )
            })
    };
    Ok(CellDecls {
        conn: find("connectivity")?,
        offsets: find("offsets")?,
        types: find("types")?,
    })
}

/// Every volume cell of the piece refers to one of the piece's points.
fn check_connectivity(
    name: &str,
    cells: &Cells,
    piece: &Piece,
    conn_d: &Decl,
    start: Start,
    conn: &[u32],
    outside: &Outside,
) -> Result<(), ParseError> {
    let (first_cell, conn_base) = (start.cell, start.conn);
    for i in first_cell..cells.types.len() {
        let t = cells.types[i];
        if !cell_type::is_volume(t) {
            continue;
        }
        let (a, b) = (
            cells.offsets[i] - conn_base,
            cells.offsets[i + 1] - conn_base,
        );
        if let Some(k) = conn[a..b].iter().position(|&n| n as usize >= piece.points) {
            let bad = outside
                .iter()
                .find(|(at, _)| *at == a + k)
                .map_or(i64::from(conn[a + k]), |(_, v)| *v);
            return Err(ParseError::new(
                name,
                conn_d.line,
                format!(
                    "connectivity: cell {} refers to point {bad}, but the piece has {} points (0-based indices 0…{})",
                    i - first_cell + 1,
                    piece.points,
                    piece.points as i64 - 1
                ),
            ));
        }
    }
    Ok(())
}
