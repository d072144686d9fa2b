//! ASCII data blocks: one element per line, its numbers separated by whitespace (thesis B.2
//! "Datensektion"); blank lines and `#` comments are skipped; a block runs to the next `@marker`
//! line or the end of the file.

use std::io::{self, BufRead, Write};

use super::input::Input;
use crate::data::{DataType, ScalarType, Values};
use crate::error::ParseError;
use crate::numbers::is_decimal;

/// The file line of every row of a block, stored compactly: rows are consecutive lines except
/// where blank or comment lines interrupt them, and only those jumps are recorded.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RowLines {
    /// `(first row of a run, its line)`, sorted by row.
    runs: Vec<(usize, usize)>,
}

impl RowLines {
    fn push(&mut self, row: usize, line: usize) {
        if self.line_of(row) != Some(line) {
            self.runs.push((row, line));
        }
    }

    /// The line of `row` (0-based), if the block has such a row.
    pub fn line_of(&self, row: usize) -> Option<usize> {
        let i = self.runs.partition_point(|&(r, _)| r <= row);
        let (r, l) = *self.runs.get(i.checked_sub(1)?)?;
        Some(l + (row - r))
    }
}

/// A number type that ASCII rows can hold.
trait AsciiNumber: Copy {
    const TYPE: ScalarType;
    fn parse(tok: &[u8]) -> Result<Self, String>;
}

fn integer(tok: &[u8]) -> Option<i64> {
    let (neg, digits) = match tok.first() {
        Some(b'-') => (true, &tok[1..]),
        Some(b'+') => (false, &tok[1..]),
        _ => (false, tok),
    };
    if digits.is_empty() || digits.len() > 18 {
        return None;
    }
    let mut v: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        v = v * 10 + i64::from(d - b'0');
    }
    Some(if neg { -v } else { v })
}

fn show(tok: &[u8]) -> String {
    let s = String::from_utf8_lossy(tok);
    if s.chars().count() > 40 {
        format!("{}…", s.chars().take(40).collect::<String>())
    } else {
        s.into_owned()
    }
}

fn int_in_range(tok: &[u8], lo: i64, hi: i64, ty: ScalarType) -> Result<i64, String> {
    let digits = tok
        .strip_prefix(b"-")
        .or(tok.strip_prefix(b"+"))
        .unwrap_or(tok);
    let too_long = digits.len() > 18 && digits.iter().all(u8::is_ascii_digit);
    match integer(tok) {
        Some(v) if (lo..=hi).contains(&v) => Ok(v),
        Some(_) => Err(format!(
            "{} is out of range for {} ({lo}…{hi})",
            show(tok),
            ty.keyword()
        )),
        None if too_long => Err(format!(
            "{} is out of range for {} ({lo}…{hi})",
            show(tok),
            ty.keyword()
        )),
        None => Err(format!(
            "expected a whole number for {}, found '{}'",
            ty.keyword(),
            show(tok)
        )),
    }
}

impl AsciiNumber for u8 {
    const TYPE: ScalarType = ScalarType::Byte;
    fn parse(tok: &[u8]) -> Result<Self, String> {
        int_in_range(tok, 0, 255, Self::TYPE).map(|v| v as u8)
    }
}

impl AsciiNumber for i16 {
    const TYPE: ScalarType = ScalarType::Short;
    fn parse(tok: &[u8]) -> Result<Self, String> {
        int_in_range(tok, i16::MIN.into(), i16::MAX.into(), Self::TYPE).map(|v| v as i16)
    }
}

impl AsciiNumber for i32 {
    const TYPE: ScalarType = ScalarType::Int;
    fn parse(tok: &[u8]) -> Result<Self, String> {
        int_in_range(tok, i32::MIN.into(), i32::MAX.into(), Self::TYPE).map(|v| v as i32)
    }
}

fn real<T: std::str::FromStr>(tok: &[u8], ty: ScalarType) -> Result<T, String> {
    if !is_decimal(tok) {
        return Err(format!(
            "expected a number for {}, found '{}'",
            ty.keyword(),
            show(tok)
        ));
    }
    // `is_decimal` admits only ASCII, so this conversion cannot fail.
    let s = std::str::from_utf8(tok)
        .map_err(|_| format!("expected a number, found '{}'", show(tok)))?;
    s.parse::<T>().map_err(|_| {
        format!(
            "expected a number for {}, found '{}'",
            ty.keyword(),
            show(tok)
        )
    })
}

impl AsciiNumber for f32 {
    const TYPE: ScalarType = ScalarType::Float;
    fn parse(tok: &[u8]) -> Result<Self, String> {
        let v: f32 = real(tok, Self::TYPE)?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("{} is out of range for float", show(tok)))
        }
    }
}

impl AsciiNumber for f64 {
    const TYPE: ScalarType = ScalarType::Double;
    fn parse(tok: &[u8]) -> Result<Self, String> {
        let v: f64 = real(tok, Self::TYPE)?;
        if !v.is_finite() {
            Err(format!("{} is out of range for double", show(tok)))
        } else if v.abs() > super::MAX_MAGNITUDE {
            Err(format!(
                "{} is too large: values up to ±{:e} are accepted (sums and products of larger ones overflow while rendering)",
                show(tok),
                super::MAX_MAGNITUDE
            ))
        } else {
            Ok(v)
        }
    }
}

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
    let start = line.iter().position(|b| !b.is_ascii_whitespace())?;
    (line[start] == b'@').then_some(&line[start..])
}

fn is_blank_or_comment(line: &[u8]) -> bool {
    match line.iter().position(|b| !b.is_ascii_whitespace()) {
        None => true,
        Some(i) => line[i] == b'#',
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
    let next_marker = match &mut values {
        Values::U8(v) => rows_into(input, info, ty, count, v, &mut rows, &mut n_rows),
        Values::I16(v) => rows_into(input, info, ty, count, v, &mut rows, &mut n_rows),
        Values::I32(v) => rows_into(input, info, ty, count, v, &mut rows, &mut n_rows),
        Values::F32(v) => rows_into(input, info, ty, count, v, &mut rows, &mut n_rows),
        Values::F64(v) => rows_into(input, info, ty, count, v, &mut rows, &mut n_rows),
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

fn rows_into<R: BufRead, T: AsciiNumber>(
    input: &mut Input<R>,
    info: &BlockInfo,
    ty: DataType,
    count: usize,
    out: &mut Vec<T>,
    rows: &mut RowLines,
    n_rows: &mut usize,
) -> Result<Option<(Vec<u8>, usize)>, ParseError> {
    let numbers = ty.numbers();
    let io_err =
        |e: io::Error| ParseError::new(info.file, info.marker_line, format!("read error: {e}"));
    loop {
        let Some((line_no, line)) = input.next_line().map_err(io_err)? else {
            return Ok(None);
        };
        if let Some(m) = marker_line(line) {
            return Ok(Some((m.to_vec(), line_no)));
        }
        if is_blank_or_comment(line) {
            continue;
        }
        if *n_rows == count {
            return Err(ParseError::new(
                info.file,
                info.marker_line,
                format!(
                    "block @{} ({}) has more than {count} rows ({} = {count}); the extra row is on line {line_no}",
                    info.marker, info.what, info.count_keyword
                ),
            ));
        }
        let content = match line.iter().position(|&b| b == b'#') {
            Some(i) => &line[..i],
            None => line,
        };
        let mut found = 0usize;
        for tok in content
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty())
        {
            found += 1;
            if found > numbers {
                continue;
            }
            let v = T::parse(tok).map_err(|msg| {
                ParseError::new(
                    info.file,
                    line_no,
                    format!(
                        "{} {} of block @{}: {msg}",
                        element_noun(info.what),
                        *n_rows + 1,
                        info.marker
                    ),
                )
            })?;
            out.push(v);
        }
        if found != numbers {
            return Err(ParseError::new(
                info.file,
                line_no,
                format!(
                    "{} {} of block @{}: expected {numbers} number{} ({ty}), found {found}",
                    element_noun(info.what),
                    *n_rows + 1,
                    info.marker,
                    if numbers == 1 { "" } else { "s" },
                ),
            ));
        }
        rows.push(*n_rows, line_no);
        *n_rows += 1;
    }
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
    fn integers_take_whole_numbers_only() {
        assert_eq!(<i32 as AsciiNumber>::parse(b"-12"), Ok(-12));
        assert!(<i32 as AsciiNumber>::parse(b"1.0").is_err());
        assert!(
            <u8 as AsciiNumber>::parse(b"256")
                .unwrap_err()
                .contains("out of range")
        );
        assert!(<i16 as AsciiNumber>::parse(b"40000").is_err());
        assert!(<i32 as AsciiNumber>::parse(b"99999999999999999999999").is_err());
        assert!(
            <f32 as AsciiNumber>::parse(b"1e39")
                .unwrap_err()
                .contains("out of range")
        );
        assert_eq!(<f64 as AsciiNumber>::parse(b"1e150"), Ok(1e150));
        assert!(
            <f64 as AsciiNumber>::parse(b"1e308")
                .unwrap_err()
                .contains("too large")
        );
    }

    #[test]
    fn row_lines_follow_jumps() {
        let mut r = RowLines::default();
        r.push(0, 10);
        r.push(1, 11);
        r.push(2, 14);
        r.push(3, 15);
        assert_eq!(r.line_of(0), Some(10));
        assert_eq!(r.line_of(1), Some(11));
        assert_eq!(r.line_of(2), Some(14));
        assert_eq!(r.line_of(3), Some(15));
        assert_eq!(r.runs.len(), 2);
    }

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
