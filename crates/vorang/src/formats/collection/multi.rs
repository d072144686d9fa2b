//! Files that hold a whole time series themselves — Exodus II, XDMF, VTKHDF — as
//! [`Series`](super::Series): each of their steps is a step whose one part is the file and
//! the step's number inside it ([`super::Part::within`]). So `volume`, `timestep`, mesh
//! reuse between steps and `vorang info` work on them exactly as on a `.pvd`
//! (docs/formats.md, "Time series and collections"). Their readers only list a file's steps
//! and read one; this module turns that into series steps and registry entries.

use std::path::Path;

use super::merge::{Merge, PieceLabel};
use super::{Part, Step};
use crate::error::ParseError;
use crate::formats::{FileStep, Format, MeshDescription, build, exodus, vtkhdf, xdmf};

/// The formats whose files hold time steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Multi {
    Exodus,
    Xdmf,
    VtkHdf,
}

impl Multi {
    /// The kind of a registry entry, `None` for the others.
    pub fn of_format(format: &Format) -> Option<Multi> {
        [
            (EXODUS.name, Multi::Exodus),
            (XDMF.name, Multi::Xdmf),
            (VTKHDF.name, Multi::VtkHdf),
        ]
        .into_iter()
        .find(|(name, _)| *name == format.name)
        .map(|(_, m)| m)
    }

    pub fn noun(self) -> &'static str {
        match self {
            Multi::Exodus => "Exodus II file",
            Multi::Xdmf => "XDMF file",
            Multi::VtkHdf => "VTKHDF file",
        }
    }

    /// The steps of the file at `path`, in the order of their time (stable).
    pub fn steps(self, path: &Path) -> Result<Vec<Step>, ParseError> {
        let name = path.display().to_string();
        let mut list: Vec<FileStep> = match self {
            Multi::Exodus => exodus::steps(path, &name)?,
            Multi::Xdmf => xdmf::steps(path, &name)?,
            Multi::VtkHdf => vtkhdf::steps(path, &name)?,
        };
        list.sort_by(|a, b| a.time.total_cmp(&b.time));
        Ok(list
            .into_iter()
            .map(|s| Step {
                time: s.time,
                parts: vec![Part {
                    path: s.file,
                    line: 1,
                    within: Some(s.index),
                }],
            })
            .collect())
    }

    /// Step `index` of the file at `path` (as numbered inside that file).
    pub fn read_step(self, path: &Path, index: usize) -> Result<MeshDescription, ParseError> {
        let name = path.display().to_string();
        match self {
            Multi::Exodus => exodus::read_step(path, &name, index),
            Multi::Xdmf => xdmf::read_step(path, &name, index),
            Multi::VtkHdf => merged(vtkhdf::read_step(path, &name, index)?, &name),
        }
    }
}

/// The partitions of a VTKHDF step as one description ([`Merge`]: shared points joined,
/// ghost cells dropped).
fn merged(parts: Vec<MeshDescription>, name: &str) -> Result<MeshDescription, ParseError> {
    let mut merge = Merge::new();
    for (k, part) in parts.into_iter().enumerate() {
        let label = PieceLabel {
            file: format!("{name} (partition {k})"),
            from: name.to_string(),
            line: 0,
        };
        merge.add(part, label)?;
    }
    merge
        .finish()
        .ok_or_else(|| ParseError::new(name, 0, "the step has no partition"))
}

/// Step 0 of a VTKHDF file held in memory.
fn vtkhdf_read(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    merged(vtkhdf::read_parts(bytes, name)?, name)
}

/// The registry entry of a format whose files hold time steps: `read` gives step 0 of a file
/// held in memory; loading, `data` and `vorang info` go through the series.
macro_rules! multi_format {
    ($name:expr, $extensions:expr, $sniff:expr, $read:expr) => {
        Format {
            name: $name,
            extensions: $extensions,
            sniff: $sniff,
            read: Some($read),
            load: super::load_first,
            load_bytes: |bytes, name| build::volume($read(bytes, name)?),
            load_data: super::load_data,
            describe: super::describe,
            write: None,
        }
    };
}

pub const EXODUS: Format = multi_format!(
    "Exodus II",
    &["e", "exo", "ex2", "exii", "gen"],
    exodus::sniff,
    exodus::read
);
pub const XDMF: Format = multi_format!("XDMF", &["xdmf", "xmf"], xdmf::sniff, xdmf::read);
pub const VTKHDF: Format = multi_format!(
    "VTKHDF UnstructuredGrid",
    &["vtkhdf", "hdf"],
    vtkhdf::sniff,
    vtkhdf_read
);
