//! VTK XML `UnstructuredGrid` files (`.vtu`), as VTK, ParaView, meshio, FEniCS/dolfinx and
//! others write them.
//!
//! Reading covers every encoding VTK defines: `format="ascii"`, `format="binary"` (base64
//! inline), `format="appended"` with `<AppendedData encoding="raw">` or `encoding="base64"`;
//! `compressor` none, `vtkZLibDataCompressor`, `vtkLZ4DataCompressor` and
//! `vtkLZMADataCompressor` (xz streams); `header_type` `UInt32` (the default) or `UInt64`;
//! `byte_order` `LittleEndian` or `BigEndian`; several `<Piece>`s (concatenated).
//!
//! A binary array is a header followed by the data. Uncompressed: one header word, the number
//! of data bytes. Compressed: `[nblocks, block size, last block size (0 = full), compressed
//! size of each block…]`, then the compressed blocks back to back. In base64 the header and the
//! data are usually encoded separately (VTK, meshio), sometimes as one stream: the padding at
//! the header's end tells which.
//!
//! The XML part is parsed with `quick-xml`; raw appended data (which is not XML) is cut off at
//! the `_` that starts it. Every length, offset and block size is checked against the file before
//! use, and decompression never produces more than the header declares, which itself is bounded
//! by a multiple of the file size — so allocation stays bounded by the input.
//!
//! Writing ([`save`]) produces what ParaView reads fastest: appended raw data, zlib-compressed,
//! `UInt64` headers, little-endian.
//!
//! Reading goes in phases, one private module each, so that each can be read (and measured) on
//! its own: the XML walk (`xml`: declarations and settings, nothing decoded), array decoding
//! (`arrays`: text or bytes to numbers), the binary layouts (`binary`: headers, base64,
//! compressed-block tables) and the codecs (`compress`), then the assembly of the pieces into
//! one description (`pieces`), with the polyhedra's faces in either of VTK's two layouts
//! (`faces`). Files before version 2.1 list Lagrange hexahedra in VTK 8's node order; they are
//! put into today's, as VTK reads them. Writing is `write`.

mod arrays;
mod binary;
mod compress;
mod faces;
mod pieces;
mod sink;
mod write;
mod xml;

use super::MeshDescription;
use crate::error::ParseError;

pub use write::{save, write};

pub fn sniff(head: &[u8]) -> bool {
    let probe = &head[..head.len().min(1024)];
    probe.windows(8).any(|w| w == b"<VTKFile")
}

/// Reads a whole `.vtu` file.
pub fn read(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    let doc = xml::parse(bytes, name)?;
    pieces::assemble(&doc)
}

#[cfg(test)]
mod tests {
    use base64::Engine as _;

    use super::binary::b64;
    use super::*;
    use crate::formats::ArrayValues;

    #[test]
    fn information_keys_inside_a_data_array_are_not_data() {
        let text = r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0">
  <UnstructuredGrid>
    <Piece NumberOfPoints="4" NumberOfCells="1">
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii" RangeMin="0" RangeMax="1">
          0 0 0  1 0 0  0 1 0  0 0 1
          <InformationKey name="L2_NORM_RANGE" location="vtkDataArray" length="2">
            <Value index="0">0</Value>
            <Value index="1">1</Value>
          </InformationKey>
        </DataArray>
      </Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">4</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"#;
        let d = read(text.as_bytes(), "info.vtu").unwrap();
        assert_eq!(d.nodes.len(), 4);
        assert_eq!(d.nodes[3], [0.0, 0.0, 1.0]);
        assert_eq!(d.cells.nodes(0), &[0, 1, 2, 3]);
    }

    #[test]
    fn pieces_are_concatenated() {
        let piece = |z: f64, t: f64, id: i32| {
            format!(
                r#"<Piece NumberOfPoints="4" NumberOfCells="1">
      <PointData><DataArray type="Float64" Name="T" format="ascii">{t} {t} {t} {t}</DataArray></PointData>
      <CellData><DataArray type="Int32" Name="id" format="ascii">{id}</DataArray></CellData>
      <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 {z} 1 0 {z} 0 1 {z} 0 0 {}</DataArray></Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">4</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10</DataArray>
      </Cells>
    </Piece>"#,
                z + 1.0
            )
        };
        let text = format!(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n{}\n{}\n</UnstructuredGrid>\n</VTKFile>\n",
            piece(0.0, 1.0, 5),
            piece(5.0, 2.0, 6)
        );
        let d = read(text.as_bytes(), "two.vtu").unwrap();
        assert_eq!(d.nodes.len(), 8);
        assert_eq!(d.cells.nodes(1), &[4, 5, 6, 7]);
        assert_eq!(d.point_arrays[0].values.len(), 8);
        assert_eq!(d.point_arrays[0].values.get(5), 2.0);
        assert_eq!(d.cell_arrays[0].values, ArrayValues::Int(vec![5, 6]));
        let (vol, _) = crate::formats::build::volume(d).unwrap();
        assert_eq!(vol.mesh.tet_count(), 2);
    }

    #[test]
    fn binary_connectivity_out_of_range_names_the_index() {
        let b64arr = |bytes: Vec<u8>| {
            let header = (bytes.len() as u32).to_le_bytes();
            [b64().encode(header), b64().encode(bytes)].concat()
        };
        let points: Vec<u8> = [0.0f64, 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        for (bad, shown) in [(-1i64, "-1"), (1 << 40, "1099511627776"), (4, "4")] {
            let conn: Vec<u8> = [0i64, 1, 2, bad]
                .iter()
                .flat_map(|x| x.to_le_bytes())
                .collect();
            let text = format!(
                r#"<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="4" NumberOfCells="1">
<Points><DataArray type="Float64" NumberOfComponents="3" format="binary">{}</DataArray></Points>
<Cells><DataArray type="Int64" Name="connectivity" format="binary">{}</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">4</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">10</DataArray></Cells>
</Piece></UnstructuredGrid></VTKFile>"#,
                b64arr(points.clone()),
                b64arr(conn)
            );
            let e = read(text.as_bytes(), "c.vtu").unwrap_err();
            assert_eq!(e.line, 3, "{e}");
            assert!(
                e.message.contains(&format!(
                    "cell 1 refers to point {shown}, but the piece has 4"
                )),
                "{e}"
            );
        }
    }
}
