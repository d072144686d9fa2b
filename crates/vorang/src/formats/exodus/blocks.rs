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

/// The VTK type of an `elem_type` with `nodes` nodes per element, and how many of the nodes
/// it takes (the corners, for the higher-order elements VoRANG has no cell for); `None`:
/// not a volume element.
fn cell_type(elem_type: &str, nodes: usize) -> Option<(u8, usize)> {
    let t = elem_type.trim().to_ascii_uppercase();
    let (linear, corners) = if t.starts_with("TET") {
        if nodes == 10 {
            return Some((vtk::QUADRATIC_TETRA, 10));
        }
        (vtk::TETRA, 4)
    } else if t.starts_with("HEX") {
        (vtk::HEXAHEDRON, 8)
    } else if t.starts_with("WEDGE") {
        (vtk::WEDGE, 6)
    } else if t.starts_with("PYR") {
        (vtk::PYRAMID, 5)
    } else {
        return None;
    };
    (nodes >= corners).then_some((linear, corners))
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
        let Some((ty, take)) = cell_type(&elem_type, per) else {
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
        if take < per && ty != vtk::QUADRATIC_TETRA {
            warn(
                warnings,
                format!(
                    "block {id} ({elem_type}): {per}-node elements read as their {take} corners (VoRANG has no cell for them)"
                ),
            );
        }
        let conn = exo.read(&var, &[])?;
        if per == 0 || Some(conn.len()) != elements.checked_mul(per) {
            return Err(exo.error(
                &format!("variable {var}"),
                format!(
                    "{} node numbers for {elements} elements of {per} nodes",
                    conn.len()
                ),
            ));
        }
        let mut nodes = Vec::with_capacity(take);
        for e in 0..elements {
            nodes.clear();
            for k in 0..take {
                let n = conn.get(e * per + k) as i64;
                if n < 1 || n as usize > points {
                    return Err(exo.error(&format!("variable {var}"), format!("element {}: node {n} is not one of the {points} nodes (numbered from 1)", e + 1)));
                }
                nodes.push(n as u64 - 1);
            }
            cells.push(ty, &nodes);
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

    #[test]
    fn element_types_by_name_and_node_count() {
        assert_eq!(cell_type("TETRA", 4), Some((vtk::TETRA, 4)));
        assert_eq!(cell_type("tet4", 4), Some((vtk::TETRA, 4)));
        assert_eq!(cell_type("TETRA10", 10), Some((vtk::QUADRATIC_TETRA, 10)));
        assert_eq!(cell_type("HEX27", 27), Some((vtk::HEXAHEDRON, 8)));
        assert_eq!(cell_type("Wedge6", 6), Some((vtk::WEDGE, 6)));
        assert_eq!(cell_type("PYRAMID5", 5), Some((vtk::PYRAMID, 5)));
        assert_eq!(cell_type("SHELL4", 4), None);
        assert_eq!(cell_type("QUAD4", 4), None);
        assert_eq!(cell_type("TETRA", 3), None);
    }
}
