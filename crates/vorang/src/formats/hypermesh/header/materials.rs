//! `Materials { { id=0, name="Tumor", eps=1.25 }, … }`: the one statement of the header that
//! may span several lines, and whose values are numbers or names. Kept apart from the other
//! statements because its grammar (nested braces, `key=value` lists, required `id` and `name`)
//! and its messages (which point back at the line that opened the block) are its own.

use super::statements::Cursor;
use super::tokens::{Tok, TokKind};
use crate::data::{Material, MaterialValue, Materials};
use crate::error::ParseError;

impl Cursor<'_> {
    /// `Materials { { id=0, name="x", k=v, … }, … }`, possibly over several lines.
    pub(super) fn materials(&mut self, open_line: usize) -> Result<Materials, ParseError> {
        let unterminated = |c: &Self| {
            c.err(
                open_line,
                "unterminated Materials block: expected '}' closing the block opened here",
            )
        };
        match self.next() {
            Some(Tok {
                kind: TokKind::Punct(b'{'),
                ..
            }) => {}
            Some(t) => {
                let (l, d) = (t.line, t.kind.describe());
                return Err(self.err(l, format!("expected '{{' after Materials, found {d}")));
            }
            None => return Err(unterminated(self)),
        }
        let mut list = Vec::new();
        loop {
            let Some(t) = self.next().cloned() else {
                return Err(unterminated(self));
            };
            match t.kind {
                TokKind::Punct(b'}') => break,
                TokKind::Punct(b',') => continue,
                TokKind::Punct(b'{') => {
                    let m = self.material(t.line, open_line)?;
                    if let Some(prev) = list.iter().find(|p: &&Material| p.id == m.id) {
                        return Err(self.err(
                            t.line,
                            format!(
                                "material id {} is defined twice (also as \"{}\")",
                                m.id, prev.name
                            ),
                        ));
                    }
                    list.push(m);
                }
                other => {
                    return Err(self.err(open_line, format!(
                        "unterminated Materials block: expected '}}' closing the block opened here, found {} on line {}",
                        other.describe(),
                        t.line
                    )));
                }
            }
        }
        Ok(Materials { list })
    }

    fn material(&mut self, line: usize, open_line: usize) -> Result<Material, ParseError> {
        let mut id = None;
        let mut name = None;
        let mut props = Vec::new();
        loop {
            let Some(t) = self.next().cloned() else {
                return Err(self.err(
                    open_line,
                    "unterminated Materials block: expected '}' closing the block opened here",
                ));
            };
            let key = match t.kind {
                TokKind::Punct(b'}') => break,
                TokKind::Punct(b',') => continue,
                TokKind::Ident(k) => k,
                other => {
                    return Err(self.err(
                        t.line,
                        format!(
                            "expected 'key=value' in a material, found {}",
                            other.describe()
                        ),
                    ));
                }
            };
            let eq = self.next().cloned();
            if !matches!(eq.as_ref().map(|t| &t.kind), Some(TokKind::Punct(b'='))) {
                return Err(self.err(t.line, format!("expected '=' after '{key}' in a material")));
            }
            let (value, vline) = self.material_value(&key, open_line)?;
            match key.as_str() {
                "id" => match &value {
                    MaterialValue::Number { value: x, .. }
                        if x.fract() == 0.0 && (0.0..=255.0).contains(x) =>
                    {
                        id = Some(*x as u8)
                    }
                    _ => {
                        return Err(self.err(
                            vline,
                            "material id must be a whole number 0…255 (a byte value)",
                        ));
                    }
                },
                "name" => name = Some(value.to_string()),
                _ => {
                    if props.iter().any(|(k, _)| *k == key) {
                        return Err(self.err(vline, format!("material key '{key}' is given twice")));
                    }
                    props.push((key, value));
                }
            }
        }
        let Some(id) = id else {
            return Err(self.err(
                line,
                "material without 'id=': every material needs an id and a name",
            ));
        };
        let Some(name) = name else {
            return Err(self.err(
                line,
                format!("material {id} has no 'name=\"…\"': every material needs an id and a name"),
            ));
        };
        Ok(Material { id, name, props })
    }

    /// The value after `key=` (a number, a string or a bare name) and its line.
    fn material_value(
        &mut self,
        key: &str,
        open_line: usize,
    ) -> Result<(MaterialValue, usize), ParseError> {
        let Some(v) = self.next().cloned() else {
            return Err(self.err(
                open_line,
                "unterminated Materials block: expected '}' closing the block opened here",
            ));
        };
        let value = match v.kind {
            TokKind::Num(text) => match text.parse::<f64>() {
                Ok(x) if x.is_finite() => MaterialValue::Number { value: x, text },
                _ => {
                    return Err(self.err(
                        v.line,
                        format!("'{text}' is not a number (material key '{key}')"),
                    ));
                }
            },
            TokKind::Str(s) => MaterialValue::Text(s),
            TokKind::Ident(s) => MaterialValue::Text(s),
            other => {
                return Err(self.err(
                    v.line,
                    format!(
                        "expected a value after '{key}=', found {}",
                        other.describe()
                    ),
                ));
            }
        };
        Ok((value, v.line))
    }
}
