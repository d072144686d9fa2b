//! Exodus element blocks: `connect{j}` with its `elem_type` becomes VTK cells (Exodus numbers
//! the nodes of its tetrahedra, hexahedra, wedges and pyramids as VTK does), the block ids
//! (`eb_prop1`) the cell array `block`, and the element variables of a step
//! (`vals_elem_var{i}eb{j}`) cell arrays. 2-D and shell blocks (triangles, quadrilaterals,
//! shells, beams) are not volumes: they are skipped with a warning, as the other readers skip
//! cells that are no volume (docs/formats.md, "Exodus II").

use super::Exo;
use crate::error::{ParseError, Warning};
use crate::formats::cell_type as vtk;
use crate::formats::{Array, ArrayValues, Cells};

/// One element block as read.
pub(super) struct Block {
    /// The block's id (`eb_prop1`; its number from 1 where the file has no ids).
    id: i64,
    /// Its number in the file (1-based: `connect{number}`).
    number: usize,
    /// Its elements (all of them are cells when the block is kept).
    elements: usize,
    kept: bool,
}

/// How the elements of a block become VTK cells: the VTK type, and for each of the cell's
/// nodes (in VTK's order) the element's node it is (0-based, in Exodus's order).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Kind {
    ty: u8,
    order: &'static [usize],
    /// Whether the cell renders the element as it is (not only some of its nodes).
    exact: bool,
}

/// The first `n` node numbers (the linear cells, the corners of the higher-order ones, and
/// the quadratic tetrahedron, whose mid-edge nodes Exodus numbers as VTK does).
const IDENTITY: [usize; 14] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13];

/// `HEX27` as a degree-2 Lagrange hexahedron. Exodus lists the mid-edge nodes of the
/// vertical edges (1-5, 2-6, 3-7, 4-8) before those of the top face, VTK after; and its
/// centre node first (21), then the face nodes of the bottom, top, x = 0 (1-4-8-5),
/// x = 1 (2-3-7-6), y = 0 (1-2-6-5) and y = 1 (3-4-8-7) faces, where VTK has x = 0, x = 1,
/// y = 0, y = 1, bottom, top, centre (the Exodus II manual's HEX27 figure; VTK's own Exodus
/// reader and libMesh's Exodus writer number it the same way).
const HEX27: [usize; 27] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 16, 17, 18, 19, 12, 13, 14, 15, 23, 24, 25, 26, 21, 22,
    20,
];

/// `WEDGE18` as a degree-2 Lagrange wedge: Exodus lists the vertical edges' nodes (1-4, 2-5,
/// 3-6) before the top triangle's, VTK after; the three quadrilateral faces' centres (1-2-5-4,
/// 2-3-6-5, 3-1-4-6) come last in both.
const WEDGE18: [usize; 18] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 13, 14, 9, 10, 11, 15, 16, 17];

/// `HEX20` as VTK's quadratic hexahedron: Exodus lists the vertical edges' nodes (1-5, 2-6,
/// 3-7, 4-8) before the top face's, VTK after.
const HEX20: [usize; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 16, 17, 18, 19, 12, 13, 14, 15,
];

/// `WEDGE15` as VTK's quadratic wedge: the vertical edges' nodes before the top triangle's.
const WEDGE15: [usize; 15] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 13, 14, 9, 10, 11];

/// How elements of `elem_type` with `nodes` nodes each become cells; `None`: not a volume
/// element. The serendipity `HEX20`, `WEDGE15` and `PYRAMID13` become VTK's quadratic cells
/// (read as Lagrange cells with their face centres added: crates/vorang/src/formats/build/
/// serendipity.rs); elements of other node counts keep their corners (`exact` false); a
/// tetrahedron with more than 10 nodes (`TETRA14`, `TETRA15`: face nodes) its 10 quadratic
/// nodes.
fn kind(elem_type: &str, nodes: usize) -> Option<Kind> {
    let t = elem_type.trim().to_ascii_uppercase();
    let exact = |ty: u8, order: &'static [usize]| Kind {
        ty,
        order,
        exact: true,
    };
    let corners = |ty: u8, n: usize| {
        (nodes >= n).then_some(Kind {
            ty,
            order: &IDENTITY[..n],
            exact: nodes == n,
        })
    };
    if t.starts_with("TET") {
        if nodes >= 10 {
            return Some(Kind {
                exact: nodes == 10,
                ..exact(vtk::QUADRATIC_TETRA, &IDENTITY[..10])
            });
        }
        corners(vtk::TETRA, 4)
    } else if t.starts_with("HEX") {
        if nodes == 27 {
            return Some(exact(vtk::LAGRANGE_HEXAHEDRON, &HEX27));
        }
        if nodes == 20 {
            return Some(exact(vtk::QUADRATIC_HEXAHEDRON, &HEX20));
        }
        corners(vtk::HEXAHEDRON, 8)
    } else if t.starts_with("WEDGE") {
        if nodes == 18 {
            return Some(exact(vtk::LAGRANGE_WEDGE, &WEDGE18));
        }
        if nodes == 15 {
            return Some(exact(vtk::QUADRATIC_WEDGE, &WEDGE15));
        }
        corners(vtk::WEDGE, 6)
    } else if t.starts_with("PYR") {
        // PYRAMID14: corners, mid-edge nodes (base, then to the apex), the base's centre —
        // the order of VoRANG's degree-2 Lagrange pyramid (crates/vorang/src/formats/lagrange.rs).
        if nodes == 14 {
            return Some(exact(vtk::LAGRANGE_PYRAMID, &IDENTITY[..14]));
        }
        // PYRAMID13: VTK's quadratic pyramid, the same order.
        if nodes == 13 {
            return Some(exact(vtk::QUADRATIC_PYRAMID, &IDENTITY[..13]));
        }
        corners(vtk::PYRAMID, 5)
    } else {
        None
    }
}

/// The blocks' cells into `cells` (node numbers checked against `points`), warnings for the
/// blocks skipped and the higher-order ones cut to their corners.
pub(super) fn read(
    exo: &Exo,
    points: usize,
    cells: &mut Cells,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<Block>, ParseError> {
    let count = exo.dim("num_el_blk");
    let ids = if exo.has("eb_prop1") {
        let v = exo.read("eb_prop1", &[])?;
        (0..v.len()).map(|i| v.get(i) as i64).collect()
    } else {
        Vec::new()
    };
    // Every block has its dimension num_el_in_blk{j}: a count beyond the file's dimensions is
    // corrupt (and must not drive a loop of billions).
    if count > exo.dimensions() {
        return Err(exo.error(
            "dimension num_el_blk",
            format!(
                "{count} blocks, but the file has {} dimensions",
                exo.dimensions()
            ),
        ));
    }
    let mut blocks = Vec::new();
    let warn = |warnings: &mut Vec<Warning>, message: String| {
        warnings.push(Warning {
            file: exo.name.clone(),
            line: None,
            message,
        })
    };
    for number in 1..=count {
        let id = ids.get(number - 1).copied().unwrap_or(number as i64);
        let var = format!("connect{number}");
        let elements = exo.dim(&format!("num_el_in_blk{number}"));
        if !exo.has(&var) {
            if elements == 0 {
                blocks.push(Block {
                    id,
                    number,
                    elements: 0,
                    kept: false,
                });
                continue;
            }
            return Err(exo.error(
                &format!("variable {var}"),
                format!("not in the file: block {id} has {elements} elements"),
            ));
        }
        let shape = exo.shape(&var)?;
        let per = shape.get(1).copied().unwrap_or(0) as usize;
        let elem_type = exo.text_attr(&var, "elem_type").unwrap_or_default();
        let Some(kind) = kind(&elem_type, per) else {
            warn(
                warnings,
                format!("block {id} ({elem_type}, {per} nodes) is not a volume block: skipped"),
            );
            blocks.push(Block {
                id,
                number,
                elements,
                kept: false,
            });
            continue;
        };
        if !kind.exact {
            let take = kind.order.len();
            let what = if take == 10 {
                "quadratic nodes"
            } else {
                "corners"
            };
            warn(
                warnings,
                format!(
                    "block {id} ({elem_type}): {per}-node elements read as their {take} {what} (VoRANG has no cell for them): the field is interpolated from those nodes only"
                ),
            );
        }
        let conn = exo.read_nodes(&var)?;
        if per == 0 || Some(conn.len()) != elements.checked_mul(per) {
            return Err(exo.error(
                &format!("variable {var}"),
                format!(
                    "{} node numbers for {elements} elements of {per} nodes",
                    conn.len()
                ),
            ));
        }
        // The numbers are in memory: the cells they make can be reserved.
        cells.types.reserve(elements);
        cells.offsets.reserve(elements + 1);
        cells.connectivity.reserve(elements * kind.order.len());
        let mut nodes = Vec::with_capacity(kind.order.len());
        for e in 0..elements {
            nodes.clear();
            for &k in kind.order {
                let n = conn.get(e * per + k) as i64;
                if n < 1 || n as usize > points {
                    return Err(exo.error(&format!("variable {var}"), format!("element {}: node {n} is not one of the {points} nodes (numbered from 1)", e + 1)));
                }
                nodes.push(n as u64 - 1);
            }
            cells.push(kind.ty, &nodes);
        }
        blocks.push(Block {
            id,
            number,
            elements,
            kept: true,
        });
    }
    Ok(blocks)
}

/// The cell array `block`: each cell's block id.
pub(super) fn ids_array(blocks: &[Block]) -> Array {
    let values = blocks
        .iter()
        .filter(|b| b.kept)
        .flat_map(|b| std::iter::repeat_n(b.id, b.elements))
        .collect();
    Array {
        name: "block".into(),
        components: 1,
        values: ArrayValues::Int(values),
        line: 0,
    }
}

/// The element variables of step `step` as cell arrays: each kept block's values where the
/// block has the variable (`elem_var_tab`, or where `vals_elem_var{i}eb{j}` exists without
/// a table), 0 where it has not.
pub(super) fn element_arrays(
    exo: &Exo,
    blocks: &[Block],
    step: usize,
) -> Result<Vec<Array>, ParseError> {
    let names = exo.names("name_elem_var")?;
    let table = if exo.has("elem_var_tab") {
        Some(exo.read("elem_var_tab", &[])?)
    } else {
        None
    };
    // elem_var_tab[block, variable]: non-zero where the block has the variable.
    let per_block = names.len();
    let mut out = Vec::new();
    for (i, name) in names.into_iter().enumerate() {
        let mut values = Vec::new();
        let mut float = true;
        for b in blocks.iter().filter(|b| b.kept) {
            let var = format!("vals_elem_var{}eb{}", i + 1, b.number);
            let at = (b.number - 1) * per_block + i;
            let listed = table
                .as_ref()
                .is_none_or(|t| at < t.len() && t.get(at) != 0.0);
            if listed && exo.has(&var) {
                let v = exo.read(&var, &[step as u64])?;
                if v.len() != b.elements {
                    return Err(exo.error(
                        &format!("variable {var}"),
                        format!(
                            "{} values for the {} elements of block {}",
                            v.len(),
                            b.elements,
                            b.id
                        ),
                    ));
                }
                float &= matches!(v, ArrayValues::F32(_));
                values.extend((0..v.len()).map(|k| v.get(k)));
            } else {
                values.extend(std::iter::repeat_n(0.0, b.elements));
            }
        }
        let values = if float {
            ArrayValues::F32(values.into_iter().map(|v| v as f32).collect())
        } else {
            ArrayValues::F64(values)
        };
        out.push(Array {
            name,
            components: 1,
            values,
            line: 0,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::lagrange::Shape;

    fn ty(elem_type: &str, nodes: usize) -> Option<(u8, usize, bool)> {
        kind(elem_type, nodes).map(|k| (k.ty, k.order.len(), k.exact))
    }

    #[test]
    fn element_types_by_name_and_node_count() {
        assert_eq!(ty("TETRA", 4), Some((vtk::TETRA, 4, true)));
        assert_eq!(ty("tet4", 4), Some((vtk::TETRA, 4, true)));
        assert_eq!(ty("TETRA10", 10), Some((vtk::QUADRATIC_TETRA, 10, true)));
        assert_eq!(ty("TETRA14", 14), Some((vtk::QUADRATIC_TETRA, 10, false)));
        assert_eq!(ty("HEX27", 27), Some((vtk::LAGRANGE_HEXAHEDRON, 27, true)));
        assert_eq!(ty("HEX20", 20), Some((vtk::QUADRATIC_HEXAHEDRON, 20, true)));
        assert_eq!(ty("Wedge6", 6), Some((vtk::WEDGE, 6, true)));
        assert_eq!(ty("WEDGE15", 15), Some((vtk::QUADRATIC_WEDGE, 15, true)));
        assert_eq!(ty("WEDGE18", 18), Some((vtk::LAGRANGE_WEDGE, 18, true)));
        assert_eq!(ty("PYRAMID5", 5), Some((vtk::PYRAMID, 5, true)));
        assert_eq!(
            ty("PYRAMID13", 13),
            Some((vtk::QUADRATIC_PYRAMID, 13, true))
        );
        assert_eq!(ty("HEX9", 9), Some((vtk::HEXAHEDRON, 8, false)));
        assert_eq!(ty("PYRAMID14", 14), Some((vtk::LAGRANGE_PYRAMID, 14, true)));
        assert_eq!(ty("SHELL4", 4), None);
        assert_eq!(ty("QUAD4", 4), None);
        assert_eq!(ty("TETRA", 3), None);
    }

    /// The Exodus II manual's HEX20 (the first 20 nodes of its HEX27): each node on the unit
    /// cell, times 2.
    const EXODUS_HEX20: [[usize; 3]; 20] = [
        [0, 0, 0],
        [2, 0, 0],
        [2, 2, 0],
        [0, 2, 0],
        [0, 0, 2],
        [2, 0, 2],
        [2, 2, 2],
        [0, 2, 2],
        // Bottom edges, vertical edges, top edges.
        [1, 0, 0],
        [2, 1, 0],
        [1, 2, 0],
        [0, 1, 0],
        [0, 0, 1],
        [2, 0, 1],
        [2, 2, 1],
        [0, 2, 1],
        [1, 0, 2],
        [2, 1, 2],
        [1, 2, 2],
        [0, 1, 2],
    ];

    /// The Exodus II manual's WEDGE15 (the first 15 nodes of its WEDGE18).
    const EXODUS_WEDGE15: [[usize; 3]; 15] = [
        [0, 0, 0],
        [2, 0, 0],
        [0, 2, 0],
        [0, 0, 2],
        [2, 0, 2],
        [0, 2, 2],
        // Bottom edges 1-2, 2-3, 3-1; vertical 1-4, 2-5, 3-6; top 4-5, 5-6, 6-4.
        [1, 0, 0],
        [1, 1, 0],
        [0, 1, 0],
        [0, 0, 1],
        [2, 0, 1],
        [0, 2, 1],
        [1, 0, 2],
        [1, 1, 2],
        [0, 1, 2],
    ];

    /// Where the Exodus II manual places each node of an element (on the unit cell, times 2:
    /// the degree-2 lattice), checked against where VoRANG's Lagrange cells expect the node
    /// that the order puts there.
    fn check_order(shape: Shape, exodus: &[[usize; 3]], order: &[usize]) {
        assert_eq!(exodus.len(), order.len());
        for (v, &e) in order.iter().enumerate() {
            assert_eq!(
                shape.index(2, exodus[e]),
                v,
                "{shape:?}: VTK node {v} = Exodus node {}",
                e + 1
            );
        }
    }

    #[test]
    fn hex27_nodes_land_where_the_lagrange_hexahedron_has_them() {
        let mut exodus = EXODUS_HEX20.to_vec();
        // Centre; faces bottom, top, 1-4-8-5 (x = 0), 2-3-7-6, 1-2-6-5 (y = 0), 3-4-8-7.
        exodus.extend([
            [1, 1, 1],
            [1, 1, 0],
            [1, 1, 2],
            [0, 1, 1],
            [2, 1, 1],
            [1, 0, 1],
            [1, 2, 1],
        ]);
        check_order(Shape::Hexahedron, &exodus, &HEX27);
    }

    /// HEX20 and WEDGE15: each VTK node (VTK's parametric coordinates of its quadratic
    /// hexahedron and wedge, times 2, as vtkQuadraticHexahedron/vtkQuadraticWedge give them) is
    /// the Exodus node the order puts there (the Exodus II manual's numbering).
    #[test]
    fn hex20_and_wedge15_nodes_land_where_vtk_has_them() {
        let exodus_hex = EXODUS_HEX20;
        let vtk_hex = [
            [0, 0, 0],
            [2, 0, 0],
            [2, 2, 0],
            [0, 2, 0],
            [0, 0, 2],
            [2, 0, 2],
            [2, 2, 2],
            [0, 2, 2],
            [1, 0, 0],
            [2, 1, 0],
            [1, 2, 0],
            [0, 1, 0],
            [1, 0, 2],
            [2, 1, 2],
            [1, 2, 2],
            [0, 1, 2],
            [0, 0, 1],
            [2, 0, 1],
            [2, 2, 1],
            [0, 2, 1],
        ];
        for (v, &e) in HEX20.iter().enumerate() {
            assert_eq!(exodus_hex[e], vtk_hex[v], "HEX20: VTK node {v}");
        }
        let exodus_wedge = EXODUS_WEDGE15;
        let vtk_wedge = [
            [0, 0, 0],
            [2, 0, 0],
            [0, 2, 0],
            [0, 0, 2],
            [2, 0, 2],
            [0, 2, 2],
            [1, 0, 0],
            [1, 1, 0],
            [0, 1, 0],
            [1, 0, 2],
            [1, 1, 2],
            [0, 1, 2],
            [0, 0, 1],
            [2, 0, 1],
            [0, 2, 1],
        ];
        for (v, &e) in WEDGE15.iter().enumerate() {
            assert_eq!(exodus_wedge[e], vtk_wedge[v], "WEDGE15: VTK node {v}");
        }
    }

    #[test]
    fn wedge18_nodes_land_where_the_lagrange_wedge_has_them() {
        let mut exodus = EXODUS_WEDGE15.to_vec();
        // Faces 1-2-5-4, 2-3-6-5, 3-1-4-6.
        exodus.extend([[1, 0, 1], [1, 1, 1], [0, 1, 1]]);
        check_order(Shape::Wedge, &exodus, &WEDGE18);
    }

    #[test]
    fn pyramid14_nodes_land_where_the_lagrange_pyramid_has_them() {
        // Corners as the Lagrange pyramid places them (apex at (0, 0, 2)), then the
        // midpoints of the edges 1-2, 2-3, 3-4, 4-1, 1-5, 2-5, 3-5, 4-5 and of the base.
        let c: Vec<[usize; 3]> = (0..5).map(|v| Shape::Pyramid.corner(2, v)).collect();
        let mid = |a: usize, b: usize| [0, 1, 2].map(|d| (c[a][d] + c[b][d]) / 2);
        let mut exodus = c.clone();
        for (a, b) in [
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (0, 4),
            (1, 4),
            (2, 4),
            (3, 4),
            (0, 2),
        ] {
            exodus.push(mid(a, b));
        }
        check_order(Shape::Pyramid, &exodus, &IDENTITY[..14]);
    }
}
