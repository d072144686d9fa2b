//! Cells to tetrahedra: the rule for each kind of cell, and the warnings about cells not
//! rendered as they are. Tetrahedra stay, quadratic tetrahedra keep their corners (their
//! mid-edge nodes are remembered for the `HigherOrder` fields), hexahedra, voxels, wedges and
//! pyramids are split conformingly ([`super::split_cell`]), Lagrange cells by their degree
//! (`higher`), quadratic hexahedra, wedges and pyramids as Lagrange cells with their face
//! centres added (`serendipity`), polyhedra around added centre points (`polyhedra`);
//! everything else is counted
//! and skipped. Apart from the fields because every tetrahedron remembers the cell it was cut
//! from, which is all the field step needs to know about the split; apart from the rules of
//! each kind of cell so that this dispatch (the checks every cell passes first: a volume type,
//! a node count its type allows, points that exist) reads in one place.

use std::collections::HashMap;

use super::cut::{Added, Tetrahedra};
use super::{polyhedra, serendipity};
use crate::error::{ParseError, Warning};
use crate::formats::lagrange::Shape;
use crate::formats::{Cells, cell_type};

/// Cells → tetrahedra, each remembering the cell it came from. A volume cell needs its number
/// of nodes, each one of the `nodes` (their positions place the polyhedra's added points,
/// rounded to `float` when every coordinate is one: `float32`).
pub(super) fn tetrahedra(
    source: &str,
    cells: &Cells,
    (nodes, float32): (&[[f64; 3]], bool),
    cells_line: usize,
) -> Result<Tetrahedra, ParseError> {
    let err = |line: usize, msg: String| ParseError::new(source, line.max(1), msg);
    let n_nodes = nodes.len();
    // Every volume cell gives at least one tetrahedron: room for a file of tetrahedra at once
    // (no vector grown past what it holds at the load's highest point).
    let volume_cells = cells
        .types
        .iter()
        .filter(|&&t| cell_type::is_volume(t))
        .count();
    let mut out = Tetrahedra {
        tets: Vec::with_capacity(volume_cells),
        parent: Vec::with_capacity(volume_cells),
        skipped: HashMap::new(),
        midpoints: HashMap::new(),
        quadratic: false,
        subdivided: 0,
        unordered: 0,
        added: Added::new(n_nodes, float32),
        serendipity_faces: HashMap::new(),
    };
    for i in 0..cells.len() {
        let ty = cells.types[i];
        let conn = cells.nodes(i);
        if !cell_type::is_volume(ty) {
            *out.skipped.entry(ty).or_default() += 1;
            continue;
        }
        if let Some(need) = cell_type::node_count_problem(ty, conn.len()) {
            return Err(err(
                cells_line,
                format!(
                    "cell {} is a {} and {need}, but the connectivity gives it {}",
                    i + 1,
                    cell_type::name(ty),
                    conn.len()
                ),
            ));
        }
        if let Some(&bad) = conn.iter().find(|&&n| n as usize >= n_nodes) {
            return Err(err(
                cells_line,
                format!(
                    "cell {} refers to point {bad} (0-based), but there are only {n_nodes} points",
                    i + 1
                ),
            ));
        }
        if i >= u32::MAX as usize {
            return Err(err(cells_line, "too many cells".into()));
        }
        if ty == cell_type::POLYHEDRON {
            let faces = polyhedra::faces_of(cells, i, n_nodes).map_err(|m| {
                err(
                    cells_line,
                    format!("cell {} is a polyhedron, but {m}", i + 1),
                )
            })?;
            polyhedra::split(&mut out, i as u32, &faces, nodes);
        } else if serendipity::handles(ty) {
            serendipity::add(&mut out, i as u32, ty, conn, nodes);
        } else {
            out.add_cell(i as u32, ty, conn);
        }
    }
    Ok(out)
}

impl Tetrahedra {
    /// The tetrahedra of volume cell `i` of type `ty` with nodes `conn` (not a polyhedron).
    fn add_cell(&mut self, i: u32, ty: u8, conn: &[u32]) {
        match ty {
            cell_type::TETRA => self.push(i, [conn[0], conn[1], conn[2], conn[3]]),
            cell_type::QUADRATIC_TETRA => {
                self.push(i, [conn[0], conn[1], conn[2], conn[3]]);
                // VTK order of the mid-edge nodes 4…9.
                const EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
                for (k, [a, b]) in EDGES.iter().enumerate() {
                    self.midpoint(conn[*a], conn[*b], conn[4 + k]);
                }
            }
            // A voxel is a hexahedron whose nodes 2 and 3, 6 and 7 come the other way round.
            cell_type::VOXEL => {
                let hex = [0, 1, 3, 2, 4, 5, 7, 6].map(|k| conn[k]);
                self.split(i, cell_type::HEXAHEDRON, &hex);
            }
            _ => match Shape::of(ty) {
                Some(shape) => super::higher::add(self, i, shape, conn),
                None => {
                    self.split(i, ty, conn);
                }
            },
        }
    }
}

/// The warnings about cells not rendered as they are: skipped cells counted by type, Lagrange
/// cells subdivided, Lagrange pyramids VTK gives no node order for.
pub(super) fn warnings(source: &str, cells_line: usize, out: &mut Tetrahedra) -> Vec<Warning> {
    let warning = |message: String| Warning {
        file: source.to_string(),
        line: Some(cells_line.max(1)),
        message,
    };
    let plural = |n: usize, one: &'static str, many: &'static str| if n == 1 { one } else { many };
    let mut list = Vec::new();
    list.extend(skipped_warning(
        source,
        cells_line,
        std::mem::take(&mut out.skipped),
    ));
    if out.subdivided > 0 {
        let n = out.subdivided;
        list.push(warning(format!(
            "{n} Lagrange cell{} of degree 3 or more {} subdivided into tetrahedra between {} nodes: the field is linear between neighbouring nodes there, not a polynomial of the cell's degree",
            plural(n, "", "s"),
            plural(n, "was", "were"),
            plural(n, "its", "their")
        )));
    }
    if out.unordered > 0 {
        let n = out.unordered;
        list.push(warning(format!(
            "skipped {n} Lagrange pyramid{} of degree 3 or more: VTK defines no order for the nodes of such pyramids",
            plural(n, "", "s")
        )));
    }
    list
}

/// One warning that counts the skipped cells by type, if there are any.
fn skipped_warning(
    source: &str,
    cells_line: usize,
    skipped: HashMap<u8, usize>,
) -> Option<Warning> {
    if skipped.is_empty() {
        return None;
    }
    let mut kinds: Vec<(u8, usize)> = skipped.into_iter().collect();
    kinds.sort_unstable();
    let total: usize = kinds.iter().map(|k| k.1).sum();
    let list: Vec<String> = kinds
        .iter()
        .map(|(t, n)| format!("{n} × {}", cell_type::name(*t)))
        .collect();
    Some(Warning {
        file: source.to_string(),
        line: Some(cells_line.max(1)),
        message: format!(
            "skipped {total} cell{} that VoRANG does not render ({}); the volume cells are tetrahedra, hexahedra, voxels, wedges, pyramids, quadratic tetrahedra, hexahedra, wedges and pyramids, Lagrange cells and polyhedra",
            if total == 1 { "" } else { "s" },
            list.join(", ")
        ),
    })
}
