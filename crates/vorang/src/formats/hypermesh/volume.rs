//! A HyperMesh file as a [`Volume`]: the reader depends on the volume, never the other way.

use super::HyperMeshFile;
use crate::error::ParseError;
use crate::volume::Volume;

impl Volume {
    /// Builds a volume from a parsed file; fails for a data-only file.
    pub fn from_file(file: HyperMeshFile) -> Result<Volume, ParseError> {
        let Some(geometry) = file.geometry else {
            return Err(ParseError::new(
                &file.name,
                1,
                "this file has no tetrahedra: expected 'Nodes' and 'Tetrahedra' blocks (use 'data' to load a data-only file onto a volume)",
            ));
        };
        Volume::new(file.name, geometry, file.data)
    }

    /// Loads a data-only file's fields onto this grid (`data file` replaces all fields,
    /// `data + file` appends). Counts must match the grid; on any error nothing changes.
    pub fn attach_data(&mut self, file: HyperMeshFile, append: bool) -> Result<(), ParseError> {
        self.attach_dataset(&file.name, file.data, append)
    }
}
