//! Parallel unstructured grids (`.pvtu`): `<VTKFile type="PUnstructuredGrid">` with the
//! arrays' declarations (`<PPointData>`, `<PCellData>`, `<PPoints>`) and one
//! `<Piece Source="…"/>` per `.vtu` file, as a parallel VTK or ParaView run writes them, one
//! piece per process. All pieces together are the grid: they are read one after the other and
//! merged ([`super::merge`]), their ghost cells dropped. The declarations are not needed to read
//! the pieces (each piece declares its own arrays, and those must agree).

use super::Entry;
use super::xml::vtk_file;
use crate::error::ParseError;

/// The pieces a `.pvtu` lists, in file order (time 0: a `.pvtu` is one step).
pub fn entries(bytes: &[u8], name: &str) -> Result<Vec<Entry>, ParseError> {
    let elements = vtk_file(bytes, name, "PUnstructuredGrid")?;
    let mut out = Vec::new();
    for e in elements.iter().filter(|e| e.name == "Piece") {
        let file = e
            .attr("Source")
            .filter(|f| !f.trim().is_empty())
            .ok_or_else(|| {
                ParseError::new(
                    name,
                    e.line,
                    "<Piece> needs Source=\"…\" (the piece's .vtu file)",
                )
            })?;
        out.push(Entry {
            time: 0.0,
            file: file.trim().to_string(),
            line: e.line,
        });
    }
    if out.is_empty() {
        return Err(ParseError::new(
            name,
            elements.first().map_or(1, |e| e.line),
            "the collection is empty: it lists no <Piece Source=\"…\"/>",
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_in_order() {
        let text = br#"<?xml version="1.0"?>
<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <PUnstructuredGrid GhostLevel="1">
    <PPointData><PDataArray type="Float64" Name="T"/></PPointData>
    <PPoints><PDataArray type="Float32" NumberOfComponents="3"/></PPoints>
    <Piece Source="p/p_0.vtu"/>
    <Piece Source="p/p_1.vtu"/>
  </PUnstructuredGrid>
</VTKFile>
"#;
        let e = entries(text, "p.pvtu").unwrap();
        let files: Vec<_> = e.iter().map(|e| (e.file.as_str(), e.line)).collect();
        assert_eq!(files, [("p/p_0.vtu", 6), ("p/p_1.vtu", 7)]);
    }

    #[test]
    fn no_pieces_is_an_empty_collection() {
        let text = b"<VTKFile type=\"PUnstructuredGrid\"><PUnstructuredGrid>\n</PUnstructuredGrid></VTKFile>";
        let e = entries(text, "p.pvtu").unwrap_err();
        assert!(e.message.contains("the collection is empty"), "{e}");
        let no_source = b"<VTKFile type=\"PUnstructuredGrid\">\n<Piece/></VTKFile>";
        assert_eq!(entries(no_source, "p.pvtu").unwrap_err().line, 2);
    }
}
