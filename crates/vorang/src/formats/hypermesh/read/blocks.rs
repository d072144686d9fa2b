//! Reading a file's text: the title and the header, then the data blocks in the order the file
//! gives them, each found by its `@marker` line and read as ASCII rows or BINARY data. Kept
//! apart from resolving (`geometry`, `data`) because only this phase touches the input: it
//! reads the file once, front to back, and hands on values, never bytes.

use std::collections::HashMap;
use std::io::BufRead;

use super::super::ascii::{self, BlockInfo, marker_line};
use super::super::binary;
use super::super::header::{
    BlockDecl, Encoding, Header, HeaderParser, Target, is_marker_char, parse_title,
};
use super::super::input::Input;
use super::{Block, Blocks};
use crate::data::ElementKind;
use crate::error::ParseError;
use crate::field::Interpolator;

/// A marker line's text and line number, read but not yet parsed.
type Pending = Option<(Vec<u8>, usize)>;

pub(super) fn read_blocks<R: BufRead>(
    input: &mut Input<R>,
    file: &str,
) -> Result<Blocks, ParseError> {
    let (header, mut pending) = read_header(input, file)?;
    let field_blocks = resolve_field_markers(file, &header)?;
    let counts: Vec<usize> = header
        .blocks
        .iter()
        .map(|d| block_count(file, &header, d))
        .collect::<Result<_, _>>()?;
    let by_marker: HashMap<&str, usize> = header
        .blocks
        .iter()
        .enumerate()
        .map(|(i, b)| (b.marker.as_str(), i))
        .collect();
    let mut blocks: Vec<Option<Block>> = (0..header.blocks.len()).map(|_| None).collect();

    while let Some((text, line)) = pending.take() {
        let marker = parse_marker_line(file, &text, line)?;
        let Some(&i) = by_marker.get(marker.as_str()) else {
            return Err(undeclared(file, &header, &marker, line));
        };
        if let Some(prev) = &blocks[i] {
            return Err(ParseError::new(
                file,
                line,
                format!(
                    "block @{marker} appears twice (first on line {})",
                    prev.marker_line
                ),
            ));
        }
        let (block, next) = read_block(input, file, &header, i, counts[i], line)?;
        pending = next;
        blocks[i] = Some(block);
    }
    for (d, b) in header.blocks.iter().zip(&blocks) {
        if b.is_none() {
            return Err(ParseError::new(
                file,
                d.line,
                format!(
                    "block @{} is declared here but never appears in the file",
                    d.marker
                ),
            ));
        }
    }
    Ok((header, blocks, field_blocks))
}

/// The title line and the header lines, up to the first marker line (returned, unparsed).
fn read_header<R: BufRead>(
    input: &mut Input<R>,
    file: &str,
) -> Result<(Header, Pending), ParseError> {
    let io_err = |line: usize, e: std::io::Error| {
        ParseError::new(file, line.max(1), format!("read error: {e}"))
    };
    let title = match input.next_line() {
        Ok(Some((_, l))) => l.to_vec(),
        Ok(None) => {
            return Err(ParseError::new(
                file,
                1,
                "empty file: expected the title line '# HyperMesh 3D ASCII 0.7'",
            ));
        }
        Err(e) => return Err(io_err(1, e)),
    };
    let (encoding, version) = parse_title(file, &title)?;
    let mut parser = HeaderParser::new(file);
    let mut pending = None;
    loop {
        match input.next_line() {
            Ok(Some((n, line))) => {
                if let Some(m) = marker_line(line) {
                    pending = Some((m.to_vec(), n));
                    break;
                }
                parser.push_line(n, line)?;
            }
            Ok(None) => break,
            Err(e) => return Err(io_err(input.line + 1, e)),
        }
    }
    Ok((parser.finish(encoding, version)?, pending))
}

/// The message for a marker line that names no declared block.
fn undeclared(file: &str, header: &Header, marker: &str, line: usize) -> ParseError {
    let mut known: Vec<String> = header
        .blocks
        .iter()
        .map(|b| format!("@{}", b.marker))
        .collect();
    known.sort();
    ParseError::new(
        file,
        line,
        format!(
            "block @{marker} is not declared in the header (declared: {})",
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        ),
    )
}

/// Block `i` of the header (`count` rows), whose marker line is `line`, and the marker line
/// that follows it.
fn read_block<R: BufRead>(
    input: &mut Input<R>,
    file: &str,
    header: &Header,
    i: usize,
    count: usize,
    line: usize,
) -> Result<(Block, Pending), ParseError> {
    let decl = &header.blocks[i];
    let what = decl.target.describe();
    let kind = decl.target.element_kind();
    let info = BlockInfo {
        file,
        marker: &decl.marker,
        marker_line: line,
        what: &what,
        count_keyword: kind.count_keyword(),
    };
    Ok(match header.encoding {
        Encoding::Ascii => {
            let b = ascii::read_block(input, &info, decl.ty, count)?;
            let block = Block {
                values: b.values,
                rows: Some(b.rows),
                marker_line: line,
            };
            (block, b.next_marker)
        }
        Encoding::Binary => {
            let values = binary::read_block(input, &info, decl.ty, count)?;
            let next = next_binary_marker(input, file, &decl.marker)?;
            let block = Block {
                values,
                rows: None,
                marker_line: line,
            };
            (block, next)
        }
    })
}

/// For every `Field` line: its interpolator and the declaration index of each marker. Checked
/// before any block is read, so a wrong name fails at once.
pub(super) fn resolve_field_markers(
    file: &str,
    header: &Header,
) -> Result<Vec<(Interpolator, Vec<usize>)>, ParseError> {
    header
        .fields
        .iter()
        .map(|f| {
            let err = |msg: String| ParseError::new(file, f.line, msg);
            let Some(interp) = Interpolator::from_name(&f.interpolator) else {
                return Err(err(format!(
                    "unknown interpolator '{}': expected one of {}",
                    f.interpolator,
                    Interpolator::names()
                )));
            };
            let info = interp.info();
            let mut decls = Vec::with_capacity(f.markers.len());
            for (k, m) in f.markers.iter().enumerate() {
                let want = info.required.iter().chain(info.optional).nth(k).map_or("raw data", |w| w.data_keyword());
                match header.blocks.iter().position(|b| &b.marker == m) {
                    None => return Err(err(format!("marker @{m} is not declared in the header ({} needs {want})", info.name))),
                    Some(i) if !matches!(header.blocks[i].target, Target::Data(_)) => {
                        return Err(err(format!(
                            "{} needs {want} for marker {}, but @{m} is a {} block (geometry, not raw data)",
                            info.name,
                            k + 1,
                            header.blocks[i].target.describe()
                        )));
                    }
                    Some(i) => decls.push(i),
                }
            }
            Ok((interp, decls))
        })
        .collect()
}

/// The number of rows a declared block must have.
pub(super) fn block_count(file: &str, header: &Header, d: &BlockDecl) -> Result<usize, ParseError> {
    let kind = d.target.element_kind();
    match header.count(kind) {
        Some(c) => Ok(c.value),
        // nExtra defaults to 1 (thesis B.2).
        None if kind == ElementKind::Extra => Ok(1),
        None => Err(ParseError::new(
            file,
            d.line,
            format!(
                "{} needs the count '{} = …' in the header",
                d.target.describe(),
                kind.count_keyword()
            ),
        )),
    }
}

/// `@name` followed by nothing but whitespace or a comment.
fn parse_marker_line(file: &str, text: &[u8], line: usize) -> Result<String, ParseError> {
    let body = &text[1..];
    let len = body.iter().take_while(|&&b| is_marker_char(b)).count();
    let rest = &body[len..];
    let rest_ok = rest
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .is_none_or(|i| rest[i] == b'#');
    if len == 0 || !rest_ok {
        return Err(ParseError::new(
            file,
            line,
            format!(
                "expected a marker line such as '@1', found '{}'",
                String::from_utf8_lossy(&text[..text.len().min(40)])
            ),
        ));
    }
    Ok(String::from_utf8_lossy(&body[..len]).into_owned())
}

/// After a BINARY block: skip blank and comment lines, return the next marker line, if any.
fn next_binary_marker<R: BufRead>(
    input: &mut Input<R>,
    file: &str,
    after: &str,
) -> Result<Option<(Vec<u8>, usize)>, ParseError> {
    loop {
        let next = input.line + 1;
        let line = input
            .next_line()
            .map_err(|e| ParseError::new(file, next, format!("read error: {e}")))?;
        let Some((n, line)) = line else {
            return Ok(None);
        };
        if let Some(m) = marker_line(line) {
            return Ok(Some((m.to_vec(), n)));
        }
        let blank = line
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .is_none_or(|i| line[i] == b'#');
        if !blank {
            return Err(ParseError::new(
                file,
                n,
                format!(
                    "expected the next '@marker' line after binary block @{after}, found other bytes (does the block's count match its data?)"
                ),
            ));
        }
    }
}
