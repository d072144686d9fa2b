//! Array decoding: the middle phase of reading a `.vtu` file, from one declared `<DataArray>`
//! to its numbers. ASCII arrays are parsed as text; binary and appended ones go through
//! [`super::binary`] (headers, base64, compressed blocks) into a [`Sink`], which converts bytes
//! to values as they arrive so that a large array never exists twice. The connectivity has its
//! own path ([`decode_indices`]) straight into 32-bit indices. Kept apart from the XML walk and
//! from the binary layouts because this is where the reading time of a large file goes: the
//! conversion loops stay together, small and easy to measure.

use super::binary::{binary_base64, binary_raw};
use super::sink::{IndexOut, MAX_OUTSIDE, Outside, Sink};
use super::xml::{DataFormat, Decl, NumType, Section, Settings, decl_text};
use crate::error::ParseError;
use crate::formats::ArrayValues;
use crate::formats::text::{parse_float, parse_int};

/// Appends piece `v` to the values of the same array from the pieces before (mixed types
/// become `f64`).
pub(super) fn append_values(dest: &mut ArrayValues, v: ArrayValues) {
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
pub(super) fn decode(s: &Settings, d: &Decl, count: usize) -> Result<ArrayValues, ParseError> {
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
            appended_into(s, offset, want_bytes, sink).map_err(&err)?;
        }
    }
    if sink.seen < want_bytes {
        return Err(err(format!(
            "holds {} bytes, but {count} values of {:?} need {want_bytes}",
            sink.seen, d.ty
        )));
    }
    if sink.seen > want_bytes && !may_be_longer(d) {
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

/// Whether an array may hold more values than are read from it: the cell offsets (some
/// writers add a leading 0, one entry more than cells), and the face offsets and face
/// connectivity of polyhedra, of which only the faces the polyhedra use are read (no count
/// says how many faces there are).
fn may_be_longer(d: &Decl) -> bool {
    d.section == Section::Cells
        && matches!(
            d.name.as_str(),
            "offsets" | "face_offsets" | "face_connectivity"
        )
}

/// An appended array at `offset` of the appended data, raw or base64.
fn appended_into(
    s: &Settings,
    offset: u64,
    want_bytes: usize,
    sink: &mut Sink,
) -> Result<(), String> {
    let Some((app, start, raw)) = s.appended else {
        return Err("format=\"appended\", but the file has no <AppendedData> section".into());
    };
    if offset >= app.len() as u64 && want_bytes > 0 {
        return Err(format!(
            "offset {offset} lies beyond the appended data ({} bytes from byte {start})",
            app.len()
        ));
    }
    let o = offset.min(app.len() as u64) as usize;
    if raw {
        binary_raw(s, &app[o..], start + o, want_bytes, sink)
    } else {
        // A base64 chunk ends where the next array's begins.
        let end = s
            .offsets
            .iter()
            .find(|&&x| x > offset)
            .map_or(app.len(), |&x| (x as usize).min(app.len()));
        binary_base64(s, &without_whitespace(&app[o..end]), want_bytes, sink)
    }
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
pub(super) fn decode_indices(
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
            let v = parse_float(t).ok_or_else(|| {
                ParseError::new(
                    s.name,
                    line_of_tok(k),
                    format!("{what}: expected a number, found '{t}'"),
                )
            })?;
            floats.push(v);
        } else {
            let v = parse_int(t).ok_or_else(|| {
                ParseError::new(
                    s.name,
                    line_of_tok(k),
                    format!("{what}: expected an integer, found '{t}'"),
                )
            })?;
            ints.push(v);
        }
    }
    if toks.next().is_some() && !may_be_longer(d) {
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
