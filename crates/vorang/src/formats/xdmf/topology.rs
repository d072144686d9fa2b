//! XDMF Topology and Geometry to VoRANG's cells and points. XDMF numbers the nodes of its
//! cells as VTK does (Tetrahedron_10 included), so a cell only needs its VTK type; a Mixed
//! topology gives each cell's XDMF type code before its nodes (docs/formats.md, "XDMF").
//! `Hexahedron_27` and `Wedge_18` are VTK's triquadratic hexahedron and biquadratic-quadratic
//! wedge, whose nodes are those of the degree-2 Lagrange hexahedron and wedge in the same
//! order (crates/vorang/src/formats/lagrange.rs), so they become those; the serendipity
//! `Hexahedron_20`, `Wedge_15` and `Pyramid_13` are VTK's quadratic cells, read as the `.vtu`
//! reader reads them (crates/vorang/src/formats/build/serendipity.rs).

use super::data::Items;
use super::tree::Node;
use crate::error::ParseError;
use crate::formats::Cells;
use crate::formats::cell_type as vtk;

/// The VTK type and node count of a TopologyType name (case-insensitive; XDMF 2's `Type`
/// spelling and dolfinx's lower-case names included).
fn by_name(name: &str) -> Option<(u8, usize)> {
    Some(match name.to_ascii_lowercase().as_str() {
        "tetrahedron" => (vtk::TETRA, 4),
        "tetrahedron_10" | "tet_10" => (vtk::QUADRATIC_TETRA, 10),
        "hexahedron" => (vtk::HEXAHEDRON, 8),
        "wedge" => (vtk::WEDGE, 6),
        "pyramid" => (vtk::PYRAMID, 5),
        "hexahedron_27" | "hex_27" => (vtk::LAGRANGE_HEXAHEDRON, 27),
        "wedge_18" => (vtk::LAGRANGE_WEDGE, 18),
        "hexahedron_20" | "hex_20" => (vtk::QUADRATIC_HEXAHEDRON, 20),
        "wedge_15" => (vtk::QUADRATIC_WEDGE, 15),
        "pyramid_13" => (vtk::QUADRATIC_PYRAMID, 13),
        "triangle" => (vtk::TRIANGLE, 3),
        "quadrilateral" => (vtk::QUAD, 4),
        "polyline" => (vtk::LINE, 2),
        "polyvertex" => (vtk::VERTEX, 1),
        _ => return None,
    })
}

/// The VTK type and node count of an XDMF type code in a Mixed topology; `None` for codes
/// VoRANG does not know. Polyvertex (1), Polyline (2) and Polygon (3) give their node count
/// after the code (`count` is 0 for them here).
fn by_code(code: i64) -> Option<(u8, usize)> {
    Some(match code {
        1 => (vtk::VERTEX, 0),
        2 => (vtk::LINE, 0),
        3 => (7, 0), // polygon
        4 => (vtk::TRIANGLE, 3),
        5 => (vtk::QUAD, 4),
        6 => (vtk::TETRA, 4),
        7 => (vtk::PYRAMID, 5),
        8 => (vtk::WEDGE, 6),
        9 => (vtk::HEXAHEDRON, 8),
        34 => (21, 3), // quadratic edge
        36 => (22, 6), // 6-node triangle
        37 => (23, 8), // 8-node quadrilateral
        38 => (vtk::QUADRATIC_TETRA, 10),
        39 => (vtk::QUADRATIC_PYRAMID, 13),
        40 => (vtk::QUADRATIC_WEDGE, 15),
        41 => (vtk::LAGRANGE_WEDGE, 18),
        48 => (vtk::QUADRATIC_HEXAHEDRON, 20),
        50 => (vtk::LAGRANGE_HEXAHEDRON, 27),
        _ => return None,
    })
}

/// The points of a Geometry (`XYZ`, `XY` with z = 0, or `X_Y_Z` from three items) and
/// whether they are 32-bit floats.
pub fn geometry(items: &mut Items, g: &Node) -> Result<(Vec<[f64; 3]>, bool), ParseError> {
    let kind = g
        .attr("GeometryType")
        .or_else(|| g.attr("Type"))
        .unwrap_or("XYZ");
    let list: Vec<&Node> = g.all("DataItem").collect();
    let need = if kind == "X_Y_Z" { 3 } else { 1 };
    if list.len() < need {
        return Err(items.error(
            g.line,
            format!(
                "Geometry {kind} needs {need} DataItem(s), found {}",
                list.len()
            ),
        ));
    }
    match kind {
        "XYZ" | "XY" => {
            let dim = if kind == "XYZ" { 3 } else { 2 };
            let d = items.read(list[0])?;
            if d.values.len() % dim != 0 {
                return Err(items.error(
                    list[0].line,
                    format!(
                        "{} values are no whole number of {dim}-D points",
                        d.values.len()
                    ),
                ));
            }
            let float = matches!(d.values, crate::formats::ArrayValues::F32(_));
            let nodes = (0..d.values.len() / dim)
                .map(|i| {
                    let c = |k: usize| {
                        if k < dim {
                            d.values.get(i * dim + k)
                        } else {
                            0.0
                        }
                    };
                    [c(0), c(1), c(2)]
                })
                .collect();
            Ok((nodes, float))
        }
        "X_Y_Z" => {
            let axes = [
                items.read(list[0])?,
                items.read(list[1])?,
                items.read(list[2])?,
            ];
            let n = axes[0].values.len();
            if axes.iter().any(|a| a.values.len() != n) {
                return Err(items.error(g.line, "X_Y_Z: the three DataItems differ in length"));
            }
            let float = axes
                .iter()
                .all(|a| matches!(a.values, crate::formats::ArrayValues::F32(_)));
            let nodes = (0..n)
                .map(|i| {
                    [
                        axes[0].values.get(i),
                        axes[1].values.get(i),
                        axes[2].values.get(i),
                    ]
                })
                .collect();
            Ok((nodes, float))
        }
        other => Err(items.error(
            g.line,
            format!("GeometryType=\"{other}\": VoRANG reads XYZ, XY and X_Y_Z"),
        )),
    }
}

/// The cells of a Topology over `points` points (0-based node numbers, checked).
pub fn cells(items: &mut Items, t: &Node, points: usize) -> Result<Cells, ParseError> {
    let kind = t
        .attr("TopologyType")
        .or_else(|| t.attr("Type"))
        .unwrap_or("");
    let item = t
        .first("DataItem")
        .ok_or_else(|| items.error(t.line, "Topology without a DataItem"))?;
    let data = items.read(item)?;
    // Taken, not copied: a large connectivity exists once while its cells are built.
    let ids: Vec<i64> = match data.values {
        crate::formats::ArrayValues::Int(v) => v,
        other => (0..other.len()).map(|i| other.get(i) as i64).collect(),
    };
    let check = |i: usize, n: i64| -> Result<u64, ParseError> {
        if n < 0 || n as usize >= points {
            return Err(items.error(
                item.line,
                format!("cell {i}: node {n} is not one of the {points} points"),
            ));
        }
        Ok(n as u64)
    };
    let mut cells = Cells::default();
    if kind.eq_ignore_ascii_case("mixed") {
        let mut at = 0;
        let mut nodes = Vec::new();
        while at < ids.len() {
            let i = cells.len();
            let code = ids[at];
            let (ty, fixed) = by_code(code).ok_or_else(|| {
                items.error(
                    item.line,
                    format!("cell {i}: unknown XDMF cell type {code}"),
                )
            })?;
            at += 1;
            let count = if fixed > 0 {
                fixed
            } else {
                let n = ids.get(at).copied().unwrap_or(-1);
                at += 1;
                usize::try_from(n)
                    .map_err(|_| items.error(item.line, format!("cell {i}: node count {n}")))?
            };
            let Some(list) = ids.get(at..at.saturating_add(count)) else {
                return Err(items.error(
                    item.line,
                    format!("cell {i}: the Mixed topology ends inside the cell"),
                ));
            };
            nodes.clear();
            for &n in list {
                nodes.push(check(i, n)?);
            }
            cells.push(ty, &nodes);
            at += count;
        }
        return Ok(cells);
    }
    let (ty, mut per) = by_name(kind).ok_or_else(|| {
        items.error(
            t.line,
            format!("TopologyType=\"{kind}\": VoRANG reads Tetrahedron, Tetrahedron_10, Hexahedron, Hexahedron_20, Hexahedron_27, Wedge, Wedge_15, Wedge_18, Pyramid, Pyramid_13 and Mixed (Triangle, Quadrilateral, Polyline and Polyvertex are skipped)"),
        )
    })?;
    if let Some(n) = t
        .attr("NodesPerElement")
        .and_then(|n| n.trim().parse().ok())
    {
        per = n;
    }
    if per == 0 || !ids.len().is_multiple_of(per) {
        return Err(items.error(
            item.line,
            format!(
                "{} node numbers are no whole number of {kind} cells of {per} nodes",
                ids.len()
            ),
        ));
    }
    cells.types.reserve_exact(ids.len() / per);
    cells.offsets.reserve_exact(ids.len() / per + 1);
    cells.connectivity.reserve_exact(ids.len());
    let mut nodes = Vec::with_capacity(per);
    for (i, cell) in ids.chunks_exact(per).enumerate() {
        nodes.clear();
        for &n in cell {
            nodes.push(check(i, n)?);
        }
        cells.push(ty, &nodes);
    }
    Ok(cells)
}
