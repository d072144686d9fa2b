//! ParaView's file series (`.series`, e.g. `flow.vtu.series`): a JSON file
//!
//! ```json
//! { "file-series-version": "1.0",
//!   "files": [ { "name": "flow_0.vtu", "time": 0 }, { "name": "flow_1.vtu", "time": 0.5 } ] }
//! ```
//!
//! naming one file per step with its time (a missing `time` is the entry's position). The
//! schema is this fixed, so the file is read by a small JSON parser of its own rather than a
//! serialisation library: it reads all of JSON (RFC 8259: objects, arrays, strings with every
//! escape, numbers, `true`, `false`, `null`), keeps the line of every value for messages, nests
//! at most [`MAX_DEPTH`] deep, and never panics on any input (fuzzed:
//! `fuzz/fuzz_targets/collection_read.rs`).

use super::Entry;
use crate::error::ParseError;
use crate::formats::line_of;

/// How deep arrays and objects may nest (the schema needs 3).
pub const MAX_DEPTH: usize = 64;

/// A JSON value with the line it starts on.
#[derive(Debug, Clone, PartialEq)]
pub struct Value {
    pub kind: Kind,
    pub line: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Kind {
    Null,
    Bool(bool),
    Number(f64),
    String(String),
    Array(Vec<Value>),
    Object(Vec<(String, Value)>),
}

impl Kind {
    fn what(&self) -> &'static str {
        match self {
            Kind::Null => "null",
            Kind::Bool(_) => "a boolean",
            Kind::Number(_) => "a number",
            Kind::String(_) => "a string",
            Kind::Array(_) => "an array",
            Kind::Object(_) => "an object",
        }
    }
}

impl Value {
    /// The value of `key` in an object (the first, if repeated).
    pub fn get(&self, key: &str) -> Option<&Value> {
        match &self.kind {
            Kind::Object(members) => members.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }
}

/// The entries of a `.series` file, in file order.
pub fn entries(bytes: &[u8], name: &str) -> Result<Vec<Entry>, ParseError> {
    let root = parse(bytes, name)?;
    let err = |line: usize, msg: String| ParseError::new(name, line, msg);
    if !matches!(root.kind, Kind::Object(_)) {
        return Err(err(
            root.line,
            format!(
                "expected a JSON object {{\"file-series-version\": \"1.0\", \"files\": […]}}, found {}",
                root.kind.what()
            ),
        ));
    }
    match root.get("file-series-version").map(|v| (&v.kind, v.line)) {
        Some((Kind::String(v), _)) if v == "1.0" => {}
        Some((other, line)) => {
            let shown = match other {
                Kind::String(s) => format!("\"{s}\""),
                k => k.what().to_string(),
            };
            return Err(err(
                line,
                format!("\"file-series-version\" is {shown}: VoRANG reads version \"1.0\""),
            ));
        }
        None => {
            return Err(err(
                root.line,
                "no \"file-series-version\": expected ParaView's file series, {\"file-series-version\": \"1.0\", \"files\": […]}".into(),
            ));
        }
    }
    let files = root.get("files").ok_or_else(|| {
        err(
            root.line,
            "no \"files\": [ {\"name\": …, \"time\": …}, … ]".into(),
        )
    })?;
    let Kind::Array(list) = &files.kind else {
        return Err(err(
            files.line,
            format!("\"files\" must be an array, found {}", files.kind.what()),
        ));
    };
    if list.is_empty() {
        return Err(err(
            files.line,
            "the collection is empty: \"files\" lists no file".into(),
        ));
    }
    list.iter()
        .enumerate()
        .map(|(i, v)| entry(v, i, name))
        .collect()
}

/// One `{"name": …, "time": …}` entry (the `i`-th).
fn entry(v: &Value, i: usize, name: &str) -> Result<Entry, ParseError> {
    let err = |line: usize, msg: String| ParseError::new(name, line, msg);
    if !matches!(v.kind, Kind::Object(_)) {
        return Err(err(
            v.line,
            format!(
                "file {}: expected an object {{\"name\": …, \"time\": …}}, found {}",
                i + 1,
                v.kind.what()
            ),
        ));
    }
    let file = match v.get("name").map(|n| &n.kind) {
        Some(Kind::String(s)) if !s.trim().is_empty() => s.trim().to_string(),
        _ => {
            return Err(err(
                v.line,
                format!(
                    "file {}: needs \"name\": \"…\" (the file of the step)",
                    i + 1
                ),
            ));
        }
    };
    let time = match v.get("time") {
        None => i as f64,
        Some(Value {
            kind: Kind::Number(t),
            ..
        }) if t.is_finite() => *t,
        Some(t) => {
            return Err(err(
                t.line,
                format!(
                    "file {}: \"time\" must be a finite number, found {}",
                    i + 1,
                    t.kind.what()
                ),
            ));
        }
    };
    let line = v.get("name").map_or(v.line, |n| n.line);
    Ok(Entry { time, file, line })
}

/// Parses a whole JSON text (surrounding whitespace allowed, nothing else after the value).
pub fn parse(bytes: &[u8], name: &str) -> Result<Value, ParseError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let mut p = Parser {
        bytes,
        pos: 0,
        name,
    };
    let v = p.value(0)?;
    p.space();
    if p.pos < bytes.len() {
        return Err(p.err("unexpected text after the JSON value"));
    }
    Ok(v)
}

struct Parser<'a> {
    bytes: &'a [u8],
    pos: usize,
    name: &'a str,
}

impl Parser<'_> {
    fn err(&self, msg: &str) -> ParseError {
        ParseError::new(
            self.name,
            line_of(self.bytes, self.pos),
            format!("malformed JSON at byte {}: {msg}", self.pos),
        )
    }

    fn space(&mut self) {
        while self
            .bytes
            .get(self.pos)
            .is_some_and(|b| matches!(b, b' ' | b'\t' | b'\n' | b'\r'))
        {
            self.pos += 1;
        }
    }

    fn value(&mut self, depth: usize) -> Result<Value, ParseError> {
        self.space();
        let line = line_of(self.bytes, self.pos);
        let kind = match self.bytes.get(self.pos) {
            None => return Err(self.err("the text ends where a value was expected")),
            Some(b'{') | Some(b'[') if depth >= MAX_DEPTH => {
                return Err(self.err(&format!("nested more than {MAX_DEPTH} deep")));
            }
            Some(b'{') => self.object(depth)?,
            Some(b'[') => self.array(depth)?,
            Some(b'"') => Kind::String(self.string()?),
            Some(b't') => self.word("true", Kind::Bool(true))?,
            Some(b'f') => self.word("false", Kind::Bool(false))?,
            Some(b'n') => self.word("null", Kind::Null)?,
            Some(b'-' | b'0'..=b'9') => Kind::Number(self.number()?),
            Some(_) => {
                return Err(self
                    .err("expected a value (object, array, string, number, true, false or null)"));
            }
        };
        Ok(Value { kind, line })
    }

    fn word(&mut self, word: &str, kind: Kind) -> Result<Kind, ParseError> {
        if self.bytes[self.pos..].starts_with(word.as_bytes()) {
            self.pos += word.len();
            Ok(kind)
        } else {
            Err(self.err(&format!("expected {word}")))
        }
    }

    fn object(&mut self, depth: usize) -> Result<Kind, ParseError> {
        self.pos += 1;
        let mut members = Vec::new();
        self.space();
        if self.bytes.get(self.pos) == Some(&b'}') {
            self.pos += 1;
            return Ok(Kind::Object(members));
        }
        loop {
            self.space();
            if self.bytes.get(self.pos) != Some(&b'"') {
                return Err(self.err("expected a member name in double quotes"));
            }
            let key = self.string()?;
            self.space();
            if self.bytes.get(self.pos) != Some(&b':') {
                return Err(self.err("expected ':' after the member name"));
            }
            self.pos += 1;
            members.push((key, self.value(depth + 1)?));
            self.space();
            match self.bytes.get(self.pos) {
                Some(b',') => self.pos += 1,
                Some(b'}') => {
                    self.pos += 1;
                    return Ok(Kind::Object(members));
                }
                _ => return Err(self.err("expected ',' or '}' in the object")),
            }
        }
    }

    fn array(&mut self, depth: usize) -> Result<Kind, ParseError> {
        self.pos += 1;
        let mut items = Vec::new();
        self.space();
        if self.bytes.get(self.pos) == Some(&b']') {
            self.pos += 1;
            return Ok(Kind::Array(items));
        }
        loop {
            items.push(self.value(depth + 1)?);
            self.space();
            match self.bytes.get(self.pos) {
                Some(b',') => self.pos += 1,
                Some(b']') => {
                    self.pos += 1;
                    return Ok(Kind::Array(items));
                }
                _ => return Err(self.err("expected ',' or ']' in the array")),
            }
        }
    }

    /// A number as JSON writes it: `-? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?`.
    fn number(&mut self) -> Result<f64, ParseError> {
        let start = self.pos;
        let digits = |p: &mut Self| {
            let from = p.pos;
            while p.bytes.get(p.pos).is_some_and(u8::is_ascii_digit) {
                p.pos += 1;
            }
            p.pos > from
        };
        if self.bytes.get(self.pos) == Some(&b'-') {
            self.pos += 1;
        }
        let leading_zero = self.bytes.get(self.pos) == Some(&b'0');
        if !digits(self)
            || (leading_zero && self.pos - start > 1 + usize::from(self.bytes[start] == b'-'))
        {
            return Err(self.err("malformed number"));
        }
        if self.bytes.get(self.pos) == Some(&b'.') {
            self.pos += 1;
            if !digits(self) {
                return Err(self.err("malformed number: digits must follow '.'"));
            }
        }
        if matches!(self.bytes.get(self.pos), Some(b'e' | b'E')) {
            self.pos += 1;
            if matches!(self.bytes.get(self.pos), Some(b'+' | b'-')) {
                self.pos += 1;
            }
            if !digits(self) {
                return Err(self.err("malformed number: digits must follow the exponent"));
            }
        }
        let text = std::str::from_utf8(&self.bytes[start..self.pos]).unwrap_or("");
        text.parse::<f64>()
            .map_err(|_| self.err("malformed number"))
    }

    /// A string (at its opening quote), escapes resolved.
    fn string(&mut self) -> Result<String, ParseError> {
        self.pos += 1;
        let mut out: Vec<u8> = Vec::new();
        loop {
            let Some(&b) = self.bytes.get(self.pos) else {
                return Err(self.err("the string is not closed by '\"'"));
            };
            self.pos += 1;
            match b {
                b'"' => break,
                b'\\' => self.escape(&mut out)?,
                0..=0x1F => {
                    self.pos -= 1;
                    return Err(self.err("a control character inside a string (escape it)"));
                }
                _ => out.push(b),
            }
        }
        String::from_utf8(out).map_err(|_| self.err("the string is not valid UTF-8"))
    }

    fn escape(&mut self, out: &mut Vec<u8>) -> Result<(), ParseError> {
        let Some(&e) = self.bytes.get(self.pos) else {
            return Err(self.err("the string ends inside an escape"));
        };
        self.pos += 1;
        let c = match e {
            b'"' => '"',
            b'\\' => '\\',
            b'/' => '/',
            b'b' => '\u{8}',
            b'f' => '\u{c}',
            b'n' => '\n',
            b'r' => '\r',
            b't' => '\t',
            b'u' => self.unicode()?,
            _ => {
                self.pos -= 1;
                return Err(self.err(
                    "unknown escape (expected \\\" \\\\ \\/ \\b \\f \\n \\r \\t or \\uXXXX)",
                ));
            }
        };
        let mut buf = [0u8; 4];
        out.extend_from_slice(c.encode_utf8(&mut buf).as_bytes());
        Ok(())
    }

    /// `\uXXXX` (after the `u`), a surrogate pair as one character.
    fn unicode(&mut self) -> Result<char, ParseError> {
        let high = self.hex4()?;
        let code = if (0xD800..0xDC00).contains(&high) {
            if !self.bytes[self.pos..].starts_with(b"\\u") {
                return Err(self.err("a high surrogate without its low surrogate"));
            }
            self.pos += 2;
            let low = self.hex4()?;
            if !(0xDC00..0xE000).contains(&low) {
                return Err(self.err("a high surrogate without its low surrogate"));
            }
            0x10000 + ((high - 0xD800) << 10) + (low - 0xDC00)
        } else {
            high
        };
        char::from_u32(code).ok_or_else(|| self.err("an escape that is no character"))
    }

    fn hex4(&mut self) -> Result<u32, ParseError> {
        let digits = self
            .bytes
            .get(self.pos..self.pos + 4)
            .and_then(|d| std::str::from_utf8(d).ok())
            .filter(|d| d.bytes().all(|b| b.is_ascii_hexdigit()))
            .ok_or_else(|| self.err("\\u needs four hexadecimal digits"))?;
        let v = u32::from_str_radix(digits, 16).map_err(|_| self.err("bad \\u escape"))?;
        self.pos += 4;
        Ok(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paraview_series() {
        let text = br#"{
  "file-series-version" : "1.0",
  "files" : [
    { "name" : "flow_0.vtu", "time" : 0 },
    { "name" : "flow_1.vtu", "time" : 5.5e-1 },
    { "name" : "d\u00e9j\u00e0 \ud83d\ude00.vtu" }
  ]
}
"#;
        let e = entries(text, "flow.vtu.series").unwrap();
        assert_eq!(e.len(), 3);
        assert_eq!(
            (e[1].time, e[1].file.as_str(), e[1].line),
            (0.55, "flow_1.vtu", 5)
        );
        assert_eq!((e[2].time, e[2].file.as_str()), (2.0, "déjà 😀.vtu"));
    }

    #[test]
    fn json_values() {
        let v = parse(
            b" [1, -0.5e2, true, false, null, \"a\\n\\\"\", {}, []] ",
            "j",
        )
        .unwrap();
        let Kind::Array(items) = v.kind else { panic!() };
        assert_eq!(items[1].kind, Kind::Number(-50.0));
        assert_eq!(items[5].kind, Kind::String("a\n\"".into()));
        for bad in [
            "",
            "[",
            "[1,]",
            "{\"a\" 1}",
            "01",
            "1.",
            "-",
            "1e",
            "\"\\x\"",
            "\"a",
            "[1] 2",
            "tru",
            "\"\\ud800\"",
            "{\"a\":1,}",
            "\"\u{1}\"",
            "nul",
        ] {
            assert!(parse(bad.as_bytes(), "j").is_err(), "{bad:?}");
        }
        let deep = "[".repeat(MAX_DEPTH + 1) + &"]".repeat(MAX_DEPTH + 1);
        assert!(
            parse(deep.as_bytes(), "j")
                .unwrap_err()
                .message
                .contains("nested")
        );
        let ok = "[".repeat(MAX_DEPTH) + &"]".repeat(MAX_DEPTH);
        assert!(parse(ok.as_bytes(), "j").is_ok());
    }

    #[test]
    fn schema_errors_are_located() {
        let cases: [(&str, usize, &str); 6] = [
            ("[]", 1, "expected a JSON object"),
            ("{\"files\": []}", 1, "no \"file-series-version\""),
            (
                "{\"file-series-version\": \"2.0\",\n\"files\": []}",
                1,
                "version \"1.0\"",
            ),
            (
                "{\"file-series-version\": \"1.0\",\n\"files\": []}",
                2,
                "the collection is empty",
            ),
            (
                "{\"file-series-version\": \"1.0\",\n\"files\": [\n{\"time\": 1}]}",
                3,
                "needs \"name\"",
            ),
            (
                "{\"file-series-version\": \"1.0\", \"files\": [\n{\"name\": \"a\",\n \"time\": \"1\"}]}",
                3,
                "finite number",
            ),
        ];
        for (text, line, fragment) in cases {
            let e = entries(text.as_bytes(), "s.series").unwrap_err();
            assert_eq!(e.line, line, "{text}: {e}");
            assert!(e.message.contains(fragment), "{text}: {e}");
        }
    }

    #[test]
    fn random_bytes_never_panic() {
        let mut rng = crate::mesh::generate::SplitMix64(7);
        let alphabet = b"{}[]\":,0123456789-+.eE tfnrul\\\n\"name\"time\"files\"";
        for _ in 0..20_000 {
            let len = (rng.next_u64() % 40) as usize;
            let text: Vec<u8> = (0..len)
                .map(|_| alphabet[(rng.next_u64() % alphabet.len() as u64) as usize])
                .collect();
            let _ = entries(&text, "r.series");
        }
    }
}
