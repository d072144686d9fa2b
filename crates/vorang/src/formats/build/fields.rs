//! Arrays to fields: point arrays become `Linear` fields (`HigherOrder` ones, with mid-edge
//! values, when the file has quadratic cells), cell arrays `Constant` fields carried by every
//! tetrahedron cut from their cell, and each array's values get a HyperMesh type by the table
//! in docs/formats.md ("Fields (VTK and Gmsh)"). Separate from the cells because it is a rule of its own — the
//! types a file's arrays become — and needs of the split only each tetrahedron's parent cell.

use std::collections::HashMap;

use crate::data::{DataType, ElementKind, RawData, ScalarType, Values};
use crate::error::ParseError;
use crate::field::{Field, Interpolator, Origin};
use crate::formats::{Array, ArrayValues};
use crate::mesh::TetMesh;
use crate::volume::DataSet;

/// A cell array as read, or its values per tetrahedron already made ([`early`]).
pub(super) enum CellArray {
    Read(Array),
    Made {
        name: String,
        line: usize,
        ty: DataType,
        values: Values,
    },
}

/// The cell arrays whose values per tetrahedron take no more room than the array as read
/// (a byte array of 64-bit integers on tetrahedra: material or block ids) made now, before the
/// mesh is built, so that the array is freed before the mesh's adjacency, the highest point of
/// a load's memory; the others as read (on hexahedra, made now, they would be larger then).
/// The fields are the same either way.
pub(super) fn early(arrays: Vec<Array>, parent: &[u32]) -> Vec<CellArray> {
    arrays
        .into_iter()
        .map(|a| {
            let (stored, made) = match &a.values {
                ArrayValues::F32(_) => (4, 4),
                ArrayValues::F64(_) => (8, 8),
                ArrayValues::Int(x) => {
                    let byte = a.components == 1 && x.iter().all(|v| (0..=255).contains(v));
                    (8, if byte { 1 } else { 8 })
                }
            };
            let room = |n: usize, bytes: usize| n.saturating_mul(bytes);
            if room(parent.len().saturating_mul(a.components), made) > room(a.values.len(), stored)
            {
                return CellArray::Read(a);
            }
            let (ty, values) = cell_values(&a.values, a.components, parent);
            CellArray::Made {
                name: a.name,
                line: a.line,
                ty,
                values,
            }
        })
        .collect()
}

/// The raw data and fields of the arrays, in file order (point arrays first). `edges` and
/// `midpoints` are given for files with quadratic cells; `parent` is each tetrahedron's cell.
pub(super) fn data_set(
    source: &str,
    mesh: &TetMesh,
    edges: Option<&[[u32; 2]]>,
    midpoints: &HashMap<(u32, u32), u32>,
    point_arrays: Vec<Array>,
    cell_arrays: Vec<CellArray>,
    parent: &[u32],
) -> DataSet {
    let origin = |line: usize| Origin {
        file: source.to_string(),
        line,
    };
    let mut data = DataSet::default();
    data.counts[ElementKind::Node.index()] = Some(mesh.node_count());
    data.counts[ElementKind::Tetrahedron.index()] = Some(mesh.tet_count());
    if let Some(e) = edges {
        data.counts[ElementKind::Edge.index()] = Some(e.len());
    }
    for a in point_arrays {
        let line = a.line;
        match edges {
            Some(list) if !linear_on_edges(&a, midpoints) => {
                higher_order_field(&mut data, a, list, midpoints, origin(line))
            }
            _ => linear_field(&mut data, a, origin(line)),
        }
    }
    for a in cell_arrays {
        let (name, line, ty, values) = match a {
            CellArray::Read(a) => {
                let (ty, values) = cell_values(&a.values, a.components, parent);
                (a.name, a.line, ty, values)
            }
            CellArray::Made {
                name,
                line,
                ty,
                values,
            } => (name, line, ty, values),
        };
        data.raw.push(RawData {
            kind: ElementKind::Tetrahedron,
            ty,
            denominator: None,
            values,
        });
        data.fields.push(Field {
            name: Some(name),
            ty,
            denominator: None,
            interpolator: Interpolator::Constant,
            sources: vec![data.raw.len() - 1],
            origin: origin(line),
        });
    }
    data
}

/// Whether every mid-edge value of the array lies exactly halfway between the values at the
/// edge's ends (in every component): then the quadratic interpolation is the linear one, and
/// the array is a `Linear` field.
pub(super) fn linear_on_edges(a: &Array, midpoints: &HashMap<(u32, u32), u32>) -> bool {
    let n = a.components;
    let v = |node: u32, c: usize| a.values.get(node as usize * n + c);
    midpoints
        .iter()
        .all(|(&(p, q), &m)| (0..n).all(|c| v(m, c) == 0.5 * (v(p, c) + v(q, c))))
}

/// A point array as a `Linear` field.
fn linear_field(data: &mut DataSet, a: Array, origin: Origin) {
    let (ty, values) = point_values(&a.values, a.components);
    let node_raw = data.raw.len();
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
        origin,
    });
}

/// A point array as a `HigherOrder` field: its node values and a value on every edge of
/// `list`, the mid-edge node's where a quadratic cell has one, else the mean of the ends.
fn higher_order_field(
    data: &mut DataSet,
    a: Array,
    list: &[[u32; 2]],
    midpoints: &HashMap<(u32, u32), u32>,
    origin: Origin,
) {
    let (ty, values) = point_values(&a.values, a.components);
    let node_raw = data.raw.len();
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
        origin,
    });
}

pub(super) fn check_array(
    source: &str,
    a: &Array,
    want: usize,
    what: &str,
) -> Result<(), ParseError> {
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
/// HyperMesh (thesis appendices B and C: what EdgeElem gives and IDENTITY takes): values are
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
}
