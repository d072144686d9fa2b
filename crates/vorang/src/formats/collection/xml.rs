//! The XML of the collection files (`.pvd`, `.pvtu`, `.vtm`) as a flat list of elements with
//! their attributes and lines. The three formats only list files and a few attributes — no
//! data — so one walk serves them all, and each format reads the elements it knows in document
//! order (nested `<Block>`s of a `.vtm` included).

use quick_xml::events::{BytesStart, Event};

use crate::error::ParseError;
use crate::formats::line_of;

/// One start (or empty) tag.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Element {
    pub(super) name: String,
    pub(super) attributes: Vec<(String, String)>,
    /// 1-based line of the tag.
    pub(super) line: usize,
    /// How many elements enclose it (`<VTKFile>` is at depth 0).
    pub(super) depth: usize,
}

impl Element {
    pub(super) fn attr(&self, key: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

/// At most this many elements: a collection lists files, and a larger one is not a collection
/// (this keeps the walk's memory proportional to a sane file, whatever the input).
const MAX_ELEMENTS: usize = 1 << 20;

/// Every start tag of `bytes`, in document order; `name` labels messages.
pub(super) fn elements(bytes: &[u8], name: &str) -> Result<Vec<Element>, ParseError> {
    let mut reader = quick_xml::Reader::from_reader(bytes);
    reader.config_mut().check_end_names = true;
    let mut out = Vec::new();
    let mut depth = 0usize;
    loop {
        let pos = reader.buffer_position() as usize;
        let event = reader.read_event().map_err(|e| {
            ParseError::new(
                name,
                line_of(bytes, reader.error_position() as usize),
                format!("malformed XML: {e}"),
            )
        })?;
        match event {
            Event::Eof => break,
            Event::Start(ref e) | Event::Empty(ref e) => {
                if out.len() >= MAX_ELEMENTS {
                    return Err(ParseError::new(
                        name,
                        line_of(bytes, pos),
                        format!("more than {MAX_ELEMENTS} XML elements: not a collection file"),
                    ));
                }
                out.push(element(e, line_of(bytes, pos), depth));
                if matches!(event, Event::Start(_)) {
                    depth += 1;
                }
            }
            Event::End(_) => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    Ok(out)
}

fn element(e: &BytesStart, line: usize, depth: usize) -> Element {
    let attributes = crate::formats::text::xml_attributes(e);
    Element {
        name: String::from_utf8_lossy(e.name().as_ref()).into_owned(),
        attributes,
        line,
        depth,
    }
}

/// The elements of a VTK XML file of `ty` (`<VTKFile type="ty">` first), or an error naming
/// what the file is instead.
pub(super) fn vtk_file(bytes: &[u8], name: &str, ty: &str) -> Result<Vec<Element>, ParseError> {
    let list = elements(bytes, name)?;
    match list.first() {
        Some(e) if e.name == "VTKFile" => {
            let found = e.attr("type").unwrap_or("");
            if found != ty {
                return Err(ParseError::new(
                    name,
                    e.line,
                    format!("VTKFile type=\"{found}\": expected type=\"{ty}\""),
                ));
            }
        }
        _ => {
            return Err(ParseError::new(
                name,
                1,
                format!("expected a VTK XML file starting with <VTKFile type=\"{ty}\" …>"),
            ));
        }
    }
    Ok(list)
}

/// The `type` of a VTK XML file from its first bytes (`<VTKFile type="…"`), if it is one.
pub(crate) fn vtk_type(head: &[u8]) -> Option<String> {
    let probe = &head[..head.len().min(4096)];
    let at = probe.windows(8).position(|w| w == b"<VTKFile")?;
    let rest = &probe[at..];
    let end = rest.iter().position(|&b| b == b'>').unwrap_or(rest.len());
    let tag = String::from_utf8_lossy(&rest[..end]);
    let after = tag.split("type=").nth(1)?;
    let quote = after.chars().next().filter(|c| *c == '"' || *c == '\'')?;
    Some(after[1..].split(quote).next()?.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_carry_lines_and_depth() {
        let text = b"<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n  <Collection>\n    <DataSet timestep=\"0.5\" file=\"a&amp;b.vtu\"/>\n  </Collection>\n</VTKFile>\n";
        let list = vtk_file(text, "c.pvd", "Collection").unwrap();
        assert_eq!(list.len(), 3);
        assert_eq!(list[2].name, "DataSet");
        assert_eq!(list[2].line, 4);
        assert_eq!(list[2].depth, 2);
        assert_eq!(list[2].attr("file"), Some("a&b.vtu"));
        let e = vtk_file(text, "c.pvd", "PUnstructuredGrid").unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("type=\"Collection\""), "{e}");
    }

    #[test]
    fn malformed_xml_is_located() {
        let e = elements(b"<VTKFile>\n<Collection>\n</VTKFile>", "x.pvd").unwrap_err();
        assert!(e.message.contains("malformed XML"), "{e}");
        assert_eq!(e.line, 3);
    }

    #[test]
    fn the_type_of_a_head() {
        assert_eq!(
            vtk_type(b"<?xml?>\n<VTKFile type='PolyData' version=\"1\">").as_deref(),
            Some("PolyData")
        );
        assert_eq!(vtk_type(b"# vtk DataFile"), None);
    }
}
