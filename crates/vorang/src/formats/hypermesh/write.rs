//! Writing HyperMesh files (`save_volume`, `save_subset`, `vorang convert`; thesis A.1).
//!
//! - **Full** format: nodes, triangles by nodes, tetrahedra by triangles, data — the most
//!   complete description. If the volume came with a partial triangle list, those triangles keep
//!   their numbers and the missing faces follow; their `TriangleData` rows are written as zeros.
//! - **Small** format: nodes, tetrahedra by nodes, and edges/triangles only where data are
//!   attached to them.
//!
//! BINARY files keep every value bit for bit; ASCII files print doubles in shortest round-trip
//! form and floats exactly, so reading back gives the same numbers.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;

use super::header::Encoding;
use super::{ascii, binary};
use crate::atomic::write_atomically;
use crate::data::{DataType, ElementKind, RawData, ScalarType, Values};
use crate::error::Error;
use crate::mesh::FACE_NODES;
use crate::volume::Volume;

/// Full or small layout (thesis A.1 `save_volume … [small]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    Full,
    Small,
}

/// How to write a volume.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WriteOptions {
    pub encoding: Encoding,
    pub layout: Layout,
}

impl Default for WriteOptions {
    /// The thesis's default: ASCII, full format.
    fn default() -> Self {
        WriteOptions {
            encoding: Encoding::Ascii,
            layout: Layout::Full,
        }
    }
}

/// One block to write: its declaration (without the marker) and its values.
struct OutBlock {
    /// e.g. `Nodes { double[3] Coordinates }`.
    decl: String,
    values: Values,
    numbers: usize,
}

/// Writes `vol` to `out`.
pub fn write_volume(vol: &Volume, out: &mut impl Write, opts: WriteOptions) -> io::Result<()> {
    let mut blocks: Vec<OutBlock> = Vec::new();
    let mut counts: Vec<(ElementKind, usize)> = vec![(ElementKind::Node, vol.mesh.node_count())];
    let mesh = &vol.mesh;

    blocks.push(OutBlock {
        decl: format!(
            "Nodes {{ {} Coordinates }}",
            DataType::array(vol.coord_type, 3)
        ),
        values: coordinates(vol),
        numbers: 3,
    });

    let has_data = |k: ElementKind| vol.data.raw.iter().any(|r| r.kind == k);
    let write_edges =
        vol.edges.is_some() && (opts.layout == Layout::Full || has_data(ElementKind::Edge));
    let mut tri_padding = 0;
    match opts.layout {
        Layout::Full => {
            let (tris, tet_tris) = all_faces(vol);
            tri_padding = tris.len() - vol.triangles.as_ref().map_or(0, Vec::len);
            counts.push((ElementKind::Triangle, tris.len()));
            blocks.push(OutBlock {
                decl: "Triangles { int[3] Nodes }".into(),
                values: one_based(tris.iter().flatten()),
                numbers: 3,
            });
            blocks.push(OutBlock {
                decl: "Tetrahedra { int[4] Triangles }".into(),
                values: one_based(tet_tris.iter().flatten()),
                numbers: 4,
            });
        }
        Layout::Small => {
            if let (Some(t), true) = (&vol.triangles, has_data(ElementKind::Triangle)) {
                counts.push((ElementKind::Triangle, t.len()));
                blocks.push(OutBlock {
                    decl: "Triangles { int[3] Nodes }".into(),
                    values: one_based(t.iter().flatten()),
                    numbers: 3,
                });
            }
            blocks.push(OutBlock {
                decl: "Tetrahedra { int[4] Nodes }".into(),
                values: one_based(mesh.tets().iter().flatten()),
                numbers: 4,
            });
        }
    }
    counts.push((ElementKind::Tetrahedron, mesh.tet_count()));
    if let (true, Some(e)) = (write_edges, &vol.edges) {
        counts.push((ElementKind::Edge, e.len()));
        blocks.push(OutBlock {
            decl: "Edges { int[2] FromTo }".into(),
            values: one_based(e.iter().flatten()),
            numbers: 2,
        });
    }
    // Data on elements whose list is not written still need their count.
    for r in &vol.data.raw {
        if !counts.iter().any(|(k, _)| *k == r.kind) {
            let n = match r.kind {
                ElementKind::Triangle if opts.layout == Layout::Full => r.elements() + tri_padding,
                _ => r.elements(),
            };
            counts.push((r.kind, n));
        }
    }

    let first_data = blocks.len();
    for r in &vol.data.raw {
        let mut values = r.values.clone();
        if r.kind == ElementKind::Triangle && opts.layout == Layout::Full {
            values.pad_zeros(tri_padding * r.ty.numbers());
        }
        blocks.push(OutBlock {
            decl: data_decl(r),
            values,
            numbers: r.ty.numbers(),
        });
    }

    let mut header = String::new();
    let _ = writeln!(header, "# HyperMesh 3D {} 0.7", opts.encoding.keyword());
    let _ = writeln!(header, "# written by vorang {}", env!("CARGO_PKG_VERSION"));
    if let Some(m) = &vol.data.materials {
        header.push_str(&m.to_header());
    }
    for (kind, n) in &counts {
        let _ = writeln!(header, "{} = {n}", kind.count_keyword());
    }
    for (i, b) in blocks.iter().enumerate() {
        let _ = writeln!(header, "{} = @{}", b.decl, i + 1);
    }
    for f in &vol.data.fields {
        header.push_str("Field ");
        if let Some(name) = &f.name {
            let _ = write!(header, "\"{name}\" ");
        }
        let _ = write!(header, "{{ {}", f.ty);
        if let Some(d) = &f.denominator {
            let _ = write!(header, " {d}");
        }
        let markers: Vec<String> = f
            .sources
            .iter()
            .map(|s| format!("@{}", first_data + s + 1))
            .collect();
        let _ = writeln!(
            header,
            " }} = {}({})",
            f.interpolator.name(),
            markers.join(", ")
        );
    }
    if opts.encoding == Encoding::Binary {
        // A form-feed comment line lets `more` stop before the binary data (thesis B.2).
        header.push_str("#\x0c\n");
    }
    out.write_all(header.as_bytes())?;
    for (i, b) in blocks.iter().enumerate() {
        writeln!(out, "@{}", i + 1)?;
        match opts.encoding {
            Encoding::Ascii => ascii::write_rows(out, &b.values, b.numbers)?,
            Encoding::Binary => {
                binary::write_values(out, &b.values)?;
                out.write_all(b"\n")?;
            }
        }
    }
    Ok(())
}

fn data_decl(r: &RawData) -> String {
    match &r.denominator {
        Some(d) => format!("{} {{ {} {d} }}", r.kind.data_keyword(), r.ty),
        None => format!("{} {{ {} }}", r.kind.data_keyword(), r.ty),
    }
}

/// Coordinates in the type they were read with (exact: the values came from that type).
fn coordinates(vol: &Volume) -> Values {
    let flat = vol.mesh.nodes().iter().flatten().copied();
    match vol.coord_type {
        ScalarType::Float => Values::F32(flat.map(|v| v as f32).collect()),
        ScalarType::Byte => Values::U8(flat.map(|v| v as u8).collect()),
        ScalarType::Short => Values::I16(flat.map(|v| v as i16).collect()),
        ScalarType::Int | ScalarType::Long => Values::I32(flat.map(|v| v as i32).collect()),
        ScalarType::Double | ScalarType::Complex => Values::F64(flat.collect()),
    }
}

fn one_based<'a>(idx: impl Iterator<Item = &'a u32>) -> Values {
    Values::I32(idx.map(|&i| i as i32 + 1).collect())
}

/// The triangle list of the full format (the volume's own triangles first) and, per cell, the
/// triangle of each face.
fn all_faces(vol: &Volume) -> (Vec<[u32; 3]>, Vec<[u32; 4]>) {
    let key = |mut t: [u32; 3]| {
        t.sort_unstable();
        t
    };
    let mut tris: Vec<[u32; 3]> = vol.triangles.clone().unwrap_or_default();
    let mut index: HashMap<[u32; 3], u32> =
        HashMap::with_capacity(vol.mesh.tet_count() * 2 + tris.len());
    for (i, t) in tris.iter().enumerate() {
        index.entry(key(*t)).or_insert(i as u32);
    }
    let mut tet_tris = Vec::with_capacity(vol.mesh.tet_count());
    for tet in vol.mesh.tets() {
        let faces = FACE_NODES.map(|f| {
            let t = f.map(|k| tet[k]);
            *index.entry(key(t)).or_insert_with(|| {
                tris.push(t);
                (tris.len() - 1) as u32
            })
        });
        tet_tris.push(faces);
    }
    (tris, tet_tris)
}

/// `save_volume file [binary|ascii] [small]`.
pub fn save_volume(vol: &Volume, path: &Path, opts: WriteOptions) -> Result<(), Error> {
    write_atomically(path, |w| write_volume(vol, w, opts))
}

/// `save_subset file field_nr [binary|ascii]`: the cells where Constant field `field` is not
/// zero, in the small format.
pub fn save_subset(
    vol: &Volume,
    path: &Path,
    field: usize,
    encoding: Encoding,
) -> Result<(), Error> {
    let sub = crate::volume::subset(vol, field)?;
    save_volume(
        &sub,
        path,
        WriteOptions {
            encoding,
            layout: Layout::Small,
        },
    )
}
