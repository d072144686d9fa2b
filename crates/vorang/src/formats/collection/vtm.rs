//! Multi-block data sets (`.vtm`): `<VTKFile type="vtkMultiBlockDataSet">` whose
//! `<vtkMultiBlockDataSet>` holds `<DataSet index=… name=… file=…/>` leaves, nested `<Block>`s
//! of more of them, and `<Piece>`s (multi-piece blocks), as ParaView, VTK's
//! `vtkXMLMultiBlockDataWriter` and many coupled solvers write them (one block per region or
//! per process). Every leaf with a file is listed in document order, nested blocks followed;
//! which of them are unstructured grids — merged into one volume — and which are other block
//! types, skipped with a warning, is decided when the step is read ([`super::step`]), from
//! each file's content. Leaves without a file are empty blocks.

use super::Entry;
use super::xml::vtk_file;
use crate::error::ParseError;

/// A leaf's file with its line, and the name of the block (its own `name`, or the enclosing
/// block's) for messages.
#[derive(Debug, Clone, PartialEq)]
pub struct Leaf {
    pub entry: Entry,
    pub name: Option<String>,
}

/// The files a `.vtm` lists, in document order.
pub fn leaves(bytes: &[u8], name: &str) -> Result<Vec<Leaf>, ParseError> {
    let elements = vtk_file(bytes, name, "vtkMultiBlockDataSet")?;
    let mut out = Vec::new();
    // The names of the enclosing blocks, by depth.
    let mut blocks: Vec<Option<String>> = Vec::new();
    for e in &elements {
        blocks.truncate(e.depth);
        if e.name == "Block" || e.name == "Piece" {
            blocks.resize(e.depth, None);
            blocks.push(e.attr("name").map(str::to_string));
            continue;
        }
        if e.name != "DataSet" {
            continue;
        }
        let Some(file) = e.attr("file").map(str::trim).filter(|f| !f.is_empty()) else {
            continue;
        };
        let name = e
            .attr("name")
            .map(str::to_string)
            .or_else(|| blocks.iter().rev().flatten().next().cloned());
        out.push(Leaf {
            entry: Entry {
                time: 0.0,
                file: file.to_string(),
                line: e.line,
            },
            name,
        });
    }
    if out.is_empty() {
        return Err(ParseError::new(
            name,
            elements.first().map_or(1, |e| e.line),
            "the collection is empty: no block lists a file (<DataSet file=\"…\"/>)",
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_blocks_are_followed() {
        let text = br#"<?xml version="1.0"?>
<VTKFile type="vtkMultiBlockDataSet" version="1.0">
  <vtkMultiBlockDataSet>
    <DataSet index="0" name="fluid" file="m/m_0.vtu"/>
    <Block index="1" name="solid">
      <DataSet index="0" file="m/m_1.vtu"/>
      <DataSet index="1" file="m/m_2.vtp"/>
      <DataSet index="2"/>
    </Block>
    <DataSet index="2" file="m/m_3.vtu"/>
  </vtkMultiBlockDataSet>
</VTKFile>
"#;
        let l = leaves(text, "m.vtm").unwrap();
        let got: Vec<_> = l
            .iter()
            .map(|l| (l.entry.file.as_str(), l.entry.line, l.name.as_deref()))
            .collect();
        assert_eq!(
            got,
            [
                ("m/m_0.vtu", 4, Some("fluid")),
                ("m/m_1.vtu", 6, Some("solid")),
                ("m/m_2.vtp", 7, Some("solid")),
                ("m/m_3.vtu", 10, None),
            ]
        );
    }

    #[test]
    fn no_files_is_an_empty_collection() {
        let text = b"<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet>\n<Block index=\"0\"/></vtkMultiBlockDataSet></VTKFile>";
        let e = leaves(text, "m.vtm").unwrap_err();
        assert!(e.message.contains("the collection is empty"), "{e}");
    }
}
