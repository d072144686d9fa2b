//! HyperMesh's entry in the format registry ([`crate::formats::FORMATS`]): the streaming reader
//! ([`super::read`]) and writer ([`super::write`]) behind the same operations as every other
//! format. What only HyperMesh has — data-only files for `data`, several encodings — is handled
//! here, so callers never ask which format they got.

use std::path::Path;

use super::{HyperMeshFile, read_bytes, read_file, save_volume};
use crate::error::{Error, ParseError};
use crate::formats::{Described, DescribedFile, Format, Loaded};
use crate::volume::Volume;

/// The registry entry.
pub const FORMAT: Format = Format {
    name: "HyperMesh",
    extensions: &["hmesh", "hmascii", "hmbin", "bin", "asc", "hm"],
    sniff: |b| {
        crate::formats::starts_after_space(b, b"# HyperMesh")
            || crate::formats::starts_after_space(b, b"#HyperMesh")
    },
    read: None,
    load: |path| volume_of(read_file(path)?).map_err(Error::from),
    load_bytes: |bytes, name| volume_of(read_bytes(bytes, name)?),
    load_data,
    describe,
    write: Some(|vol, path, opts| save_volume(vol, path, opts).map(|()| Vec::new())),
};

fn volume_of(file: HyperMeshFile) -> Result<Loaded, ParseError> {
    let warnings = file.warnings.clone();
    Ok((Volume::from_file(file)?, warnings))
}

/// `data`: only data-only files; a file with a grid is the business of `volume`.
fn load_data(vol: &Volume, path: &Path, append: bool) -> Result<Loaded, Error> {
    let file = read_file(path)?;
    if file.geometry.is_some() {
        return Err(Error::Invalid(format!(
            "data: {} holds a grid; 'data' loads data-only files (use 'volume' for a grid with its data)",
            file.name
        )));
    }
    let warnings = file.warnings.clone();
    let mut next = vol.clone();
    next.attach_data(file, append)?;
    Ok((next, warnings))
}

fn describe(path: &Path) -> Result<DescribedFile, Error> {
    let file = read_file(path)?;
    let warnings = file.warnings.clone();
    let label = format!("HyperMesh {} {}", file.encoding.keyword(), file.version);
    if file.geometry.is_some() {
        let volume = Volume::from_file(file)?;
        return Ok((Described::Volume { volume, label }, warnings));
    }
    Ok((
        Described::Data {
            name: file.name,
            label,
            data: file.data,
        },
        warnings,
    ))
}
