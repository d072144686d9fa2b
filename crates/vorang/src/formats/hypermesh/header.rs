//! The ASCII header of a HyperMesh file (thesis B.2): the title line, `Materials`, the element
//! counts, the block declarations and the `Field` declarations.
//!
//! The header is tokenized first (so tokens may be separated by any or no whitespace, SPEC §7
//! "Decisions (reading)") and then parsed statement by statement; every token remembers its line
//! so that a bad declaration is reported on its own line.

use crate::data::{DataType, ElementKind, ScalarType};
use crate::data::{Material, MaterialValue, Materials};
use crate::error::ParseError;

/// How the data blocks after the header are encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    Ascii,
    Binary,
}

impl Encoding {
    pub fn keyword(self) -> &'static str {
        match self {
            Encoding::Ascii => "ASCII",
            Encoding::Binary => "BINARY",
        }
    }
}

/// How triangles are coded (`Triangles { int[3] Nodes }` …).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TriangleCoding {
    Nodes,
    Edges,
    UpperLower,
}

/// How tetrahedra are coded (`Tetrahedra { int[4] Nodes }` …).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TetCoding {
    Nodes,
    Edges,
    Triangles,
}

/// What a block declaration describes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Target {
    Nodes,
    Edges,
    Triangles(TriangleCoding),
    Tetrahedra(TetCoding),
    Data(ElementKind),
}

impl Target {
    /// The element kind whose count gives the block's number of rows.
    pub fn element_kind(self) -> ElementKind {
        match self {
            Target::Nodes => ElementKind::Node,
            Target::Edges => ElementKind::Edge,
            Target::Triangles(_) => ElementKind::Triangle,
            Target::Tetrahedra(_) => ElementKind::Tetrahedron,
            Target::Data(kind) => kind,
        }
    }

    /// A short description for messages (`Tetrahedra by Nodes`, `NodeData`).
    pub fn describe(self) -> String {
        match self {
            Target::Nodes => "Nodes".into(),
            Target::Edges => "Edges".into(),
            Target::Triangles(c) => format!("Triangles by {c:?}"),
            Target::Tetrahedra(c) => format!("Tetrahedra by {c:?}"),
            Target::Data(kind) => kind.data_keyword().into(),
        }
    }
}

/// `Kind { type [word] } = @marker`.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockDecl {
    pub target: Target,
    pub ty: DataType,
    /// For data blocks: the optional denominator.
    pub denominator: Option<String>,
    pub marker: String,
    pub line: usize,
}

/// `Field ["name"] { type [denominator] } = Interpolator(@m1, …)`.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldDecl {
    pub name: Option<String>,
    pub ty: DataType,
    pub denominator: Option<String>,
    pub interpolator: String,
    pub markers: Vec<String>,
    pub line: usize,
}

/// A count line (`nNodes = 4`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Count {
    pub value: usize,
    pub line: usize,
}

/// The parsed header.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    pub encoding: Encoding,
    pub version: String,
    pub materials: Option<Materials>,
    /// Indexed by [`ElementKind::index`].
    pub counts: [Option<Count>; 5],
    pub blocks: Vec<BlockDecl>,
    /// `Kind = NULL` statements (explicitly absent), with their lines.
    pub nulls: Vec<(String, usize)>,
    pub fields: Vec<FieldDecl>,
}

impl Header {
    pub fn count(&self, kind: ElementKind) -> Option<Count> {
        self.counts[kind.index()]
    }
}

/// The largest count a file may declare (SPEC §7: counts lie in 0…2³¹−1).
pub const MAX_COUNT: u64 = (1 << 31) - 1;
/// The largest array length accepted in a type (`float[n]`); keeps size arithmetic far from
/// overflow while allowing any realistic vector.
pub const MAX_ARRAY: u64 = 1 << 20;

/// Parses the title line `# HyperMesh 3D ASCII 0.7`.
pub fn parse_title(file: &str, line: &[u8]) -> Result<(Encoding, String), ParseError> {
    let err = |msg: String| ParseError::new(file, 1, msg);
    let text = String::from_utf8_lossy(line);
    let expected = "expected the title line '# HyperMesh 3D ASCII 0.7' (or BINARY)";
    let Some(rest) = text.trim_start().strip_prefix('#') else {
        return Err(err(format!("{expected}, found '{}'", shorten(&text))));
    };
    let words: Vec<&str> = rest.split_whitespace().collect();
    if words.first() != Some(&"HyperMesh") {
        return Err(err(format!("{expected}, found '{}'", shorten(&text))));
    }
    match words.get(1) {
        Some(&"3D") => {}
        Some(&"2D") => {
            return Err(err(
                "2D HyperMesh files are not supported: VoRANG renders 3D tetrahedral meshes".into(),
            ));
        }
        other => {
            return Err(err(format!(
                "{expected}: the dimension must be 3D, found '{}'",
                other.unwrap_or(&"")
            )));
        }
    }
    let encoding = match words.get(2) {
        Some(&"ASCII") => Encoding::Ascii,
        Some(&"BINARY") => Encoding::Binary,
        other => {
            return Err(err(format!(
                "{expected}: the encoding must be ASCII or BINARY, found '{}'",
                other.unwrap_or(&"")
            )));
        }
    };
    let version = match words.get(3) {
        Some(v) if v.parse::<f64>().is_ok() => v.to_string(),
        other => {
            return Err(err(format!(
                "{expected}: expected a version number such as 0.7, found '{}'",
                other.unwrap_or(&"")
            )));
        }
    };
    if words.len() > 4 {
        return Err(err(format!(
            "{expected}: unexpected '{}' after the version",
            words[4]
        )));
    }
    Ok((encoding, version))
}

fn shorten(s: &str) -> String {
    let s = s.trim();
    if s.chars().count() > 60 {
        format!("{}…", s.chars().take(60).collect::<String>())
    } else {
        s.to_string()
    }
}

#[derive(Debug, Clone, PartialEq)]
enum TokKind {
    Ident(String),
    Num(String),
    Str(String),
    Marker(String),
    Punct(u8),
}

#[derive(Debug, Clone)]
struct Tok {
    kind: TokKind,
    line: usize,
}

impl TokKind {
    fn describe(&self) -> String {
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

/// Collects header lines and turns them into a [`Header`].
pub struct HeaderParser {
    file: String,
    tokens: Vec<Tok>,
}

impl HeaderParser {
    pub fn new(file: &str) -> Self {
        HeaderParser {
            file: file.to_string(),
            tokens: Vec::new(),
        }
    }

    fn err(&self, line: usize, msg: impl Into<String>) -> ParseError {
        ParseError::new(&self.file, line, msg)
    }

    /// Tokenizes one header line (after the title). `#` starts a comment outside strings.
    pub fn push_line(&mut self, line_no: usize, line: &[u8]) -> Result<(), ParseError> {
        let mut i = 0;
        while i < line.len() {
            let c = line[i];
            match c {
                b' ' | b'\t' | b'\r' | 0x0c | 0x0b => i += 1,
                b'#' => break,
                b'{' | b'}' | b'[' | b']' | b'=' | b',' | b'(' | b')' => {
                    self.tokens.push(Tok {
                        kind: TokKind::Punct(c),
                        line: line_no,
                    });
                    i += 1;
                }
                b'"' => {
                    let start = i + 1;
                    let Some(len) = line[start..].iter().position(|&b| b == b'"') else {
                        return Err(
                            self.err(line_no, "unterminated string: expected a closing '\"'")
                        );
                    };
                    let s = String::from_utf8_lossy(&line[start..start + len]).into_owned();
                    self.tokens.push(Tok {
                        kind: TokKind::Str(s),
                        line: line_no,
                    });
                    i = start + len + 1;
                }
                b'@' => {
                    let start = i + 1;
                    let len = line[start..]
                        .iter()
                        .take_while(|&&b| is_marker_char(b))
                        .count();
                    if len == 0 {
                        return Err(self.err(line_no, "expected a marker name after '@'"));
                    }
                    let s = String::from_utf8_lossy(&line[start..start + len]).into_owned();
                    self.tokens.push(Tok {
                        kind: TokKind::Marker(s),
                        line: line_no,
                    });
                    i = start + len;
                }
                c if c.is_ascii_alphabetic() || c == b'_' => {
                    let len = line[i..]
                        .iter()
                        .take_while(|&&b| b.is_ascii_alphanumeric() || b == b'_')
                        .count();
                    let s = String::from_utf8_lossy(&line[i..i + len]).into_owned();
                    self.tokens.push(Tok {
                        kind: TokKind::Ident(s),
                        line: line_no,
                    });
                    i += len;
                }
                c if c.is_ascii_digit() || matches!(c, b'+' | b'-' | b'.') => {
                    let len = line[i..]
                        .iter()
                        .take_while(|&&b| {
                            b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E')
                        })
                        .count();
                    let s = String::from_utf8_lossy(&line[i..i + len]).into_owned();
                    self.tokens.push(Tok {
                        kind: TokKind::Num(s),
                        line: line_no,
                    });
                    i += len;
                }
                other => {
                    let shown = if other.is_ascii_graphic() {
                        format!("'{}'", other as char)
                    } else {
                        format!("byte 0x{other:02x}")
                    };
                    return Err(self.err(line_no, format!("unexpected {shown} in the header")));
                }
            }
        }
        Ok(())
    }

    /// Parses the collected tokens. `encoding`/`version` come from the title line.
    pub fn finish(self, encoding: Encoding, version: String) -> Result<Header, ParseError> {
        let mut p = Cursor {
            file: &self.file,
            toks: &self.tokens,
            pos: 0,
        };
        let mut header = Header {
            encoding,
            version,
            materials: None,
            counts: [None; 5],
            blocks: Vec::new(),
            nulls: Vec::new(),
            fields: Vec::new(),
        };
        let mut materials_line = 0;
        while let Some(tok) = p.next().cloned() {
            let line = tok.line;
            let TokKind::Ident(word) = &tok.kind else {
                return Err(p.err(line, format!(
                    "expected a declaration (Materials, nNodes …, Nodes, Tetrahedra, NodeData …, Field), found {}",
                    tok.kind.describe()
                )));
            };
            if word == "Materials" {
                if header.materials.is_some() {
                    return Err(p.err(line, format!(
                        "a second Materials block (the first one starts on line {materials_line})"
                    )));
                }
                materials_line = line;
                header.materials = Some(p.materials(line)?);
            } else if let Some(kind) = ElementKind::ALL
                .iter()
                .copied()
                .find(|k| k.count_keyword() == word)
            {
                p.expect_punct(b'=', line, &format!("'=' after {word}"))?;
                let value = p.count_value(word, line)?;
                if let Some(prev) = header.counts[kind.index()] {
                    return Err(p.err(
                        line,
                        format!("{word} is given twice (first on line {})", prev.line),
                    ));
                }
                header.counts[kind.index()] = Some(Count { value, line });
            } else if word == "Field" {
                header.fields.push(p.field(line)?);
            } else if let Some(base) = DeclKeyword::from_word(word) {
                match p.declaration(base, line)? {
                    Decl::Null => header.nulls.push((word.clone(), line)),
                    Decl::Block(b) => header.blocks.push(b),
                }
            } else {
                return Err(p.err(line, format!(
                    "unknown keyword '{word}': expected Materials, nNodes, nEdges, nTriangles, nTetrahedra, nExtra, Nodes, Edges, Triangles, Tetrahedra, NodeData, EdgeData, TriangleData, TetrahedronData, ExtraData or Field"
                )));
            }
        }
        check_declarations(&self.file, &header)?;
        Ok(header)
    }
}

/// Checks that span several statements: unique markers, no duplicate geometry declarations, no
/// block declared both NULL and present.
fn check_declarations(file: &str, h: &Header) -> Result<(), ParseError> {
    use std::collections::HashMap;
    let mut markers: HashMap<&str, usize> = HashMap::new();
    let mut targets: HashMap<Target, usize> = HashMap::new();
    for b in &h.blocks {
        if let Some(first) = markers.insert(&b.marker, b.line) {
            return Err(ParseError::new(
                file,
                b.line,
                format!(
                    "marker @{} is already declared on line {first}: every block needs its own marker",
                    b.marker
                ),
            ));
        }
        if !matches!(b.target, Target::Data(_))
            && let Some(first) = targets.insert(b.target, b.line)
        {
            return Err(ParseError::new(
                file,
                b.line,
                format!(
                    "{} is declared twice (first on line {first})",
                    b.target.describe()
                ),
            ));
        }
    }
    for (word, line) in &h.nulls {
        let clash = h.blocks.iter().find(|b| decl_word(b.target) == word);
        if let Some(b) = clash {
            let (first, second) = if b.line < *line {
                (b.line, *line)
            } else {
                (*line, b.line)
            };
            return Err(ParseError::new(
                file,
                second,
                format!("{word} is declared NULL and also given a block (line {first})"),
            ));
        }
    }
    Ok(())
}

fn decl_word(t: Target) -> &'static str {
    match t {
        Target::Nodes => "Nodes",
        Target::Edges => "Edges",
        Target::Triangles(_) => "Triangles",
        Target::Tetrahedra(_) => "Tetrahedra",
        Target::Data(k) => k.data_keyword(),
    }
}

#[derive(Clone, Copy)]
enum DeclKeyword {
    Nodes,
    Edges,
    Triangles,
    Tetrahedra,
    Data(ElementKind),
}

impl DeclKeyword {
    fn from_word(w: &str) -> Option<DeclKeyword> {
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

enum Decl {
    Null,
    Block(BlockDecl),
}

struct Cursor<'a> {
    file: &'a str,
    toks: &'a [Tok],
    pos: usize,
}

impl Cursor<'_> {
    fn err(&self, line: usize, msg: impl Into<String>) -> ParseError {
        ParseError::new(self.file, line, msg)
    }

    fn next(&mut self) -> Option<&Tok> {
        let t = self.toks.get(self.pos);
        if t.is_some() {
            self.pos += 1;
        }
        t
    }

    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos)
    }

    /// Next token on `line`, or an error saying what was expected there.
    fn next_on(&mut self, line: usize, what: &str) -> Result<Tok, ParseError> {
        match self.toks.get(self.pos) {
            Some(t) if t.line == line => {
                self.pos += 1;
                Ok(t.clone())
            }
            _ => Err(self.err(line, format!("expected {what} before the end of the line"))),
        }
    }

    fn expect_punct(&mut self, c: u8, line: usize, what: &str) -> Result<(), ParseError> {
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

    fn count_value(&mut self, word: &str, line: usize) -> Result<usize, ParseError> {
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

    fn declaration(&mut self, kw: DeclKeyword, line: usize) -> Result<Decl, ParseError> {
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

    fn field(&mut self, line: usize) -> Result<FieldDecl, ParseError> {
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

    /// `Materials { { id=0, name="x", k=v, … }, … }`, possibly over several lines.
    fn materials(&mut self, open_line: usize) -> Result<Materials, ParseError> {
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
            match key.as_str() {
                "id" => match &value {
                    MaterialValue::Number { value: x, .. }
                        if x.fract() == 0.0 && (0.0..=255.0).contains(x) =>
                    {
                        id = Some(*x as u8)
                    }
                    _ => {
                        return Err(self.err(
                            v.line,
                            "material id must be a whole number 0…255 (a byte value)",
                        ));
                    }
                },
                "name" => name = Some(value.to_string()),
                _ => {
                    if props.iter().any(|(k, _)| *k == key) {
                        return Err(
                            self.err(v.line, format!("material key '{key}' is given twice"))
                        );
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

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(lines: &[&str]) -> Result<Header, ParseError> {
        let mut p = HeaderParser::new("t.hmesh");
        for (i, l) in lines.iter().enumerate() {
            p.push_line(i + 2, l.as_bytes())?;
        }
        p.finish(Encoding::Ascii, "0.7".into())
    }

    #[test]
    fn title_line_variants() {
        assert_eq!(
            parse_title("f", b"# HyperMesh 3D ASCII 0.7").unwrap().0,
            Encoding::Ascii
        );
        assert_eq!(
            parse_title("f", b"#HyperMesh 3D BINARY 0.6").unwrap().0,
            Encoding::Binary
        );
        assert!(
            parse_title("f", b"# HyperMesh 2D ASCII 0.7")
                .unwrap_err()
                .message
                .contains("2D")
        );
        assert!(parse_title("f", b"# HyperMesh 3D UTF8 0.7").is_err());
        assert!(parse_title("f", b"HyperMesh 3D ASCII 0.7").is_err());
        assert!(parse_title("f", b"# HyperMesh 3D ASCII").is_err());
    }

    #[test]
    fn tokens_need_no_whitespace() {
        let h = parse(&[
            "nTetrahedra=12 nNodes =4",
            "Tetrahedra{int[4] Nodes}=@2",
            "Field\"t\"{double Temperature}=Linear(@5)",
            "NodeData{double}=@5  # trailing comment",
        ])
        .unwrap();
        assert_eq!(h.count(ElementKind::Tetrahedron).unwrap().value, 12);
        assert_eq!(h.count(ElementKind::Node).unwrap().value, 4);
        assert_eq!(h.blocks[0].target, Target::Tetrahedra(TetCoding::Nodes));
        assert_eq!(h.fields[0].name.as_deref(), Some("t"));
        assert_eq!(h.fields[0].denominator.as_deref(), Some("Temperature"));
        assert_eq!(h.blocks[1].marker, "5");
    }

    #[test]
    fn materials_span_lines_and_keep_extra_keys() {
        let h = parse(&[
            "Materials {",
            "  { id=0, name=\"Tumor\", eps=1.25, sigma= 986 },",
            "  { id=1, name=\"Bone\", rho=1.9e3 }",
            "}",
        ])
        .unwrap();
        let m = h.materials.unwrap();
        assert_eq!(m.list.len(), 2);
        assert_eq!(m.list[0].prop("sigma"), Some(986.0));
        assert_eq!(m.list[1].prop("rho"), Some(1900.0));
        assert_eq!(m.list[1].name, "Bone");
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse(&[
            "nNodes = 4",
            "Nodes { float[3] Coordinates } = @1",
            "Nodes { float[3] } = @2",
        ])
        .unwrap_err();
        assert_eq!(e.line, 4);
        let e = parse(&["nNodes = 4000000000"]).unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("out of range"));
        let e = parse(&["Materials {", "{ id=0, name=\"a\" }", "nNodes = 3"]).unwrap_err();
        assert_eq!(e.line, 2, "{e}");
        let e = parse(&["NodeData { float } = @1", "EdgeData { float } = @1"]).unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.message.contains("already declared"));
        let e = parse(&["Tetrahedra { float[4] Nodes } = @1"]).unwrap_err();
        assert!(e.message.contains("integer"), "{e}");
        let e = parse(&["Nodes { quad[3] Coordinates } = @1"]).unwrap_err();
        assert!(e.message.contains("unknown type"), "{e}");
        let e = parse(&["Foo = 3"]).unwrap_err();
        assert!(e.message.contains("unknown keyword 'Foo'"), "{e}");
        let e = parse(&["Nodes = NULL", "Nodes { double[3] } = @1"]).unwrap_err();
        assert_eq!(e.line, 3);
    }

    #[test]
    fn null_declarations_are_accepted() {
        let h = parse(&["Nodes = NULL", "EdgeData = NULL"]).unwrap();
        assert_eq!(h.nulls.len(), 2);
        assert!(h.blocks.is_empty());
    }
}
