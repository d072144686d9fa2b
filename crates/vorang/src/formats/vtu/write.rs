//! Writing `.vtu` files ([`write`], [`save`]): what ParaView reads fastest — appended raw data,
//! zlib-compressed in VTK's 32 KiB blocks, `UInt64` headers, little-endian — with VoRANG's
//! layout ([`layout`]) in `<FieldData>` so that the file reads back as the identical volume.
//! Separate from reading, with which it shares nothing but the format: the writer produces one
//! fixed form, the reader accepts every form VTK defines.

use std::io::Write as _;
use std::path::Path;

use crate::data::{ScalarType, Values};
use crate::error::{Error, Warning};
use crate::formats::{cell_type, layout};
use crate::mesh::TetMesh;
use crate::volume::Volume;

/// One array to write: its XML attributes and little-endian bytes.
struct OutArray {
    name: String,
    ty: &'static str,
    components: usize,
    /// `NumberOfTuples`, written for FieldData arrays.
    tuples: Option<usize>,
    data: Vec<u8>,
}

fn le<T: Copy>(v: &[T], f: impl Fn(T) -> Vec<u8>) -> Vec<u8> {
    v.iter().flat_map(|&x| f(x)).collect()
}

fn values_out(values: &Values) -> (&'static str, Vec<u8>) {
    match values {
        Values::U8(v) => ("UInt8", v.clone()),
        Values::I16(v) => ("Int16", le(v, |x| x.to_le_bytes().to_vec())),
        Values::I32(v) => ("Int32", le(v, |x| x.to_le_bytes().to_vec())),
        Values::F32(v) => ("Float32", le(v, |x| x.to_le_bytes().to_vec())),
        Values::F64(v) => ("Float64", le(v, |x| x.to_le_bytes().to_vec())),
    }
}

fn out_array(a: layout::NamedValues, field_data: bool) -> OutArray {
    let (ty, data) = values_out(&a.values);
    OutArray {
        tuples: field_data.then(|| a.values.len() / a.components.max(1)),
        name: a.name,
        ty,
        components: a.components,
        data,
    }
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\n', "&#10;")
        .replace('\r', "&#13;")
        .replace('\t', "&#9;")
}

/// Writes a volume as `.vtu`: every node data block as a point array and every cell data
/// block as a cell array (named after the first field that uses it), tetrahedra as VTK type
/// 10, and VoRANG's layout ([`layout`]) in `<FieldData>`, so that the file reads back as the
/// identical volume. Nothing is left out, so the warnings are always empty.
pub fn write(vol: &Volume, out: &mut impl std::io::Write) -> std::io::Result<Vec<Warning>> {
    let m = &vol.mesh;
    let points = points_array(vol);
    let [conn, offsets, types] = cell_arrays(m);
    let parts = layout::parts(vol);
    let arrays = |list: Vec<layout::NamedValues>, field_data: bool| -> Vec<OutArray> {
        list.into_iter().map(|a| out_array(a, field_data)).collect()
    };
    let point_data = arrays(parts.point_arrays, false);
    let cell_data = arrays(parts.cell_arrays, false);
    let field_data = arrays(parts.field_arrays, true);

    // Compress everything first: the offsets in the XML depend on the compressed sizes.
    let mut blobs: Vec<Vec<u8>> = Vec::new();
    let order: Vec<&OutArray> = field_data
        .iter()
        .chain(point_data.iter())
        .chain(cell_data.iter())
        .chain([&points, &conn, &offsets, &types])
        .collect();
    for a in &order {
        blobs.push(compress_array(&a.data)?);
    }
    let mut offset = 0usize;
    let mut offs = Vec::new();
    for b in &blobs {
        offs.push(offset);
        offset += b.len();
    }
    let sections = Sections {
        field: &field_data,
        point: &point_data,
        cell: &cell_data,
        points: &points,
        cells: [&conn, &offsets, &types],
    };
    let x = xml_text(m, &sections, &offs);
    out.write_all(x.as_bytes())?;
    for b in &blobs {
        out.write_all(b)?;
    }
    out.write_all(b"\n  </AppendedData>\n</VTKFile>\n")?;
    Ok(Vec::new())
}

/// The points: `Float32` when the volume's coordinates are `float` and every one is exactly a
/// 32-bit float (so they read back the same), else `Float64`.
fn points_array(vol: &Volume) -> OutArray {
    let m = &vol.mesh;
    if vol.coord_type == ScalarType::Float
        && m.nodes()
            .iter()
            .flatten()
            .all(|&c| f64::from(c as f32) == c)
    {
        OutArray {
            name: "Points".into(),
            ty: "Float32",
            components: 3,
            tuples: None,
            data: m
                .nodes()
                .iter()
                .flatten()
                .flat_map(|&c| (c as f32).to_le_bytes())
                .collect(),
        }
    } else {
        OutArray {
            name: "Points".into(),
            ty: "Float64",
            components: 3,
            tuples: None,
            data: m
                .nodes()
                .iter()
                .flatten()
                .flat_map(|c| c.to_le_bytes())
                .collect(),
        }
    }
}

/// The `<Cells>` arrays: connectivity, offsets and types of the tetrahedra.
fn cell_arrays(m: &TetMesh) -> [OutArray; 3] {
    let conn = OutArray {
        name: "connectivity".into(),
        ty: "Int64",
        components: 1,
        tuples: None,
        data: m
            .tets()
            .iter()
            .flatten()
            .flat_map(|&n| i64::from(n).to_le_bytes())
            .collect(),
    };
    let offsets = OutArray {
        name: "offsets".into(),
        ty: "Int64",
        components: 1,
        tuples: None,
        data: (1..=m.tet_count() as i64)
            .flat_map(|k| (4 * k).to_le_bytes())
            .collect(),
    };
    let types = OutArray {
        name: "types".into(),
        ty: "UInt8",
        components: 1,
        tuples: None,
        data: vec![cell_type::TETRA; m.tet_count()],
    };
    [conn, offsets, types]
}

/// The arrays of each section of the file, in the order their data are appended.
struct Sections<'a> {
    field: &'a [OutArray],
    point: &'a [OutArray],
    cell: &'a [OutArray],
    points: &'a OutArray,
    cells: [&'a OutArray; 3],
}

/// The XML part, up to the `_` that starts the appended data; `offs` are the arrays' offsets
/// in the appended data, in the order of [`Sections`].
fn xml_text(m: &TetMesh, sections: &Sections, offs: &[usize]) -> String {
    let decl = |a: &OutArray, off: usize| {
        let comps = if a.components > 1 {
            format!(" NumberOfComponents=\"{}\"", a.components)
        } else {
            String::new()
        };
        let tuples = a
            .tuples
            .map_or(String::new(), |t| format!(" NumberOfTuples=\"{t}\""));
        format!(
            "        <DataArray type=\"{}\" Name=\"{}\"{comps}{tuples} format=\"appended\" offset=\"{off}\"/>\n",
            a.ty,
            xml_escape(&a.name)
        )
    };
    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\"?>\n");
    x.push_str("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n");
    x.push_str("  <UnstructuredGrid>\n");
    let mut k = 0;
    x.push_str("    <FieldData>\n");
    for a in sections.field {
        x.push_str(&decl(a, offs[k]));
        k += 1;
    }
    x.push_str("    </FieldData>\n");
    x.push_str(&format!(
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
        m.node_count(),
        m.tet_count()
    ));
    x.push_str("      <PointData>\n");
    for a in sections.point {
        x.push_str(&decl(a, offs[k]));
        k += 1;
    }
    x.push_str("      </PointData>\n      <CellData>\n");
    for a in sections.cell {
        x.push_str(&decl(a, offs[k]));
        k += 1;
    }
    x.push_str("      </CellData>\n      <Points>\n");
    x.push_str(&decl(sections.points, offs[k]));
    k += 1;
    x.push_str("      </Points>\n      <Cells>\n");
    for a in sections.cells {
        x.push_str(&decl(a, offs[k]));
        k += 1;
    }
    x.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
    x.push_str("  <AppendedData encoding=\"raw\">\n   _");
    x
}

/// VTK's block size for compressed arrays.
const BLOCK: usize = 1 << 15;

/// An array as zlib-compressed blocks behind a UInt64 header.
fn compress_array(data: &[u8]) -> std::io::Result<Vec<u8>> {
    let blocks: Vec<&[u8]> = data.chunks(BLOCK).collect();
    let mut compressed = Vec::with_capacity(blocks.len());
    for b in &blocks {
        let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::new(6));
        e.write_all(b)?;
        compressed.push(e.finish()?);
    }
    let mut out = Vec::new();
    let last = blocks.last().map_or(0, |b| b.len());
    for w in [blocks.len(), BLOCK, if last == BLOCK { 0 } else { last }] {
        out.extend_from_slice(&(w as u64).to_le_bytes());
    }
    for c in &compressed {
        out.extend_from_slice(&(c.len() as u64).to_le_bytes());
    }
    for c in compressed {
        out.extend_from_slice(&c);
    }
    Ok(out)
}

/// `save_volume file.vtu` / `vorang convert … file.vtu`, written atomically.
pub fn save(vol: &Volume, path: &Path) -> Result<Vec<Warning>, Error> {
    let mut warnings = Vec::new();
    crate::atomic::write_atomically(path, |w| {
        warnings = write(vol, w)?;
        Ok(())
    })?;
    Ok(warnings)
}
