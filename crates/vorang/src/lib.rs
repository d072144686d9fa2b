//! # VoRANG — volume rendering on unstructured tetrahedral grids
//!
//! A direct volume renderer for scalar and vector fields on tetrahedral meshes (FEM/CFD
//! results), after the 1996 thesis *Volume Rendering auf irregulären Gittern*. This crate holds
//! the library; the `vorang` binary drives it.
//!
//! Loading a HyperMesh file and evaluating a field:
//!
//! ```
//! use vorang::hypermesh;
//! use vorang::volume::Volume;
//!
//! let text = "# HyperMesh 3D ASCII 0.7
//! nNodes = 4
//! nTetrahedra = 1
//! Nodes { double[3] Coordinates } = @1
//! Tetrahedra { int[4] Nodes } = @2
//! NodeData { float } = @3
//! Field \"t\" { float } = Linear(@3)
//! @1
//! 0 0 0
//! 1 0 0
//! 0 1 0
//! 0 0 1
//! @2
//! 1 2 3 4
//! @3
//! 0
//! 1
//! 2
//! 3
//! ";
//! let file = hypermesh::read_bytes(text.as_bytes(), "tet.hmesh").unwrap();
//! let vol = Volume::from_file(file).unwrap();
//! let field = vol.field(0).unwrap();
//! let mut value = [0.0];
//! // At the centroid every node weighs 1/4: (0 + 1 + 2 + 3) / 4.
//! field.eval(&vol.support(), 0, &[0.25; 4], [0.25; 3], &mut value);
//! assert_eq!(value[0], 1.5);
//! ```

// Numerical code indexes several arrays by the same component or corner index (`p[k]`,
// `grads[i][k]`), which reads like the formulas it implements; iterator chains would not.
#![allow(clippy::needless_range_loop)]

pub mod accuracy;
pub mod atomic;
pub mod cache;
pub mod data;
pub mod distributed;
pub mod error;
pub mod field;
pub mod formats;
pub mod framebuffer;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod info;
pub mod integrate;
pub mod legend;
pub mod mapping;
pub mod mesh;
pub mod movie;
pub mod numbers;
pub mod predicates;
pub mod reference;
pub mod render;
pub mod scene;
pub mod session;
pub mod sort;
pub mod volume;

pub use error::{Error, ParseError, Result, Warning};
/// HyperMesh, the thesis's format, is one codec of [`formats`]; `vorang::hypermesh` names it.
pub use formats::hypermesh;
pub use mesh::TetMesh;
pub use session::{Notice, Session};
pub use volume::Volume;
