//! A cursor over a file's bytes shared by the line-oriented readers (legacy VTK, Gmsh): tokens
//! with their line numbers, whole lines, and raw binary runs, every step bounds-checked so a
//! truncated or corrupt file gives an error at a line or byte offset, never a panic.

use crate::error::ParseError;

pub struct Cursor<'a> {
    pub bytes: &'a [u8],
    pub pos: usize,
    pub line: usize,
    pub name: &'a str,
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8], name: &'a str) -> Self {
        Cursor {
            bytes,
            pos: 0,
            line: 1,
            name,
        }
    }

    pub fn err(&self, msg: impl Into<String>) -> ParseError {
        ParseError::new(self.name, self.line, msg)
    }

    pub fn err_at(&self, line: usize, msg: impl Into<String>) -> ParseError {
        ParseError::new(self.name, line, msg)
    }

    pub fn at_end(&self) -> bool {
        self.pos >= self.bytes.len()
    }

    /// Skips spaces, tabs and line ends.
    pub fn skip_space(&mut self) {
        while let Some(&b) = self.bytes.get(self.pos) {
            if b == b'\n' {
                self.line += 1;
            } else if !b.is_ascii_whitespace() {
                break;
            }
            self.pos += 1;
        }
    }

    /// The next whitespace-separated token and its line, or `None` at the end.
    pub fn token(&mut self) -> Option<(&'a str, usize)> {
        self.skip_space();
        let start = self.pos;
        while self
            .bytes
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        if start == self.pos {
            return None;
        }
        let t = std::str::from_utf8(&self.bytes[start..self.pos]).unwrap_or("\u{fffd}");
        Some((t, self.line))
    }

    /// The next token, or an error saying what was expected.
    pub fn expect_token(&mut self, what: &str) -> Result<(&'a str, usize), ParseError> {
        self.token()
            .ok_or_else(|| self.err(format!("unexpected end of file: expected {what}")))
    }

    pub fn int(&mut self, what: &str) -> Result<i64, ParseError> {
        let (t, line) = self.expect_token(what)?;
        parse_int(t).ok_or_else(|| self.err_at(line, format!("expected {what}, found '{t}'")))
    }

    /// A non-negative count, bounded by what the rest of the file could hold at `min_bytes`
    /// bytes per item (so absurd counts are refused before anything is allocated).
    pub fn count(&mut self, what: &str, min_bytes: usize) -> Result<usize, ParseError> {
        let (t, line) = self.expect_token(what)?;
        let n = parse_int(t).filter(|&n| n >= 0).ok_or_else(|| {
            self.err_at(
                line,
                format!("expected {what} (a whole number ≥ 0), found '{t}'"),
            )
        })? as u64;
        let left = (self.bytes.len() - self.pos) as u64;
        if n.saturating_mul(min_bytes.max(1) as u64) > left + 1 {
            return Err(self.err_at(
                line,
                format!(
                    "{what} is {n}, but the {left} bytes left in the file cannot hold that many"
                ),
            ));
        }
        Ok(n as usize)
    }

    pub fn float(&mut self, what: &str) -> Result<f64, ParseError> {
        let (t, line) = self.expect_token(what)?;
        parse_float(t).ok_or_else(|| self.err_at(line, format!("expected {what}, found '{t}'")))
    }

    /// The rest of the current line (without the line end), moving to the next line.
    pub fn rest_of_line(&mut self) -> &'a str {
        let start = self.pos;
        while self.bytes.get(self.pos).is_some_and(|&b| b != b'\n') {
            self.pos += 1;
        }
        let s = &self.bytes[start..self.pos];
        if self.pos < self.bytes.len() {
            self.pos += 1;
            self.line += 1;
        }
        std::str::from_utf8(s).unwrap_or("").trim_end_matches('\r')
    }

    /// Skips to the start of the next line (after the current line's end).
    pub fn next_line(&mut self) {
        self.rest_of_line();
    }

    /// `n` raw bytes from the current position.
    pub fn raw(&mut self, n: usize, what: &str) -> Result<&'a [u8], ParseError> {
        let left = self.bytes.len() - self.pos;
        if n > left {
            return Err(self.err(format!(
                "{what}: the file ends at byte {}, {} bytes short of the {n} bytes needed from byte {}",
                self.bytes.len(),
                n - left,
                self.pos
            )));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.line += count_lines(s);
        self.pos += n;
        Ok(s)
    }
}

/// The line ends in `bytes`: byte sums of 64 comparisons at a time, which the compiler turns
/// into vector compares (a plain filtered count ran at under 2 GB/s).
pub fn count_lines(bytes: &[u8]) -> usize {
    bytes
        .chunks(64)
        .map(|c| usize::from(c.iter().map(|&b| u8::from(b == b'\n')).sum::<u8>()))
        .sum()
}

pub fn parse_int(t: &str) -> Option<i64> {
    t.strip_prefix('+').unwrap_or(t).parse::<i64>().ok()
}

pub fn parse_float(t: &str) -> Option<f64> {
    match crate::numbers::parse_f64(t) {
        Some(v) => Some(v),
        // Fortran-style exponents and the spellings other writers use for special values.
        None => {
            let lower = t.to_ascii_lowercase();
            match lower.as_str() {
                "nan" | "-nan" | "+nan" => Some(f64::NAN),
                "inf" | "+inf" | "infinity" => Some(f64::INFINITY),
                "-inf" | "-infinity" => Some(f64::NEG_INFINITY),
                _ => lower.replace(['d'], "e").parse::<f64>().ok(),
            }
        }
    }
}

/// An XML element's attributes as `(name, value)`, values unescaped (the raw text where an
/// entity is malformed), for the XML readers (`.vtu`, collections, XDMF).
pub fn xml_attributes(e: &quick_xml::events::BytesStart) -> Vec<(String, String)> {
    e.attributes()
        .flatten()
        .map(|a| {
            (
                String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                xml_value(&a),
            )
        })
        .collect()
}

/// One attribute's value, unescaped (the raw text where an entity is malformed).
pub fn xml_value(a: &quick_xml::events::attributes::Attribute) -> String {
    a.unescape_value()
        .map(|v| v.into_owned())
        .unwrap_or_else(|_| String::from_utf8_lossy(&a.value).into_owned())
}
