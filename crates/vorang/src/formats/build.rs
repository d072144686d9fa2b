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
//! 3, a pyramid 2. Quadratic tetrahedra (VTK 24, Gmsh 11) become their corner tetrahedron, and
//! every point array then becomes a `HigherOrder` (P2) field from the corner values and the
//! mid-edge values (edges without a mid-edge node, e.g. of linear cells in the same file, get
//! the mean of their ends, which keeps the field linear along them). Other cells (points, lines,
//! faces, polyhedra, other higher-order cells) are skipped with one warning that counts them by
//! type; a file without volume cells is an error.
//!
//! **Fields** (SPEC **Decision**): field number = position in the file, point arrays first,
//! then cell arrays. Point arrays become `Linear` fields (`HigherOrder` with quadratic cells),
//! cell arrays `Constant` fields; a cell's value is carried by every tetrahedron cut from it.
//! Integer arrays become `int` data, except scalar integer *cell* arrays whose values all lie
//! in 0…255: those are `byte`, so that `CONST_CELL`, `CategoryField` and `linedraw` take them
//! (material ids, Gmsh physical groups). Float32 data stay `float`, everything else `double`;
//! arrays of `n` > 1 components are `type[n]`, except that 3-component arrays are `float[3]`,
//! HyperMesh's vector type (values rounded to `float`). Names are kept.

use std::collections::HashMap;

use super::{ArrayValues, MeshDescription, cell_type};
use crate::data::{DataType, ElementKind, RawData, ScalarType, Values};
use crate::error::{ParseError, Warning};
use crate::field::{Field, Interpolator, Origin};
use crate::mesh::{EDGE_NODES, TetMesh};
use crate::volume::{DataSet, Geometry, Volume};

/// The smallest non-zero coordinate magnitude accepted (see [`volume`]).
pub const MIN_MAGNITUDE: f64 = 1e-50;

/// The tetrahedra of a hexahedron, wedge or pyramid (VTK node order) under the smallest-node
/// rule, as local node indices. `global` are the cell's global node numbers.
pub fn split_cell(ty: u8, global: &[u32]) -> Vec<[usize; 4]> {
    // Faces in VTK order, each listed so that consecutive entries are neighbours on the face.
    const HEX_FACES: [&[usize]; 6] = [
        &[0, 3, 2, 1],
        &[4, 5, 6, 7],
        &[0, 1, 5, 4],
        &[1, 2, 6, 5],
        &[2, 3, 7, 6],
        &[3, 0, 4, 7],
    ];
    const WEDGE_FACES: [&[usize]; 5] = [
        &[0, 1, 2],
        &[3, 5, 4],
        &[0, 3, 4, 1],
        &[1, 4, 5, 2],
        &[2, 5, 3, 0],
    ];
    const PYRAMID_FACES: [&[usize]; 5] = [
        &[0, 3, 2, 1],
        &[0, 1, 4],
        &[1, 2, 4],
        &[2, 3, 4],
        &[3, 0, 4],
    ];
    let faces: &[&[usize]] = match ty {
        cell_type::HEXAHEDRON => &HEX_FACES,
        cell_type::WEDGE => &WEDGE_FACES,
        cell_type::PYRAMID => &PYRAMID_FACES,
        _ => return vec![[0, 1, 2, 3]],
    };
    let v = (0..global.len())
        .min_by_key(|&i| global[i])
        .unwrap_or_default();
    let mut tets = Vec::with_capacity(6);
    for f in faces {
        if f.contains(&v) {
            continue;
        }
        match f.len() {
            3 => tets.push([v, f[0], f[1], f[2]]),
            _ => {
                // The quad's smallest node and its opposite corner form the diagonal.
                let k = (0..4).min_by_key(|&k| global[f[k]]).unwrap_or_default();
                let (a, b, c, d) = (f[k], f[(k + 1) % 4], f[(k + 2) % 4], f[(k + 3) % 4]);
                tets.push([v, a, b, c]);
                tets.push([v, a, c, d]);
            }
        }
    }
    tets
}

/// Builds the volume; warnings (skipped cells, re-oriented tetrahedra) are returned.
pub fn volume(mut desc: MeshDescription) -> Result<(Volume, Vec<Warning>), ParseError> {
    // A .vtu that VoRANG wrote: its layout gives back the volume exactly.
    if let Some(done) = super::layout::volume(&mut desc) {
        return done;
    }
    let MeshDescription {
        source,
        nodes,
        float_coordinates,
        cells,
        point_arrays,
        cell_arrays,
        points_line,
        cells_line,
        mut warnings,
        ..
    } = desc;
    let err = |line: usize, msg: String| ParseError::new(&source, line.max(1), msg);
    let n_nodes = nodes.len();
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
    for a in point_arrays.iter() {
        check_array(&source, a, n_nodes, "points")?;
    }
    for a in cell_arrays.iter() {
        check_array(&source, a, cells.len(), "cells")?;
    }

    // Cells → tetrahedra, each remembering the cell it came from.
    let mut tets: Vec<[u32; 4]> = Vec::new();
    let mut parent: Vec<u32> = Vec::new();
    let mut skipped: HashMap<u8, usize> = HashMap::new();
    // Mid-edge node of each (sorted) corner pair, from quadratic cells.
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut quadratic = false;
    for i in 0..cells.len() {
        let ty = cells.types[i];
        let conn = cells.nodes(i);
        let Some(need) = cell_type::volume_nodes(ty) else {
            *skipped.entry(ty).or_default() += 1;
            continue;
        };
        if conn.len() != need {
            return Err(err(
                cells_line,
                format!(
                    "cell {} is a {} and needs {need} nodes, but the connectivity gives it {}",
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
        let g = |k: usize| conn[k];
        match ty {
            cell_type::TETRA => {
                tets.push([g(0), g(1), g(2), g(3)]);
                parent.push(i as u32);
            }
            cell_type::QUADRATIC_TETRA => {
                quadratic = true;
                tets.push([g(0), g(1), g(2), g(3)]);
                parent.push(i as u32);
                // VTK order of the mid-edge nodes 4…9.
                const EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
                for (k, [a, b]) in EDGES.iter().enumerate() {
                    let (a, b) = (g(*a), g(*b));
                    midpoints.insert((a.min(b), a.max(b)), g(4 + k));
                }
            }
            _ => {
                for t in split_cell(ty, conn) {
                    let tet = t.map(g);
                    // Collapsed cells (repeated nodes) give empty pieces; drop those.
                    let distinct = (0..4).all(|a| (0..a).all(|b| tet[a] != tet[b]));
                    if distinct {
                        tets.push(tet);
                        parent.push(i as u32);
                    }
                }
            }
        }
    }
    // The cell list is no longer needed (only the types, for messages): free it before the
    // mesh builds its adjacency, which keeps the peak memory of a load low.
    let cell_types = cells.types;
    drop((cells.offsets, cells.connectivity));
    if !skipped.is_empty() {
        let mut kinds: Vec<(u8, usize)> = skipped.into_iter().collect();
        kinds.sort_unstable();
        let total: usize = kinds.iter().map(|k| k.1).sum();
        let list: Vec<String> = kinds
            .iter()
            .map(|(t, n)| format!("{n} × {}", cell_type::name(*t)))
            .collect();
        warnings.push(Warning {
            file: source.clone(),
            line: Some(cells_line.max(1)),
            message: format!(
                "skipped {total} cell{} that VoRANG does not render ({}); only tetrahedra, hexahedra, wedges, pyramids and quadratic tetrahedra are volume cells",
                if total == 1 { "" } else { "s" },
                list.join(", ")
            ),
        });
    }
    if tets.is_empty() {
        return Err(err(
            cells_line,
            "this file has no volume cells (tetrahedra, hexahedra, wedges, pyramids or quadratic tetrahedra): nothing to render".into(),
        ));
    }
    let mesh = TetMesh::new(nodes, tets).map_err(|e| match e.tet() {
        Some(t) => {
            let c = parent[t] as usize;
            err(
                cells_line,
                format!(
                    "cell {} ({}): {}",
                    c + 1,
                    cell_type::name(cell_types[c]),
                    e.detail()
                ),
            )
        }
        None => err(points_line, e.to_string()),
    })?;
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
        let te = crate::mesh::edges::edges_of_cells(&mesh, &list, &index);
        (Some(list), Some(te))
    } else {
        (None, None)
    };

    let origin = |line: usize| Origin {
        file: source.clone(),
        line,
    };
    let mut data = DataSet::default();
    data.counts[ElementKind::Node.index()] = Some(mesh.node_count());
    data.counts[ElementKind::Tetrahedron.index()] = Some(mesh.tet_count());
    if let Some(e) = &edges {
        data.counts[ElementKind::Edge.index()] = Some(e.len());
    }
    for a in point_arrays {
        let (ty, values) = point_values(&a.values, a.components);
        let node_raw = data.raw.len();
        if let Some(list) = &edges {
            let n = a.components;
            let mut mid: Vec<f64> = Vec::with_capacity(list.len() * n);
            for &[p, q] in list {
                match midpoints.get(&(p, q)) {
                    Some(&m) => mid.extend((0..n).map(|c| a.values.get(m as usize * n + c))),
                    None => mid.extend((0..n).map(|c| {
                        0.5 * (a.values.get(p as usize * n + c) + a.values.get(q as usize * n + c))
                    })),
                }
            }
            // Vectors stay float[3]; everything else becomes double (the mid-edge means).
            let vector = ty == DataType::array(ScalarType::Float, 3);
            let edge_ty = DataType {
                scalar: if vector {
                    ScalarType::Float
                } else {
                    ScalarType::Double
                },
                array: ty.array,
            };
            let node_values = match values {
                Values::F32(v) if !vector => Values::F64(v.into_iter().map(f64::from).collect()),
                other => other,
            };
            let mid = if vector {
                Values::F32(mid.into_iter().map(|x| x as f32).collect())
            } else {
                Values::F64(mid)
            };
            data.raw.push(RawData {
                kind: ElementKind::Node,
                ty: edge_ty,
                denominator: None,
                values: node_values,
            });
            data.raw.push(RawData {
                kind: ElementKind::Edge,
                ty: edge_ty,
                denominator: None,
                values: mid,
            });
            data.fields.push(Field {
                name: Some(a.name),
                ty: edge_ty,
                denominator: None,
                interpolator: Interpolator::HigherOrder,
                sources: vec![node_raw, node_raw + 1],
                origin: origin(a.line),
            });
        } else {
            data.raw.push(RawData {
                kind: ElementKind::Node,
                ty,
                denominator: None,
                values,
            });
            data.fields.push(Field {
                name: Some(a.name),
                ty,
                denominator: None,
                interpolator: Interpolator::Linear,
                sources: vec![node_raw],
                origin: origin(a.line),
            });
        }
    }
    for a in cell_arrays {
        let (ty, values) = cell_values(&a.values, a.components, &parent);
        data.raw.push(RawData {
            kind: ElementKind::Tetrahedron,
            ty,
            denominator: None,
            values,
        });
        data.fields.push(Field {
            name: Some(a.name),
            ty,
            denominator: None,
            interpolator: Interpolator::Constant,
            sources: vec![data.raw.len() - 1],
            origin: origin(a.line),
        });
    }
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
    Ok((vol, warnings))
}

fn check_array(source: &str, a: &super::Array, want: usize, what: &str) -> Result<(), ParseError> {
    if a.components == 0 || a.values.len() != want * a.components {
        return Err(ParseError::new(
            source,
            a.line.max(1),
            format!(
                "array \"{}\" has {} values, but {want} {what} × {} component{} need {}",
                a.name,
                a.values.len(),
                a.components,
                if a.components == 1 { "" } else { "s" },
                want.saturating_mul(a.components)
            ),
        ));
    }
    let bad = match &a.values {
        ArrayValues::Int(_) => None,
        ArrayValues::F32(v) => v
            .iter()
            .position(|x| !x.is_finite() || f64::from(x.abs()) > crate::data::MAX_MAGNITUDE),
        ArrayValues::F64(v) => v
            .iter()
            .position(|x| !x.is_finite() || x.abs() > crate::data::MAX_MAGNITUDE),
    };
    if let Some(i) = bad {
        return Err(ParseError::new(
            source,
            a.line.max(1),
            format!(
                "array \"{}\": value {} of {} {} is {}: values must be finite and at most ±{:e}",
                a.name,
                i % a.components + 1,
                what.trim_end_matches('s'),
                i / a.components + 1,
                a.values.get(i),
                crate::data::MAX_MAGNITUDE
            ),
        ));
    }
    if let ArrayValues::Int(v) = &a.values
        && let Some(x) = v.iter().find(|x| x.unsigned_abs() > 1 << 53)
    {
        return Err(ParseError::new(
            source,
            a.line.max(1),
            format!(
                "array \"{}\": the integer {x} is too large to be a field value (at most ±2^53)",
                a.name
            ),
        ));
    }
    Ok(())
}

fn data_type(scalar: ScalarType, components: usize) -> DataType {
    if components == 1 {
        DataType::scalar(scalar)
    } else {
        DataType::array(scalar, components as u32)
    }
}

/// 3-component arrays (velocities, displacements, colours) are `float[3]`, the vector type of
/// HyperMesh (SPEC §7, §8: EdgeElem gives float[3], IDENTITY takes float[3]): values are
/// rounded to the nearest `float`. An array with a value beyond `float`'s range (±3.4e38)
/// keeps its type rather than turning into infinities.
fn as_float3(ty: DataType, values: Values) -> (DataType, Values) {
    if ty.components() != 3 || ty.scalar == ScalarType::Float {
        return (ty, values);
    }
    let n = values.len();
    if (0..n).any(|i| values.get(i).abs() > f64::from(f32::MAX)) {
        return (ty, values);
    }
    (
        DataType::array(ScalarType::Float, 3),
        Values::F32((0..n).map(|i| values.get(i) as f32).collect()),
    )
}

/// Point data: float stays float, integers that fit in `int` become int, the rest double;
/// 3-component arrays are `float[3]` ([`as_float3`]).
fn point_values(v: &ArrayValues, components: usize) -> (DataType, Values) {
    let (ty, values) = point_values_as_stored(v, components);
    as_float3(ty, values)
}

fn point_values_as_stored(v: &ArrayValues, components: usize) -> (DataType, Values) {
    match v {
        ArrayValues::F32(x) => (
            data_type(ScalarType::Float, components),
            Values::F32(x.clone()),
        ),
        ArrayValues::F64(x) => (
            data_type(ScalarType::Double, components),
            Values::F64(x.clone()),
        ),
        ArrayValues::Int(x) => int_values(x, components, false),
    }
}

fn int_values(x: &[i64], components: usize, allow_byte: bool) -> (DataType, Values) {
    if allow_byte && components == 1 && x.iter().all(|v| (0..=255).contains(v)) {
        return (
            DataType::scalar(ScalarType::Byte),
            Values::U8(x.iter().map(|&v| v as u8).collect()),
        );
    }
    if x.iter().all(|v| i32::try_from(*v).is_ok()) {
        return (
            data_type(ScalarType::Int, components),
            Values::I32(x.iter().map(|&v| v as i32).collect()),
        );
    }
    (
        data_type(ScalarType::Double, components),
        Values::F64(x.iter().map(|&v| v as f64).collect()),
    )
}

/// Cell data, one row per tetrahedron (its parent cell's row); 3-component arrays are
/// `float[3]` ([`as_float3`]).
fn cell_values(v: &ArrayValues, n: usize, parent: &[u32]) -> (DataType, Values) {
    let (ty, values) = cell_values_as_stored(v, n, parent);
    as_float3(ty, values)
}

fn cell_values_as_stored(v: &ArrayValues, n: usize, parent: &[u32]) -> (DataType, Values) {
    let pick = |i: usize| (0..n).map(move |c| (parent[i] as usize) * n + c);
    match v {
        ArrayValues::F32(x) => (
            data_type(ScalarType::Float, n),
            Values::F32((0..parent.len()).flat_map(pick).map(|k| x[k]).collect()),
        ),
        ArrayValues::F64(x) => (
            data_type(ScalarType::Double, n),
            Values::F64((0..parent.len()).flat_map(pick).map(|k| x[k]).collect()),
        ),
        ArrayValues::Int(x) => {
            // The type is decided on the whole array, not only on the cells kept.
            let (ty, _) = int_values(x, n, true);
            let rows = (0..parent.len()).flat_map(pick).map(|k| x[k]);
            let values = match ty.scalar {
                ScalarType::Byte => Values::U8(rows.map(|v| v as u8).collect()),
                ScalarType::Int => Values::I32(rows.map(|v| v as i32).collect()),
                _ => Values::F64(rows.map(|v| v as f64).collect()),
            };
            (ty, values)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tet_volume;

    fn cube() -> Vec<[f64; 3]> {
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ]
    }

    fn volume_of(p: &[[f64; 3]], tets: &[[usize; 4]]) -> f64 {
        tets.iter()
            .map(|t| tet_volume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]).abs())
            .sum()
    }

    #[test]
    fn three_component_arrays_are_float3() {
        let (ty, v) = point_values(&ArrayValues::F64(vec![0.1, 2.0, -3.5, 1e-3, 0.0, 7.0]), 3);
        assert_eq!(ty, DataType::array(ScalarType::Float, 3));
        assert_eq!(v, Values::F32(vec![0.1, 2.0, -3.5, 1e-3, 0.0, 7.0]));
        let (ty, _) = cell_values(&ArrayValues::Int(vec![1, 2, 3]), 3, &[0, 0]);
        assert_eq!(ty, DataType::array(ScalarType::Float, 3));
        // Other component counts keep their type; values beyond float's range too.
        let (ty, _) = point_values(&ArrayValues::F64(vec![0.1, 2.0]), 2);
        assert_eq!(ty, DataType::array(ScalarType::Double, 2));
        let (ty, _) = point_values(&ArrayValues::F64(vec![1e100, 0.0, 0.0]), 3);
        assert_eq!(ty, DataType::array(ScalarType::Double, 3));
    }

    #[test]
    fn every_numbering_of_a_hexahedron_fills_it() {
        let p = cube();
        // Each rotation of the global numbering puts the smallest node at another corner.
        for shift in 0..8u32 {
            let global: Vec<u32> = (0..8).map(|i| (i + shift) % 8).collect();
            let tets = split_cell(cell_type::HEXAHEDRON, &global);
            assert_eq!(tets.len(), 6);
            assert!((volume_of(&p, &tets) - 1.0).abs() < 1e-12, "shift {shift}");
            for t in &tets {
                assert!(tet_volume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]).abs() > 1e-9);
            }
        }
    }

    #[test]
    fn wedges_and_pyramids_fill_themselves() {
        let w = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 1.0],
        ];
        for shift in 0..6u32 {
            let global: Vec<u32> = (0..6).map(|i| (i * 5 + shift) % 6).collect();
            let tets = split_cell(cell_type::WEDGE, &global);
            assert_eq!(tets.len(), 3);
            assert!((volume_of(&w, &tets) - 0.5).abs() < 1e-12);
        }
        let py = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1.0],
        ];
        for shift in 0..5u32 {
            let global: Vec<u32> = (0..5).map(|i| (i + shift) % 5).collect();
            let tets = split_cell(cell_type::PYRAMID, &global);
            assert_eq!(tets.len(), 2);
            assert!((volume_of(&py, &tets) - 1.0 / 3.0).abs() < 1e-12);
        }
    }

    #[test]
    fn a_shared_quad_face_is_cut_the_same_way_from_both_sides() {
        // Two hexahedra stacked along z share the face 4 5 6 7 (global numbers).
        let lower: Vec<u32> = (0..8).collect();
        let upper: Vec<u32> = (4..12).collect();
        let face_tris = |ty: u8, g: &[u32]| -> Vec<[u32; 3]> {
            let mut out = Vec::new();
            for t in split_cell(ty, g) {
                let nodes = t.map(|k| g[k]);
                for skip in 0..4 {
                    let mut tri: Vec<u32> =
                        (0..4).filter(|&k| k != skip).map(|k| nodes[k]).collect();
                    if tri.iter().all(|n| (4..8).contains(n)) {
                        tri.sort_unstable();
                        out.push([tri[0], tri[1], tri[2]]);
                    }
                }
            }
            out.sort_unstable();
            out
        };
        let a = face_tris(cell_type::HEXAHEDRON, &lower);
        let b = face_tris(cell_type::HEXAHEDRON, &upper);
        assert_eq!(a.len(), 2);
        assert_eq!(a, b);
    }
}
