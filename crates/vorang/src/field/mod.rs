//! Field distributions (thesis 6.1.2, B.2 "Deklaration der Datenfelder"): an interpolator that
//! turns raw data on nodes, edges, cells or extra rows into a function defined everywhere in the
//! mesh. Only fields are visualised; they are numbered 0… in order of appearance.
//!
//! Each interpolator lives in its own file and is listed once in [`INTERPOLATORS`]; the parser,
//! its error messages, `vorang info` and the tests all read that table.

mod constant;
mod edge_elem;
mod edge_elem_sar;
mod gauss_test;
mod higher_order;
mod linear;

use crate::data::{DataType, ElementKind, Materials, RawData, ScalarType};
use crate::mesh::TetMesh;
use crate::mesh::edges::NONE;

/// What fields are evaluated on: the mesh, the edges of each cell (edge elements and quadratic
/// fields need them), the raw data blocks that fields refer to by index, and the materials
/// (EdgeElemSAR). A field depends on these alone, not on where they were loaded from.
#[derive(Debug, Clone, Copy)]
pub struct Support<'a> {
    pub mesh: &'a TetMesh,
    /// For each cell, its six edges in [`crate::mesh::EDGE_NODES`] order as indices into the
    /// edge list, with bit 31 set where the list directs the edge against the local order;
    /// [`NONE`] where the list lacks it. `None` without an edge list.
    pub cell_edges: Option<&'a [[u32; 6]]>,
    pub raw: &'a [RawData],
    pub materials: Option<&'a Materials>,
}

impl Support<'_> {
    /// A cell's six edges: index into the edge list and whether the list directs the edge
    /// against the local order. `None` without edges, or if the list lacks one of them.
    pub fn tet_edges(&self, cell: usize) -> Option<[(usize, bool); 6]> {
        let e = self.cell_edges?.get(cell)?;
        if e.contains(&NONE) {
            return None;
        }
        Some(e.map(|x| ((x & !(1 << 31)) as usize, x & (1 << 31) != 0)))
    }
}

/// Which interpolator a field uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Interpolator {
    Linear,
    Constant,
    GaussTest,
    EdgeElem,
    EdgeElemSar,
    HigherOrder,
}

/// The raw data a field's sources must be, as the checks see them.
pub struct Sources<'a> {
    /// The declared field type (`{ float[3] }`).
    pub ty: DataType,
    /// The referenced raw data blocks, in marker order.
    pub raw: Vec<&'a RawData>,
    pub materials: Option<&'a Materials>,
}

/// One registry entry.
pub struct InterpolatorInfo {
    pub interpolator: Interpolator,
    pub name: &'static str,
    pub summary: &'static str,
    /// How it is written, for messages and help (`Linear(@nodedata)`).
    pub signature: &'static str,
    /// Element kinds of the required sources, then of the optional ones.
    pub required: &'static [ElementKind],
    pub optional: &'static [ElementKind],
    /// Checks data types and the declared field type; `Err` says what was expected.
    pub check: fn(&Sources) -> Result<(), String>,
}

/// Every interpolator, in the order of the thesis.
pub const INTERPOLATORS: &[InterpolatorInfo] = &[
    linear::INFO,
    constant::INFO,
    gauss_test::INFO,
    edge_elem::INFO,
    edge_elem_sar::INFO,
    higher_order::INFO,
];

impl Interpolator {
    pub fn info(self) -> &'static InterpolatorInfo {
        // Every variant has exactly one entry (checked by a test).
        INTERPOLATORS
            .iter()
            .find(|i| i.interpolator == self)
            .unwrap_or(&INTERPOLATORS[0])
    }

    pub fn name(self) -> &'static str {
        self.info().name
    }

    pub fn from_name(name: &str) -> Option<Interpolator> {
        INTERPOLATORS
            .iter()
            .find(|i| i.name == name)
            .map(|i| i.interpolator)
    }

    /// "Linear, Constant, …" for "expected one of" messages.
    pub fn names() -> String {
        INTERPOLATORS
            .iter()
            .map(|i| i.name)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Where a field was declared, for messages that come later (e.g. at render time).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Origin {
    pub file: String,
    pub line: usize,
}

/// A declared field: `Field "name" { type denominator } = Interpolator(@m, …)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    pub name: Option<String>,
    pub ty: DataType,
    pub denominator: Option<String>,
    pub interpolator: Interpolator,
    /// Indices into the owning data set's raw data, in marker order.
    pub sources: Vec<usize>,
    pub origin: Origin,
}

impl Field {
    /// Declares a field over raw data blocks, checking what the interpolator needs: the number
    /// of sources, their element kinds and types, and the declared field type. `name_source(k)`
    /// names source `k` in messages (a marker in a file, a block number in code).
    #[allow(clippy::too_many_arguments)]
    pub fn build(
        name: Option<String>,
        ty: DataType,
        denominator: Option<String>,
        interpolator: Interpolator,
        sources: Vec<usize>,
        raw: &[RawData],
        materials: Option<&Materials>,
        origin: Origin,
        name_source: &dyn Fn(usize) -> String,
    ) -> Result<Field, String> {
        let info = interpolator.info();
        let (lo, hi) = (
            info.required.len(),
            info.required.len() + info.optional.len(),
        );
        if !(lo..=hi).contains(&sources.len()) {
            return Err(format!(
                "{} takes {} source{}: {}, found {}",
                info.name,
                if lo == hi {
                    lo.to_string()
                } else {
                    format!("{lo} or {hi}")
                },
                if hi == 1 { "" } else { "s" },
                info.signature,
                sources.len()
            ));
        }
        for (k, (&s, want)) in sources
            .iter()
            .zip(info.required.iter().chain(info.optional))
            .enumerate()
        {
            let Some(r) = raw.get(s) else {
                return Err(format!(
                    "{}: there is no raw data block {s}",
                    name_source(k)
                ));
            };
            if r.kind != *want {
                return Err(format!(
                    "{} needs {} for its source {} ({}), but {} is {}",
                    info.name,
                    want.data_keyword(),
                    k + 1,
                    info.signature,
                    name_source(k),
                    r.kind.data_keyword()
                ));
            }
        }
        let s = Sources {
            ty,
            raw: sources.iter().map(|&k| &raw[k]).collect(),
            materials,
        };
        (info.check)(&s)?;
        Ok(Field {
            name,
            ty,
            denominator,
            interpolator,
            sources,
            origin,
        })
    }

    /// How many numbers [`Field::eval`] writes: the declared components (two per complex
    /// component for Linear/Constant/HigherOrder: re, im), 3 for EdgeElem, 1 for the scalar
    /// interpolators.
    pub fn components(&self) -> usize {
        match self.interpolator {
            Interpolator::GaussTest | Interpolator::EdgeElemSar => 1,
            Interpolator::EdgeElem => 3,
            Interpolator::Linear | Interpolator::Constant | Interpolator::HigherOrder => {
                self.ty.numbers()
            }
        }
    }

    /// True for a scalar field (one number per point).
    pub fn is_scalar(&self) -> bool {
        self.components() == 1
    }

    /// A `byte` field that is constant per cell (the kind CONST_CELL maps and `linedraw`
    /// selects by): Constant interpolation of scalar byte data, or a Constant field declared
    /// `byte`.
    /// `raw` are the raw data blocks its sources index.
    pub fn is_byte_constant(&self, raw: &[RawData]) -> bool {
        self.interpolator == Interpolator::Constant
            && self.is_scalar()
            && (self.ty.scalar == ScalarType::Byte
                || self
                    .sources
                    .first()
                    .is_some_and(|&s| raw.get(s).is_some_and(RawData::is_byte_scalar)))
    }

    /// Evaluates the field in `cell` at barycentric coordinates `lambda` (with respect to the
    /// cell's nodes in [`crate::mesh::TetMesh::tets`] order), i.e. at `point` in the file's own
    /// coordinates. Writes [`Field::components`] numbers into `out`.
    pub fn eval(
        &self,
        on: &Support,
        cell: usize,
        lambda: &[f64; 4],
        point: [f64; 3],
        out: &mut [f64],
    ) {
        let raw = |k: usize| &on.raw[self.sources[k]];
        match self.interpolator {
            Interpolator::Linear => linear::eval(on, raw(0), cell, lambda, out),
            Interpolator::Constant => constant::eval(raw(0), cell, out),
            Interpolator::GaussTest => out[0] = gauss_test::eval(raw(0), point),
            Interpolator::EdgeElem => {
                let e = edge_elem::eval(on, raw(0), cell, lambda);
                out[..3].copy_from_slice(&e.re);
            }
            Interpolator::EdgeElemSar => {
                out[0] = edge_elem_sar::eval(on, raw(0), raw(1), cell, lambda)
            }
            Interpolator::HigherOrder => {
                let bubble = (self.sources.len() > 2).then(|| raw(2));
                higher_order::eval(on, raw(0), raw(1), bubble, cell, lambda, out)
            }
        }
    }

    /// The constant gradient of component `c` of a Linear field in `cell` (file coordinates);
    /// `None` for other interpolators, whose gradient varies inside a cell.
    pub fn gradient(&self, on: &Support, cell: usize, c: usize) -> Option<[f64; 3]> {
        match self.interpolator {
            Interpolator::Linear => linear::gradient(on, &on.raw[self.sources[0]], cell, c),
            _ => None,
        }
    }

    /// The gradient of a scalar field at a point of `cell` (file coordinates), for lighting
    /// (`LIT_EMITTER`). Linear fields have their exact constant gradient, Constant fields
    /// zero; the others (whose gradient varies inside a cell) central differences with a step
    /// of 10⁻⁴ of the cell's size along each axis — exact up to rounding for the quadratic
    /// HigherOrder and EdgeElemSAR fields, second-order accurate for GaussTest. Zero for a
    /// degenerate cell.
    pub fn gradient_at(
        &self,
        on: &Support,
        cell: usize,
        lambda: &[f64; 4],
        point: [f64; 3],
    ) -> [f64; 3] {
        match self.interpolator {
            Interpolator::Constant => return [0.0; 3],
            Interpolator::Linear => return self.gradient(on, cell, 0).unwrap_or([0.0; 3]),
            _ => {}
        }
        let corners = on.mesh.corners(cell);
        let Some(grads) = crate::mesh::barycentric_gradients(&corners) else {
            return [0.0; 3];
        };
        let size = (1..4)
            .flat_map(|i| (0..3).map(move |k| (i, k)))
            .map(|(i, k)| (corners[i][k] - corners[0][k]).abs())
            .fold(0.0, f64::max);
        let h = 1e-4 * size;
        let mut out = [0.0; 1];
        let mut at = |sign: f64, k: usize| {
            let l: [f64; 4] = std::array::from_fn(|i| lambda[i] + sign * h * grads[i][k]);
            let mut p = point;
            p[k] += sign * h;
            self.eval(on, cell, &l, p, &mut out);
            out[0]
        };
        std::array::from_fn(|k| (at(1.0, k) - at(-1.0, k)) / (2.0 * h))
    }
}

/// Checks that a source is scalar real or complex data (edge values of edge elements).
fn scalar_edge_values(raw: &RawData, who: &str) -> Result<(), String> {
    let real_or_complex = raw.ty.scalar == ScalarType::Complex || !raw.ty.scalar.is_integer();
    if raw.ty.components() != 1 || !real_or_complex {
        return Err(format!(
            "{who} needs scalar float, double or complex EdgeData, found {}",
            raw.ty
        ));
    }
    Ok(())
}

/// Checks that a field declared `decl` can hold values with the components of `data`.
fn same_shape(decl: DataType, data: DataType, who: &str) -> Result<(), String> {
    let complex = |t: DataType| t.scalar == ScalarType::Complex;
    if decl.components() != data.components() || complex(decl) != complex(data) {
        return Err(format!(
            "{who}: the field is declared {decl} but its data are {data}; they need the same number of components"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registry_has_each_interpolator_once() {
        for i in [
            Interpolator::Linear,
            Interpolator::Constant,
            Interpolator::GaussTest,
            Interpolator::EdgeElem,
            Interpolator::EdgeElemSar,
            Interpolator::HigherOrder,
        ] {
            assert_eq!(
                INTERPOLATORS.iter().filter(|e| e.interpolator == i).count(),
                1
            );
            assert_eq!(Interpolator::from_name(i.name()), Some(i));
        }
        assert_eq!(Interpolator::from_name("Cubic"), None);
    }
}
