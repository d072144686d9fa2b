//! The XML walk: the first phase of reading a `.vtu` file. It goes through the XML part once
//! and collects what the file declares — the file-wide settings of `<VTKFile>` (byte order,
//! header type, compressor), the `<Piece>` counts and every `<DataArray>` with the place of its
//! inline content — and finds where the appended data lie. Nothing is decoded here: keeping
//! the walk apart from decoding lets every declaration be checked (and a bad attribute
//! reported on its own line) before any array, possibly gigabytes, is touched.

use quick_xml::events::{BytesStart, Event};

use super::super::line_of;
use super::compress::Compressor;
use crate::error::ParseError;

/// The numeric types of `DataArray type="…"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum NumType {
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
    pub(super) fn parse(s: &str) -> Option<NumType> {
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

    pub(super) fn size(self) -> usize {
        match self {
            NumType::I8 | NumType::U8 => 1,
            NumType::I16 | NumType::U16 => 2,
            NumType::I32 | NumType::U32 | NumType::F32 => 4,
            NumType::I64 | NumType::U64 | NumType::F64 => 8,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Section {
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
pub(super) struct Decl {
    pub(super) section: Section,
    pub(super) piece: usize,
    pub(super) name: String,
    pub(super) ty: NumType,
    pub(super) components: usize,
    pub(super) format: DataFormat,
    /// `NumberOfTuples` (FieldData arrays say how long they are).
    pub(super) tuples: Option<usize>,
    pub(super) line: usize,
    /// Inline content (ascii numbers or base64 text), as places in the file: a large inline
    /// array is never copied before it is decoded.
    pub(super) text: Vec<TextPart>,
}

/// A piece of a `DataArray`'s inline content.
#[derive(Debug)]
pub(super) enum TextPart {
    /// Bytes `start..end` of the file.
    At(usize, usize),
    /// Content the XML reader did not borrow from the file (not expected; kept for safety).
    Owned(Vec<u8>),
}

impl TextPart {
    /// The part of `t` (content of an event borrowed from `file`).
    pub(super) fn of(t: &[u8], file: &[u8]) -> TextPart {
        let start = (t.as_ptr() as usize).wrapping_sub(file.as_ptr() as usize);
        if start <= file.len() && t.len() <= file.len() - start {
            TextPart::At(start, start + t.len())
        } else {
            TextPart::Owned(t.to_vec())
        }
    }
}

/// The inline content of `d`: borrowed from the file when it is one piece (the usual case).
pub(super) fn decl_text<'a>(s: &Settings<'a>, d: &'a Decl) -> std::borrow::Cow<'a, [u8]> {
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
pub(super) enum DataFormat {
    Ascii,
    Binary,
    Appended(u64),
}

/// File-wide settings from `<VTKFile …>` and `<AppendedData …>`.
pub(super) struct Settings<'a> {
    pub(super) name: &'a str,
    /// The whole file (inline array contents are places in it).
    pub(super) file: &'a [u8],
    pub(super) big_endian: bool,
    pub(super) header64: bool,
    pub(super) compressor: Compressor,
    /// `<VTKFile version="major.minor">` ((0, 0) when absent): files before 2.1 list
    /// Lagrange hexahedra in VTK 8's node order.
    pub(super) version: (u32, u32),
    /// The appended data after the `_` (raw bytes, or base64 text without the closing tag).
    pub(super) appended: Option<(&'a [u8], usize, bool)>,
    /// Offsets of all appended arrays, sorted (to find where a base64 chunk ends).
    pub(super) offsets: Vec<u64>,
    /// Upper bound on any decoded size.
    pub(super) limit: usize,
}

pub(super) struct Piece {
    pub(super) points: usize,
    pub(super) cells: usize,
    pub(super) line: usize,
}

fn attr(e: &BytesStart, key: &[u8]) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == key)
        .map(|a| crate::formats::text::xml_value(&a))
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn rfind(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).rposition(|w| w == needle)
}

/// What the XML part declares, with the settings that decoding needs.
pub(super) struct Document<'a> {
    pub(super) settings: Settings<'a>,
    pub(super) decls: Vec<Decl>,
    pub(super) pieces: Vec<Piece>,
}

/// Walks the XML part of `bytes` and locates the appended data.
pub(super) fn parse<'a>(bytes: &'a [u8], name: &'a str) -> Result<Document<'a>, ParseError> {
    let (xml_end, appended_tag) = xml_end(bytes, name)?;
    let walk = Walk::new(bytes, name).run(xml_end)?;
    walk.check_complete()?;
    let appended = match appended_tag {
        Some(_) => Some(appended_data(bytes, name, xml_end, walk.appended_raw)?),
        None => None,
    };
    let offsets = appended_offsets(&walk.decls);
    let settings = Settings {
        name,
        file: bytes,
        big_endian: walk.big_endian,
        header64: walk.header64,
        compressor: walk.compressor,
        version: walk.version,
        appended,
        offsets,
        limit: bytes.len().saturating_mul(1100).saturating_add(1 << 20),
    };
    Ok(Document {
        settings,
        decls: walk.decls,
        pieces: walk.pieces,
    })
}

/// Where the XML part ends — after the `<AppendedData …>` start tag, if there is one, since
/// raw appended data are not XML — and where that tag starts.
fn xml_end(bytes: &[u8], name: &str) -> Result<(usize, Option<usize>), ParseError> {
    match find(bytes, b"<AppendedData") {
        Some(p) => {
            let close = bytes[p..]
                .iter()
                .position(|&b| b == b'>')
                .map(|k| p + k + 1)
                .ok_or_else(|| {
                    ParseError::new(
                        name,
                        line_of(bytes, p),
                        "<AppendedData is not closed by '>'",
                    )
                })?;
            Ok((close, Some(p)))
        }
        None => Ok((bytes.len(), None)),
    }
}

/// The state of the walk: what has been declared so far and where in the document it is.
struct Walk<'a> {
    bytes: &'a [u8],
    name: &'a str,
    decls: Vec<Decl>,
    pieces: Vec<Piece>,
    section: Section,
    /// The `<DataArray>` whose content is being read.
    current: Option<Decl>,
    /// Depth of elements inside the current `<DataArray>`.
    nested: usize,
    saw_vtkfile: bool,
    big_endian: bool,
    header64: bool,
    compressor: Compressor,
    version: (u32, u32),
    appended_raw: bool,
    /// Whether the XML was complete: `</VTKFile>` seen, or the appended data reached.
    complete: bool,
}

impl<'a> Walk<'a> {
    fn new(bytes: &'a [u8], name: &'a str) -> Self {
        Walk {
            bytes,
            name,
            decls: Vec::new(),
            pieces: Vec::new(),
            section: Section::Other,
            current: None,
            nested: 0,
            saw_vtkfile: false,
            big_endian: false,
            header64: false,
            compressor: Compressor::None,
            version: (0, 0),
            appended_raw: true,
            complete: false,
        }
    }

    fn err(&self, pos: usize, msg: String) -> ParseError {
        ParseError::new(self.name, line_of(self.bytes, pos), msg)
    }

    /// Reads every event of the XML part (`bytes[..xml_end]`).
    fn run(mut self, xml_end: usize) -> Result<Self, ParseError> {
        let bytes = self.bytes;
        let mut reader = quick_xml::Reader::from_reader(&bytes[..xml_end]);
        reader.config_mut().check_end_names = false;
        loop {
            let pos = reader.buffer_position() as usize;
            let ev = reader.read_event().map_err(|e| {
                self.err(
                    reader.error_position() as usize,
                    format!("malformed XML: {e}"),
                )
            })?;
            match ev {
                Event::Eof => break,
                Event::Start(_) | Event::Empty(_) if self.current.is_some() => {
                    // Elements inside a DataArray (VTK's <InformationKey>, ranges): their text is
                    // not the array's data.
                    if matches!(ev, Event::Start(_)) {
                        self.nested += 1;
                    }
                }
                Event::Start(ref e) => self.start(e, false, pos)?,
                Event::Empty(ref e) => self.start(e, true, pos)?,
                Event::Text(t) => self.text(&t),
                Event::CData(t) => self.text(&t),
                Event::End(_) if self.nested > 0 => self.nested -= 1,
                Event::End(e) => self.end(e.name().as_ref()),
                _ => {}
            }
        }
        Ok(self)
    }

    /// A start tag (`empty` for `<…/>`) at byte `pos`.
    fn start(&mut self, e: &BytesStart, empty: bool, pos: usize) -> Result<(), ParseError> {
        match e.name().as_ref() {
            b"VTKFile" => self.vtk_file(e, pos)?,
            b"Piece" => self.piece(e, pos)?,
            b"PointData" if !empty => self.section = Section::PointData,
            b"CellData" if !empty => self.section = Section::CellData,
            b"Points" if !empty => self.section = Section::Points,
            b"Cells" if !empty => self.section = Section::Cells,
            b"FieldData" if !empty => self.section = Section::FieldData,
            b"DataArray" => {
                let d = self.data_array(e, pos)?;
                if empty {
                    self.decls.push(d);
                } else {
                    self.current = Some(d);
                }
            }
            b"AppendedData" => {
                self.complete = true;
                self.appended_raw = appended_encoding(e).map_err(|m| self.err(pos, m))?;
            }
            _ => {}
        }
        Ok(())
    }

    /// Text or CDATA: part of the current array's content unless inside a nested element.
    fn text(&mut self, t: &[u8]) {
        if let (Some(d), 0) = (&mut self.current, self.nested) {
            d.text.push(TextPart::of(t, self.bytes));
        }
    }

    fn end(&mut self, tag: &[u8]) {
        match tag {
            b"DataArray" => {
                if let Some(d) = self.current.take() {
                    self.decls.push(d);
                }
            }
            b"PointData" | b"CellData" | b"Points" | b"Cells" | b"FieldData" => {
                self.section = Section::Other
            }
            b"VTKFile" => self.complete = true,
            _ => {}
        }
    }

    /// `<VTKFile type=… byte_order=… header_type=… compressor=…>`.
    fn vtk_file(&mut self, e: &BytesStart, pos: usize) -> Result<(), ParseError> {
        self.saw_vtkfile = true;
        let ty = attr(e, b"type").unwrap_or_default();
        if ty != "UnstructuredGrid" {
            return Err(self.err(
                pos,
                format!(
                    "VTKFile type=\"{ty}\": VoRANG reads only type=\"UnstructuredGrid\" (.vtu)"
                ),
            ));
        }
        self.big_endian = byte_order(e).map_err(|m| self.err(pos, m))?;
        self.header64 = header_type(e).map_err(|m| self.err(pos, m))?;
        self.compressor = compressor(e).map_err(|m| self.err(pos, m))?;
        self.version = file_version(e);
        Ok(())
    }

    /// `<Piece NumberOfPoints=… NumberOfCells=…>`.
    fn piece(&mut self, e: &BytesStart, pos: usize) -> Result<(), ParseError> {
        let count = |k: &[u8]| -> Result<usize, ParseError> {
            let v = attr(e, k).ok_or_else(|| {
                self.err(
                    pos,
                    format!("<Piece> needs {}=\"…\"", String::from_utf8_lossy(k)),
                )
            })?;
            v.trim().parse::<usize>().map_err(|_| {
                self.err(
                    pos,
                    format!(
                        "{}=\"{v}\": expected a whole number ≥ 0",
                        String::from_utf8_lossy(k)
                    ),
                )
            })
        };
        let piece = Piece {
            points: count(b"NumberOfPoints")?,
            cells: count(b"NumberOfCells")?,
            line: line_of(self.bytes, pos),
        };
        self.pieces.push(piece);
        Ok(())
    }

    /// A `<DataArray …>` declaration, in the current section and piece.
    fn data_array(&self, e: &BytesStart, pos: usize) -> Result<Decl, ParseError> {
        let line = line_of(self.bytes, pos);
        let ty_s = attr(e, b"type").unwrap_or_default();
        let ty = NumType::parse(&ty_s).ok_or_else(|| {
            self.err(
                pos,
                format!(
                    "DataArray type=\"{ty_s}\": expected Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32 or Float64"
                ),
            )
        })?;
        let components = match attr(e, b"NumberOfComponents") {
            None => 1,
            Some(c) => c
                .trim()
                .parse::<usize>()
                .ok()
                .filter(|&c| (1..=64).contains(&c))
                .ok_or_else(|| {
                    self.err(
                        pos,
                        format!("NumberOfComponents=\"{c}\": expected a whole number 1…64"),
                    )
                })?,
        };
        let format = data_format(e).map_err(|m| self.err(pos, m))?;
        Ok(Decl {
            section: self.section,
            piece: self.pieces.len().saturating_sub(1),
            name: attr(e, b"Name").unwrap_or_default(),
            ty,
            components,
            format,
            tuples: attr(e, b"NumberOfTuples").and_then(|t| t.trim().parse::<usize>().ok()),
            line,
            text: Vec::new(),
        })
    }

    /// The checks once the walk is over: a `<VTKFile>`, not cut off, with at least one piece.
    fn check_complete(&self) -> Result<(), ParseError> {
        if !self.saw_vtkfile {
            return Err(ParseError::new(
                self.name,
                1,
                "expected a VTK XML file starting with <VTKFile type=\"UnstructuredGrid\" …>",
            ));
        }
        if !self.complete {
            return Err(self.err(
                self.bytes.len(),
                format!(
                    "the file ends at byte {} before </VTKFile>: it is truncated",
                    self.bytes.len()
                ),
            ));
        }
        if self.pieces.is_empty() {
            return Err(ParseError::new(
                self.name,
                1,
                "no <Piece NumberOfPoints=… NumberOfCells=…> in this file",
            ));
        }
        Ok(())
    }
}

/// `byte_order`: whether the file is big-endian.
fn byte_order(e: &BytesStart) -> Result<bool, String> {
    match attr(e, b"byte_order").as_deref() {
        None | Some("LittleEndian") => Ok(false),
        Some("BigEndian") => Ok(true),
        Some(o) => Err(format!(
            "byte_order=\"{o}\": expected LittleEndian or BigEndian"
        )),
    }
}

/// `version="major.minor"`; (0, 0) when absent or not two numbers (VTK reads such files as
/// old ones too).
fn file_version(e: &BytesStart) -> (u32, u32) {
    let v = attr(e, b"version").unwrap_or_default();
    let mut parts = v.trim().splitn(2, '.').map(|x| x.parse::<u32>().ok());
    match (parts.next().flatten(), parts.next().flatten()) {
        (Some(major), minor) => (major, minor.unwrap_or(0)),
        _ => (0, 0),
    }
}

/// `header_type`: whether binary headers are 64-bit words.
fn header_type(e: &BytesStart) -> Result<bool, String> {
    match attr(e, b"header_type").as_deref() {
        None | Some("UInt32") => Ok(false),
        Some("UInt64") => Ok(true),
        Some(h) => Err(format!("header_type=\"{h}\": expected UInt32 or UInt64")),
    }
}

fn compressor(e: &BytesStart) -> Result<Compressor, String> {
    match attr(e, b"compressor").as_deref() {
        None | Some("") => Ok(Compressor::None),
        Some("vtkZLibDataCompressor") => Ok(Compressor::Zlib),
        Some("vtkLZ4DataCompressor") => Ok(Compressor::Lz4),
        Some("vtkLZMADataCompressor") => Ok(Compressor::Lzma),
        Some(c) => Err(format!(
            "compressor=\"{c}\": expected vtkZLibDataCompressor, vtkLZ4DataCompressor or vtkLZMADataCompressor"
        )),
    }
}

/// A `DataArray`'s `format` (and `offset`, for appended data).
fn data_format(e: &BytesStart) -> Result<DataFormat, String> {
    match attr(e, b"format").as_deref() {
        Some("ascii") => Ok(DataFormat::Ascii),
        Some("binary") => Ok(DataFormat::Binary),
        Some("appended") => {
            let o = attr(e, b"offset").unwrap_or_default();
            o.trim().parse::<u64>().map(DataFormat::Appended).map_err(|_| {
                format!(
                    "DataArray format=\"appended\" needs offset=\"<bytes>\", found offset=\"{o}\""
                )
            })
        }
        other => Err(format!(
            "DataArray format=\"{}\": expected ascii, binary or appended",
            other.unwrap_or("")
        )),
    }
}

/// `<AppendedData encoding=…>`: whether the data are raw (else base64).
fn appended_encoding(e: &BytesStart) -> Result<bool, String> {
    match attr(e, b"encoding").as_deref() {
        None | Some("raw") => Ok(true),
        Some("base64") => Ok(false),
        Some(x) => Err(format!(
            "AppendedData encoding=\"{x}\": expected raw or base64"
        )),
    }
}

/// The appended data: after the '_' that follows the AppendedData start tag (which ends at
/// `xml_end`), up to the end of the file (raw) or to `</AppendedData>` (base64), in the form
/// that `Settings::appended` keeps them.
fn appended_data<'a>(
    bytes: &'a [u8],
    name: &str,
    xml_end: usize,
    raw: bool,
) -> Result<(&'a [u8], usize, bool), ParseError> {
    let err = |pos: usize, msg: String| ParseError::new(name, line_of(bytes, pos), msg);
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
    let end = if raw {
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
    Ok((&bytes[start..end], start, raw))
}

/// The offsets of all appended arrays, sorted and without repeats.
fn appended_offsets(decls: &[Decl]) -> Vec<u64> {
    let mut offsets: Vec<u64> = decls
        .iter()
        .filter_map(|d| match d.format {
            DataFormat::Appended(o) => Some(o),
            _ => None,
        })
        .collect();
    offsets.sort_unstable();
    offsets.dedup();
    offsets
}
