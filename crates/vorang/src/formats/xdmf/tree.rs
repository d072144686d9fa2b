//! An XDMF file as a tree of elements (name, attributes, text, children, line). XDMF keeps
//! its light data in the XML — the element nesting says which DataItem belongs to which
//! Topology, Geometry or Attribute, and a DataItem's text is its values or where in an HDF5
//! file they are — so, unlike the collection files, it needs the tree and the text.

use quick_xml::events::{BytesStart, Event};

use crate::error::ParseError;
use crate::formats::line_of;

/// One element.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Node {
    /// The name as written (`Grid`, `xi:include`).
    pub name: String,
    pub attributes: Vec<(String, String)>,
    /// The text directly inside it (all pieces joined).
    pub text: String,
    pub children: Vec<Node>,
    /// 1-based line of the start tag.
    pub line: usize,
}

impl Node {
    /// An attribute's value (`key` matched exactly).
    pub fn attr(&self, key: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The children named `name`.
    pub fn all<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Node> + 'a {
        self.children.iter().filter(move |c| c.name == name)
    }

    /// The first child named `name`.
    pub fn first(&self, name: &str) -> Option<&Node> {
        self.children.iter().find(|c| c.name == name)
    }
}

/// At most this many elements and this deep: XDMF files list grids and data items, and
/// larger values of either are not a sane file (this bounds memory and recursion whatever
/// the input).
const MAX_ELEMENTS: usize = 1 << 20;
const MAX_DEPTH: usize = 64;

/// The root element of `bytes`; `name` labels messages.
pub fn parse(bytes: &[u8], name: &str) -> Result<Node, ParseError> {
    let mut reader = quick_xml::Reader::from_reader(bytes);
    reader.config_mut().check_end_names = true;
    let mut stack: Vec<Node> = Vec::new();
    let mut root = None;
    let mut count = 0usize;
    loop {
        let pos = reader.buffer_position() as usize;
        let event = reader.read_event().map_err(|e| {
            ParseError::new(
                name,
                line_of(bytes, reader.error_position() as usize),
                format!("malformed XML: {e}"),
            )
        })?;
        let line = || line_of(bytes, pos);
        match event {
            Event::Eof => break,
            Event::Start(ref e) | Event::Empty(ref e) => {
                count += 1;
                if count > MAX_ELEMENTS || stack.len() >= MAX_DEPTH {
                    return Err(ParseError::new(
                        name,
                        line(),
                        format!(
                            "more than {MAX_ELEMENTS} XML elements or deeper than {MAX_DEPTH}: not an XDMF file VoRANG reads"
                        ),
                    ));
                }
                let node = element(e, line());
                if matches!(event, Event::Start(_)) {
                    stack.push(node);
                } else {
                    close(&mut stack, &mut root, node);
                }
            }
            Event::End(_) => {
                if let Some(node) = stack.pop() {
                    close(&mut stack, &mut root, node);
                }
            }
            Event::Text(t) => {
                if let Some(top) = stack.last_mut() {
                    let text = t
                        .unescape()
                        .map(|c| c.into_owned())
                        .unwrap_or_else(|_| String::from_utf8_lossy(&t).into_owned());
                    top.text.push_str(&text);
                }
            }
            Event::CData(t) => {
                if let Some(top) = stack.last_mut() {
                    top.text.push_str(&String::from_utf8_lossy(&t));
                }
            }
            _ => {}
        }
    }
    root.ok_or_else(|| ParseError::new(name, 1, "no XML element: not an XDMF file"))
}

/// A finished element goes into its parent (or is the root).
fn close(stack: &mut [Node], root: &mut Option<Node>, node: Node) {
    match stack.last_mut() {
        Some(parent) => parent.children.push(node),
        None => {
            root.get_or_insert(node);
        }
    }
}

fn element(e: &BytesStart, line: usize) -> Node {
    let attributes = crate::formats::text::xml_attributes(e);
    Node {
        name: String::from_utf8_lossy(e.name().as_ref()).into_owned(),
        attributes,
        line,
        ..Node::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_nest_with_their_text_and_lines() {
        let xml = b"<Xdmf>\n<Domain>\n<DataItem Dimensions=\"2\">1 2</DataItem>\n<Empty/></Domain></Xdmf>";
        let root = parse(xml, "a.xdmf").unwrap();
        assert_eq!(root.name, "Xdmf");
        let domain = root.first("Domain").unwrap();
        let item = domain.first("DataItem").unwrap();
        assert_eq!((item.text.as_str(), item.line), ("1 2", 3));
        assert_eq!(item.attr("Dimensions"), Some("2"));
        assert!(domain.first("Empty").is_some());
    }

    #[test]
    fn malformed_xml_is_located() {
        let e = parse(b"<Xdmf>\n<Domain>\n</Grid>", "a.xdmf").unwrap_err();
        assert_eq!(e.line, 3, "{e}");
        assert!(parse(b"", "a.xdmf").is_err());
    }
}
