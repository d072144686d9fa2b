//! Gmsh meshes (`.msh`), format versions 2.2 and 4.1, ASCII and binary.
//!
//! Read: `$Nodes`, `$Elements` (Gmsh element types become VTK cell types; the 10-node
//! tetrahedron's last two nodes are swapped into VTK order), `$PhysicalNames` and, in 4.1,
//! `$Entities` for the physical groups, `$NodeData` and `$ElementData` (one array per section,
//! named by its first string tag). Other sections (`$Periodic`, `$ElementNodeData`,
//! `$Parametrizations`, …) are read past.
//!
//! Arrays, in file order: first the point arrays (`$NodeData`), then the cell arrays: the
//! physical group of each element as the integer cell array `gmsh:physical` (0 = none; in 4.1
//! the first physical tag of the element's entity), then every `$ElementData`. Element data that
//! Gmsh stores as doubles but that are all whole numbers in 0…255 (material ids, region
//! numbers) are read as integers, so they become `byte` fields usable by `CONST_CELL` and
//! `CategoryField`.
//!
//! Node and element tags may be sparse; data refer to them by tag. Binary files carry their own
//! byte order (the `1` after the format line).
//!
//! Reading is one pass over the sections, then an assembly. Each kind of section has its own
//! module (`nodes`: `$Entities` and `$Nodes`; `elements`: `$Elements`; `data`: `$NodeData` and
//! `$ElementData`), each reading both versions and both encodings through `input`, which hides
//! whether a number is a token or a binary word. Elements and data refer to nodes by tag and may
//! come in any order, so tags are resolved only once every section has been read (`finish`).
//!
//! In ASCII files the rows of `$Nodes` and `$Elements` are parsed on every core where each row
//! is one line, as Gmsh and meshio write them ([`super::lines`]); anything else is read token by
//! token, with the same result. Tags are found through [`tags::TagIndex`], a vector for the
//! usual 1…n numbering.

mod data;
mod elements;
mod input;
mod nodes;
mod tags;

use std::collections::HashMap;

use super::text::Cursor;
use super::{Array, ArrayValues, MeshDescription};
use crate::error::ParseError;
use data::Data;
use input::{Msh, find};
use tags::TagIndex;

pub fn sniff(head: &[u8]) -> bool {
    let start = head
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(0);
    head[start..].starts_with(b"$MeshFormat")
}

pub fn read(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    let mut m = Msh {
        c: Cursor::new(bytes, name),
        binary: false,
        swap: false,
        size_t: 8,
    };
    let (version, ver) = mesh_format(&mut m)?;
    let mut r = Sections {
        version,
        desc: MeshDescription {
            source: name.to_string(),
            format: format!("Gmsh {ver} {}", if m.binary { "binary" } else { "ASCII" }),
            ..MeshDescription::default()
        },
        node_index: TagIndex::default(),
        element_tags: Vec::new(),
        physical: Vec::new(),
        has_physical: false,
        entity_physical: HashMap::new(),
        data: Vec::new(),
        raw_elements: RawElements::default(),
    };
    while let Some((sec, line)) = m.c.token() {
        r.section(&mut m, sec, line)?;
    }
    r.finish(name, m.c.line)
}

/// `$MeshFormat`: the version (2 or 4) and as written, and for binary files the byte order.
fn mesh_format<'a>(m: &mut Msh<'a>) -> Result<(u8, &'a str), ParseError> {
    let (t, _) = m.c.expect_token("$MeshFormat")?;
    if t != "$MeshFormat" {
        return Err(m.c.err_at(1, format!("expected $MeshFormat, found '{t}'")));
    }
    let (ver, vline) = m.c.expect_token("the format version")?;
    let version = match ver {
        "2.2" | "2.1" | "2" | "2.0" => 2,
        "4.1" => 4,
        v => {
            return Err(m.c.err_at(
                vline,
                format!("Gmsh format version {v}: VoRANG reads versions 2.2 and 4.1"),
            ));
        }
    };
    let ft = m.c.int("the file type (0 ASCII, 1 binary)")?;
    let ds = m.c.int("the data size")?;
    if !(ft == 0 || ft == 1) || !(ds == 4 || ds == 8) {
        return Err(m.c.err_at(
            vline,
            format!("expected file type 0 or 1 and data size 4 or 8, found {ft} {ds}"),
        ));
    }
    m.size_t = ds as usize;
    if ft == 1 {
        m.binary = true;
        m.c.next_line();
        let one = m.bytes(4, "the byte-order check")?;
        if one == 1u32.to_le_bytes() {
            m.swap = false;
        } else if one == 1u32.to_be_bytes() {
            m.swap = true;
        } else {
            return Err(m.c.err(format!(
                "the binary byte-order check is not the integer 1 (bytes {one:?})"
            )));
        }
    }
    m.end("MeshFormat")?;
    Ok((version, ver))
}

/// What the sections have given so far.
struct Sections {
    /// The format version: 2 or 4.
    version: u8,
    desc: MeshDescription,
    /// Node tag → index in `desc.nodes`.
    node_index: TagIndex,
    /// Per element, in file order: its tag, its physical group (0 = none) and, in
    /// `raw_elements`, its VTK type, node tags and line.
    element_tags: Vec<u64>,
    physical: Vec<i64>,
    /// Whether the file names physical groups (then `gmsh:physical` is a cell array).
    has_physical: bool,
    /// 4.1: (dim, entity tag) → first physical tag.
    entity_physical: HashMap<(i64, i64), i64>,
    data: Vec<Data>,
    raw_elements: RawElements,
}

/// The elements as read, before their node tags are resolved: flat, one allocation per array
/// rather than one per element.
#[derive(Debug, Default)]
struct RawElements {
    /// VTK cell type (255: a type VoRANG does not name).
    types: Vec<u8>,
    /// Element `i`'s node tags are `tags[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<usize>,
    tags: Vec<u64>,
    /// The line each element was read at, for messages.
    lines: Vec<usize>,
}

impl Sections {
    /// One section, from its `$Name` (read, at `line`) to past its `$EndName`.
    fn section(&mut self, m: &mut Msh, sec: &str, line: usize) -> Result<(), ParseError> {
        match sec {
            "$PhysicalNames" => {
                self.has_physical = true;
                m.end("PhysicalNames")
            }
            "$Entities" if self.version == 4 => self.entities(m, line),
            "$Nodes" => self.nodes(m, line),
            "$Elements" => self.elements(m, line),
            "$NodeData" | "$ElementData" => self.data_section(m, sec, line),
            s if s.starts_with('$') && !s.starts_with("$End") => skip_section(m, s, line),
            other => Err(m.c.err_at(
                line,
                format!("expected a section such as $Nodes or $Elements, found '{other}'"),
            )),
        }
    }

    /// Resolves tags once every section is read: elements to node indices, data to rows.
    fn finish(mut self, name: &str, end_line: usize) -> Result<MeshDescription, ParseError> {
        if self.desc.nodes.is_empty() {
            return Err(ParseError::new(
                name,
                end_line,
                "no $Nodes section (or no nodes) in this file",
            ));
        }
        self.connect_elements(name)?;
        let mut desc = self.desc;
        if self.has_physical {
            desc.cell_arrays.push(Array {
                name: "gmsh:physical".into(),
                components: 1,
                values: ArrayValues::Int(self.physical),
                line: desc.cells_line,
            });
        }
        let (points, cells) =
            data::arrays(name, self.data, &self.node_index, &self.element_tags, &desc)?;
        desc.point_arrays = points;
        desc.cell_arrays.extend(cells);
        Ok(desc)
    }
}

/// A section VoRANG does not use: skipped to its end marker.
fn skip_section(m: &mut Msh, s: &str, line: usize) -> Result<(), ParseError> {
    let want = format!("$End{}", &s[1..]);
    if m.binary {
        let Some(k) = find(&m.c.bytes[m.c.pos..], want.as_bytes()) else {
            return Err(m.c.err_at(line, format!("{s} is not closed by {want}")));
        };
        m.c.raw(k + want.len(), s)?;
        Ok(())
    } else {
        m.end(&s[1..])
    }
}

#[cfg(test)]
mod tests;
