//! The header's tokens: identifiers, numbers, strings, `@markers` and punctuation, each with
//! its line. The header is tokenized line by line before any statement is parsed, so tokens may
//! be separated by any or no whitespace and a statement may run over several lines (as
//! `Materials` does), while every message can still name the line of the token it is about.

use crate::error::ParseError;

#[derive(Debug, Clone, PartialEq)]
pub(super) enum TokKind {
    Ident(String),
    Num(String),
    Str(String),
    Marker(String),
    Punct(u8),
}

#[derive(Debug, Clone)]
pub(super) struct Tok {
    pub(super) kind: TokKind,
    pub(super) line: usize,
}

impl TokKind {
    pub(super) fn describe(&self) -> String {
        match self {
            TokKind::Ident(s) => format!("'{s}'"),
            TokKind::Num(s) => format!("number {s}"),
            TokKind::Str(s) => format!("string \"{s}\""),
            TokKind::Marker(s) => format!("marker @{s}"),
            TokKind::Punct(c) => format!("'{}'", *c as char),
        }
    }
}

/// Characters allowed in a marker after `@`.
pub fn is_marker_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, b'_' | b'.' | b'-')
}

/// Appends the tokens of header line `line_no` to `out`. `#` starts a comment outside strings.
pub(super) fn tokenize(
    file: &str,
    line_no: usize,
    line: &[u8],
    out: &mut Vec<Tok>,
) -> Result<(), ParseError> {
    let err = |msg: String| ParseError::new(file, line_no, msg);
    let mut i = 0;
    while i < line.len() {
        let c = line[i];
        let (kind, next) = match c {
            b' ' | b'\t' | b'\r' | 0x0c | 0x0b => {
                i += 1;
                continue;
            }
            b'#' => break,
            b'{' | b'}' | b'[' | b']' | b'=' | b',' | b'(' | b')' => (TokKind::Punct(c), i + 1),
            b'"' => string(line, i)
                .ok_or_else(|| err("unterminated string: expected a closing '\"'".into()))?,
            b'@' => {
                marker(line, i).ok_or_else(|| err("expected a marker name after '@'".into()))?
            }
            c if c.is_ascii_alphabetic() || c == b'_' => identifier(line, i),
            c if c.is_ascii_digit() || matches!(c, b'+' | b'-' | b'.') => number(line, i),
            other => {
                let shown = if other.is_ascii_graphic() {
                    format!("'{}'", other as char)
                } else {
                    format!("byte 0x{other:02x}")
                };
                return Err(err(format!("unexpected {shown} in the header")));
            }
        };
        out.push(Tok {
            kind,
            line: line_no,
        });
        i = next;
    }
    Ok(())
}

/// The string whose opening quote is at `i`, and where the line goes on; `None` if unclosed.
fn string(line: &[u8], i: usize) -> Option<(TokKind, usize)> {
    let start = i + 1;
    let len = line[start..].iter().position(|&b| b == b'"')?;
    let s = String::from_utf8_lossy(&line[start..start + len]).into_owned();
    Some((TokKind::Str(s), start + len + 1))
}

/// The marker whose `@` is at `i`; `None` if no marker character follows.
fn marker(line: &[u8], i: usize) -> Option<(TokKind, usize)> {
    let start = i + 1;
    let len = line[start..]
        .iter()
        .take_while(|&&b| is_marker_char(b))
        .count();
    if len == 0 {
        return None;
    }
    let s = String::from_utf8_lossy(&line[start..start + len]).into_owned();
    Some((TokKind::Marker(s), start + len))
}

fn identifier(line: &[u8], i: usize) -> (TokKind, usize) {
    let len = line[i..]
        .iter()
        .take_while(|&&b| b.is_ascii_alphanumeric() || b == b'_')
        .count();
    let s = String::from_utf8_lossy(&line[i..i + len]).into_owned();
    (TokKind::Ident(s), i + len)
}

/// A number's characters (checked when the statement reads it).
fn number(line: &[u8], i: usize) -> (TokKind, usize) {
    let len = line[i..]
        .iter()
        .take_while(|&&b| b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E'))
        .count();
    let s = String::from_utf8_lossy(&line[i..i + len]).into_owned();
    (TokKind::Num(s), i + len)
}
