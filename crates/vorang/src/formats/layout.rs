//! VoRANG's layout inside the `.vtu` files it writes, so that a volume written as `.vtu` reads
//! back *identical*: the same nodes and cells, edges and triangles, every raw data block with
//! its type and denominator, the Materials table, and every field in its place with its
//! interpolator (GaussTest, EdgeElem, HigherOrder … included).
//!
//! The file stays a plain VTK `UnstructuredGrid` that ParaView, VisIt and meshio open: node
//! data blocks are point arrays, cell data blocks are cell arrays (named after the field that
//! uses them), and what VTK has no place for per point or cell — edges, triangles, edge,
//! triangle and extra data — are `<FieldData>` arrays whose names start with `VoRANG_`. One more
//! FieldData array, `VoRANG_HyperMesh` (UInt8: UTF-8 text), holds a HyperMesh header (thesis appendix B, docs/formats.md)
//! that declares all of it, its markers naming the arrays:
//!
//! ```text
//! # HyperMesh 3D BINARY 0.7
//! nNodes = 27
//! nTetrahedra = 48
//! Nodes { double[3] Coordinates } = @Points
//! Tetrahedra { int[4] Nodes } = @connectivity
//! NodeData { double } = @p0
//! TetrahedronData { byte Materials } = @c0
//! Field "temperature" { double } = Linear(@p0)
//! Field "material" { byte Materials } = Constant(@c0)
//! #@p0 temperature
//! #@c0 material
//! ```
//!
//! `@Points` and `@connectivity` are the piece's points and cells (0-based, as VTK stores
//! them), `@p<k>` / `@c<k>` the k-th point / cell array, every other marker the FieldData array
//! of that name (indices 0-based there too). The `#@` lines record the names of the point and
//! cell arrays: a file that another program has since changed (arrays added, removed or
//! renamed) no longer matches them, and is then read as any other `.vtu` (with a warning).
//! Complex data are stored as `Float64` arrays of two numbers (re, im) per component.
//!
//! Reading resolves the header with the HyperMesh reader's own code
//! ([`crate::formats::hypermesh::read::read_with_blocks`]), so every check and every rule is the one
//! HyperMesh files get.

use std::collections::HashMap;
use std::fmt::Write as _;

use super::{ArrayValues, MeshDescription, cell_type};
use crate::data::{DataType, ElementKind, ScalarType, Values};
use crate::error::{ParseError, Warning};
use crate::formats::hypermesh::header::{BlockDecl, Target};
use crate::volume::Volume;

/// The FieldData array that holds the layout text.
pub const LAYOUT_ARRAY: &str = "VoRANG_HyperMesh";

/// One array to write: name, components per tuple, values.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedValues {
    pub name: String,
    pub components: usize,
    pub values: Values,
}

/// What VoRANG writes besides the points and cells.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Parts {
    pub point_arrays: Vec<NamedValues>,
    pub cell_arrays: Vec<NamedValues>,
    /// FieldData arrays, the layout text last.
    pub field_arrays: Vec<NamedValues>,
}

fn data_decl(kind: ElementKind, ty: DataType, denominator: &Option<String>) -> String {
    match denominator {
        Some(d) => format!("{} {{ {ty} {d} }}", kind.data_keyword()),
        None => format!("{} {{ {ty} }}", kind.data_keyword()),
    }
}

fn zero_based(list: &[[u32; 2]]) -> Values {
    Values::I32(list.iter().flatten().map(|&i| i as i32).collect())
}

/// Splits a volume into the arrays of its `.vtu` file and the layout text that ties them
/// together.
pub fn parts(vol: &Volume) -> Parts {
    let mut parts = Parts::default();
    let mut header = String::new();
    let _ = writeln!(header, "# HyperMesh 3D BINARY 0.7");
    let _ = writeln!(
        header,
        "# VoRANG {} layout of a .vtu file: @Points and @connectivity are the piece's points and cells, @p<k> and @c<k> its k-th point and cell array, other markers FieldData arrays; indices 0-based",
        env!("CARGO_PKG_VERSION")
    );
    if let Some(m) = &vol.data.materials {
        header.push_str(&m.to_header());
    }
    let mut counts: Vec<(ElementKind, usize)> = vec![
        (ElementKind::Node, vol.mesh.node_count()),
        (ElementKind::Tetrahedron, vol.mesh.tet_count()),
    ];
    let mut decls = vec![
        format!(
            "Nodes {{ {} Coordinates }} = @Points",
            DataType::array(vol.coord_type, 3)
        ),
        "Tetrahedra { int[4] Nodes } = @connectivity".to_string(),
    ];
    if let Some(e) = &vol.edges {
        counts.push((ElementKind::Edge, e.len()));
        decls.push("Edges { int[2] FromTo } = @VoRANG_edges".into());
        parts.field_arrays.push(NamedValues {
            name: "VoRANG_edges".into(),
            components: 2,
            values: zero_based(e),
        });
    }
    if let Some(t) = &vol.triangles {
        counts.push((ElementKind::Triangle, t.len()));
        decls.push("Triangles { int[3] Nodes } = @VoRANG_triangles".into());
        parts.field_arrays.push(NamedValues {
            name: "VoRANG_triangles".into(),
            components: 3,
            values: Values::I32(t.iter().flatten().map(|&i| i as i32).collect()),
        });
    }
    // Counts the volume keeps without a list (a file's `nTriangles` with `Triangles = NULL`,
    // `nExtra`), then those of data on elements without one.
    for kind in ElementKind::ALL {
        if let (Some(n), false) = (
            vol.data.counts[kind.index()],
            counts.iter().any(|(k, _)| *k == kind),
        ) {
            counts.push((kind, n));
        }
    }
    for r in &vol.data.raw {
        if !counts.iter().any(|(k, _)| *k == r.kind) {
            counts.push((r.kind, r.elements()));
        }
    }
    // Array names: the first field that uses a block names it (VTK looks arrays up by name,
    // so names are made unique).
    let mut used: HashMap<String, usize> = HashMap::new();
    let mut markers = Vec::with_capacity(vol.data.raw.len());
    let mut names = String::new();
    for (k, r) in vol.data.raw.iter().enumerate() {
        let field_name = vol
            .data
            .fields
            .iter()
            .find(|f| f.sources.contains(&k))
            .and_then(|f| f.name.clone())
            .filter(|n| !n.is_empty());
        let components = r.ty.numbers();
        let values = r.values.clone();
        let marker = match r.kind {
            ElementKind::Node | ElementKind::Tetrahedron => {
                let (list, prefix) = if r.kind == ElementKind::Node {
                    (&mut parts.point_arrays, "p")
                } else {
                    (&mut parts.cell_arrays, "c")
                };
                let mut name = field_name.unwrap_or_else(|| format!("raw{k}"));
                let n = used.entry(name.clone()).or_default();
                *n += 1;
                if *n > 1 {
                    name = format!("{name}_{k}");
                }
                let marker = format!("{prefix}{}", list.len());
                let _ = writeln!(names, "#@{marker} {}", name.replace(['\n', '\r'], " "));
                list.push(NamedValues {
                    name,
                    components,
                    values,
                });
                marker
            }
            _ => {
                let name = format!("VoRANG_raw{k}");
                parts.field_arrays.push(NamedValues {
                    name: name.clone(),
                    components,
                    values,
                });
                name
            }
        };
        decls.push(format!(
            "{} = @{marker}",
            data_decl(r.kind, r.ty, &r.denominator)
        ));
        markers.push(marker);
    }
    for (kind, n) in &counts {
        let _ = writeln!(header, "{} = {n}", kind.count_keyword());
    }
    for d in &decls {
        let _ = writeln!(header, "{d}");
    }
    for f in &vol.data.fields {
        header.push_str("Field ");
        if let Some(name) = &f.name {
            let _ = write!(header, "\"{}\" ", escape(name));
        }
        let _ = write!(header, "{{ {}", f.ty);
        if let Some(d) = &f.denominator {
            let _ = write!(header, " {d}");
        }
        let m: Vec<String> = f
            .sources
            .iter()
            .map(|&s| format!("@{}", markers[s]))
            .collect();
        let _ = writeln!(header, " }} = {}({})", f.interpolator.name(), m.join(", "));
    }
    header.push_str(&names);
    parts.field_arrays.push(NamedValues {
        name: LAYOUT_ARRAY.into(),
        components: 1,
        values: Values::U8(header.into_bytes()),
    });
    parts
}

/// A field name as a HyperMesh string can hold it: `%`, `"`, line feeds and carriage returns
/// (which other formats allow in names) are written `%25`, `%22`, `%0A`, `%0D`.
fn escape(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for c in name.chars() {
        match c {
            '%' => out.push_str("%25"),
            '"' => out.push_str("%22"),
            '\n' => out.push_str("%0A"),
            '\r' => out.push_str("%0D"),
            c => out.push(c),
        }
    }
    out
}

/// The inverse of [`escape`].
fn unescape(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    let mut rest = name;
    while let Some(k) = rest.find('%') {
        out.push_str(&rest[..k]);
        let code = rest.get(k + 1..k + 3);
        let c = match code {
            Some("25") => Some('%'),
            Some("22") => Some('"'),
            Some("0A") => Some('\n'),
            Some("0D") => Some('\r'),
            _ => None,
        };
        match c {
            Some(c) => {
                out.push(c);
                rest = &rest[k + 3..];
            }
            None => {
                out.push('%');
                rest = &rest[k + 1..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// The layout text of a description, if it has one.
fn layout_text(desc: &MeshDescription) -> Option<(Vec<u8>, usize)> {
    let a = desc.field_arrays.iter().find(|a| a.name == LAYOUT_ARRAY)?;
    let ArrayValues::Int(v) = &a.values else {
        return None;
    };
    Some((v.iter().map(|&b| b as u8).collect(), a.line))
}

/// Whether the arrays of `desc` are still the ones the layout names (`#@p0 name` lines).
fn matches(desc: &MeshDescription, text: &[u8]) -> bool {
    let text = String::from_utf8_lossy(text);
    let mut points = Vec::new();
    let mut cells = Vec::new();
    for l in text.lines() {
        let Some(rest) = l.strip_prefix("#@") else {
            continue;
        };
        let Some((marker, name)) = rest.split_once(' ') else {
            return false;
        };
        match marker.as_bytes().first() {
            Some(b'p') => points.push(name.to_string()),
            Some(b'c') => cells.push(name.to_string()),
            _ => return false,
        }
    }
    let same = |arrays: &[super::Array], names: &[String]| {
        arrays.len() == names.len()
            && arrays
                .iter()
                .zip(names)
                .all(|(a, n)| a.name.replace(['\n', '\r'], " ") == *n)
    };
    same(&desc.point_arrays, &points)
        && same(&desc.cell_arrays, &cells)
        && desc.cells.types.iter().all(|&t| t == cell_type::TETRA)
}

/// Numbers of an array as storage for a HyperMesh type, exactly (a value the type cannot hold
/// is an error); `shift` is added to integers (1 for the 0-based index lists).
fn convert(v: &ArrayValues, scalar: ScalarType, shift: i64) -> Result<Values, String> {
    let not_exact =
        |i: usize, x: f64| format!("value {} ({x}) is not a {} value", i + 1, scalar.keyword());
    let int = |i: usize, lo: i64, hi: i64| -> Result<i64, String> {
        let x = v.get(i);
        let n = match v {
            ArrayValues::Int(a) => a[i],
            _ if x.fract() == 0.0 && x.abs() < 9.0e15 => x as i64,
            _ => return Err(not_exact(i, x)),
        };
        let n = n + shift;
        if (lo..=hi).contains(&n) {
            Ok(n)
        } else {
            Err(not_exact(i, x))
        }
    };
    let n = v.len();
    Ok(match scalar {
        ScalarType::Byte => Values::U8(
            (0..n)
                .map(|i| int(i, 0, 255).map(|x| x as u8))
                .collect::<Result<_, _>>()?,
        ),
        ScalarType::Short => Values::I16(
            (0..n)
                .map(|i| int(i, i16::MIN.into(), i16::MAX.into()).map(|x| x as i16))
                .collect::<Result<_, _>>()?,
        ),
        ScalarType::Int | ScalarType::Long => Values::I32(
            (0..n)
                .map(|i| int(i, i32::MIN.into(), i32::MAX.into()).map(|x| x as i32))
                .collect::<Result<_, _>>()?,
        ),
        ScalarType::Float => Values::F32(match v {
            ArrayValues::F32(a) => a.clone(),
            _ => (0..n)
                .map(|i| {
                    let x = v.get(i);
                    if f64::from(x as f32) == x {
                        Ok(x as f32)
                    } else {
                        Err(not_exact(i, x))
                    }
                })
                .collect::<Result<_, _>>()?,
        }),
        ScalarType::Double | ScalarType::Complex => Values::F64(match v {
            ArrayValues::F64(a) => a.clone(),
            _ => (0..n).map(|i| v.get(i)).collect(),
        }),
    })
}

/// Builds the volume of a `.vtu` file that VoRANG wrote, from its layout; `None` if the file
/// has no layout (or one that no longer matches its arrays: then with a warning in
/// `warnings`, and the file is read as any other `.vtu`).
pub fn volume(desc: &mut MeshDescription) -> Option<Result<(Volume, Vec<Warning>), ParseError>> {
    let (text, line) = layout_text(desc)?;
    if !matches(desc, &text) {
        desc.warnings.push(Warning {
            file: desc.source.clone(),
            line: Some(line.max(1)),
            message: format!(
                "the {LAYOUT_ARRAY} array that VoRANG wrote no longer matches the file's arrays (changed by another program?); the file is read as a plain .vtu"
            ),
        });
        return None;
    }
    let name = desc.source.clone();
    let mut nodes = std::mem::take(&mut desc.nodes);
    // Only the connectivity is needed (all cells are tetrahedra, checked above): the offsets
    // and types are freed before the mesh is built (peak memory of a load).
    let mut connectivity = std::mem::take(&mut desc.cells).connectivity;
    let mut point_arrays: Vec<Option<ArrayValues>> = desc
        .point_arrays
        .iter_mut()
        .map(|a| {
            Some(std::mem::replace(
                &mut a.values,
                ArrayValues::Int(Vec::new()),
            ))
        })
        .collect();
    let mut cell_arrays: Vec<Option<ArrayValues>> = desc
        .cell_arrays
        .iter_mut()
        .map(|a| {
            Some(std::mem::replace(
                &mut a.values,
                ArrayValues::Int(Vec::new()),
            ))
        })
        .collect();
    let field_arrays = &desc.field_arrays;
    let block = |d: &BlockDecl, _count: usize| -> Result<Values, String> {
        let geometry = !matches!(d.target, Target::Data(_));
        let shift = i64::from(geometry && d.target != Target::Nodes);
        let m = d.marker.as_str();
        if m == "Points" {
            let flat = std::mem::take(&mut nodes);
            let v = ArrayValues::F64(flat.into_iter().flatten().collect());
            return convert(&v, d.ty.scalar, 0);
        }
        if m == "connectivity" {
            let c = std::mem::take(&mut connectivity);
            if c.iter().any(|&n| n >= i32::MAX as u32) {
                return Err("a node index is too large".into());
            }
            // In place: u32 and i32 have the same size.
            return Ok(Values::I32(c.into_iter().map(|n| n as i32 + 1).collect()));
        }
        let numbered = |prefix: char, list: &mut Vec<Option<ArrayValues>>| {
            m.strip_prefix(prefix)
                .and_then(|k| k.parse::<usize>().ok())
                .and_then(|k| list.get_mut(k))
                .and_then(Option::take)
        };
        let v = match m.as_bytes().first() {
            Some(b'p') => numbered('p', &mut point_arrays),
            Some(b'c') => numbered('c', &mut cell_arrays),
            _ => None,
        };
        let v = match v {
            Some(v) => v,
            None => field_arrays
                .iter()
                .find(|a| a.name == m)
                .map(|a| a.values.clone())
                .ok_or_else(|| format!("the file has no array for @{m}"))?,
        };
        convert(&v, d.ty.scalar, shift)
    };
    let mut file =
        match crate::formats::hypermesh::read::read_with_blocks(&name, &text, line.max(1), block) {
            Ok(f) => f,
            Err(e) => return Some(Err(e)),
        };
    for f in &mut file.data.fields {
        if let Some(n) = &mut f.name {
            *n = unescape(n);
        }
    }
    let mut warnings = std::mem::take(&mut desc.warnings);
    warnings.extend(file.warnings.iter().cloned());
    Some(Volume::from_file(file).map(|v| (v, warnings)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn written(text_edit: impl Fn(String) -> String) -> MeshDescription {
        let root = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
        let file =
            crate::formats::hypermesh::read_file(&root.join("tests/data/two_tets_data.hmesh"))
                .unwrap_or_else(|e| panic!("{e}"));
        let vol = Volume::from_file(file).unwrap_or_else(|e| panic!("{e}"));
        let mut bytes = Vec::new();
        super::super::vtu::write(&vol, &mut bytes).unwrap();
        let mut desc = super::super::vtu::read(&bytes, "t.vtu").unwrap_or_else(|e| panic!("{e}"));
        let a = desc
            .field_arrays
            .iter_mut()
            .find(|a| a.name == LAYOUT_ARRAY)
            .unwrap();
        let ArrayValues::Int(v) = &a.values else {
            panic!("text")
        };
        let text = String::from_utf8(v.iter().map(|&b| b as u8).collect()).unwrap();
        a.values = ArrayValues::Int(text_edit(text).bytes().map(i64::from).collect());
        desc
    }

    #[test]
    fn a_broken_layout_is_an_error_at_its_array() {
        let (vol, _) = super::super::build::volume(written(|t| t)).unwrap();
        assert_eq!(vol.data.fields.len(), 8);
        let line = |d: &MeshDescription| {
            d.field_arrays
                .iter()
                .find(|a| a.name == LAYOUT_ARRAY)
                .unwrap()
                .line
        };
        let d = written(|t| t.replacen("Linear(", "Lineal(", 1));
        let at = line(&d);
        let e = super::super::build::volume(d).unwrap_err();
        assert_eq!(e.line, at);
        assert!(e.message.starts_with("VoRANG layout, line "), "{e}");
        assert!(e.message.contains("unknown interpolator 'Lineal'"), "{e}");
        let mut d = written(|t| t);
        d.point_arrays[0].values = ArrayValues::Int(vec![1, 2]);
        let e = super::super::build::volume(d).unwrap_err();
        assert!(e.message.contains("VoRANG layout, block @p0"), "{e}");
        // Arrays renamed by another program: read as a plain .vtu, with a warning.
        let mut d = written(|t| t);
        d.point_arrays[0].name = "renamed".into();
        let (vol, warnings) = super::super::build::volume(d).unwrap();
        assert!(
            warnings
                .iter()
                .any(|w| w.message.contains("no longer matches"))
        );
        assert!(
            vol.data
                .fields
                .iter()
                .any(|f| f.name.as_deref() == Some("renamed"))
        );
    }

    #[test]
    fn names_with_quotes_and_line_breaks_survive_the_header() {
        for name in [
            "plain",
            "a \"quoted\" word",
            "two\nlines\r",
            "100% %22",
            "%",
            "%2",
        ] {
            let e = escape(name);
            assert!(!e.contains(['"', '\n', '\r']), "{e}");
            assert_eq!(unescape(&e), name);
        }
    }
}
