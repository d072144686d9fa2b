//! Legacy VTK files (`.vtk`) with `DATASET UNSTRUCTURED_GRID`, ASCII or BINARY (big-endian, as
//! the format defines), versions 2.0 … 5.1.
//!
//! Read: `POINTS`, `CELLS` (the classic `n size` list of `npts i0 i1 …`, and 5.1's `OFFSETS` /
//! `CONNECTIVITY` arrays), `CELL_TYPES`, and in `POINT_DATA` / `CELL_DATA` the attributes
//! `SCALARS` (with `LOOKUP_TABLE`), `VECTORS`, `NORMALS`, `TENSORS`, `TEXTURE_COORDINATES`,
//! `COLOR_SCALARS` and `FIELD` arrays, in file order. Dataset-level `FIELD` data (time, cycle),
//! standalone `LOOKUP_TABLE`s and `METADATA` blocks are read past. Errors name the line of the
//! keyword, or the byte offset where binary data run out.

use super::text::Cursor;
use super::{Array, ArrayValues, MeshDescription};
use crate::error::ParseError;

pub fn sniff(head: &[u8]) -> bool {
    let start = head
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(0);
    let h = &head[start..head.len().min(start + 64)];
    h.len() >= 5 && h[..5].eq_ignore_ascii_case(b"# vtk")
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Ty {
    Int(usize, bool),
    F32,
    F64,
}

fn data_type(word: &str) -> Option<Ty> {
    Some(match word.to_ascii_lowercase().as_str() {
        "unsigned_char" | "vtktypeuint8" => Ty::Int(1, false),
        "char" | "signed_char" | "vtktypeint8" => Ty::Int(1, true),
        "unsigned_short" | "vtktypeuint16" => Ty::Int(2, false),
        "short" | "vtktypeint16" => Ty::Int(2, true),
        "unsigned_int" | "vtktypeuint32" => Ty::Int(4, false),
        "int" | "vtktypeint32" => Ty::Int(4, true),
        "unsigned_long" | "vtktypeuint64" | "unsigned_long_long" => Ty::Int(8, false),
        "long" | "vtktypeint64" | "vtkidtype" | "long_long" => Ty::Int(8, true),
        "float" | "vtktypefloat32" => Ty::F32,
        "double" | "vtktypefloat64" => Ty::F64,
        _ => return None,
    })
}

impl Ty {
    fn size(self) -> usize {
        match self {
            Ty::Int(s, _) => s,
            Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }
}

struct Reader<'a> {
    c: Cursor<'a>,
    binary: bool,
}

impl<'a> Reader<'a> {
    fn ty(&mut self) -> Result<Ty, ParseError> {
        let (w, line) = self.c.expect_token("a data type")?;
        data_type(w).ok_or_else(|| {
            self.c.err_at(
                line,
                format!(
                    "unknown data type '{w}': expected float, double, int, unsigned_char, … (the 'bit' type is not supported)"
                ),
            )
        })
    }

    /// `count` numbers of type `ty`, ASCII tokens or big-endian binary right after the current
    /// line.
    fn values(&mut self, ty: Ty, count: usize, what: &str) -> Result<ArrayValues, ParseError> {
        let left = self.c.bytes.len() - self.c.pos;
        let min = if self.binary { ty.size() } else { 2 };
        if count.saturating_mul(min) > left + 1 {
            return Err(self.c.err(format!(
                "{what}: {count} values cannot fit in the {left} bytes left in the file"
            )));
        }
        if self.binary {
            self.c.next_line();
            let start = self.c.pos;
            let raw = self.c.raw(count * ty.size(), what)?;
            let _ = start;
            return Ok(match ty {
                Ty::F32 => ArrayValues::F32(
                    raw.chunks_exact(4)
                        .map(|c| f32::from_be_bytes([c[0], c[1], c[2], c[3]]))
                        .collect(),
                ),
                Ty::F64 => ArrayValues::F64(
                    raw.chunks_exact(8)
                        .map(|c| {
                            f64::from_be_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]])
                        })
                        .collect(),
                ),
                Ty::Int(size, signed) => {
                    let mut out = Vec::with_capacity(count);
                    for c in raw.chunks_exact(size) {
                        let mut w = [0u8; 8];
                        w[8 - size..].copy_from_slice(c);
                        let u = u64::from_be_bytes(w);
                        let v = if signed {
                            // Sign-extend from `size` bytes.
                            let shift = 64 - 8 * size as u32;
                            ((u << shift) as i64) >> shift
                        } else {
                            i64::try_from(u).map_err(|_| {
                                self.c.err(format!("{what}: the value {u} is too large"))
                            })?
                        };
                        out.push(v);
                    }
                    ArrayValues::Int(out)
                }
            });
        }
        match ty {
            Ty::Int(..) => {
                let mut out = Vec::with_capacity(count);
                for _ in 0..count {
                    out.push(self.c.int(&format!("{what}: an integer"))?);
                }
                Ok(ArrayValues::Int(out))
            }
            _ => {
                let mut out = Vec::with_capacity(count);
                for _ in 0..count {
                    out.push(self.c.float(&format!("{what}: a number"))?);
                }
                Ok(if ty == Ty::F32 {
                    ArrayValues::F32(out.into_iter().map(|v| v as f32).collect())
                } else {
                    ArrayValues::F64(out)
                })
            }
        }
    }

    /// A FIELD block's arrays (`FIELD name n` already read up to `n`).
    fn field_arrays(&mut self, n: usize, line0: usize) -> Result<Vec<Array>, ParseError> {
        let mut out = Vec::new();
        for _ in 0..n {
            let (name, line) = self.c.expect_token("a FIELD array name")?;
            let name = name.to_string();
            if name == "NULL_ARRAY" {
                continue;
            }
            let comps = self.c.count("the FIELD array's number of components", 0)?;
            let tuples = self.c.count("the FIELD array's number of tuples", 0)?;
            let ty = self.ty()?;
            let total = comps.saturating_mul(tuples);
            let values = self.values(ty, total, &format!("FIELD array {name}"))?;
            self.skip_metadata();
            out.push(Array {
                name,
                components: comps.max(1),
                values,
                line,
            });
        }
        let _ = line0;
        Ok(out)
    }

    /// Skips a `METADATA` block (up to its blank line), if one follows.
    fn skip_metadata(&mut self) {
        let save = (self.c.pos, self.c.line);
        match self.c.token() {
            Some((w, _)) if w.eq_ignore_ascii_case("METADATA") => {
                self.c.next_line();
                loop {
                    if self.c.at_end() {
                        break;
                    }
                    let l = self.c.rest_of_line();
                    if l.trim().is_empty() {
                        break;
                    }
                }
            }
            _ => (self.c.pos, self.c.line) = save,
        }
    }
}

pub fn read(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    let mut c = Cursor::new(bytes, name);
    c.skip_space();
    let title = c.rest_of_line();
    if !sniff(title.as_bytes()) {
        return Err(c.err_at(1, "expected '# vtk DataFile Version x.x' on the first line"));
    }
    let version: f64 = title
        .split_whitespace()
        .last()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3.0);
    let _title = c.rest_of_line();
    let (enc, line) = c.expect_token("ASCII or BINARY")?;
    let binary = match enc.to_ascii_uppercase().as_str() {
        "ASCII" => false,
        "BINARY" => true,
        _ => return Err(c.err_at(line, format!("expected ASCII or BINARY, found '{enc}'"))),
    };
    let mut r = Reader { c, binary };
    let (kw, line) = r.c.expect_token("DATASET UNSTRUCTURED_GRID")?;
    let (kind, _) = r.c.expect_token("the dataset type")?;
    if !kw.eq_ignore_ascii_case("DATASET") || !kind.eq_ignore_ascii_case("UNSTRUCTURED_GRID") {
        return Err(r.c.err_at(
            line,
            format!("expected 'DATASET UNSTRUCTURED_GRID', found '{kw} {kind}': VoRANG reads unstructured grids"),
        ));
    }
    let mut desc = MeshDescription {
        source: name.to_string(),
        format: format!(
            "legacy VTK {version} {}",
            if binary { "BINARY" } else { "ASCII" }
        ),
        ..MeshDescription::default()
    };
    let mut have_points = false;
    let mut legacy_cells: Option<(Vec<i64>, usize, usize)> = None; // (list, n, line)
    let mut offsets: Option<Vec<i64>> = None;
    let mut connectivity: Option<Vec<i64>> = None;
    let mut types: Option<(Vec<i64>, usize)> = None;
    // Which attribute section we are in: 0 none, 1 point data, 2 cell data; and its count.
    let mut section = 0;
    let mut section_n = 0usize;
    while let Some((kw, line)) = r.c.token() {
        let up = kw.to_ascii_uppercase();
        match up.as_str() {
            "POINTS" => {
                let n = r.c.count("the number of points", 0)?;
                let ty = r.ty()?;
                desc.float_coordinates = ty == Ty::F32;
                desc.points_line = line;
                let v = r.values(ty, n.saturating_mul(3), "POINTS")?;
                desc.nodes = (0..n)
                    .map(|i| [0, 1, 2].map(|k| v.get(3 * i + k)))
                    .collect();
                have_points = true;
                r.skip_metadata();
            }
            "CELLS" if version >= 5.0 => {
                let n_off = r.c.count("the number of offsets", 0)?;
                let n_conn = r.c.count("the connectivity size", 0)?;
                desc.cells_line = line;
                for _ in 0..2 {
                    let (w, l) = r.c.expect_token("OFFSETS or CONNECTIVITY")?;
                    let ty = r.ty()?;
                    match w.to_ascii_uppercase().as_str() {
                        "OFFSETS" => {
                            let ArrayValues::Int(v) = r.values(ty, n_off, "OFFSETS")? else {
                                return Err(r.c.err_at(l, "OFFSETS must be integers"));
                            };
                            offsets = Some(v);
                        }
                        "CONNECTIVITY" => {
                            let ArrayValues::Int(v) = r.values(ty, n_conn, "CONNECTIVITY")? else {
                                return Err(r.c.err_at(l, "CONNECTIVITY must be integers"));
                            };
                            connectivity = Some(v);
                        }
                        _ => {
                            return Err(r.c.err_at(
                                l,
                                format!("expected OFFSETS or CONNECTIVITY, found '{w}'"),
                            ));
                        }
                    }
                }
            }
            "CELLS" => {
                let n = r.c.count("the number of cells", 0)?;
                let size = r.c.count("the cell list size", 0)?;
                desc.cells_line = line;
                let ArrayValues::Int(v) = r.values(Ty::Int(4, true), size, "CELLS")? else {
                    unreachable!("integer type gives integers")
                };
                legacy_cells = Some((v, n, line));
            }
            "CELL_TYPES" => {
                let n = r.c.count("the number of cell types", 0)?;
                let ArrayValues::Int(v) = r.values(Ty::Int(4, true), n, "CELL_TYPES")? else {
                    unreachable!("integer type gives integers")
                };
                types = Some((v, line));
            }
            "POINT_DATA" | "CELL_DATA" => {
                section = if up == "POINT_DATA" { 1 } else { 2 };
                section_n = r.c.count("the number of values", 0)?;
            }
            "SCALARS"
            | "VECTORS"
            | "NORMALS"
            | "TENSORS"
            | "TEXTURE_COORDINATES"
            | "COLOR_SCALARS" => {
                if section == 0 {
                    return Err(r
                        .c
                        .err_at(line, format!("{kw} before POINT_DATA or CELL_DATA")));
                }
                let (aname, _) = r.c.expect_token("the array name")?;
                let aname = aname.to_string();
                let (ty, comps) = match up.as_str() {
                    "SCALARS" => {
                        let ty = r.ty()?;
                        // An optional component count on the same line.
                        let save = (r.c.pos, r.c.line);
                        let comps = match r.c.token() {
                            Some((t, l)) if l == line => t.parse::<usize>().map_err(|_| {
                                r.c.err_at(
                                    l,
                                    format!("expected the number of components, found '{t}'"),
                                )
                            })?,
                            _ => {
                                (r.c.pos, r.c.line) = save;
                                1
                            }
                        };
                        if !(1..=4).contains(&comps) {
                            return Err(r.c.err_at(
                                line,
                                format!("SCALARS with {comps} components: expected 1…4"),
                            ));
                        }
                        // LOOKUP_TABLE name (optional in practice).
                        let save = (r.c.pos, r.c.line);
                        match r.c.token() {
                            Some((t, _)) if t.eq_ignore_ascii_case("LOOKUP_TABLE") => {
                                r.c.expect_token("the lookup table name")?;
                            }
                            _ => (r.c.pos, r.c.line) = save,
                        }
                        (ty, comps)
                    }
                    "VECTORS" | "NORMALS" => (r.ty()?, 3),
                    "TENSORS" => (r.ty()?, 9),
                    "TEXTURE_COORDINATES" => {
                        let d = r.c.count("the texture dimension", 0)?;
                        (r.ty()?, d.clamp(1, 3))
                    }
                    _ => {
                        let d = r.c.count("the number of color components", 0)?;
                        (if binary { Ty::Int(1, false) } else { Ty::F32 }, d.max(1))
                    }
                };
                let values = r.values(
                    ty,
                    section_n.saturating_mul(comps),
                    &format!("{kw} {aname}"),
                )?;
                r.skip_metadata();
                let a = Array {
                    name: aname,
                    components: comps,
                    values,
                    line,
                };
                if section == 1 {
                    desc.point_arrays.push(a);
                } else {
                    desc.cell_arrays.push(a);
                }
            }
            "FIELD" => {
                r.c.expect_token("the FIELD name")?;
                let n = r.c.count("the number of FIELD arrays", 0)?;
                let arrays = r.field_arrays(n, line)?;
                match section {
                    1 => desc.point_arrays.extend(arrays),
                    2 => desc.cell_arrays.extend(arrays),
                    // Dataset-level field data (TIME, CYCLE): not attached to points or cells.
                    _ => {}
                }
            }
            "LOOKUP_TABLE" => {
                r.c.expect_token("the lookup table name")?;
                let n = r.c.count("the lookup table size", 0)?;
                let ty = if binary { Ty::Int(1, false) } else { Ty::F32 };
                r.values(ty, n.saturating_mul(4), "LOOKUP_TABLE")?;
            }
            "METADATA" => {
                // Read past up to the blank line that ends it.
                r.c.next_line();
                while !r.c.at_end() {
                    if r.c.rest_of_line().trim().is_empty() {
                        break;
                    }
                }
            }
            _ => {
                return Err(r.c.err_at(
                    line,
                    format!(
                        "unexpected '{kw}': expected POINTS, CELLS, CELL_TYPES, POINT_DATA, CELL_DATA, SCALARS, VECTORS or FIELD"
                    ),
                ));
            }
        }
    }
    if !have_points {
        return Err(ParseError::new(
            name,
            r.c.line,
            "no POINTS section in this file",
        ));
    }
    let Some((types, types_line)) = types else {
        return Err(ParseError::new(
            name,
            r.c.line,
            "no CELL_TYPES section in this file",
        ));
    };
    let n_nodes = desc.nodes.len() as i64;
    let mut push = |i: usize, nodes: &[i64], line: usize| -> Result<(), ParseError> {
        let t = types[i];
        if !(0..=255).contains(&t) {
            return Err(ParseError::new(
                name,
                types_line,
                format!("cell {}: type {t} is not a VTK cell type", i + 1),
            ));
        }
        if super::cell_type::volume_nodes(t as u8).is_some()
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
        desc.cells.push(t as u8, &nodes);
        Ok(())
    };
    if let Some((list, n, line)) = legacy_cells {
        if types.len() != n {
            return Err(ParseError::new(
                name,
                types_line,
                format!("CELL_TYPES lists {} cells, but CELLS has {n}", types.len()),
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
            push(i, nodes, line)?;
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
    } else if let (Some(off), Some(conn)) = (offsets, connectivity) {
        let line = desc.cells_line;
        if off.len() != types.len() + 1 {
            return Err(ParseError::new(
                name,
                types_line,
                format!(
                    "CELL_TYPES lists {} cells, but OFFSETS has {} entries (cells + 1)",
                    types.len(),
                    off.len()
                ),
            ));
        }
        for i in 0..types.len() {
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
            push(i, &conn[a as usize..b as usize], line)?;
        }
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
    Ok(desc)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vtk9_files_with_metadata_and_dataset_fields_read() {
        // As VTK 9 writes them: dataset-level FIELD (TIME), 5.1 cells, METADATA blocks.
        let text = "# vtk DataFile Version 5.1
vtk output
ASCII
DATASET UNSTRUCTURED_GRID
FIELD FieldData 1
TIME 1 1 double
0.5
POINTS 4 float
0 0 0 1 0 0 0 1 0
0 0 1
METADATA
INFORMATION 0

CELLS 2 4
OFFSETS vtktypeint64
0 4
CONNECTIVITY vtktypeint64
0 1 2 3
CELL_TYPES 1
10

POINT_DATA 4
SCALARS T float
LOOKUP_TABLE default
0 1 2 3
METADATA
INFORMATION 1
NAME L2_NORM_RANGE LOCATION vtkDataArray
DATA 2 0 3

CELL_DATA 1
FIELD FieldData 1
mat 1 1 int
7
";
        let d = read(text.as_bytes(), "v9.vtk").unwrap();
        assert_eq!(d.nodes.len(), 4);
        assert_eq!(d.cells.nodes(0), &[0, 1, 2, 3]);
        assert_eq!(d.point_arrays.len(), 1);
        assert_eq!(d.point_arrays[0].name, "T");
        assert_eq!(d.cell_arrays[0].name, "mat");
        assert_eq!(d.cell_arrays[0].values, ArrayValues::Int(vec![7]));
    }
}
