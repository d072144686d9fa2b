//! The header's statements: counts (`nNodes = 4`), block declarations (`Nodes { double[3]
//! Coordinates } = @1`, `Kind = NULL`) and `Field` lines, read from the tokens ([`super::tokens`])
//! one statement at a time by a [`Cursor`]. Every statement but `Materials` stays on one line,
//! which is what lets a message say "expected … before the end of the line". Separate from the
//! tokenizer (characters) and from the checks across statements (`super::check_declarations`).

use super::tokens::{Tok, TokKind};
use super::{BlockDecl, FieldDecl, MAX_ARRAY, MAX_COUNT, Target, TetCoding, TriangleCoding};
use crate::data::{DataType, ElementKind, ScalarType};
use crate::error::ParseError;

#[derive(Clone, Copy)]
pub(super) enum DeclKeyword {
    Nodes,
    Edges,
    Triangles,
    Tetrahedra,
    Data(ElementKind),
}

impl DeclKeyword {
    pub(super) fn from_word(w: &str) -> Option<DeclKeyword> {
        Some(match w {
            "Nodes" => DeclKeyword::Nodes,
            "Edges" => DeclKeyword::Edges,
            "Triangles" => DeclKeyword::Triangles,
            "Tetrahedra" => DeclKeyword::Tetrahedra,
            _ => DeclKeyword::Data(
                ElementKind::ALL
                    .into_iter()
                    .find(|k| k.data_keyword() == w)?,
            ),
        })
    }
}

pub(super) enum Decl {
    Null,
    Block(BlockDecl),
}

/// The statements' reading position in the header's tokens.
pub(super) struct Cursor<'a> {
    pub(super) file: &'a str,
    pub(super) toks: &'a [Tok],
    pub(super) pos: usize,
}

impl Cursor<'_> {
    pub(super) fn err(&self, line: usize, msg: impl Into<String>) -> ParseError {
        ParseError::new(self.file, line, msg)
    }

    pub(super) fn next(&mut self) -> Option<&Tok> {
        let t = self.toks.get(self.pos);
        if t.is_some() {
            self.pos += 1;
        }
        t
    }

    pub(super) fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos)
    }

    /// Next token on `line`, or an error saying what was expected there.
    pub(super) fn next_on(&mut self, line: usize, what: &str) -> Result<Tok, ParseError> {
        match self.toks.get(self.pos) {
            Some(t) if t.line == line => {
                self.pos += 1;
                Ok(t.clone())
            }
            _ => Err(self.err(line, format!("expected {what} before the end of the line"))),
        }
    }

    pub(super) fn expect_punct(
        &mut self,
        c: u8,
        line: usize,
        what: &str,
    ) -> Result<(), ParseError> {
        let t = self.next_on(line, what)?;
        if t.kind == TokKind::Punct(c) {
            Ok(())
        } else {
            Err(self.err(
                line,
                format!("expected {what}, found {}", t.kind.describe()),
            ))
        }
    }

    pub(super) fn count_value(&mut self, word: &str, line: usize) -> Result<usize, ParseError> {
        let t = self.next_on(line, &format!("the number of elements after '{word} ='"))?;
        let TokKind::Num(text) = &t.kind else {
            return Err(self.err(
                line,
                format!(
                    "expected a whole number after '{word} =', found {}",
                    t.kind.describe()
                ),
            ));
        };
        match parse_count(text) {
            Some(v) if v <= MAX_COUNT => Ok(v as usize),
            Some(_) => Err(self.err(
                line,
                format!("{word} = {text} is out of range: counts must lie in 0…2147483647"),
            )),
            None => Err(self.err(
                line,
                format!("expected a whole number 0…2147483647 after '{word} =', found {text}"),
            )),
        }
    }

    /// `type` or `type[n]`.
    fn data_type(&mut self, line: usize) -> Result<DataType, ParseError> {
        let types = "byte, short, int, long, float, double or complex";
        let t = self.next_on(line, &format!("a type ({types})"))?;
        let TokKind::Ident(word) = &t.kind else {
            return Err(self.err(
                line,
                format!("expected a type ({types}), found {}", t.kind.describe()),
            ));
        };
        let Some(scalar) = ScalarType::from_keyword(word) else {
            return Err(self.err(line, format!("unknown type '{word}': expected {types}")));
        };
        if self
            .peek()
            .is_some_and(|t| t.line == line && t.kind == TokKind::Punct(b'['))
        {
            self.pos += 1;
            let t = self.next_on(line, "an array length after '['")?;
            let n = match &t.kind {
                TokKind::Num(text) => parse_count(text).filter(|&n| (1..=MAX_ARRAY).contains(&n)),
                _ => None,
            };
            let Some(n) = n else {
                return Err(self.err(
                    line,
                    format!(
                        "expected an array length 1…{MAX_ARRAY} in '{word}[…]', found {}",
                        t.kind.describe()
                    ),
                ));
            };
            self.expect_punct(b']', line, "']' after the array length")?;
            Ok(DataType::array(scalar, n as u32))
        } else {
            Ok(DataType::scalar(scalar))
        }
    }

    /// `{ type [word] }`; returns the type and the optional word.
    fn braced_type(&mut self, line: usize) -> Result<(DataType, Option<String>), ParseError> {
        self.expect_punct(b'{', line, "'{' before the type")?;
        let ty = self.data_type(line)?;
        let t = self.next_on(line, "'}' after the type")?;
        match t.kind {
            TokKind::Punct(b'}') => Ok((ty, None)),
            TokKind::Ident(word) => {
                self.expect_punct(b'}', line, "'}'")?;
                Ok((ty, Some(word)))
            }
            other => Err(self.err(
                line,
                format!(
                    "expected a name or '}}' after the type, found {}",
                    other.describe()
                ),
            )),
        }
    }

    fn marker(&mut self, line: usize, what: &str) -> Result<String, ParseError> {
        let t = self.next_on(line, what)?;
        match t.kind {
            TokKind::Marker(m) => Ok(m),
            other => Err(self.err(line, format!("expected {what}, found {}", other.describe()))),
        }
    }

    pub(super) fn declaration(&mut self, kw: DeclKeyword, line: usize) -> Result<Decl, ParseError> {
        // `Kind = NULL`
        if self
            .peek()
            .is_some_and(|t| t.line == line && t.kind == TokKind::Punct(b'='))
        {
            self.pos += 1;
            let t = self.next_on(line, "NULL")?;
            return match t.kind {
                TokKind::Ident(w) if w == "NULL" => Ok(Decl::Null),
                other => Err(self.err(
                    line,
                    format!(
                        "expected '{{ type … }} = @marker' or '= NULL', found {}",
                        other.describe()
                    ),
                )),
            };
        }
        let (ty, word) = self.braced_type(line)?;
        self.expect_punct(b'=', line, "'=' after the type")?;
        let marker = self.marker(line, "a marker such as @1 after '='")?;
        let (target, denominator) = match kw {
            DeclKeyword::Data(kind) => (Target::Data(kind), word),
            DeclKeyword::Nodes => {
                expect_word(self, line, &word, &["Coordinates"], true)?;
                (Target::Nodes, None)
            }
            DeclKeyword::Edges => {
                expect_word(self, line, &word, &["FromTo"], true)?;
                (Target::Edges, None)
            }
            DeclKeyword::Triangles => {
                let w = expect_word(self, line, &word, &["Nodes", "Edges", "UpperLower"], false)?;
                let coding = match w {
                    "Nodes" => TriangleCoding::Nodes,
                    "Edges" => TriangleCoding::Edges,
                    _ => TriangleCoding::UpperLower,
                };
                (Target::Triangles(coding), None)
            }
            DeclKeyword::Tetrahedra => {
                let w = expect_word(self, line, &word, &["Nodes", "Edges", "Triangles"], false)?;
                let coding = match w {
                    "Nodes" => TetCoding::Nodes,
                    "Edges" => TetCoding::Edges,
                    _ => TetCoding::Triangles,
                };
                (Target::Tetrahedra(coding), None)
            }
        };
        check_geometry_type(self, target, ty, line)?;
        Ok(Decl::Block(BlockDecl {
            target,
            ty,
            denominator,
            marker,
            line,
        }))
    }

    pub(super) fn field(&mut self, line: usize) -> Result<FieldDecl, ParseError> {
        let mut name = None;
        if let Some(Tok {
            kind: TokKind::Str(s),
            line: l,
        }) = self.peek()
            && *l == line
        {
            name = Some(s.clone());
            self.pos += 1;
        }
        let (ty, denominator) = self.braced_type(line)?;
        self.expect_punct(b'=', line, "'=' after the field type")?;
        let t = self.next_on(line, "an interpolator such as Linear(@1)")?;
        let TokKind::Ident(interpolator) = t.kind else {
            return Err(self.err(
                line,
                format!(
                    "expected an interpolator such as Linear(@1), found {}",
                    t.kind.describe()
                ),
            ));
        };
        self.expect_punct(b'(', line, &format!("'(' after {interpolator}"))?;
        let mut markers = vec![self.marker(line, "a marker such as @1")?];
        loop {
            let t = self.next_on(line, "')' closing the marker list")?;
            match t.kind {
                TokKind::Punct(b')') => break,
                TokKind::Punct(b',') => markers.push(self.marker(line, "a marker after ','")?),
                other => {
                    return Err(self.err(
                        line,
                        format!(
                            "expected ',' or ')' in the marker list, found {}",
                            other.describe()
                        ),
                    ));
                }
            }
        }
        Ok(FieldDecl {
            name,
            ty,
            denominator,
            interpolator,
            markers,
            line,
        })
    }
}

fn expect_word<'w>(
    c: &Cursor,
    line: usize,
    word: &'w Option<String>,
    allowed: &[&'static str],
    optional: bool,
) -> Result<&'w str, ParseError> {
    match word {
        Some(w) if allowed.contains(&w.as_str()) => Ok(w.as_str()),
        None if optional => Ok(""),
        other => Err(c.err(
            line,
            format!(
                "expected {} after the type, found {}",
                allowed.join(" or "),
                other
                    .as_deref()
                    .map_or("nothing".to_string(), |w| format!("'{w}'"))
            ),
        )),
    }
}

/// Geometry blocks need particular types: 3 real coordinates, integer index lists of fixed length.
fn check_geometry_type(
    c: &Cursor,
    target: Target,
    ty: DataType,
    line: usize,
) -> Result<(), ParseError> {
    let need_int = |n: usize, example: &str| -> Result<(), ParseError> {
        if ty.scalar.is_integer() && ty.components() == n && ty.array.is_some() {
            Ok(())
        } else {
            Err(c.err(
                line,
                format!(
                    "{} needs an integer array of {n} indices (e.g. {example}), found {ty}",
                    target.describe()
                ),
            ))
        }
    };
    match target {
        Target::Nodes => {
            if ty.scalar == ScalarType::Complex || ty.components() != 3 || ty.array.is_none() {
                Err(c.err(
                    line,
                    format!("Nodes needs 3 real coordinates (float[3] or double[3]), found {ty}"),
                ))
            } else {
                Ok(())
            }
        }
        Target::Edges => need_int(2, "int[2]"),
        Target::Triangles(TriangleCoding::UpperLower) => need_int(2, "int[2]"),
        Target::Triangles(_) => need_int(3, "int[3]"),
        Target::Tetrahedra(TetCoding::Edges) => need_int(6, "int[6]"),
        Target::Tetrahedra(_) => need_int(4, "int[4]"),
        Target::Data(_) => Ok(()),
    }
}

/// A whole decimal number without sign or with '+' (counts, array lengths).
fn parse_count(text: &str) -> Option<u64> {
    let t = text.strip_prefix('+').unwrap_or(text);
    if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    // Saturate: anything longer than 20 digits is out of range anyway.
    Some(t.parse::<u64>().unwrap_or(u64::MAX))
}
