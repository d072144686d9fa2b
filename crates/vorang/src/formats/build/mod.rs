//! Building a [`Volume`] from a [`MeshDescription`]: cells become tetrahedra, arrays become
//! fields.
//!
//! **Cells.** Tetrahedra are kept as they are. Hexahedra, wedges and pyramids are split into
//! tetrahedra *conformingly*: a quadrilateral face is always cut along the diagonal through its
//! node with the smallest global index, so the two cells that share the face cut it the same
//! way whatever their own node order. The split that realises this (Dompierre et al. 1999):
//! take the cell's smallest node `v`; the cell is the union of the cones from `v` over the faces
//! that do not contain `v` — a triangle gives one tetrahedron, a quadrilateral a pyramid that is
//! cut along the face's own smallest-node diagonal into two. The faces that contain `v` are
//! cut through `v`, which is their smallest node too. A hexahedron gives 6 tetrahedra, a wedge
//! 3, a pyramid 2; a voxel is a hexahedron with its nodes in another order. Quadratic
//! tetrahedra (VTK 24, Gmsh 11) become their corner tetrahedron, and every point array then
//! becomes a `HigherOrder` (P2) field from the corner values and the mid-edge values (edges
//! without a mid-edge node, e.g. of linear cells in the same file, get the mean of their ends,
//! which keeps the field linear along them); an array whose mid-edge values all lie exactly
//! halfway is linear and stays a `Linear` field. Lagrange cells (VTK 71–74) are split by
//! their degree (`higher`), polyhedra around added centre points (`polyhedra`), which join the
//! file's points. Other cells (points, lines, faces, other higher-order cells) are skipped with
//! one warning that counts them by type; a file without volume cells is an error.
//!
//! **Fields** (docs/formats.md, "Fields (VTK and Gmsh)"): field number = position in the file, point arrays
//! first, then cell arrays. Point arrays become `Linear` fields (`HigherOrder` with quadratic
//! cells), cell arrays `Constant` fields; a cell's value is carried by every tetrahedron cut
//! from it, and a point array's value at an added point is the mean of the points it stands
//! for.
//! Integer arrays become `int` data, except scalar integer *cell* arrays whose values all lie
//! in 0…255: those are `byte`, so that `CONST_CELL`, `CategoryField` and `linedraw` take them
//! (material ids, Gmsh physical groups). Float32 data stay `float`, everything else `double`;
//! arrays of `n` > 1 components are `type[n]`, except that 3-component arrays are `float[3]`,
//! HyperMesh's vector type (values rounded to `float`). Names are kept.
//!
//! The build runs in named steps: the points are checked (`check_nodes`), the cells become
//! tetrahedra (`cells`), the tetrahedra a mesh (`tet_mesh`), and the arrays fields
//! (`fields`). Cells and fields have their own modules because each is a rule of its own (the
//! conforming split; the array-to-field-type table) with its own tests.

mod cells;
mod cut;
mod fields;
mod higher;
mod polyhedra;
mod serendipity;

use std::collections::HashMap;

use super::MeshDescription;
use crate::data::ScalarType;
use crate::error::{ParseError, Warning};
use crate::mesh::{EDGE_NODES, TetMesh};
use crate::volume::{Geometry, Volume};
use cut::Tetrahedra;

pub use cut::split_cell;

/// The smallest non-zero coordinate magnitude accepted (see [`volume`]).
pub const MIN_MAGNITUDE: f64 = 1e-50;

/// Builds the volume; warnings (skipped cells, re-oriented tetrahedra) are returned.
pub fn volume(desc: MeshDescription) -> Result<(Volume, Vec<Warning>), ParseError> {
    volume_with_shape(desc).map(|(vol, _, warnings)| (vol, warnings))
}

/// What a volume's fields are built on besides its mesh: the file's cell each tetrahedron was
/// cut from, the mid-edge nodes of quadratic cells, and the points the polyhedra added (each a
/// mean of the file's points). A time series keeps it with a step so that the next step with
/// the same points and cells builds only its fields ([`fields_on`]).
#[derive(Debug, Clone)]
pub struct Shape {
    parent: Vec<u32>,
    midpoints: HashMap<(u32, u32), u32>,
    added: cut::Added,
}

impl Shape {
    /// How many points the polyhedra added after the file's (the mesh's last points).
    pub fn added_points(&self) -> usize {
        self.added.len()
    }
}

/// [`volume`], with the [`Shape`] its fields were built on (`None` for a `.vtu` that VoRANG
/// wrote: its layout rebuilds the volume as it was, fields included).
pub fn volume_with_shape(
    mut desc: MeshDescription,
) -> Result<(Volume, Option<Shape>, Vec<Warning>), ParseError> {
    // A .vtu that VoRANG wrote: its layout gives back the volume exactly.
    if let Some(done) = super::layout::volume(&mut desc) {
        return done.map(|(vol, warnings)| (vol, None, warnings));
    }
    let MeshDescription {
        source,
        mut nodes,
        float_coordinates,
        cells,
        mut point_arrays,
        cell_arrays,
        points_line,
        cells_line,
        mut warnings,
        ..
    } = desc;
    let err = |line: usize, msg: String| ParseError::new(&source, line.max(1), msg);
    check_nodes(&source, &nodes, points_line)?;
    for a in point_arrays.iter() {
        fields::check_array(&source, a, nodes.len(), "points")?;
    }
    for a in cell_arrays.iter() {
        fields::check_array(&source, a, cells.len(), "cells")?;
    }

    let mut cut = cells::tetrahedra(&source, &cells, (&nodes, float_coordinates), cells_line)?;
    // The cell list is no longer needed (only the types, for messages): free it before the
    // mesh builds its adjacency, which keeps the peak memory of a load low.
    let cell_types = cells.types;
    drop((cells.offsets, cells.connectivity, cells.faces));
    warnings.extend(cells::warnings(&source, cells_line, &mut cut));
    let Tetrahedra {
        tets,
        parent,
        midpoints,
        quadratic,
        added,
        ..
    } = cut;
    added.extend_points(&mut nodes);
    added.extend_arrays(&mut point_arrays);
    let added = added.means_only();
    if tets.is_empty() {
        return Err(err(
            cells_line,
            "no volume cells (tetrahedra, hexahedra, voxels, wedges, pyramids, quadratic tetrahedra, hexahedra, wedges or pyramids, Lagrange cells or polyhedra): nothing to render".into(),
        ));
    }
    let cell_arrays = fields::early(cell_arrays, &parent);
    let mesh = tet_mesh(
        &source,
        nodes,
        tets,
        &parent,
        &cell_types,
        [points_line, cells_line],
    )?;
    if mesh.reoriented() > 0 {
        warnings.push(Warning {
            file: source.clone(),
            line: Some(cells_line.max(1)),
            message: format!(
                "{} tetrahedra were negatively oriented and have been re-oriented",
                mesh.reoriented()
            ),
        });
    }

    // Edges, for HigherOrder fields: every edge of every tetrahedron, in first-use order.
    let (edges, tet_edges) = if quadratic {
        let (list, te) = quadratic_edges(&mesh);
        (Some(list), Some(te))
    } else {
        (None, None)
    };
    let data = fields::data_set(
        &source,
        &mesh,
        edges.as_deref(),
        &midpoints,
        point_arrays,
        cell_arrays,
        &parent,
    );
    let geometry = Geometry {
        mesh,
        coord_type: if float_coordinates {
            ScalarType::Float
        } else {
            ScalarType::Double
        },
        edges,
        triangles: None,
        tet_edges,
    };
    let vol = Volume::new(source, geometry, data)?;
    let shape = Shape {
        parent,
        midpoints,
        added,
    };
    Ok((vol, Some(shape), warnings))
}

/// The volume of `desc` on the geometry of `like`, whose mesh was built from the same points
/// and cells with `shape`: only the fields are built, the mesh (with its adjacency and sort
/// structures), edges and triangles are shared. The caller has checked that the points and
/// cells are the same.
pub fn fields_on(
    desc: MeshDescription,
    like: &Volume,
    shape: &Shape,
) -> Result<(Volume, Vec<Warning>), ParseError> {
    let MeshDescription {
        source,
        mut point_arrays,
        cell_arrays,
        cells,
        warnings,
        ..
    } = desc;
    for a in point_arrays.iter() {
        fields::check_array(
            &source,
            a,
            like.mesh.node_count() - shape.added.len(),
            "points",
        )?;
    }
    shape.added.extend_arrays(&mut point_arrays);
    for a in cell_arrays.iter() {
        fields::check_array(&source, a, cells.len(), "cells")?;
    }
    drop(cells);
    let data = fields::data_set(
        &source,
        &like.mesh,
        like.edges.as_deref(),
        &shape.midpoints,
        point_arrays,
        cell_arrays
            .into_iter()
            .map(fields::CellArray::Read)
            .collect(),
        &shape.parent,
    );
    let vol = Volume::sharing_geometry(like, source, data)?;
    Ok((vol, warnings))
}

/// Every coordinate finite, at most [`crate::data::MAX_MAGNITUDE`] and, unless zero, at least
/// [`MIN_MAGNITUDE`].
fn check_nodes(source: &str, nodes: &[[f64; 3]], points_line: usize) -> Result<(), ParseError> {
    let err = |line: usize, msg: String| ParseError::new(source, line.max(1), msg);
    if let Some(i) = nodes.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(err(
            points_line,
            format!(
                "point {} has a non-finite coordinate ({}, {}, {})",
                i + 1,
                nodes[i][0],
                nodes[i][1],
                nodes[i][2]
            ),
        ));
    }
    if let Some((i, c)) = nodes.iter().enumerate().find_map(|(i, p)| {
        p.iter()
            .find(|c| c.abs() > crate::data::MAX_MAGNITUDE)
            .map(|c| (i, *c))
    }) {
        return Err(err(
            points_line,
            format!(
                "point {}: coordinate {c} is too large: up to ±{:e} are accepted",
                i + 1,
                crate::data::MAX_MAGNITUDE
            ),
        ));
    }
    // Orientation tests multiply three coordinate differences; below ~1e-50 those products
    // underflow and a cell's orientation depends on its node order (found by fuzzing: a mesh
    // that loads, written back, no longer loads). No real mesh needs such coordinates.
    if let Some((i, c)) = nodes.iter().enumerate().find_map(|(i, p)| {
        p.iter()
            .find(|c| **c != 0.0 && c.abs() < MIN_MAGNITUDE)
            .map(|c| (i, *c))
    }) {
        return Err(err(
            points_line,
            format!(
                "point {}: coordinate {c:e} is too small: non-zero coordinates need a magnitude of at least {MIN_MAGNITUDE:e} (scale the mesh)",
                i + 1
            ),
        ));
    }
    Ok(())
}

/// The mesh of the tetrahedra; a bad tetrahedron is reported as the file's cell it was cut
/// from (`lines` = the points' and the cells' line).
fn tet_mesh(
    source: &str,
    nodes: Vec<[f64; 3]>,
    tets: Vec<[u32; 4]>,
    parent: &[u32],
    cell_types: &[u8],
    [points_line, cells_line]: [usize; 2],
) -> Result<TetMesh, ParseError> {
    let err = |line: usize, msg: String| ParseError::new(source, line.max(1), msg);
    TetMesh::new(nodes, tets).map_err(|e| match e.tet() {
        Some(t) => {
            let c = parent[t] as usize;
            err(
                cells_line,
                format!(
                    "cell {} ({}): {}",
                    c + 1,
                    super::cell_type::name(cell_types[c]),
                    e.detail()
                ),
            )
        }
        None => err(points_line, e.to_string()),
    })
}

/// Every edge of every tetrahedron in first-use order, and each cell's six edges in it.
fn quadratic_edges(mesh: &TetMesh) -> (Vec<[u32; 2]>, Vec<[u32; 6]>) {
    let mut index: HashMap<(u32, u32), u32> = HashMap::new();
    let mut list: Vec<[u32; 2]> = Vec::new();
    for tet in mesh.tets() {
        for [i, j] in EDGE_NODES {
            let (a, b) = (tet[i], tet[j]);
            index.entry((a.min(b), a.max(b))).or_insert_with(|| {
                list.push([a.min(b), a.max(b)]);
                (list.len() - 1) as u32
            });
        }
    }
    let te = crate::mesh::edges::edges_of_cells(mesh, &list, &index);
    (list, te)
}
