//! ParaView collections (`.pvd`): `<VTKFile type="Collection"><Collection>` with one
//! `<DataSet timestep=… part=… file=…/>` per file, as ParaView and most solvers (FEniCS,
//! OpenFOAM's foamToVTK, deal.II) write them. Data sets with the same `timestep` are the parts
//! of one step and are merged; a missing `timestep` counts as 0 (a collection of parts without
//! time). The file names are relative to the collection (docs/formats.md, "Time series and
//! collections").

use super::Entry;
use super::xml::vtk_file;
use crate::error::ParseError;

/// The data sets a `.pvd` lists, in file order.
pub fn entries(bytes: &[u8], name: &str) -> Result<Vec<Entry>, ParseError> {
    let elements = vtk_file(bytes, name, "Collection")?;
    let mut out = Vec::new();
    for e in elements.iter().filter(|e| e.name == "DataSet") {
        let err = |msg: String| ParseError::new(name, e.line, msg);
        let file = e
            .attr("file")
            .filter(|f| !f.trim().is_empty())
            .ok_or_else(|| err("<DataSet> needs file=\"…\" (the data set's file)".into()))?;
        let time = match e.attr("timestep") {
            None => 0.0,
            Some(t) => crate::numbers::parse_f64(t.trim()).ok_or_else(|| {
                err(format!(
                    "timestep=\"{t}\": expected a finite number (the step's time)"
                ))
            })?,
        };
        out.push(Entry {
            time,
            file: file.trim().to_string(),
            line: e.line,
        });
    }
    if out.is_empty() {
        return Err(ParseError::new(
            name,
            elements.first().map_or(1, |e| e.line),
            "the collection is empty: it lists no <DataSet timestep=… file=…/>",
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_sets_with_times() {
        let text = br#"<?xml version="1.0"?>
<VTKFile type="Collection" version="0.1">
  <Collection>
    <DataSet timestep="0" part="0" file="a_0.vtu"/>
    <DataSet timestep="0" part="1" file="b_0.vtu"/>
    <DataSet timestep="1.5e-1" part="0" file="a_1.vtu"/>
  </Collection>
</VTKFile>
"#;
        let e = entries(text, "x.pvd").unwrap();
        assert_eq!(e.len(), 3);
        assert_eq!(
            (e[2].time, e[2].file.as_str(), e[2].line),
            (0.15, "a_1.vtu", 6)
        );
    }

    #[test]
    fn bad_data_sets_are_located() {
        let bad_time = b"<VTKFile type=\"Collection\"><Collection>\n<DataSet timestep=\"soon\" file=\"a.vtu\"/></Collection></VTKFile>";
        let e = entries(bad_time, "x.pvd").unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("timestep=\"soon\""), "{e}");
        let no_file = b"<VTKFile type=\"Collection\"><Collection>\n\n<DataSet timestep=\"1\"/></Collection></VTKFile>";
        assert_eq!(entries(no_file, "x.pvd").unwrap_err().line, 3);
        let empty = b"<VTKFile type=\"Collection\">\n<Collection/>\n</VTKFile>";
        let e = entries(empty, "x.pvd").unwrap_err();
        assert!(e.message.contains("the collection is empty"), "{e}");
    }
}
