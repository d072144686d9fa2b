//! Raw data, independent of any file format: scalar and array types, typed storage for the
//! values of a block, the elements data live on (nodes, edges, triangles, tetrahedra, extra
//! rows), raw data blocks and material tables. Readers of every format produce them, fields
//! interpolate them, writers store them; this module depends on none of those.

mod materials;
mod types;

pub use materials::{Material, MaterialValue, Materials};
pub use types::{DataType, ElementKind, RawData, ScalarType, Values};

/// The largest magnitude a value or coordinate may have. Rendering adds and multiplies values
/// (interpolation, differences along a ray, squares in the quadratic rule); beyond ~1e154 such
/// sums overflow to infinity and give NaN pixels, so readers refuse larger values at load,
/// with their line.
pub const MAX_MAGNITUDE: f64 = 1e150;
