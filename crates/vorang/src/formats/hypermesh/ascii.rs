//! ASCII data blocks: one element per line, its numbers separated by whitespace (thesis B.2
//! "Datensektion"); blank lines and `#` comments are skipped; a block runs to the next `@marker`
//! line or the end of the file.

use std::io::{self, BufRead, Write};

use super::batch;
use super::input::Input;
pub use super::row::RowLines;
use super::row::{AsciiNumber, Line, RowError, classify, parse_row};
use crate::data::{DataType, Values};
use crate::error::ParseError;

/// What the rows of a block turned into, and where the block ended.
pub struct AsciiBlock {
    pub values: Values,
    pub rows: RowLines,
    /// The `@marker` line that ended the block (its text and line), if any.
    pub next_marker: Option<(Vec<u8>, usize)>,
}

/// Identifies a block in messages.
pub struct BlockInfo<'a> {
    pub file: &'a str,
    pub marker: &'a str,
    pub marker_line: usize,
    /// e.g. `Tetrahedra by Nodes`, for messages.
    pub what: &'a str,
    /// The count keyword that sets the number of rows (e.g. `nTetrahedra`).
    pub count_keyword: &'a str,
}

/// If `line` (ignoring leading whitespace) starts with `@`, returns the trimmed text.
pub fn marker_line(line: &[u8]) -> Option<&[u8]> {
    match classify(line) {
        Line::Marker(m) => Some(m),
        _ => None,
    }
}

/// Reads the rows of one ASCII block: exactly `count` elements of type `ty`.
pub fn read_block<R: BufRead>(
    input: &mut Input<R>,
    info: &BlockInfo,
    ty: DataType,
    count: usize,
) -> Result<AsciiBlock, ParseError> {
    let numbers = ty.numbers();
    // Every number takes at least two bytes (a digit and a separator): never reserve more than
    // the rest of the file could hold.
    let bound = input.remaining().map_or(1 << 16, |r| (r / 2) as usize);
    let capacity = count.saturating_mul(numbers).min(bound);
    let mut values = Values::with_capacity(ty.scalar, capacity);
    let mut rows = RowLines::default();
    let mut n_rows = 0usize;
    // One reader per number type: the rows go straight into the typed vector.
    macro_rules! rows_of {
        ($v:expr) => {
            rows_into(
                input,
                &mut Block {
                    info,
                    ty,
                    count,
                    out: $v,
                    rows: &mut rows,
                    n_rows: &mut n_rows,
                },
            )
        };
    }
    let next_marker = match &mut values {
        Values::U8(v) => rows_of!(v),
        Values::I16(v) => rows_of!(v),
        Values::I32(v) => rows_of!(v),
        Values::F32(v) => rows_of!(v),
        Values::F64(v) => rows_of!(v),
    }?;
    if n_rows < count {
        return Err(ParseError::new(
            info.file,
            info.marker_line,
            format!(
                "block @{} ({}) has {n_rows} rows, expected {count} ({} = {count})",
                info.marker, info.what, info.count_keyword
            ),
        ));
    }
    Ok(AsciiBlock {
        values,
        rows,
        next_marker,
    })
}

/// The most bytes of rows parsed as one batch: a few dozen pieces, so every core is busy and a
/// batch that runs past its block's end wastes little.
const BATCH: usize = 1 << 20;

/// The rows of a block go in batches of whole lines straight from the reader's buffer, parsed
/// on every core ([`batch`]); a line the buffer does not hold whole goes through
/// [`Input::next_line`]. Both meet the same rows, markers and errors in the same order.
fn rows_into<R: BufRead, T: AsciiNumber>(
    input: &mut Input<R>,
    b: &mut Block<T>,
) -> Result<Option<(Vec<u8>, usize)>, ParseError> {
    let Block {
        info, ty, count, ..
    } = *b;
    let numbers = ty.numbers();
    let io_err =
        |e: io::Error| ParseError::new(info.file, info.marker_line, format!("read error: {e}"));
    let mut block_bytes = 0usize;
    loop {
        // Near the block's end a batch is kept to about the rows still expected, so that little
        // of the next block is parsed in vain: by the bytes per row so far, or generously (24
        // bytes per number) before the first row.
        let left = count.saturating_sub(*b.n_rows).max(1);
        let per_row = match *b.n_rows {
            0 => numbers.max(1) * 24,
            n => block_bytes / n + 1,
        };
        let cap = left.saturating_mul(per_row).saturating_add(4096).min(BATCH);
        let step = input
            .with_lines(cap, |text, first_line| {
                let pieces = batch::parse_lines::<T>(text, numbers);
                join(pieces, first_line, b)
            })
            .map_err(io_err)?;
        match step {
            Some((Joined::More, bytes)) => block_bytes += bytes,
            Some((Joined::End(end), _)) => return end,
            None => {
                let Some((line_no, line)) = input.next_line().map_err(io_err)? else {
                    return Ok(None);
                };
                block_bytes += line.len() + 1;
                match classify(line) {
                    Line::Marker(m) => return Ok(Some((m.to_vec(), line_no))),
                    Line::Blank => {}
                    Line::Row => {
                        if *b.n_rows == count {
                            return Err(extra_row(info, count, line_no));
                        }
                        parse_row(line, numbers, b.out)
                            .map_err(|e| row_error(info, ty, line_no, *b.n_rows + 1, e))?;
                        b.rows.push(*b.n_rows, line_no);
                        *b.n_rows += 1;
                    }
                }
            }
        }
    }
}

/// A block being read: what it is, and its rows so far.
struct Block<'a, T> {
    info: &'a BlockInfo<'a>,
    ty: DataType,
    count: usize,
    out: &'a mut Vec<T>,
    rows: &'a mut RowLines,
    n_rows: &'a mut usize,
}

/// Whether the block goes on after a batch, or how it ended.
enum Joined {
    More,
    End(Result<Option<(Vec<u8>, usize)>, ParseError>),
}

/// Joins a batch's pieces in file order onto the block: their values and rows, up to the first
/// marker or error. Returns the outcome with the bytes and lines used.
fn join<T: AsciiNumber>(
    pieces: Vec<batch::Piece<T>>,
    first_line: usize,
    b: &mut Block<T>,
) -> (Joined, usize, usize) {
    let Block {
        info, ty, count, ..
    } = *b;
    let (out, rows, n_rows) = (&mut *b.out, &mut *b.rows, &mut *b.n_rows);
    let (mut bytes, mut lines) = (0, 0);
    for mut p in pieces {
        let base = first_line + lines;
        // A row beyond the count is an error at that row, before anything after it.
        let room = count - *n_rows;
        let extra = if p.n_rows > room {
            p.rows.line_of(room)
        } else {
            match &p.stop {
                Some(batch::Stop::Row { line, row, .. }) if *row >= room => Some(*line),
                _ => None,
            }
        };
        if let Some(line) = extra {
            let e = Err(extra_row(info, count, base + line));
            return (Joined::End(e), bytes, lines);
        }
        out.append(&mut p.values);
        rows.append_shifted(&p.rows, *n_rows, base);
        let before = *n_rows;
        *n_rows += p.n_rows;
        bytes += p.bytes;
        lines += p.lines;
        match p.stop {
            None => {}
            Some(batch::Stop::Marker { line, text }) => {
                let end = Joined::End(Ok(Some((text, base + line))));
                return (end, bytes, lines);
            }
            Some(batch::Stop::Row { line, row, error }) => {
                let e = row_error(info, ty, base + line, before + row + 1, error);
                return (Joined::End(Err(e)), bytes, lines);
            }
        }
    }
    (Joined::More, bytes, lines)
}

fn extra_row(info: &BlockInfo, count: usize, line: usize) -> ParseError {
    ParseError::new(
        info.file,
        info.marker_line,
        format!(
            "block @{} ({}) has more than {count} rows ({} = {count}); the extra row is on line {line}",
            info.marker, info.what, info.count_keyword
        ),
    )
}

/// The message for a refused row (`row` counts from 1).
fn row_error(info: &BlockInfo, ty: DataType, line: usize, row: usize, e: RowError) -> ParseError {
    let noun = element_noun(info.what);
    let msg = match e {
        RowError::Number(msg) => format!("{noun} {row} of block @{}: {msg}", info.marker),
        RowError::Count(found) => {
            let numbers = ty.numbers();
            format!(
                "{noun} {row} of block @{}: expected {numbers} number{} ({ty}), found {found}",
                info.marker,
                if numbers == 1 { "" } else { "s" },
            )
        }
    };
    ParseError::new(info.file, line, msg)
}

/// `Tetrahedra by Nodes` → `tetrahedron`, for row messages.
pub fn element_noun(what: &str) -> &'static str {
    let w = what.split_whitespace().next().unwrap_or("");
    match w {
        "Nodes" | "NodeData" => "node",
        "Edges" | "EdgeData" => "edge",
        "Triangles" | "TriangleData" => "triangle",
        "Tetrahedra" | "TetrahedronData" => "tetrahedron",
        _ => "element",
    }
}

/// Writes the values of a block as ASCII rows of `numbers` numbers each. Doubles are printed in
/// shortest round-trip form, floats in their own shortest form (exact when read back as float).
pub fn write_rows(out: &mut impl Write, values: &Values, numbers: usize) -> io::Result<()> {
    if numbers == 0 {
        return Ok(());
    }
    let mut ryu = ryu::Buffer::new();
    let mut line = String::with_capacity(64);
    let n = values.len();
    let mut i = 0;
    while i < n {
        line.clear();
        for k in 0..numbers {
            if k > 0 {
                line.push(' ');
            }
            match values {
                Values::U8(v) => push_int(&mut line, v[i + k].into()),
                Values::I16(v) => push_int(&mut line, v[i + k].into()),
                Values::I32(v) => push_int(&mut line, v[i + k].into()),
                Values::F32(v) => line.push_str(trim_float(ryu.format_finite(v[i + k]))),
                Values::F64(v) => line.push_str(trim_float(ryu.format_finite(v[i + k]))),
            }
        }
        line.push('\n');
        out.write_all(line.as_bytes())?;
        i += numbers;
    }
    Ok(())
}

fn push_int(line: &mut String, v: i64) {
    use std::fmt::Write as _;
    // Writing into a String cannot fail.
    let _ = write!(line, "{v}");
}

/// `1.0` → `1`: shorter files, same value.
fn trim_float(s: &str) -> &str {
    s.strip_suffix(".0").unwrap_or(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_print_shortest_and_round_trip() {
        let mut out = Vec::new();
        let v = Values::F32(vec![0.1, 1.0, 3.4028235e38, 1e-45]);
        write_rows(&mut out, &v, 2).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(text, "0.1 1\n3.4028235e38 1e-45\n");
        let back: Vec<f32> = text
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        assert_eq!(Values::F32(back), v);
    }
}
