//! The ASCII header of a HyperMesh file (thesis B.2): the title line, `Materials`, the element
//! counts, the block declarations and the `Field` declarations.
//!
//! The header is tokenized first (`tokens`, so tokens may be separated by any or no whitespace,
//! as docs/formats.md, "HyperMesh files", allows) and then parsed statement by statement
//! (`statements`, and `materials` for the one statement that spans lines); every token
//! remembers its line so that a bad declaration is reported on its own line. The checks that
//! span statements (unique markers, no block both NULL and given) run last, here.

mod materials;
mod statements;
mod tokens;

use crate::data::{DataType, ElementKind, Materials};
use crate::error::ParseError;
use statements::{Cursor, Decl, DeclKeyword};
use tokens::{Tok, TokKind};

pub use tokens::is_marker_char;

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

/// The largest count a file may declare (docs/formats.md, "HyperMesh files"): 2³¹−1, the
/// largest HyperMesh `int` (32 bits), in which the blocks' 1-based indices are written.
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

    /// Tokenizes one header line (after the title). `#` starts a comment outside strings.
    pub fn push_line(&mut self, line_no: usize, line: &[u8]) -> Result<(), ParseError> {
        tokens::tokenize(&self.file, line_no, line, &mut self.tokens)
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
