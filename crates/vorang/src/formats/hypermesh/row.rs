//! One row of an ASCII data block (thesis B.2 "Datensektion"): its numbers separated by
//! whitespace, a `#` starting a comment. The row reader is shared by the line-at-a-time path and
//! the parallel batches ([`super::batch`]), so both accept and refuse exactly the same text.

use crate::data::ScalarType;
use crate::numbers::{is_decimal, whole};

/// The file line of every row of a block, stored compactly: rows are consecutive lines except
/// where blank or comment lines interrupt them, and only those jumps are recorded.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RowLines {
    /// `(first row of a run, its line)`, sorted by row.
    runs: Vec<(usize, usize)>,
}

impl RowLines {
    pub(super) fn push(&mut self, row: usize, line: usize) {
        if self.line_of(row) != Some(line) {
            self.runs.push((row, line));
        }
    }

    /// Appends `other`'s rows, numbered from `row0`, their lines shifted by `line0`.
    pub(super) fn append_shifted(&mut self, other: &RowLines, row0: usize, line0: usize) {
        for &(r, l) in &other.runs {
            self.push(row0 + r, line0 + l);
        }
    }

    /// The line of `row` (0-based), if the block has such a row.
    pub fn line_of(&self, row: usize) -> Option<usize> {
        let i = self.runs.partition_point(|&(r, _)| r <= row);
        let (r, l) = *self.runs.get(i.checked_sub(1)?)?;
        Some(l + (row - r))
    }
}

/// What a line of a block is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Line<'a> {
    /// An `@marker` line (its text from the `@`): the block ends here.
    Marker(&'a [u8]),
    /// Blank or a comment: skipped.
    Blank,
    /// Numbers.
    Row,
}

/// Tells a line's kind from its first non-blank byte.
pub(super) fn classify(line: &[u8]) -> Line<'_> {
    match line.iter().position(|b| !b.is_ascii_whitespace()) {
        None => Line::Blank,
        Some(i) if line[i] == b'#' => Line::Blank,
        Some(i) if line[i] == b'@' => Line::Marker(&line[i..]),
        Some(_) => Line::Row,
    }
}

/// Why a row was refused; the caller adds the file, line and row number.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum RowError {
    /// A token that is not a number of the block's type (the message says which).
    Number(String),
    /// The row holds this many numbers instead of the type's count.
    Count(usize),
}

/// Parses the first `numbers` tokens of `line` onto `out` and counts the rest. A bad number is
/// reported before a wrong count, as a reader going left to right meets them.
pub(super) fn parse_row<T: AsciiNumber>(
    line: &[u8],
    numbers: usize,
    out: &mut Vec<T>,
) -> Result<(), RowError> {
    let mut found = 0usize;
    let mut i = 0;
    let n = line.len();
    loop {
        while i < n && line[i].is_ascii_whitespace() {
            i += 1;
        }
        if i == n || line[i] == b'#' {
            break;
        }
        let start = i;
        while i < n && !line[i].is_ascii_whitespace() && line[i] != b'#' {
            i += 1;
        }
        found += 1;
        if found <= numbers {
            out.push(T::parse(&line[start..i]).map_err(RowError::Number)?);
        }
    }
    if found == numbers {
        Ok(())
    } else {
        Err(RowError::Count(found))
    }
}

/// A number type that ASCII rows can hold.
pub(super) trait AsciiNumber: Copy + Send + Sync {
    const TYPE: ScalarType;
    fn parse(tok: &[u8]) -> Result<Self, String>;
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
    // The common case first: the message's extra inspection only for a bad token.
    if let Some(v) = whole(tok).filter(|v| (lo..=hi).contains(v)) {
        return Ok(v);
    }
    let digits = tok
        .strip_prefix(b"-")
        .or(tok.strip_prefix(b"+"))
        .unwrap_or(tok);
    let too_long = digits.len() > 18 && digits.iter().all(u8::is_ascii_digit);
    match whole(tok) {
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
    fn rows_split_at_whitespace_and_comments() {
        let mut out: Vec<i32> = Vec::new();
        assert_eq!(parse_row(b"  1\t2 3#4 5", 3, &mut out), Ok(()));
        assert_eq!(out, [1, 2, 3]);
        assert_eq!(parse_row(b"1 2 # 3", 3, &mut out), Err(RowError::Count(2)));
        assert_eq!(parse_row(b"1 2 3 4", 3, &mut out), Err(RowError::Count(4)));
        // The bad number comes first, even in a row that is also too long.
        assert!(matches!(
            parse_row::<i32>(b"1 x 3 4", 3, &mut out),
            Err(RowError::Number(m)) if m.contains("'x'")
        ));
        assert_eq!(classify(b"  @12 "), Line::Marker(b"@12 "));
        assert_eq!(classify(b" \t# c"), Line::Blank);
        assert_eq!(classify(b""), Line::Blank);
        assert_eq!(classify(b" 1"), Line::Row);
    }
}
