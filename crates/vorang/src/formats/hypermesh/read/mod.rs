//! Reading a HyperMesh file: header, blocks, then resolving the geometry (every coding of
//! triangles and tetrahedra becomes node indices), the mesh, the raw data and the fields.
//!
//! Indices in files are 1-based (a decision of VoRANG's, as the thesis does not say where they
//! start: docs/formats.md, "Indices and orientation"); in memory they are 0-based `u32`.

//!
//! One module per phase: `blocks` reads the text (header, then the blocks by marker),
//! `geometry` resolves the codings into the mesh, `data` the raw data and the fields. Files and
//! VoRANG's layout inside `.vtu` files ([`read_with_blocks`]) share the two resolving phases,
//! so a volume reads back the same whichever way it was stored.

mod blocks;
mod data;
mod geometry;

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use super::ascii::RowLines;
use super::header::{BlockDecl, Encoding, Header, HeaderParser, parse_title};
use super::input::Input;
use crate::data::Values;
use crate::error::{Error, ParseError, Warning};
use crate::field::Interpolator;
use crate::volume::DataSet;
use blocks::{block_count, read_blocks, resolve_field_markers};
use data::resolve_data;
use geometry::resolve_geometry;

pub use crate::mesh::edges::{NONE, edge_index, edges_of_cells};

pub use crate::volume::Geometry;

/// Everything a HyperMesh file holds.
#[derive(Debug, Clone, PartialEq)]
pub struct HyperMeshFile {
    pub name: String,
    pub encoding: Encoding,
    pub version: String,
    /// `None` for a data-only file (no tetrahedra).
    pub geometry: Option<Geometry>,
    pub data: DataSet,
    pub warnings: Vec<Warning>,
}

/// Reads a file from disk.
pub fn read_file(path: &Path) -> Result<HyperMeshFile, Error> {
    let f = File::open(path).map_err(|e| Error::io(path, e))?;
    let meta = f.metadata().map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        return Err(Error::io(
            path,
            std::io::Error::other("is a directory, expected a HyperMesh file"),
        ));
    }
    // A buffer of one batch of ASCII rows (parsed on every core straight from it).
    let reader = BufReader::with_capacity(1 << 20, f);
    Ok(read(reader, &path.display().to_string(), Some(meta.len()))?)
}

/// Reads a file held in memory (`name` labels messages).
pub fn read_bytes(bytes: &[u8], name: &str) -> Result<HyperMeshFile, ParseError> {
    read(bytes, name, Some(bytes.len() as u64))
}

/// Reads from any buffered source; `size` (total bytes, if known) bounds allocations.
pub fn read<R: BufRead>(
    reader: R,
    name: &str,
    size: Option<u64>,
) -> Result<HyperMeshFile, ParseError> {
    let mut input = Input::new(reader, size);
    let (header, mut blocks, field_blocks) = read_blocks(&mut input, name)?;
    let mut warnings = Vec::new();
    let geometry = resolve_geometry(name, &header, &mut blocks, &mut warnings)?;
    let data = resolve_data(name, &header, &mut blocks, &field_blocks)?;
    Ok(HyperMeshFile {
        name: name.to_string(),
        encoding: header.encoding,
        version: header.version,
        geometry,
        data,
        warnings,
    })
}

/// Reads a HyperMesh header held as text whose blocks are stored elsewhere (the layout that
/// VoRANG writes into its `.vtu` files, [`crate::formats::layout`]): `block(decl, count)` gives
/// the values of each declared block (`count` elements of `decl.ty`), or says why it cannot.
/// The geometry, raw data and fields are then resolved exactly as for a file, so a volume
/// written this way reads back identical. Every message points at `line` (where the text is
/// stored in its file) and says which line of the text it is about.
pub fn read_with_blocks(
    name: &str,
    text: &[u8],
    line: usize,
    mut block: impl FnMut(&BlockDecl, usize) -> Result<Values, String>,
) -> Result<HyperMeshFile, ParseError> {
    let at = |e: ParseError| {
        ParseError::new(
            name,
            line,
            format!("VoRANG layout, line {}: {}", e.line, e.message),
        )
    };
    let mut lines = text.split(|&b| b == b'\n');
    let (encoding, version) = parse_title(name, lines.next().unwrap_or_default()).map_err(at)?;
    let mut parser = HeaderParser::new(name);
    for (i, l) in lines.enumerate() {
        parser.push_line(i + 2, l).map_err(at)?;
    }
    let header = parser.finish(encoding, version).map_err(at)?;
    let field_blocks = resolve_field_markers(name, &header).map_err(at)?;
    let mut blocks = Vec::with_capacity(header.blocks.len());
    for d in &header.blocks {
        let count = block_count(name, &header, d).map_err(at)?;
        let values = block(d, count).map_err(|m| {
            ParseError::new(
                name,
                line,
                format!(
                    "VoRANG layout, block @{} ({}): {m}",
                    d.marker,
                    d.target.describe()
                ),
            )
        })?;
        if values.len() != count.saturating_mul(d.ty.numbers()) {
            return Err(ParseError::new(
                name,
                line,
                format!(
                    "VoRANG layout, block @{} ({}): {} numbers, but {count} × {} need {}",
                    d.marker,
                    d.target.describe(),
                    values.len(),
                    d.ty,
                    count.saturating_mul(d.ty.numbers())
                ),
            ));
        }
        blocks.push(Some(Block {
            values,
            rows: None,
            marker_line: line,
        }));
    }
    let mut warnings = Vec::new();
    let geometry = resolve_geometry(name, &header, &mut blocks, &mut warnings)?;
    let data = resolve_data(name, &header, &mut blocks, &field_blocks)?;
    Ok(HyperMeshFile {
        name: name.to_string(),
        encoding: header.encoding,
        version: header.version,
        geometry,
        data,
        warnings,
    })
}

/// The values of one block and where its rows are.
struct Block {
    values: Values,
    /// Row lines for ASCII blocks; `None` for BINARY ones.
    rows: Option<RowLines>,
    marker_line: usize,
}

/// The header, the blocks (parallel to its declarations) and the resolved `Field` markers.
type Blocks = (Header, Vec<Option<Block>>, Vec<(Interpolator, Vec<usize>)>);

#[cfg(test)]
mod tests;
