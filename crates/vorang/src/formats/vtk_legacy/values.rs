//! Numbers of a legacy VTK file: the data type keywords and the values after them, either
//! ASCII tokens or big-endian binary right after the keyword's line. Every section (points,
//! cells, attributes, FIELD arrays) reads its numbers through [`Reader::values`], so the two
//! encodings, the bounds check against the file's size and the `METADATA` blocks that VTK 9
//! writes after arrays are handled once, apart from the sections' own grammar.

use crate::error::ParseError;
use crate::formats::text::Cursor;
use crate::formats::{Array, ArrayValues};

/// A data type keyword: integers by size and signedness, or floats.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Ty {
    Int(usize, bool),
    F32,
    F64,
}

fn data_type(word: &str) -> Option<Ty> {
    Some(match word.to_ascii_lowercase().as_str() {
        "unsigned_char" | "vtktypeuint8" => Ty::Int(1, false),
        "char" | "signed_char" | "vtktypeint8" => Ty::Int(1, true),
        "unsigned_short" | "vtktypeuint16" => Ty::Int(2, false),
        "short" | "vtktypeint16" => Ty::Int(2, true),
        "unsigned_int" | "vtktypeuint32" => Ty::Int(4, false),
        "int" | "vtktypeint32" => Ty::Int(4, true),
        "unsigned_long" | "vtktypeuint64" | "unsigned_long_long" => Ty::Int(8, false),
        "long" | "vtktypeint64" | "vtkidtype" | "long_long" => Ty::Int(8, true),
        "float" | "vtktypefloat32" => Ty::F32,
        "double" | "vtktypefloat64" => Ty::F64,
        _ => return None,
    })
}

impl Ty {
    pub(super) fn size(self) -> usize {
        match self {
            Ty::Int(s, _) => s,
            Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }
}

/// The file's cursor and its encoding.
pub(super) struct Reader<'a> {
    pub(super) c: Cursor<'a>,
    pub(super) binary: bool,
}

impl<'a> Reader<'a> {
    pub(super) fn ty(&mut self) -> Result<Ty, ParseError> {
        let (w, line) = self.c.expect_token("a data type")?;
        data_type(w).ok_or_else(|| {
            self.c.err_at(
                line,
                format!(
                    "unknown data type '{w}': expected float, double, int, unsigned_char, … (the 'bit' type is not supported)"
                ),
            )
        })
    }

    /// `count` numbers of type `ty`, ASCII tokens or big-endian binary right after the current
    /// line.
    pub(super) fn values(
        &mut self,
        ty: Ty,
        count: usize,
        what: &str,
    ) -> Result<ArrayValues, ParseError> {
        let left = self.c.bytes.len() - self.c.pos;
        let min = if self.binary { ty.size() } else { 2 };
        if count.saturating_mul(min) > left + 1 {
            return Err(self.c.err(format!(
                "{what}: {count} values cannot fit in the {left} bytes left in the file"
            )));
        }
        if self.binary {
            self.c.next_line();
            let raw = self.c.raw(count * ty.size(), what)?;
            return big_endian_values(&self.c, raw, ty, count, what);
        }
        match ty {
            Ty::Int(..) => {
                let mut out = Vec::with_capacity(count);
                for _ in 0..count {
                    out.push(self.c.int(&format!("{what}: an integer"))?);
                }
                Ok(ArrayValues::Int(out))
            }
            _ => {
                let mut out = Vec::with_capacity(count);
                for _ in 0..count {
                    out.push(self.c.float(&format!("{what}: a number"))?);
                }
                Ok(if ty == Ty::F32 {
                    ArrayValues::F32(out.into_iter().map(|v| v as f32).collect())
                } else {
                    ArrayValues::F64(out)
                })
            }
        }
    }

    /// A FIELD block's arrays (`FIELD name n` already read up to `n`).
    pub(super) fn field_arrays(&mut self, n: usize) -> Result<Vec<Array>, ParseError> {
        let mut out = Vec::new();
        for _ in 0..n {
            let (name, line) = self.c.expect_token("a FIELD array name")?;
            let name = name.to_string();
            if name == "NULL_ARRAY" {
                continue;
            }
            let comps = self.c.count("the FIELD array's number of components", 0)?;
            let tuples = self.c.count("the FIELD array's number of tuples", 0)?;
            let ty = self.ty()?;
            let total = comps.saturating_mul(tuples);
            let values = self.values(ty, total, &format!("FIELD array {name}"))?;
            self.skip_metadata();
            out.push(Array {
                name,
                components: comps.max(1),
                values,
                line,
            });
        }
        Ok(out)
    }

    /// Skips a `METADATA` block (up to its blank line), if one follows.
    pub(super) fn skip_metadata(&mut self) {
        let save = (self.c.pos, self.c.line);
        match self.c.token() {
            Some((w, _)) if w.eq_ignore_ascii_case("METADATA") => {
                self.c.next_line();
                loop {
                    if self.c.at_end() {
                        break;
                    }
                    let l = self.c.rest_of_line();
                    if l.trim().is_empty() {
                        break;
                    }
                }
            }
            _ => (self.c.pos, self.c.line) = save,
        }
    }
}

/// `count` big-endian numbers of type `ty` from `raw` (`c` is where they were read, for the
/// message about an unsigned 64-bit value beyond `i64`).
fn big_endian_values(
    c: &Cursor,
    raw: &[u8],
    ty: Ty,
    count: usize,
    what: &str,
) -> Result<ArrayValues, ParseError> {
    Ok(match ty {
        Ty::F32 => ArrayValues::F32(
            raw.chunks_exact(4)
                .map(|c| f32::from_be_bytes([c[0], c[1], c[2], c[3]]))
                .collect(),
        ),
        Ty::F64 => ArrayValues::F64(
            raw.chunks_exact(8)
                .map(|c| f64::from_be_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
                .collect(),
        ),
        Ty::Int(size, signed) => {
            let mut out = Vec::with_capacity(count);
            for w8 in raw.chunks_exact(size) {
                let mut w = [0u8; 8];
                w[8 - size..].copy_from_slice(w8);
                let u = u64::from_be_bytes(w);
                let v = if signed {
                    // Sign-extend from `size` bytes.
                    let shift = 64 - 8 * size as u32;
                    ((u << shift) as i64) >> shift
                } else {
                    i64::try_from(u)
                        .map_err(|_| c.err(format!("{what}: the value {u} is too large")))?
                };
                out.push(v);
            }
            ArrayValues::Int(out)
        }
    })
}
