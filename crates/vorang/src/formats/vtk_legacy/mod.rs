//! Legacy VTK files (`.vtk`) with `DATASET UNSTRUCTURED_GRID`, ASCII or BINARY (big-endian, as
//! the format defines), versions 2.0 … 5.1.
//!
//! Read: `POINTS`, `CELLS` (the classic `n size` list of `npts i0 i1 …`, and 5.1's `OFFSETS` /
//! `CONNECTIVITY` arrays), `CELL_TYPES`, and in `POINT_DATA` / `CELL_DATA` the attributes
//! `SCALARS` (with `LOOKUP_TABLE`), `VECTORS`, `NORMALS`, `TENSORS`, `TEXTURE_COORDINATES`,
//! `COLOR_SCALARS` and `FIELD` arrays, in file order. Dataset-level `FIELD` data (time, cycle),
//! standalone `LOOKUP_TABLE`s and `METADATA` blocks are read past. A polyhedron's entry in the
//! cell list is its face stream; Lagrange hexahedra of files before 5.1 are in VTK 8's node
//! order and put into today's, as VTK reads them. Errors name the line of the keyword, or the
//! byte offset where binary data run out.
//!
//! Reading is a preamble (title, encoding, `DATASET`), then one keyword at a time (`sections`),
//! each reading its numbers through `values` (ASCII or big-endian binary), and last the cells
//! (`cells`), which need `CELLS` and `CELL_TYPES` together.

mod cells;
mod sections;
mod values;

use super::MeshDescription;
use super::text::Cursor;
use crate::error::ParseError;
use values::Reader;

pub fn sniff(head: &[u8]) -> bool {
    let start = head
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(0);
    let h = &head[start..head.len().min(start + 64)];
    h.len() >= 5 && h[..5].eq_ignore_ascii_case(b"# vtk")
}

/// What the keywords have given so far.
struct Sections {
    version: f64,
    desc: MeshDescription,
    have_points: bool,
    /// The classic `CELLS` list, its number of cells and its line.
    legacy_cells: Option<(Vec<i64>, usize, usize)>,
    /// 5.1's `OFFSETS` and `CONNECTIVITY`.
    offsets: Option<Vec<i64>>,
    connectivity: Option<Vec<i64>>,
    /// `CELL_TYPES` and its line.
    types: Option<(Vec<i64>, usize)>,
    /// Which attribute section we are in: 0 none, 1 point data, 2 cell data; and its count.
    section: u8,
    section_n: usize,
}

pub fn read(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    let (mut r, version) = preamble(bytes, name)?;
    let mut s = Sections {
        version,
        desc: MeshDescription {
            source: name.to_string(),
            format: format!(
                "legacy VTK {version} {}",
                if r.binary { "BINARY" } else { "ASCII" }
            ),
            ..MeshDescription::default()
        },
        have_points: false,
        legacy_cells: None,
        offsets: None,
        connectivity: None,
        types: None,
        section: 0,
        section_n: 0,
    };
    while let Some((kw, line)) = r.c.token() {
        s.keyword(&mut r, kw, line)?;
    }
    s.finish(name, r.c.line)
}

/// The title line (with the version), the free-text line, `ASCII` or `BINARY`, and
/// `DATASET UNSTRUCTURED_GRID`.
fn preamble<'a>(bytes: &'a [u8], name: &'a str) -> Result<(Reader<'a>, f64), ParseError> {
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
    Ok((r, version))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::ArrayValues;

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
