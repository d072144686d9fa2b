//! The map file parser (thesis appendix C).
//!
//! ```text
//! # VoRANG Colormap 1.0
//! DataField 0
//! CategoryField 1
//! SIMPLE_EMITTER field:global from:0 to:6 @1
//! CONST_CELL field:1 from:6 to:7 @2
//! @1
//! 0 0 0      0
//! 25 25 0    12.3537998
//! @2
//! 0 1 5      6
//! ```
//!
//! Method lines come before the first `@marker`; a parameter block runs to the next marker or
//! the end of the file and may be shared by several lines. `field:`, `from:` and `to:` may be
//! written with or without a space after the colon.

use std::collections::HashMap;
use std::path::Path;

use super::block::{ParamBlock, Row};
use super::{
    ALPHA_METHODS, AlphaShading, COLOR_METHODS, ColorShading, FieldRef, Interval, MapField,
    MapFile, MapKind, MethodInfo, MethodLine, names,
};
use crate::error::{Error, ParseError, Warning};
use crate::numbers::parse_f64;

/// The registry of a map kind.
pub trait Registry: 'static {
    const KIND: MapKind;
    fn methods() -> &'static [MethodInfo<Self>];
}

impl Registry for dyn ColorShading {
    const KIND: MapKind = MapKind::Color;
    fn methods() -> &'static [MethodInfo<Self>] {
        COLOR_METHODS
    }
}

impl Registry for dyn AlphaShading {
    const KIND: MapKind = MapKind::Alpha;
    fn methods() -> &'static [MethodInfo<Self>] {
        ALPHA_METHODS
    }
}

/// Reads a colormap (`T = dyn ColorShading`) or alphamap (`T = dyn AlphaShading`) file.
pub fn read_map<T: Registry + ?Sized>(path: &Path) -> Result<(MapFile<T>, Vec<Warning>), Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    Ok(parse_map::<T>(&bytes, &path.display().to_string())?)
}

/// A method line before its block is resolved.
struct PendingLine {
    info: &'static str,
    index: usize,
    field: Option<MapField>,
    interval: Option<Interval>,
    marker: Option<String>,
    line: usize,
}

/// The part of a line before a `#` comment; a `#` inside a quoted field name is part of it.
fn strip_comment(line: &str) -> &str {
    let mut quoted = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '#' if !quoted => return &line[..i],
            _ => {}
        }
    }
    line
}

/// Whitespace-separated words, where a double-quoted name (`"heat flux"`, also after a key as
/// in `field:"heat flux"`) stays one word with its quotes. `Err` for an unclosed quote.
fn split_words(content: &str) -> Result<Vec<&str>, ()> {
    let mut words = Vec::new();
    let mut start: Option<usize> = None;
    let mut quoted = false;
    for (i, c) in content.char_indices() {
        if c == '"' {
            quoted = !quoted;
            start.get_or_insert(i);
        } else if c.is_whitespace() && !quoted {
            if let Some(s) = start.take() {
                words.push(&content[s..i]);
            }
        } else {
            start.get_or_insert(i);
        }
    }
    if quoted {
        return Err(());
    }
    if let Some(s) = start {
        words.push(&content[s..]);
    }
    Ok(words)
}

/// A field reference word: a whole number ≥ 0 or a name in double quotes (the name is taken
/// exactly as written between the quotes). A complex field's part (`abs(0)`) is
/// [`MapField::parse`].
pub(super) fn field_ref(word: &str) -> Option<FieldRef> {
    if let Some(inner) = word.strip_prefix('"').and_then(|w| w.strip_suffix('"')) {
        if inner.is_empty() || inner.contains('"') {
            return None;
        }
        return Some(FieldRef::Name(inner.to_string()));
    }
    word.parse::<usize>().ok().map(FieldRef::Number)
}

/// Parses map text; `file` labels messages.
pub fn parse_map<T: Registry + ?Sized>(
    bytes: &[u8],
    file: &str,
) -> Result<(MapFile<T>, Vec<Warning>), ParseError> {
    // A UTF-8 byte-order mark (as some Windows editors write) is not part of the title.
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let text = String::from_utf8_lossy(bytes);
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let title = T::KIND.title();
    check_title::<T>(file, lines.next().map(|(_, l)| l))?;

    let mut s = Statements {
        file,
        data_field: None,
        category: None,
        pending: Vec::new(),
        blocks: HashMap::new(),
        current: None,
    };
    for (n, raw) in lines {
        s.line::<T>(n, raw)?;
    }
    if let Some(prev) = s.current.take() {
        s.blocks.insert(prev.marker.clone(), prev);
    }
    if s.pending.is_empty() {
        return Err(ParseError::new(
            file,
            1,
            format!(
                "this {title} has no method line: expected e.g. 'SIMPLE_EMITTER @1' before the parameter blocks"
            ),
        ));
    }
    let warnings = category_warnings(file, s.category.is_some(), &s.pending);
    let lines_out = method_lines::<T>(file, s.pending, &s.blocks)?;
    let (data_field, data_field_line) = s.data_field.unwrap_or((MapField::from(0), 1));
    Ok((
        MapFile {
            file: file.to_string(),
            data_field,
            data_field_line,
            category: s.category,
            lines: lines_out,
        },
        warnings,
    ))
}

/// What the lines of a map file have given so far.
struct Statements<'f> {
    file: &'f str,
    data_field: Option<(MapField, usize)>,
    category: Option<(MapField, usize)>,
    /// Method lines, in file order, their blocks not yet resolved.
    pending: Vec<PendingLine>,
    /// Parameter blocks by marker.
    blocks: HashMap<String, ParamBlock>,
    /// The block whose rows are being read.
    current: Option<ParamBlock>,
}

impl Statements<'_> {
    fn err(&self, line: usize, msg: String) -> ParseError {
        ParseError::new(self.file, line, msg)
    }

    /// Line `n`: blank or a comment, a marker, a row of the current block, or (before the
    /// first marker) a statement.
    fn line<T: Registry + ?Sized>(&mut self, n: usize, raw: &str) -> Result<(), ParseError> {
        let content = strip_comment(raw).trim();
        if content.is_empty() {
            return Ok(());
        }
        if let Some(name) = content.strip_prefix('@') {
            return self.marker(n, content, name);
        }
        if let Some(block) = &mut self.current {
            return block_row(self.file, block, n, content);
        }
        self.statement::<T>(n, content)
    }

    /// `@name`: the start of a parameter block, which runs to the next marker.
    fn marker(&mut self, n: usize, content: &str, name: &str) -> Result<(), ParseError> {
        let valid = !name.is_empty()
            && name
                .bytes()
                .all(crate::formats::hypermesh::header::is_marker_char);
        if !valid {
            return Err(self.err(
                n,
                format!("expected a marker line such as '@1', found '{content}'"),
            ));
        }
        if let Some(prev) = self.current.take() {
            self.blocks.insert(prev.marker.clone(), prev);
        }
        if let Some(first) = self.blocks.get(name) {
            return Err(self.err(
                n,
                format!("block @{name} appears twice (first on line {})", first.line),
            ));
        }
        self.current = Some(ParamBlock {
            marker: name.to_string(),
            line: n,
            rows: Vec::new(),
        });
        Ok(())
    }

    /// `DataField …`, `CategoryField …` or a method line.
    fn statement<T: Registry + ?Sized>(
        &mut self,
        n: usize,
        content: &str,
    ) -> Result<(), ParseError> {
        let Ok(all_words) = split_words(content) else {
            return Err(self.err(
                n,
                "a field name in double quotes is not closed: expected e.g. \"temperature\"".into(),
            ));
        };
        let mut words = all_words.into_iter();
        let Some(first) = words.next() else {
            return Ok(());
        };
        match first {
            "DataField" | "CategoryField" => {
                let slot = if first == "DataField" {
                    &mut self.data_field
                } else {
                    &mut self.category
                };
                if let Some((_, l)) = slot {
                    return Err(ParseError::new(
                        self.file,
                        n,
                        format!("{first} is given twice (first on line {l})"),
                    ));
                }
                let v = words.next().and_then(MapField::parse);
                let (Some(v), None) = (v, words.next()) else {
                    return Err(ParseError::new(
                        self.file,
                        n,
                        format!(
                            "expected '{first} <field number>' (a whole number ≥ 0) or '{first} \"<field name>\"', for a complex field inside re(…), im(…) or abs(…)"
                        ),
                    ));
                };
                *slot = Some((v, n));
            }
            name => {
                let Some(index) = T::methods().iter().position(|m| m.name == name) else {
                    return Err(self.err(
                        n,
                        format!(
                            "unknown {} method '{name}': expected one of {}",
                            T::KIND.title().to_lowercase(),
                            names(T::methods())
                        ),
                    ));
                };
                let rest: Vec<&str> = words.collect();
                self.pending.push(method_options(
                    self.file,
                    n,
                    &rest,
                    index,
                    T::methods()[index].name,
                )?);
            }
        }
        Ok(())
    }
}

/// A row of numbers of the parameter block `block`.
fn block_row(
    file: &str,
    block: &mut ParamBlock,
    n: usize,
    content: &str,
) -> Result<(), ParseError> {
    let mut numbers = Vec::new();
    for tok in content.split_whitespace() {
        match parse_f64(tok) {
            Some(v) if v.abs() > crate::data::MAX_MAGNITUDE => {
                return Err(ParseError::new(
                    file,
                    n,
                    format!(
                        "block @{}: {tok} is too large: numbers up to ±{:e} are accepted",
                        block.marker,
                        crate::data::MAX_MAGNITUDE
                    ),
                ));
            }
            Some(v) => numbers.push(v),
            None => {
                return Err(ParseError::new(
                    file,
                    n,
                    format!("block @{}: expected numbers, found '{tok}'", block.marker),
                ));
            }
        }
    }
    block.rows.push(Row { line: n, numbers });
    Ok(())
}

/// Without a CategoryField only the first method line applies: a warning if the file seems to
/// expect more (intervals, or several method lines).
fn category_warnings(file: &str, has_category: bool, pending: &[PendingLine]) -> Vec<Warning> {
    let mut warnings = Vec::new();
    if !has_category {
        if let Some(p) = pending.iter().find(|p| p.interval.is_some()) {
            warnings.push(Warning {
                file: file.into(),
                line: Some(p.line),
                message: "from:/to: select by the CategoryField's value, but there is no CategoryField line: the first method line applies everywhere".into(),
            });
        } else if pending.len() > 1 {
            warnings.push(Warning {
                file: file.into(),
                line: Some(pending[1].line),
                message: "without a CategoryField only the first method line is used".into(),
            });
        }
    }
    warnings
}

/// Each method line with its parameter block, built into its method.
fn method_lines<T: Registry + ?Sized>(
    file: &str,
    pending: Vec<PendingLine>,
    blocks: &HashMap<String, ParamBlock>,
) -> Result<Vec<MethodLine<T>>, ParseError> {
    let err = |line: usize, msg: String| ParseError::new(file, line, msg);
    let mut lines_out = Vec::with_capacity(pending.len());
    for p in pending {
        let info = &T::methods()[p.index];
        let block = match (&p.marker, info.needs_block) {
            (Some(m), true) => Some(blocks.get(m).ok_or_else(|| {
                err(
                    p.line,
                    format!("{}: there is no parameter block @{m} in this file", p.info),
                )
            })?),
            (None, true) => {
                return Err(err(
                    p.line,
                    format!(
                        "{} needs a parameter block ({}): expected '@marker' on this line",
                        p.info, info.params
                    ),
                ));
            }
            (_, false) => None,
        };
        let method = (info.build)(block).map_err(|e| {
            let line = if e.line == 0 { p.line } else { e.line };
            err(line, format!("{}: {}", p.info, e.message))
        })?;
        lines_out.push(MethodLine {
            name: info.name,
            method,
            field: p.field,
            interval: p.interval,
            line: p.line,
        });
    }
    Ok(lines_out)
}

fn check_title<T: Registry + ?Sized>(file: &str, line: Option<&str>) -> Result<(), ParseError> {
    let title = T::KIND.title();
    let expected = format!("expected the title line '# VoRANG {title} 1.0'");
    let line = line.unwrap_or("");
    let words: Vec<&str> = line
        .trim_start()
        .strip_prefix('#')
        .unwrap_or("")
        .split_whitespace()
        .collect();
    let other = if T::KIND == MapKind::Color {
        "Alphamap"
    } else {
        "Colormap"
    };
    match words.as_slice() {
        ["VoRANG", kind, version] if *kind == title && parse_f64(version).is_some() => Ok(()),
        ["VoRANG", kind, ..] if *kind == other => Err(ParseError::new(
            file,
            1,
            format!("this is an {other} file; {expected}"),
        )),
        _ => Err(ParseError::new(
            file,
            1,
            format!("{expected}, found '{}'", line.trim()),
        )),
    }
}

/// `[field:n|global] [from:v] [to:v] [@marker]` after the method name.
fn method_options(
    file: &str,
    n: usize,
    words: &[&str],
    index: usize,
    name: &'static str,
) -> Result<PendingLine, ParseError> {
    let err = |msg: String| ParseError::new(file, n, msg);
    let mut field: Option<Option<MapField>> = None;
    let mut from: Option<f64> = None;
    let mut to: Option<f64> = None;
    let mut marker: Option<String> = None;
    let mut i = 0;
    while i < words.len() {
        let w = words[i];
        i += 1;
        if let Some(m) = w.strip_prefix('@') {
            if marker.is_some() {
                return Err(err(format!(
                    "{name}: a second marker '{w}'; a method line takes one"
                )));
            }
            if m.is_empty()
                || !m
                    .bytes()
                    .all(crate::formats::hypermesh::header::is_marker_char)
            {
                return Err(err(format!("{name}: '{w}' is not a marker such as @1")));
            }
            marker = Some(m.to_string());
            continue;
        }
        let Some((key, value)) = w.split_once(':') else {
            return Err(err(format!(
                "{name}: unexpected '{w}': expected field:, from:, to: or @marker"
            )));
        };
        // `from: 3` — the value is the next word.
        let value = if value.is_empty() {
            let Some(v) = words.get(i) else {
                return Err(err(format!("{name}: expected a value after '{key}:'")));
            };
            i += 1;
            *v
        } else {
            value
        };
        match key {
            "field" => {
                if field.is_some() {
                    return Err(err(format!("{name}: field: is given twice")));
                }
                field = Some(match value {
                    "global" => None,
                    v => Some(MapField::parse(v).ok_or_else(|| {
                        err(format!(
                            "{name}: expected field:global or field:<number>, found field:{v} (a field name goes in double quotes: field:\"name\"; a complex field's part is field:re(n), field:im(n) or field:abs(n))"
                        ))
                    })?),
                });
            }
            "from" | "to" => {
                let slot = if key == "from" { &mut from } else { &mut to };
                if slot.is_some() {
                    return Err(err(format!("{name}: {key}: is given twice")));
                }
                *slot = Some(parse_f64(value).ok_or_else(|| {
                    err(format!(
                        "{name}: expected a number after '{key}:', found '{value}'"
                    ))
                })?);
            }
            other => {
                return Err(err(format!(
                    "{name}: unknown option '{other}:': expected field:, from: or to:"
                )));
            }
        }
    }
    if let (Some(f), Some(t)) = (from, to)
        && f >= t
    {
        return Err(err(format!(
            "{name}: the category interval [from:{f}, to:{t}) is empty: from must be less than to"
        )));
    }
    let interval = (from.is_some() || to.is_some()).then_some(Interval { from, to });
    Ok(PendingLine {
        info: name,
        index,
        field: field.flatten(),
        interval,
        marker,
        line: n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::{ColorMap, Point};

    fn color(text: &str) -> Result<ColorMap, ParseError> {
        parse_map::<dyn ColorShading>(text.as_bytes(), "c.map").map(|(m, _)| m)
    }

    #[test]
    fn the_thesis_example_parses() {
        let m = color(
            "# VoRANG Colormap 1.0\nDataField 0\nCategoryField 1\n\nSIMPLE_EMITTER field:global from:0 to:6 @1\nSIMPLE_EMITTER field:global from:7 to:9 @1\nCONST_CELL field:1 from:6 to:7 @2\n\n@1\n0 0 0      0\n0 0 0      5\n0.5 0.1 0  7\n1 0.3 0    10\n10 7 0     12.0\n15 12 0    12.2\n25 25 0    12.3537998\n\n@2\n0 1 5      6\n",
        )
        .unwrap();
        assert_eq!(m.category, Some((1.into(), 3)));
        assert_eq!(m.lines.len(), 3);
        assert_eq!(m.lines[2].field, Some(1.into()));
        assert_eq!(
            m.lines[0].interval,
            Some(Interval {
                from: Some(0.0),
                to: Some(6.0)
            })
        );
        let p = Point {
            value: &[8.5],
            cell: 0,
            pos: [0.0; 3],
        };
        assert_eq!(m.lines[1].method.color(&p, 0.0), [0.75, 0.2, 0.0]);
    }

    #[test]
    fn fields_may_be_named_in_double_quotes() {
        let m = color(
            "# VoRANG Colormap 1.0\nDataField \"temperature\"  # the solution\nCategoryField \"material # 2\"\nSIMPLE_EMITTER from:0 to:1 @1\nCONST_CELL field:\"heat flux\" from:1 @2\nCONST_CELL field: \"material\" from:2 @2\n@1\n0 0 0 0\n1 1 1 1\n@2\n1 0 0 1\n",
        )
        .unwrap();
        let name = |s: &str| MapField::from(FieldRef::Name(s.into()));
        assert_eq!(m.data_field, name("temperature"));
        assert_eq!(m.category, Some((name("material # 2"), 3)));
        assert_eq!(m.lines[1].field, Some(name("heat flux")));
        assert_eq!(m.lines[2].field, Some(name("material")));
        for bad in [
            "DataField temperature",
            "DataField \"temperature",
            "DataField \"\"",
        ] {
            let e = color(&format!(
                "# VoRANG Colormap 1.0\n{bad}\nCONSTANT @1\n@1\n1 0 0\n"
            ))
            .unwrap_err();
            assert_eq!(e.line, 2, "{bad}: {e}");
        }
    }

    #[test]
    fn options_may_have_a_space_after_the_colon() {
        let m = color("# VoRANG Colormap 1.0\nCategoryField 2\nCONSTANT field: 3 from: -1 to: 2.5 @a\n@a\n1 2 3\n").unwrap();
        assert_eq!(m.lines[0].field, Some(3.into()));
        assert_eq!(
            m.lines[0].interval,
            Some(Interval {
                from: Some(-1.0),
                to: Some(2.5)
            })
        );
    }

    #[test]
    fn complex_parts_are_written_where_the_field_is_named() {
        use crate::mapping::Part;
        let m = color("# VoRANG Colormap 1.0\nDataField abs(0)\nCategoryField re(\"z\")\nCONSTANT from:0 @a\nSIMPLE_EMITTER field: im(2) to:0 @b\n@a\n1 2 3\n@b\n0 0 0 0\n").unwrap();
        assert_eq!(m.data_field.part, Some(Part::Abs));
        assert_eq!(m.data_field.field, FieldRef::Number(0));
        let c = m.category.unwrap().0;
        assert_eq!(
            (c.field, c.part),
            (FieldRef::Name("z".into()), Some(Part::Re))
        );
        assert_eq!(m.lines[1].field.as_ref().unwrap().part, Some(Part::Im));
        for bad in ["DataField mod(0)", "DataField abs(x)", "DataField abs 0"] {
            let e = color(&format!(
                "# VoRANG Colormap 1.0\n{bad}\nCONSTANT @1\n@1\n1 0 0\n"
            ))
            .unwrap_err();
            assert_eq!(e.line, 2, "{bad}: {e}");
            assert!(e.message.contains("abs(…)"), "{e}");
        }
        let e =
            color("# VoRANG Colormap 1.0\nCONSTANT field:modulus(1) @1\n@1\n1 0 0\n").unwrap_err();
        assert!(e.message.contains("field:abs(n)"), "{e}");
    }

    #[test]
    fn errors_name_the_line() {
        let e = color("# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n2\n").unwrap_err();
        assert_eq!(e.line, 1);
        assert!(e.message.contains("Alphamap"), "{e}");
        let e = color("# VoRANG Colormap 1.0\nDataField 0\nGLOW @1\n").unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.message.contains("CONSTANT, IDENTITY"), "{e}");
        let e =
            color("# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 0 1\n1 1 1 1\n").unwrap_err();
        assert_eq!(e.line, 5);
        let e = color("# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@2\n0 0 0 1\n").unwrap_err();
        assert_eq!(e.line, 2);
        let e = color("# VoRANG Colormap 1.0\nSIMPLE_EMITTER\n").unwrap_err();
        assert_eq!(e.line, 2);
        let e = color("# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 1\n").unwrap_err();
        assert_eq!(e.line, 4);
        let e = color("# VoRANG Colormap 1.0\nCONSTANT @1\n@1\n1 1 1\n@1\n2 2 2\n").unwrap_err();
        assert_eq!(e.line, 5);
        let e = color("# VoRANG Colormap 1.0\nCONSTANT from:2 to:1 @1\n@1\n1 1 1\n").unwrap_err();
        assert_eq!(e.line, 2);
    }

    #[test]
    fn identity_needs_no_block_and_ranges_without_category_warn() {
        let (m, w) =
            parse_map::<dyn ColorShading>(b"# VoRANG Colormap 1.0\nIDENTITY from:0 to:1\n", "c")
                .unwrap();
        assert_eq!(m.lines[0].name, "IDENTITY");
        assert_eq!(w.len(), 1);
    }
}
