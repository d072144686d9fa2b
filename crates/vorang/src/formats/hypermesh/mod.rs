//! The HyperMesh file format for grids and data (thesis 6.1.1 and appendix B; docs/formats.md).
//!
//! A file is a line-oriented ASCII header followed by data blocks introduced by `@marker` lines:
//!
//! ```text
//! # HyperMesh 3D ASCII 0.7
//! nNodes = 4
//! nTetrahedra = 1
//! Nodes { double[3] Coordinates } = @1
//! Tetrahedra { int[4] Nodes } = @2
//! NodeData { float } = @3
//! Field "temperature" { float } = Linear(@3)
//! @1
//! 0 0 0
//! 1 0 0
//! 0 1 0
//! 0 0 1
//! @2
//! 1 2 3 4
//! @3
//! 36.5
//! 37
//! 38.2
//! 41
//! ```
//!
//! In `BINARY` files the header stays ASCII and each block is raw big-endian data. Indices are
//! 1-based. Triangles may be coded by nodes or edges, tetrahedra by nodes, edges or triangles;
//! every coding is resolved to node indices and cross-checked. See [`read`](mod@read) and [`write`](mod@write).

mod ascii;
mod batch;
mod binary;
mod codec;
pub mod header;
mod input;
pub mod read;
mod row;
mod volume;
pub mod write;

pub use codec::FORMAT;
pub use header::Encoding;

// The data types live in [`crate::data`] (every format uses them); re-exported here, where
// they were first defined, so that `hypermesh::DataType` etc. keep working.
pub use crate::data::{
    DataType, ElementKind, MAX_MAGNITUDE, Material, MaterialValue, Materials, RawData, ScalarType,
    Values,
};
pub use read::{Geometry, HyperMeshFile, read, read_bytes, read_file};
pub use write::{Layout, WriteOptions, save_subset, save_volume, write_volume};
