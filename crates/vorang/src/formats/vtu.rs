//! VTK XML `UnstructuredGrid` files (`.vtu`), as VTK, ParaView, meshio, FEniCS/dolfinx and
//! others write them.
//!
//! Reading covers every encoding VTK defines: `format="ascii"`, `format="binary"` (base64
//! inline), `format="appended"` with `<AppendedData encoding="raw">` or `encoding="base64"`;
//! `compressor` none, `vtkZLibDataCompressor`, `vtkLZ4DataCompressor` and
//! `vtkLZMADataCompressor` (xz streams); `header_type` `UInt32` (the default) or `UInt64`;
//! `byte_order` `LittleEndian` or `BigEndian`; several `<Piece>`s (concatenated).
//!
//! A binary array is a header followed by the data. Uncompressed: one header word, the number
//! of data bytes. Compressed: `[nblocks, block size, last block size (0 = full), compressed
//! size of each block…]`, then the compressed blocks back to back. In base64 the header and the
//! data are usually encoded separately (VTK, meshio), sometimes as one stream: the padding at
//! the header's end tells which.
//!
//! The XML part is parsed with `quick-xml`; raw appended data (which is not XML) is cut off at
//! the `_` that starts it. Every length, offset and block size is checked against the file before
//! use, and decompression never produces more than the header declares, which itself is bounded
//! by a multiple of the file size — so allocation stays bounded by the input.
//!
//! Writing ([`save`]) produces what ParaView reads fastest: appended raw data, zlib-compressed,
//! `UInt64` headers, little-endian.

use std::io::Write as _;
use std::path::Path;

use base64::Engine as _;
use quick_xml::events::{BytesStart, Event};

use super::{Array, ArrayValues, MeshDescription, cell_type, layout, line_of};
use crate::data::{ScalarType, Values};
use crate::error::{Error, ParseError, Warning};
use crate::volume::Volume;

pub fn sniff(head: &[u8]) -> bool {
    let probe = &head[..head.len().min(1024)];
    probe.windows(8).any(|w| w == b"<VTKFile")
}

/// The numeric types of `DataArray type="…"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NumType {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl NumType {
    fn parse(s: &str) -> Option<NumType> {
        Some(match s {
            "Int8" | "Char" => NumType::I8,
            "UInt8" | "UnsignedChar" => NumType::U8,
            "Int16" | "Short" => NumType::I16,
            "UInt16" | "UnsignedShort" => NumType::U16,
            "Int32" | "Int" => NumType::I32,
            "UInt32" | "UnsignedInt" => NumType::U32,
            "Int64" | "Long" | "LongLong" | "IdType" => NumType::I64,
            "UInt64" | "UnsignedLong" | "UnsignedLongLong" => NumType::U64,
            "Float32" | "Float" => NumType::F32,
            "Float64" | "Double" => NumType::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            NumType::I8 | NumType::U8 => 1,
            NumType::I16 | NumType::U16 => 2,
            NumType::I32 | NumType::U32 | NumType::F32 => 4,
            NumType::I64 | NumType::U64 | NumType::F64 => 8,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Compressor {
    None,
    Zlib,
    Lz4,
    Lzma,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Section {
    Other,
    PointData,
    CellData,
    Points,
    Cells,
    /// Dataset-level arrays (`<FieldData>`); only VoRANG's own (`VoRANG_…`) are read.
    FieldData,
}

/// One `<DataArray>` as declared.
#[derive(Debug)]
struct Decl {
    section: Section,
    piece: usize,
    name: String,
    ty: NumType,
    components: usize,
    format: DataFormat,
    /// `NumberOfTuples` (FieldData arrays say how long they are).
    tuples: Option<usize>,
    line: usize,
    /// Inline content (ascii numbers or base64 text), as places in the file: a large inline
    /// array is never copied before it is decoded.
    text: Vec<TextPart>,
}

/// A piece of a `DataArray`'s inline content.
#[derive(Debug)]
enum TextPart {
    /// Bytes `start..end` of the file.
    At(usize, usize),
    /// Content the XML reader did not borrow from the file (not expected; kept for safety).
    Owned(Vec<u8>),
}

impl TextPart {
    /// The part of `t` (content of an event borrowed from `file`).
    fn of(t: &[u8], file: &[u8]) -> TextPart {
        let start = (t.as_ptr() as usize).wrapping_sub(file.as_ptr() as usize);
        if start <= file.len() && t.len() <= file.len() - start {
            TextPart::At(start, start + t.len())
        } else {
            TextPart::Owned(t.to_vec())
        }
    }
}

/// The inline content of `d`: borrowed from the file when it is one piece (the usual case).
fn decl_text<'a>(s: &Settings<'a>, d: &'a Decl) -> std::borrow::Cow<'a, [u8]> {
    use std::borrow::Cow;
    let part = |p: &'a TextPart| -> &'a [u8] {
        match p {
            TextPart::At(a, b) => &s.file[*a..*b],
            TextPart::Owned(v) => v,
        }
    };
    match d.text.as_slice() {
        [] => Cow::Borrowed(&[]),
        [one] => Cow::Borrowed(part(one)),
        many => Cow::Owned(many.iter().flat_map(|p| part(p).iter().copied()).collect()),
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum DataFormat {
    Ascii,
    Binary,
    Appended(u64),
}

/// File-wide settings from `<VTKFile …>` and `<AppendedData …>`.
struct Settings<'a> {
    name: &'a str,
    /// The whole file (inline array contents are places in it).
    file: &'a [u8],
    big_endian: bool,
    header64: bool,
    compressor: Compressor,
    /// The appended data after the `_` (raw bytes, or base64 text without the closing tag).
    appended: Option<(&'a [u8], usize, bool)>,
    /// Offsets of all appended arrays, sorted (to find where a base64 chunk ends).
    offsets: Vec<u64>,
    /// Upper bound on any decoded size.
    limit: usize,
}

struct Piece {
    points: usize,
    cells: usize,
    line: usize,
}

fn attr(e: &BytesStart, key: &[u8]) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == key)
        .map(|a| {
            a.unescape_value()
                .map(|v| v.into_owned())
                .unwrap_or_else(|_| String::from_utf8_lossy(&a.value).into_owned())
        })
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn rfind(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).rposition(|w| w == needle)
}

/// Reads a whole `.vtu` file.
pub fn read(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    let err = |pos: usize, msg: String| ParseError::new(name, line_of(bytes, pos), msg);
    // The XML part ends where raw appended data begins.
    let (xml_end, appended_tag) = match find(bytes, b"<AppendedData") {
        Some(p) => {
            let close = bytes[p..]
                .iter()
                .position(|&b| b == b'>')
                .map(|k| p + k + 1)
                .ok_or_else(|| err(p, "<AppendedData is not closed by '>'".into()))?;
            (close, Some(p))
        }
        None => (bytes.len(), None),
    };
    let mut reader = quick_xml::Reader::from_reader(&bytes[..xml_end]);
    reader.config_mut().check_end_names = false;
    let mut decls: Vec<Decl> = Vec::new();
    let mut pieces: Vec<Piece> = Vec::new();
    let mut section = Section::Other;
    let mut current: Option<Decl> = None;
    let mut saw_vtkfile = false;
    let mut big_endian = false;
    let mut header64 = false;
    let mut compressor = Compressor::None;
    let mut appended_encoding_raw = true;
    // Whether the XML was complete: `</VTKFile>` seen, or the appended data reached.
    let mut complete = false;
    let mut nested = 0usize;
    loop {
        let pos = reader.buffer_position() as usize;
        let ev = reader.read_event().map_err(|e| {
            err(
                reader.error_position() as usize,
                format!("malformed XML: {e}"),
            )
        })?;
        match ev {
            Event::Eof => break,
            Event::Start(_) | Event::Empty(_) if current.is_some() => {
                // Elements inside a DataArray (VTK's <InformationKey>, ranges): their text is
                // not the array's data.
                if matches!(ev, Event::Start(_)) {
                    nested += 1;
                }
            }
            Event::Start(ref e) | Event::Empty(ref e) => {
                let empty = matches!(ev, Event::Empty(_));
                match e.name().as_ref() {
                    b"VTKFile" => {
                        saw_vtkfile = true;
                        let ty = attr(e, b"type").unwrap_or_default();
                        if ty != "UnstructuredGrid" {
                            return Err(err(
                                pos,
                                format!(
                                    "VTKFile type=\"{ty}\": VoRANG reads only type=\"UnstructuredGrid\" (.vtu)"
                                ),
                            ));
                        }
                        big_endian = match attr(e, b"byte_order").as_deref() {
                            None | Some("LittleEndian") => false,
                            Some("BigEndian") => true,
                            Some(o) => {
                                return Err(err(
                                    pos,
                                    format!(
                                        "byte_order=\"{o}\": expected LittleEndian or BigEndian"
                                    ),
                                ));
                            }
                        };
                        header64 = match attr(e, b"header_type").as_deref() {
                            None | Some("UInt32") => false,
                            Some("UInt64") => true,
                            Some(h) => {
                                return Err(err(
                                    pos,
                                    format!("header_type=\"{h}\": expected UInt32 or UInt64"),
                                ));
                            }
                        };
                        compressor = match attr(e, b"compressor").as_deref() {
                            None | Some("") => Compressor::None,
                            Some("vtkZLibDataCompressor") => Compressor::Zlib,
                            Some("vtkLZ4DataCompressor") => Compressor::Lz4,
                            Some("vtkLZMADataCompressor") => Compressor::Lzma,
                            Some(c) => {
                                return Err(err(
                                    pos,
                                    format!(
                                        "compressor=\"{c}\": expected vtkZLibDataCompressor, vtkLZ4DataCompressor or vtkLZMADataCompressor"
                                    ),
                                ));
                            }
                        };
                    }
                    b"Piece" => {
                        let count = |k: &[u8]| -> Result<usize, ParseError> {
                            let v = attr(e, k).ok_or_else(|| {
                                err(
                                    pos,
                                    format!("<Piece> needs {}=\"…\"", String::from_utf8_lossy(k)),
                                )
                            })?;
                            v.trim().parse::<usize>().map_err(|_| {
                                err(
                                    pos,
                                    format!(
                                        "{}=\"{v}\": expected a whole number ≥ 0",
                                        String::from_utf8_lossy(k)
                                    ),
                                )
                            })
                        };
                        pieces.push(Piece {
                            points: count(b"NumberOfPoints")?,
                            cells: count(b"NumberOfCells")?,
                            line: line_of(bytes, pos),
                        });
                    }
                    b"PointData" if !empty => section = Section::PointData,
                    b"CellData" if !empty => section = Section::CellData,
                    b"Points" if !empty => section = Section::Points,
                    b"Cells" if !empty => section = Section::Cells,
                    b"FieldData" if !empty => section = Section::FieldData,
                    b"DataArray" => {
                        let line = line_of(bytes, pos);
                        let ty_s = attr(e, b"type").unwrap_or_default();
                        let ty = NumType::parse(&ty_s).ok_or_else(|| {
                            err(
                                pos,
                                format!(
                                    "DataArray type=\"{ty_s}\": expected Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32 or Float64"
                                ),
                            )
                        })?;
                        let components = match attr(e, b"NumberOfComponents") {
                            None => 1,
                            Some(c) => c.trim().parse::<usize>().ok().filter(|&c| (1..=64).contains(&c)).ok_or_else(|| {
                                err(pos, format!("NumberOfComponents=\"{c}\": expected a whole number 1…64"))
                            })?,
                        };
                        let format = match attr(e, b"format").as_deref() {
                            Some("ascii") => DataFormat::Ascii,
                            Some("binary") => DataFormat::Binary,
                            Some("appended") => {
                                let o = attr(e, b"offset").unwrap_or_default();
                                DataFormat::Appended(o.trim().parse::<u64>().map_err(|_| {
                                    err(pos, format!("DataArray format=\"appended\" needs offset=\"<bytes>\", found offset=\"{o}\""))
                                })?)
                            }
                            other => {
                                return Err(err(
                                    pos,
                                    format!(
                                        "DataArray format=\"{}\": expected ascii, binary or appended",
                                        other.unwrap_or("")
                                    ),
                                ));
                            }
                        };
                        let d = Decl {
                            section,
                            piece: pieces.len().saturating_sub(1),
                            name: attr(e, b"Name").unwrap_or_default(),
                            ty,
                            components,
                            format,
                            tuples: attr(e, b"NumberOfTuples")
                                .and_then(|t| t.trim().parse::<usize>().ok()),
                            line,
                            text: Vec::new(),
                        };
                        if empty {
                            decls.push(d);
                        } else {
                            current = Some(d);
                        }
                    }
                    b"AppendedData" => {
                        complete = true;
                        appended_encoding_raw = match attr(e, b"encoding").as_deref() {
                            None | Some("raw") => true,
                            Some("base64") => false,
                            Some(x) => {
                                return Err(err(
                                    pos,
                                    format!(
                                        "AppendedData encoding=\"{x}\": expected raw or base64"
                                    ),
                                ));
                            }
                        };
                    }
                    _ => {}
                }
            }
            Event::Text(t) => {
                if let (Some(d), 0) = (&mut current, nested) {
                    d.text.push(TextPart::of(&t, bytes));
                }
            }
            Event::CData(t) => {
                if let (Some(d), 0) = (&mut current, nested) {
                    d.text.push(TextPart::of(&t, bytes));
                }
            }
            Event::End(_) if nested > 0 => nested -= 1,
            Event::End(e) => match e.name().as_ref() {
                b"DataArray" => {
                    if let Some(d) = current.take() {
                        decls.push(d);
                    }
                }
                b"PointData" | b"CellData" | b"Points" | b"Cells" | b"FieldData" => {
                    section = Section::Other
                }
                b"VTKFile" => complete = true,
                _ => {}
            },
            _ => {}
        }
    }
    if !saw_vtkfile {
        return Err(ParseError::new(
            name,
            1,
            "expected a VTK XML file starting with <VTKFile type=\"UnstructuredGrid\" …>",
        ));
    }
    if !complete {
        return Err(err(
            bytes.len(),
            format!(
                "the file ends at byte {} before </VTKFile>: it is truncated",
                bytes.len()
            ),
        ));
    }
    if pieces.is_empty() {
        return Err(ParseError::new(
            name,
            1,
            "no <Piece NumberOfPoints=… NumberOfCells=…> in this file",
        ));
    }

    // The appended data: after the '_' that follows the AppendedData start tag.
    let appended = match appended_tag {
        Some(_) => {
            let mut p = xml_end;
            while bytes.get(p).is_some_and(|b| b.is_ascii_whitespace()) {
                p += 1;
            }
            if bytes.get(p) != Some(&b'_') {
                return Err(err(
                    p,
                    format!(
                        "expected '_' at byte {p}, where the appended data start (after <AppendedData>)"
                    ),
                ));
            }
            let start = p + 1;
            let end = if appended_encoding_raw {
                bytes.len()
            } else {
                rfind(&bytes[start..], b"</AppendedData>")
                    .map(|k| start + k)
                    .ok_or_else(|| {
                        err(
                            bytes.len(),
                            format!(
                                "the base64 appended data starting at byte {start} are not closed by </AppendedData>: the file is truncated"
                            ),
                        )
                    })?
            };
            Some((&bytes[start..end], start, appended_encoding_raw))
        }
        None => None,
    };
    let mut offsets: Vec<u64> = decls
        .iter()
        .filter_map(|d| match d.format {
            DataFormat::Appended(o) => Some(o),
            _ => None,
        })
        .collect();
    offsets.sort_unstable();
    offsets.dedup();
    let settings = Settings {
        name,
        file: bytes,
        big_endian,
        header64,
        compressor,
        appended,
        offsets,
        limit: bytes.len().saturating_mul(1100).saturating_add(1 << 20),
    };

    let mut desc = MeshDescription {
        source: name.to_string(),
        format: "VTK XML UnstructuredGrid".into(),
        float_coordinates: true,
        ..MeshDescription::default()
    };
    desc.cells.offsets.push(0);
    let multi = pieces.len() > 1;
    let mut point_names: Vec<(String, usize, NumType)> = Vec::new();
    let mut cell_names: Vec<(String, usize, NumType)> = Vec::new();
    // The arrays of each piece (one pass: a file with many pieces stays linear).
    let mut by_piece: Vec<Vec<&Decl>> = vec![Vec::new(); pieces.len()];
    for d in &decls {
        if let Some(list) = by_piece.get_mut(d.piece) {
            list.push(d);
        }
    }
    for (pi, piece) in pieces.iter().enumerate() {
        let here = std::mem::take(&mut by_piece[pi]);
        let node_base = desc.nodes.len() as u64;
        // Points.
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
        if desc.points_line == 0 {
            desc.points_line = pts.line;
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
        let coords = decode(&settings, pts, piece.points.saturating_mul(3))?;
        if pts.ty != NumType::F32 {
            desc.float_coordinates = false;
        }
        desc.nodes
            .extend((0..piece.points).map(|i| [0, 1, 2].map(|c| coords.get(i * 3 + c))));
        // Cells.
        let cells_decl = |n: &str| -> Result<&Decl, ParseError> {
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
        if piece.cells > 0 || here.iter().any(|d| d.section == Section::Cells) {
            let conn_d = cells_decl("connectivity")?;
            let off_d = cells_decl("offsets")?;
            let types_d = cells_decl("types")?;
            if desc.cells_line == 0 {
                desc.cells_line = conn_d.line;
            }
            // Decoded as 32-bit numbers (values that do not fit are kept aside for the
            // messages below): no 64-bit copy of the two per-cell arrays.
            let integers = |d: &Decl| {
                if matches!(d.ty, NumType::F32 | NumType::F64) {
                    Err(ParseError::new(
                        name,
                        off_d.line,
                        "offsets and types must be integer arrays",
                    ))
                } else {
                    Ok(())
                }
            };
            integers(types_d)?;
            integers(off_d)?;
            let (types, types_outside) = decode_indices(&settings, types_d, piece.cells, 256)?;
            let (offs, offs_outside) =
                decode_indices(&settings, off_d, piece.cells, u32::MAX as usize)?;
            let original = |v: &[u32], outside: &Outside, i: usize| -> i64 {
                match outside.iter().find(|(at, _)| *at == i) {
                    Some(&(_, x)) => x,
                    None => i64::from(v[i]),
                }
            };
            // Types and offsets first, so that they are checked and stored compactly before
            // the connectivity, the largest array, is decoded.
            let conn_base = desc.cells.connectivity.len();
            let first_cell = desc.cells.types.len();
            let mut prev = 0i64;
            desc.cells.types.reserve(types.len());
            desc.cells.offsets.reserve(offs.len());
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
                if let Some(need) = cell_type::volume_nodes(t as u8)
                    && (o - prev) as usize != need
                {
                    return Err(ParseError::new(
                        name,
                        off_d.line,
                        format!(
                            "offsets: cell {} is a {} (type {t}) and needs {need} nodes, but its offsets give it {}",
                            i + 1,
                            cell_type::name(t as u8),
                            o - prev
                        ),
                    ));
                }
                desc.cells.types.push(t as u8);
                desc.cells.offsets.push(conn_base + o as usize);
                prev = o;
            }
            drop((offs, types));
            // The connectivity's length is what the last offset says; decoded straight into
            // 32-bit indices, an index outside the piece's points kept aside for the message.
            if desc.nodes.len() >= u32::MAX as usize {
                return Err(ParseError::new(
                    name,
                    piece.line,
                    format!(
                        "{} points in all: VoRANG indexes at most {} points",
                        desc.nodes.len(),
                        u32::MAX - 1
                    ),
                ));
            }
            let (conn, outside) = decode_indices(&settings, conn_d, prev as usize, piece.points)?;
            for i in first_cell..desc.cells.types.len() {
                let t = desc.cells.types[i];
                if cell_type::volume_nodes(t).is_none() {
                    continue;
                }
                let (a, b) = (
                    desc.cells.offsets[i] - conn_base,
                    desc.cells.offsets[i + 1] - conn_base,
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
            // Validated: the piece's indices follow the points of the pieces before it (in
            // place, no second copy of the largest array of the file).
            let base = node_base as u32;
            if desc.cells.connectivity.is_empty() && base == 0 {
                desc.cells.connectivity = conn;
            } else {
                desc.cells
                    .connectivity
                    .extend(conn.into_iter().map(|n| n.saturating_add(base)));
            }
        }
        // Point and cell arrays, by name across pieces.
        for (sec, list, want, target) in [
            (Section::PointData, &mut point_names, piece.points, 0),
            (Section::CellData, &mut cell_names, piece.cells, 1),
        ] {
            let arrays: Vec<&&Decl> = here.iter().filter(|d| d.section == sec).collect();
            if pi == 0 {
                for d in &arrays {
                    list.push((d.name.clone(), d.components, d.ty));
                }
            } else if multi
                && (arrays.len() != list.len()
                    || arrays
                        .iter()
                        .zip(list.iter())
                        .any(|(d, l)| d.name != l.0 || d.components != l.1))
            {
                return Err(ParseError::new(
                    name,
                    piece.line,
                    "this <Piece> has other point or cell arrays than the first one; every piece needs the same arrays",
                ));
            }
            for (k, d) in arrays.iter().enumerate() {
                let v = decode(&settings, d, want.saturating_mul(d.components))?;
                let dest = if target == 0 {
                    &mut desc.point_arrays
                } else {
                    &mut desc.cell_arrays
                };
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
        }
    }
    // VoRANG's own FieldData arrays (its layout, edges, triangles, data on them); other
    // FieldData (time values, provenance) are not per point or cell and are not read.
    for d in decls
        .iter()
        .filter(|d| d.section == Section::FieldData && d.name.starts_with("VoRANG_"))
    {
        let tuples = d.tuples.ok_or_else(|| {
            ParseError::new(
                name,
                d.line,
                format!("FieldData array \"{}\" needs NumberOfTuples", d.name),
            )
        })?;
        let v = decode(&settings, d, tuples.saturating_mul(d.components))?;
        desc.field_arrays.push(Array {
            name: d.name.clone(),
            components: d.components,
            values: v,
            line: d.line,
        });
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

fn append_values(dest: &mut ArrayValues, v: ArrayValues) {
    match (dest, v) {
        (ArrayValues::Int(a), ArrayValues::Int(b)) => a.extend(b),
        (ArrayValues::F32(a), ArrayValues::F32(b)) => a.extend(b),
        (ArrayValues::F64(a), ArrayValues::F64(b)) => a.extend(b),
        (d, b) => {
            let mut all: Vec<f64> = (0..d.len()).map(|i| d.get(i)).collect();
            all.extend((0..b.len()).map(|i| b.get(i)));
            *d = ArrayValues::F64(all);
        }
    }
}

/// Decodes one array's `count` numbers.
fn decode(s: &Settings, d: &Decl, count: usize) -> Result<ArrayValues, ParseError> {
    if d.format == DataFormat::Ascii {
        want_bytes(s, d, count)?;
        return ascii_values(s, d, count, &what_of(d));
    }
    let sink = Sink::new(d.ty, s.big_endian, 0);
    Ok(decode_into(s, d, count, sink)?.values)
}

/// The bytes `count` values take, refused when more than the file can hold (allocation stays
/// bounded by the file's size).
fn want_bytes(s: &Settings, d: &Decl, count: usize) -> Result<usize, ParseError> {
    count
        .checked_mul(d.ty.size())
        .filter(|&b| b <= s.limit)
        .ok_or_else(|| {
            ParseError::new(
                s.name,
                d.line,
                format!(
                    "{}: {count} values are more than this file can hold",
                    what_of(d)
                ),
            )
        })
}

fn what_of(d: &Decl) -> String {
    if d.name.is_empty() {
        "DataArray".to_string()
    } else {
        format!("DataArray \"{}\"", d.name)
    }
}

/// What a [`Sink`] produced.
struct Decoded {
    values: ArrayValues,
    index: Option<IndexOut>,
}

/// Decodes a binary or appended array's `count` numbers into `sink`.
fn decode_into(
    s: &Settings,
    d: &Decl,
    count: usize,
    mut sink: Sink,
) -> Result<Decoded, ParseError> {
    let what = what_of(d);
    let err = |msg: String| ParseError::new(s.name, d.line, format!("{what}: {msg}"));
    let want_bytes = want_bytes(s, d, count)?;
    sink.want = want_bytes;
    let sink = &mut sink;
    match d.format {
        DataFormat::Ascii => unreachable!("ascii arrays are decoded as text"),
        DataFormat::Binary => {
            let text = decl_text(s, d);
            binary_base64(s, &without_whitespace(&text), want_bytes, sink).map_err(&err)?;
        }
        DataFormat::Appended(offset) => {
            let Some((app, start, raw)) = s.appended else {
                return Err(err(
                    "format=\"appended\", but the file has no <AppendedData> section".into(),
                ));
            };
            if offset >= app.len() as u64 && want_bytes > 0 {
                return Err(err(format!(
                    "offset {offset} lies beyond the appended data ({} bytes from byte {start})",
                    app.len()
                )));
            }
            let o = offset.min(app.len() as u64) as usize;
            if raw {
                binary_raw(s, &app[o..], start + o, want_bytes, sink).map_err(&err)?;
            } else {
                let end = s
                    .offsets
                    .iter()
                    .find(|&&x| x > offset)
                    .map_or(app.len(), |&x| (x as usize).min(app.len()));
                binary_base64(s, &without_whitespace(&app[o..end]), want_bytes, sink)
                    .map_err(&err)?;
            }
        }
    }
    if sink.seen < want_bytes {
        return Err(err(format!(
            "holds {} bytes, but {count} values of {:?} need {want_bytes}",
            sink.seen, d.ty
        )));
    }
    if sink.seen > want_bytes && !(d.section == Section::Cells && d.name == "offsets") {
        return Err(err(format!(
            "holds {} bytes, but {count} values of {:?} need {want_bytes}: the array is longer than the counts say",
            sink.seen, d.ty
        )));
    }
    let index = sink.index.take();
    let values = std::mem::replace(sink, Sink::new(d.ty, false, 0))
        .finish()
        .map_err(err)?;
    Ok(Decoded { values, index })
}

/// Base64 text without its whitespace: borrowed when only the ends have any (the usual case).
fn without_whitespace(text: &[u8]) -> std::borrow::Cow<'_, [u8]> {
    let start = text
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(text.len());
    let end = text
        .iter()
        .rposition(|b| !b.is_ascii_whitespace())
        .map_or(start, |e| e + 1);
    let inner = &text[start..end.max(start)];
    if inner.iter().any(u8::is_ascii_whitespace) {
        inner
            .iter()
            .copied()
            .filter(|b| !b.is_ascii_whitespace())
            .collect::<Vec<u8>>()
            .into()
    } else {
        inner.into()
    }
}

/// Decodes the connectivity: `count` 0-based indices of the piece's `points`, straight into
/// 32-bit storage (a large file's biggest array never exists as 64-bit numbers). An index
/// outside `0…points-1` is stored as `u32::MAX`; the first few such are returned with their
/// positions and values, for messages.
fn decode_indices(
    s: &Settings,
    d: &Decl,
    count: usize,
    points: usize,
) -> Result<(Vec<u32>, Outside), ParseError> {
    let limit = points.min(u32::MAX as usize) as u64;
    let integer = !matches!(d.ty, NumType::F32 | NumType::F64);
    if d.format == DataFormat::Ascii || !integer {
        let ArrayValues::Int(v) = decode(s, d, count)? else {
            return Err(ParseError::new(
                s.name,
                d.line,
                "connectivity must be an integer array",
            ));
        };
        let mut outside = Vec::new();
        let conn = v
            .iter()
            .enumerate()
            .map(|(i, &x)| match u32::try_from(x) {
                Ok(n) if u64::from(n) < limit => n,
                _ => {
                    if outside.len() < MAX_OUTSIDE {
                        outside.push((i, x));
                    }
                    u32::MAX
                }
            })
            .collect();
        return Ok((conn, outside));
    }
    let mut sink = Sink::new(d.ty, s.big_endian, 0);
    sink.index = Some(IndexOut {
        v: Vec::new(),
        limit,
        outside: Vec::new(),
    });
    match decode_into(s, d, count, sink)? {
        Decoded {
            index: Some(out), ..
        } => Ok((out.v, out.outside)),
        _ => Err(ParseError::new(
            s.name,
            d.line,
            "connectivity must be an integer array",
        )),
    }
}

/// Out-of-range indices with their positions (the first few), for messages.
type Outside = Vec<(usize, i64)>;

/// How many out-of-range indices [`decode_indices`] keeps for messages.
const MAX_OUTSIDE: usize = 16;

/// 32-bit index output of a [`Sink`].
struct IndexOut {
    v: Vec<u32>,
    /// Indices must be below this.
    limit: u64,
    outside: Outside,
}

/// Turns decoded bytes into values as they arrive (block by block for compressed data), so a
/// large array never exists twice — once as bytes, once as numbers.
struct Sink {
    ty: NumType,
    big: bool,
    /// Bytes wanted; what arrives beyond is counted, not kept.
    want: usize,
    seen: usize,
    carry: Vec<u8>,
    out: ArrayValues,
    /// Set for the connectivity: 32-bit indices instead of `out`.
    index: Option<IndexOut>,
    error: Option<String>,
}

impl Sink {
    fn new(ty: NumType, big: bool, want: usize) -> Sink {
        let out = match ty {
            NumType::F32 => ArrayValues::F32(Vec::new()),
            NumType::F64 => ArrayValues::F64(Vec::new()),
            _ => ArrayValues::Int(Vec::new()),
        };
        Sink {
            ty,
            big,
            want,
            seen: 0,
            carry: Vec::new(),
            out,
            index: None,
            error: None,
        }
    }

    /// Makes room for `bytes` of data — called once the file is known to hold them (the
    /// counts alone could ask for anything).
    fn reserve(&mut self, bytes: usize) {
        let n = bytes.min(self.want) / self.ty.size();
        if let Some(idx) = &mut self.index {
            idx.v.reserve_exact(n);
            return;
        }
        match &mut self.out {
            ArrayValues::F32(v) => v.reserve_exact(n),
            ArrayValues::F64(v) => v.reserve_exact(n),
            ArrayValues::Int(v) => v.reserve_exact(n),
        }
    }

    fn push(&mut self, bytes: &[u8]) {
        let keep = bytes.len().min(self.want.saturating_sub(self.seen));
        self.seen = self.seen.saturating_add(bytes.len());
        let mut bytes = &bytes[..keep];
        let size = self.ty.size();
        if !self.carry.is_empty() {
            let take = (size - self.carry.len()).min(bytes.len());
            self.carry.extend_from_slice(&bytes[..take]);
            bytes = &bytes[take..];
            if self.carry.len() == size {
                let c = std::mem::take(&mut self.carry);
                self.convert(&c);
            }
        }
        let whole = bytes.len() / size * size;
        self.convert(&bytes[..whole]);
        self.carry.extend_from_slice(&bytes[whole..]);
    }

    fn convert(&mut self, data: &[u8]) {
        if let Some(idx) = &mut self.index {
            convert_indices(data, self.ty, self.big, idx);
            return;
        }
        if let Err(e) = convert_into(data, self.ty, self.big, &mut self.out) {
            self.error.get_or_insert(e);
        }
    }

    fn finish(self) -> Result<ArrayValues, String> {
        match self.error {
            Some(e) => Err(e),
            None => Ok(self.out),
        }
    }
}

/// Appends the integers in `data` to `out` as 32-bit indices (see [`decode_indices`]).
fn convert_indices(data: &[u8], ty: NumType, big: bool, out: &mut IndexOut) {
    let IndexOut { v, limit, outside } = out;
    let limit = *limit;
    let first = v.len();
    let mut check = |i: usize, x: i64| -> u32 {
        if (0..limit as i64).contains(&x) {
            x as u32
        } else {
            if outside.len() < MAX_OUTSIDE {
                outside.push((first + i, x));
            }
            u32::MAX
        }
    };
    let size = ty.size();
    let chunks = data.chunks_exact(size);
    match (ty, big) {
        (NumType::I64, false) => v.extend(chunks.enumerate().map(|(i, c)| {
            check(
                i,
                i64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]),
            )
        })),
        (NumType::I32, false) => v.extend(
            chunks
                .enumerate()
                .map(|(i, c)| check(i, i64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]])))),
        ),
        _ => {
            let mut tmp = ArrayValues::Int(Vec::with_capacity(data.len() / size));
            let result = convert_into(data, ty, big, &mut tmp);
            if let (Ok(()), ArrayValues::Int(t)) = (result, tmp) {
                v.extend(t.into_iter().enumerate().map(|(i, x)| check(i, x)));
            } else {
                // A UInt64 beyond i64: out of range like any other.
                let n = data.len() / size;
                v.extend((0..n).map(|i| check(i, -1)));
            }
        }
    }
}

fn convert_into(data: &[u8], ty: NumType, big: bool, out: &mut ArrayValues) -> Result<(), String> {
    let size = ty.size();
    // The common cases, little-endian and whole numbers of elements, in tight loops that the
    // compiler vectorises (large connectivity arrays spend most of their reading time here).
    if !big {
        let chunks = data.chunks_exact(size);
        let four = |c: &[u8]| [c[0], c[1], c[2], c[3]];
        let eight = |c: &[u8]| [c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]];
        match (ty, &mut *out) {
            (NumType::F32, ArrayValues::F32(v)) => {
                v.extend(chunks.map(|c| f32::from_le_bytes(four(c))));
                return Ok(());
            }
            (NumType::F64, ArrayValues::F64(v)) => {
                v.extend(chunks.map(|c| f64::from_le_bytes(eight(c))));
                return Ok(());
            }
            (NumType::I64, ArrayValues::Int(v)) => {
                v.extend(chunks.map(|c| i64::from_le_bytes(eight(c))));
                return Ok(());
            }
            (NumType::I32, ArrayValues::Int(v)) => {
                v.extend(chunks.map(|c| i64::from(i32::from_le_bytes(four(c)))));
                return Ok(());
            }
            (NumType::U8, ArrayValues::Int(v)) => {
                v.extend(data.iter().map(|&b| i64::from(b)));
                return Ok(());
            }
            _ => {}
        }
    }
    let word = |chunk: &[u8]| -> [u8; 8] {
        let mut w = [0u8; 8];
        if big {
            for (k, b) in chunk.iter().rev().enumerate() {
                w[k] = *b;
            }
        } else {
            w[..chunk.len()].copy_from_slice(chunk);
        }
        w
    };
    let chunks = data.chunks_exact(size);
    match out {
        ArrayValues::F32(v) => v.extend(chunks.map(|c| {
            let w = word(c);
            f32::from_le_bytes([w[0], w[1], w[2], w[3]])
        })),
        ArrayValues::F64(v) => v.extend(chunks.map(|c| f64::from_le_bytes(word(c)))),
        ArrayValues::Int(out) => {
            for c in chunks {
                let w = word(c);
                let v = match ty {
                    NumType::I8 => i64::from(w[0] as i8),
                    NumType::U8 => i64::from(w[0]),
                    NumType::I16 => i64::from(i16::from_le_bytes([w[0], w[1]])),
                    NumType::U16 => i64::from(u16::from_le_bytes([w[0], w[1]])),
                    NumType::I32 => i64::from(i32::from_le_bytes([w[0], w[1], w[2], w[3]])),
                    NumType::U32 => i64::from(u32::from_le_bytes([w[0], w[1], w[2], w[3]])),
                    NumType::I64 => i64::from_le_bytes(w),
                    _ => {
                        let u = u64::from_le_bytes(w);
                        i64::try_from(u).map_err(|_| format!("UInt64 value {u} is too large"))?
                    }
                };
                out.push(v);
            }
        }
    }
    Ok(())
}

fn ascii_values(
    s: &Settings,
    d: &Decl,
    count: usize,
    what: &str,
) -> Result<ArrayValues, ParseError> {
    let text = decl_text(s, d);
    let text = std::str::from_utf8(&text)
        .map_err(|_| ParseError::new(s.name, d.line, format!("{what}: ascii data are not text")))?;
    let mut toks = text.split_ascii_whitespace();
    let line_of_tok = |k: usize| {
        // The line of the k-th token, counted from the DataArray's line.
        let mut seen = 0;
        let mut line = d.line;
        let mut in_tok = false;
        for b in text.bytes() {
            if b == b'\n' {
                line += 1;
            }
            if b.is_ascii_whitespace() {
                in_tok = false;
            } else if !in_tok {
                in_tok = true;
                if seen == k {
                    return line;
                }
                seen += 1;
            }
        }
        line
    };
    let float = matches!(d.ty, NumType::F32 | NumType::F64);
    let mut ints = Vec::new();
    let mut floats = Vec::new();
    for k in 0..count {
        let Some(t) = toks.next() else {
            return Err(ParseError::new(
                s.name,
                line_of_tok(k),
                format!("{what}: has {k} values, but {count} are needed"),
            ));
        };
        if float {
            let v = super::text::parse_float(t).ok_or_else(|| {
                ParseError::new(
                    s.name,
                    line_of_tok(k),
                    format!("{what}: expected a number, found '{t}'"),
                )
            })?;
            floats.push(v);
        } else {
            let v = super::text::parse_int(t).ok_or_else(|| {
                ParseError::new(
                    s.name,
                    line_of_tok(k),
                    format!("{what}: expected an integer, found '{t}'"),
                )
            })?;
            ints.push(v);
        }
    }
    let is_offsets = d.section == Section::Cells && d.name == "offsets";
    if toks.next().is_some() && !is_offsets {
        return Err(ParseError::new(
            s.name,
            line_of_tok(count),
            format!("{what}: has more than the {count} values the counts ask for"),
        ));
    }
    Ok(match d.ty {
        NumType::F32 => ArrayValues::F32(floats.into_iter().map(|v| v as f32).collect()),
        NumType::F64 => ArrayValues::F64(floats),
        _ => ArrayValues::Int(ints),
    })
}

fn b64() -> base64::engine::GeneralPurpose {
    base64::engine::GeneralPurpose::new(
        &base64::alphabet::STANDARD,
        base64::engine::GeneralPurposeConfig::new()
            .with_decode_padding_mode(base64::engine::DecodePaddingMode::Indifferent)
            .with_decode_allow_trailing_bits(true),
    )
}

fn b64_decode(text: &[u8], what: &str) -> Result<Vec<u8>, String> {
    b64()
        .decode(text)
        .map_err(|e| format!("bad base64 in the {what}: {e}"))
}

/// Base64 characters for `n` bytes (padded).
fn b64_chars(n: usize) -> usize {
    n.div_ceil(3).saturating_mul(4)
}

/// The header (`header_bytes` long) and data of a base64 array: separately encoded if the
/// header's own encoding ends there (with padding, or on a 3-byte boundary), else one stream.
fn split_base64(text: &[u8], header_bytes: usize) -> Result<(Vec<u8>, Vec<u8>), String> {
    let c = b64_chars(header_bytes);
    if text.len() < c {
        return Err(format!(
            "the base64 text ends after {} characters, inside the {header_bytes}-byte header",
            text.len()
        ));
    }
    if header_bytes.is_multiple_of(3) || text[c - 1] == b'=' {
        let header = b64_decode(&text[..c], "header")?;
        let data = b64_decode(&text[c..], "data")?;
        Ok((header, data))
    } else {
        let mut all = b64_decode(text, "data")?;
        let data = all.split_off(header_bytes.min(all.len()));
        Ok((all, data))
    }
}

fn header_word(s: &Settings, h: &[u8], k: usize) -> u64 {
    let size = if s.header64 { 8 } else { 4 };
    let mut w = [0u8; 8];
    let chunk = &h[k * size..(k + 1) * size];
    if s.big_endian {
        for (i, b) in chunk.iter().rev().enumerate() {
            w[i] = *b;
        }
    } else {
        w[..size].copy_from_slice(chunk);
    }
    u64::from_le_bytes(w)
}

/// The compressed-block layout from a header.
struct Blocks {
    sizes: Vec<usize>,
    compressed: Vec<usize>,
}

impl Blocks {
    /// Whether the compressed blocks fit in the `available` bytes and each could expand to its
    /// declared size (zlib ≤ ~1032×, lz4 ≤ 255×): only then is room reserved up front.
    fn plausible(&self, c: Compressor, available: usize) -> bool {
        let ratio = match c {
            Compressor::Zlib => 1100,
            Compressor::Lz4 => 260,
            _ => return false,
        };
        self.compressed
            .iter()
            .fold(0usize, |a, &c| a.saturating_add(c))
            <= available
            && self
                .sizes
                .iter()
                .zip(&self.compressed)
                .all(|(&u, &c)| u <= c.saturating_mul(ratio).saturating_add(64))
    }
}

fn block_layout(s: &Settings, h: &[u8], nblocks: usize, want: usize) -> Result<Blocks, String> {
    let bs = header_word(s, h, 1);
    let last = header_word(s, h, 2);
    if nblocks > 0 && (bs == 0 || bs as usize > s.limit || last > bs) {
        return Err(format!(
            "compressed header: block size {bs} and last block size {last} are inconsistent"
        ));
    }
    let mut sizes = vec![bs as usize; nblocks];
    if let Some(l) = sizes.last_mut()
        && last != 0
    {
        *l = last as usize;
    }
    let total: usize = sizes.iter().fold(0usize, |a, &b| a.saturating_add(b));
    if total > s.limit {
        return Err(format!(
            "compressed header declares {total} bytes, more than this file can hold"
        ));
    }
    // Checked before decompressing anything: a wrong size is an error, not an allocation.
    if total < want {
        return Err(format!(
            "the compressed header declares {total} bytes, but the counts need {want}"
        ));
    }
    let compressed = (0..nblocks)
        .map(|k| header_word(s, h, 3 + k) as usize)
        .collect();
    Ok(Blocks { sizes, compressed })
}

fn header_size(s: &Settings) -> usize {
    if s.header64 { 8 } else { 4 }
}

/// Raw appended data starting at an array's offset (`at` = its byte offset in the file).
fn binary_raw(
    s: &Settings,
    app: &[u8],
    at: usize,
    want: usize,
    sink: &mut Sink,
) -> Result<(), String> {
    let hs = header_size(s);
    let short = |what: &str, need: usize, have: usize| {
        format!("the file ends inside the {what}: {need} bytes needed from byte {at}, {have} there")
    };
    if app.len() < hs {
        return Err(short("header", hs, app.len()));
    }
    let first = header_word(s, app, 0);
    if s.compressor == Compressor::None {
        let n = usize::try_from(first).unwrap_or(usize::MAX);
        if n > app.len() - hs {
            return Err(short("data", n, app.len() - hs));
        }
        // Uncompressed raw data are converted straight from the file's bytes.
        sink.reserve(n);
        sink.push(&app[hs..hs + n]);
        return Ok(());
    }
    let nblocks = usize::try_from(first).unwrap_or(usize::MAX);
    let hbytes = nblocks
        .checked_add(3)
        .and_then(|n| n.checked_mul(hs))
        .filter(|&n| n <= app.len())
        .ok_or_else(|| {
            short(
                "compressed-block header",
                (nblocks.saturating_add(3)).saturating_mul(hs),
                app.len(),
            )
        })?;
    let layout = block_layout(s, &app[..hbytes], nblocks, want)?;
    if layout.plausible(s.compressor, app.len() - hbytes) {
        sink.reserve(layout.sizes.iter().sum());
    }
    let mut pos = hbytes;
    let mut out = Vec::new();
    for (k, (&size, &csize)) in layout.sizes.iter().zip(&layout.compressed).enumerate() {
        if csize > app.len() - pos {
            return Err(format!(
                "compressed block {} of {nblocks} at byte {} needs {csize} bytes, but the file ends after {}",
                k + 1,
                at + pos,
                app.len() - pos
            ));
        }
        out.clear();
        decompress(s.compressor, &app[pos..pos + csize], size, &mut out).map_err(|e| {
            format!(
                "compressed block {} of {nblocks} at byte {}: {e}",
                k + 1,
                at + pos
            )
        })?;
        sink.push(&out);
        pos += csize;
    }
    Ok(())
}

/// Base64 text (whitespace removed) of one array.
fn binary_base64(s: &Settings, text: &[u8], want: usize, sink: &mut Sink) -> Result<(), String> {
    let hs = header_size(s);
    if s.compressor == Compressor::None {
        let (h, mut data) = split_base64(text, hs)?;
        if h.len() < hs {
            return Err("the base64 header is too short".into());
        }
        let n = usize::try_from(header_word(s, &h, 0)).unwrap_or(usize::MAX);
        if n > data.len() {
            return Err(format!(
                "the header says {n} bytes, but the base64 data hold only {}",
                data.len()
            ));
        }
        data.truncate(n);
        sink.reserve(n);
        sink.push(&data);
        return Ok(());
    }
    // The first header word (the number of blocks) decides the header's length.
    let c = b64_chars(hs);
    if text.len() < c {
        return Err("the base64 text is too short for a compressed-block header".into());
    }
    let first = b64_decode(&text[..c], "header")?;
    if first.len() < hs {
        return Err("the base64 header is too short".into());
    }
    let nblocks = usize::try_from(header_word(s, &first, 0)).unwrap_or(usize::MAX);
    let hbytes = nblocks
        .checked_add(3)
        .and_then(|n| n.checked_mul(hs))
        .filter(|&n| b64_chars(n) <= text.len())
        .ok_or_else(|| {
            format!(
                "the header declares {nblocks} compressed blocks, more than the base64 text holds"
            )
        })?;
    let (h, data) = split_base64(text, hbytes)?;
    if h.len() < hbytes {
        return Err("the base64 header is too short".into());
    }
    let layout = block_layout(s, &h, nblocks, want)?;
    if layout.plausible(s.compressor, data.len()) {
        sink.reserve(layout.sizes.iter().sum());
    }
    let mut pos = 0usize;
    let mut out = Vec::new();
    for (k, (&size, &csize)) in layout.sizes.iter().zip(&layout.compressed).enumerate() {
        if csize > data.len() - pos {
            return Err(format!(
                "compressed block {} of {nblocks} needs {csize} bytes, but the decoded data end after {}",
                k + 1,
                data.len() - pos
            ));
        }
        out.clear();
        decompress(s.compressor, &data[pos..pos + csize], size, &mut out)
            .map_err(|e| format!("compressed block {} of {nblocks}: {e}", k + 1))?;
        sink.push(&out);
        pos += csize;
    }
    Ok(())
}

/// A writer that refuses to grow past a limit (bounds what a corrupt stream can produce).
struct Limited<'a> {
    out: &'a mut Vec<u8>,
    left: usize,
}

impl std::io::Write for Limited<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if buf.len() > self.left {
            return Err(std::io::Error::other(
                "decompresses to more bytes than declared",
            ));
        }
        self.left -= buf.len();
        self.out.extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Decompresses one block of `size` bytes, appending to `out`.
fn decompress(c: Compressor, src: &[u8], size: usize, out: &mut Vec<u8>) -> Result<(), String> {
    let start = out.len();
    // Neither zlib nor lz4 can expand by more than about 1032× and 255×: a block that claims
    // more is corrupt, and refusing it here keeps allocation proportional to the input.
    let ratio = match c {
        Compressor::Zlib => Some(1100),
        Compressor::Lz4 => Some(260),
        _ => None,
    };
    if let Some(r) = ratio
        && size > src.len().saturating_mul(r).saturating_add(64)
    {
        return Err(format!(
            "{} compressed bytes cannot hold the {size} bytes the header declares",
            src.len()
        ));
    }
    match c {
        Compressor::None => out.extend_from_slice(src),
        Compressor::Zlib => {
            let mut d = flate2::Decompress::new(true);
            out.reserve(size);
            let mut buf = vec![0u8; size];
            let status = d
                .decompress(src, &mut buf, flate2::FlushDecompress::Finish)
                .map_err(|e| format!("corrupt zlib data: {e}"))?;
            let n = d.total_out() as usize;
            if status != flate2::Status::StreamEnd {
                return Err(if n == size {
                    format!("the zlib stream holds more than the {size} bytes declared")
                } else {
                    format!("the zlib stream ends early: {n} of {size} bytes")
                });
            }
            out.extend_from_slice(&buf[..n]);
        }
        Compressor::Lz4 => {
            let mut buf = vec![0u8; size];
            let n = lz4_flex::block::decompress_into(src, &mut buf)
                .map_err(|e| format!("corrupt lz4 data: {e}"))?;
            out.extend_from_slice(&buf[..n]);
        }
        Compressor::Lzma => {
            let mut input = src;
            let mut w = Limited {
                out: &mut *out,
                left: size,
            };
            // lzma-rs 0.3 overflows an addition on a corrupt stream footer (backward size
            // 2^32 − 1; found by fuzzing): a panic in builds with overflow checks, a wrapped
            // value and an error without. A corrupt block is an error here either way.
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                lzma_rs::xz_decompress(&mut input, &mut w)
            }));
            match result {
                Ok(r) => r.map_err(|e| format!("corrupt lzma (xz) data: {e}"))?,
                Err(_) => return Err("corrupt lzma (xz) data: the stream footer is invalid".into()),
            }
        }
    }
    let n = out.len() - start;
    if n != size {
        return Err(format!(
            "decompresses to {n} bytes, but the header declares {size}"
        ));
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Writing

/// One array to write: its XML attributes and little-endian bytes.
struct OutArray {
    name: String,
    ty: &'static str,
    components: usize,
    /// `NumberOfTuples`, written for FieldData arrays.
    tuples: Option<usize>,
    data: Vec<u8>,
}

fn le<T: Copy>(v: &[T], f: impl Fn(T) -> Vec<u8>) -> Vec<u8> {
    v.iter().flat_map(|&x| f(x)).collect()
}

fn values_out(values: &Values) -> (&'static str, Vec<u8>) {
    match values {
        Values::U8(v) => ("UInt8", v.clone()),
        Values::I16(v) => ("Int16", le(v, |x| x.to_le_bytes().to_vec())),
        Values::I32(v) => ("Int32", le(v, |x| x.to_le_bytes().to_vec())),
        Values::F32(v) => ("Float32", le(v, |x| x.to_le_bytes().to_vec())),
        Values::F64(v) => ("Float64", le(v, |x| x.to_le_bytes().to_vec())),
    }
}

fn out_array(a: layout::NamedValues, field_data: bool) -> OutArray {
    let (ty, data) = values_out(&a.values);
    OutArray {
        tuples: field_data.then(|| a.values.len() / a.components.max(1)),
        name: a.name,
        ty,
        components: a.components,
        data,
    }
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\n', "&#10;")
        .replace('\r', "&#13;")
        .replace('\t', "&#9;")
}

/// Writes a volume as `.vtu`: every node data block as a point array and every cell data
/// block as a cell array (named after the first field that uses it), tetrahedra as VTK type
/// 10, and VoRANG's layout ([`layout`]) in `<FieldData>`, so that the file reads back as the
/// identical volume. Nothing is left out, so the warnings are always empty.
pub fn write(vol: &Volume, out: &mut impl std::io::Write) -> std::io::Result<Vec<Warning>> {
    let m = &vol.mesh;
    let points = if vol.coord_type == ScalarType::Float
        && m.nodes()
            .iter()
            .flatten()
            .all(|&c| f64::from(c as f32) == c)
    {
        OutArray {
            name: "Points".into(),
            ty: "Float32",
            components: 3,
            tuples: None,
            data: m
                .nodes()
                .iter()
                .flatten()
                .flat_map(|&c| (c as f32).to_le_bytes())
                .collect(),
        }
    } else {
        OutArray {
            name: "Points".into(),
            ty: "Float64",
            components: 3,
            tuples: None,
            data: m
                .nodes()
                .iter()
                .flatten()
                .flat_map(|c| c.to_le_bytes())
                .collect(),
        }
    };
    let conn = OutArray {
        name: "connectivity".into(),
        ty: "Int64",
        components: 1,
        tuples: None,
        data: m
            .tets()
            .iter()
            .flatten()
            .flat_map(|&n| i64::from(n).to_le_bytes())
            .collect(),
    };
    let offsets = OutArray {
        name: "offsets".into(),
        ty: "Int64",
        components: 1,
        tuples: None,
        data: (1..=m.tet_count() as i64)
            .flat_map(|k| (4 * k).to_le_bytes())
            .collect(),
    };
    let types = OutArray {
        name: "types".into(),
        ty: "UInt8",
        components: 1,
        tuples: None,
        data: vec![cell_type::TETRA; m.tet_count()],
    };
    let parts = layout::parts(vol);
    let point_data: Vec<OutArray> = parts
        .point_arrays
        .into_iter()
        .map(|a| out_array(a, false))
        .collect();
    let cell_data: Vec<OutArray> = parts
        .cell_arrays
        .into_iter()
        .map(|a| out_array(a, false))
        .collect();
    let field_data: Vec<OutArray> = parts
        .field_arrays
        .into_iter()
        .map(|a| out_array(a, true))
        .collect();

    // Compress everything first: the offsets in the XML depend on the compressed sizes.
    let mut blobs: Vec<Vec<u8>> = Vec::new();
    let order: Vec<&OutArray> = field_data
        .iter()
        .chain(point_data.iter())
        .chain(cell_data.iter())
        .chain([&points, &conn, &offsets, &types])
        .collect();
    for a in &order {
        blobs.push(compress_array(&a.data)?);
    }
    let mut offset = 0usize;
    let mut offs = Vec::new();
    for b in &blobs {
        offs.push(offset);
        offset += b.len();
    }
    let decl = |a: &OutArray, off: usize| {
        let comps = if a.components > 1 {
            format!(" NumberOfComponents=\"{}\"", a.components)
        } else {
            String::new()
        };
        let tuples = a
            .tuples
            .map_or(String::new(), |t| format!(" NumberOfTuples=\"{t}\""));
        format!(
            "        <DataArray type=\"{}\" Name=\"{}\"{comps}{tuples} format=\"appended\" offset=\"{off}\"/>\n",
            a.ty,
            xml_escape(&a.name)
        )
    };
    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\"?>\n");
    x.push_str("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n");
    x.push_str("  <UnstructuredGrid>\n");
    let mut k = 0;
    x.push_str("    <FieldData>\n");
    for a in &field_data {
        x.push_str(&decl(a, offs[k]));
        k += 1;
    }
    x.push_str("    </FieldData>\n");
    x.push_str(&format!(
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
        m.node_count(),
        m.tet_count()
    ));
    x.push_str("      <PointData>\n");
    for a in &point_data {
        x.push_str(&decl(a, offs[k]));
        k += 1;
    }
    x.push_str("      </PointData>\n      <CellData>\n");
    for a in &cell_data {
        x.push_str(&decl(a, offs[k]));
        k += 1;
    }
    x.push_str("      </CellData>\n      <Points>\n");
    x.push_str(&decl(&points, offs[k]));
    k += 1;
    x.push_str("      </Points>\n      <Cells>\n");
    for a in [&conn, &offsets, &types] {
        x.push_str(&decl(a, offs[k]));
        k += 1;
    }
    x.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
    x.push_str("  <AppendedData encoding=\"raw\">\n   _");
    out.write_all(x.as_bytes())?;
    for b in &blobs {
        out.write_all(b)?;
    }
    out.write_all(b"\n  </AppendedData>\n</VTKFile>\n")?;
    Ok(Vec::new())
}

/// VTK's block size for compressed arrays.
const BLOCK: usize = 1 << 15;

/// An array as zlib-compressed blocks behind a UInt64 header.
fn compress_array(data: &[u8]) -> std::io::Result<Vec<u8>> {
    let blocks: Vec<&[u8]> = data.chunks(BLOCK).collect();
    let mut compressed = Vec::with_capacity(blocks.len());
    for b in &blocks {
        let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::new(6));
        e.write_all(b)?;
        compressed.push(e.finish()?);
    }
    let mut out = Vec::new();
    let last = blocks.last().map_or(0, |b| b.len());
    for w in [blocks.len(), BLOCK, if last == BLOCK { 0 } else { last }] {
        out.extend_from_slice(&(w as u64).to_le_bytes());
    }
    for c in &compressed {
        out.extend_from_slice(&(c.len() as u64).to_le_bytes());
    }
    for c in compressed {
        out.extend_from_slice(&c);
    }
    Ok(out)
}

/// `save_volume file.vtu` / `vorang convert … file.vtu`, written atomically.
pub fn save(vol: &Volume, path: &Path) -> Result<Vec<Warning>, Error> {
    let mut warnings = Vec::new();
    crate::atomic::write_atomically(path, |w| {
        warnings = write(vol, w)?;
        Ok(())
    })?;
    Ok(warnings)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn information_keys_inside_a_data_array_are_not_data() {
        let text = r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0">
  <UnstructuredGrid>
    <Piece NumberOfPoints="4" NumberOfCells="1">
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii" RangeMin="0" RangeMax="1">
          0 0 0  1 0 0  0 1 0  0 0 1
          <InformationKey name="L2_NORM_RANGE" location="vtkDataArray" length="2">
            <Value index="0">0</Value>
            <Value index="1">1</Value>
          </InformationKey>
        </DataArray>
      </Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">4</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"#;
        let d = read(text.as_bytes(), "info.vtu").unwrap();
        assert_eq!(d.nodes.len(), 4);
        assert_eq!(d.nodes[3], [0.0, 0.0, 1.0]);
        assert_eq!(d.cells.nodes(0), &[0, 1, 2, 3]);
    }

    #[test]
    fn pieces_are_concatenated() {
        let piece = |z: f64, t: f64, id: i32| {
            format!(
                r#"<Piece NumberOfPoints="4" NumberOfCells="1">
      <PointData><DataArray type="Float64" Name="T" format="ascii">{t} {t} {t} {t}</DataArray></PointData>
      <CellData><DataArray type="Int32" Name="id" format="ascii">{id}</DataArray></CellData>
      <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 {z} 1 0 {z} 0 1 {z} 0 0 {}</DataArray></Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">4</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10</DataArray>
      </Cells>
    </Piece>"#,
                z + 1.0
            )
        };
        let text = format!(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n{}\n{}\n</UnstructuredGrid>\n</VTKFile>\n",
            piece(0.0, 1.0, 5),
            piece(5.0, 2.0, 6)
        );
        let d = read(text.as_bytes(), "two.vtu").unwrap();
        assert_eq!(d.nodes.len(), 8);
        assert_eq!(d.cells.nodes(1), &[4, 5, 6, 7]);
        assert_eq!(d.point_arrays[0].values.len(), 8);
        assert_eq!(d.point_arrays[0].values.get(5), 2.0);
        assert_eq!(d.cell_arrays[0].values, ArrayValues::Int(vec![5, 6]));
        let (vol, _) = crate::formats::build::volume(d).unwrap();
        assert_eq!(vol.mesh.tet_count(), 2);
    }

    #[test]
    fn absurd_block_counts_are_errors() {
        // Found by fuzzing: a block count near 2^64 in a base64 header.
        assert_eq!(b64_chars(usize::MAX), usize::MAX);
        let text = b64().encode([0xffu8; 8]);
        let s = Settings {
            name: "x.vtu",
            file: &[],
            big_endian: false,
            header64: true,
            compressor: Compressor::Zlib,
            appended: None,
            offsets: Vec::new(),
            limit: 1 << 20,
        };
        let mut sink = Sink::new(NumType::F64, false, 8);
        assert!(binary_base64(&s, text.as_bytes(), 8, &mut sink).is_err());
    }

    #[test]
    fn header_and_data_in_one_or_two_base64_streams() {
        let header = 8u32.to_le_bytes();
        let data = [1u8, 2, 3, 4, 5, 6, 7, 8];
        let two = [b64().encode(header), b64().encode(data)].concat();
        let one = b64().encode([&header[..], &data[..]].concat());
        for text in [two, one] {
            let (h, d) = split_base64(text.as_bytes(), 4).unwrap();
            assert_eq!(h, header);
            assert_eq!(d, data);
        }
    }

    #[test]
    fn binary_connectivity_out_of_range_names_the_index() {
        let b64arr = |bytes: Vec<u8>| {
            let header = (bytes.len() as u32).to_le_bytes();
            [b64().encode(header), b64().encode(bytes)].concat()
        };
        let points: Vec<u8> = [0.0f64, 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        for (bad, shown) in [(-1i64, "-1"), (1 << 40, "1099511627776"), (4, "4")] {
            let conn: Vec<u8> = [0i64, 1, 2, bad]
                .iter()
                .flat_map(|x| x.to_le_bytes())
                .collect();
            let text = format!(
                r#"<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="4" NumberOfCells="1">
<Points><DataArray type="Float64" NumberOfComponents="3" format="binary">{}</DataArray></Points>
<Cells><DataArray type="Int64" Name="connectivity" format="binary">{}</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">4</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">10</DataArray></Cells>
</Piece></UnstructuredGrid></VTKFile>"#,
                b64arr(points.clone()),
                b64arr(conn)
            );
            let e = read(text.as_bytes(), "c.vtu").unwrap_err();
            assert_eq!(e.line, 3, "{e}");
            assert!(
                e.message.contains(&format!(
                    "cell 1 refers to point {shown}, but the piece has 4"
                )),
                "{e}"
            );
        }
    }
}
