//! `volume FILE` on one rank of a distributed session: the rank reads its share of the file
//! ([`super::partition`]) and the ranks agree on the whole's bounding box
//! (docs/distributed.md).
//!
//! A `.pvtu` is read piece by piece: only this rank's pieces are opened, merged as one process
//! merges all of them ([`crate::formats::collection::Merge`]: shared points by exact
//! coordinates, ghost cells dropped, the arrays' names and numbering kept). Any other file is
//! read whole by every rank, each keeping its part of the cells.

use std::path::Path;

use super::partition::{NodeKey, Share, morton_part, piece, share};
use super::{Comm, max_f64};
use crate::error::{Error, ParseError, Warning};
use crate::formats::collection::{Entry, Kind, Merge, PieceLabel, pvtu};
use crate::formats::{build, format_of_file, format_to_read};
use crate::mesh::Aabb;
use crate::volume::Volume;

/// Rank `rank` of `ranks`'s cells of `path`, as a volume whose bounding box is that of every
/// node the rank read (the whole's box is agreed on by [`load`]).
pub fn load_share(path: &Path, rank: usize, ranks: usize) -> Result<(Volume, Vec<Warning>), Error> {
    let pieces = pvtu_pieces(path)?;
    let count = pieces.as_ref().map_or(1, Vec::len);
    let (range, part) = match share(count, rank, ranks) {
        Share::Pieces(range) => (range, None),
        Share::Part { piece, part, parts } => (piece..piece + 1, Some((part, parts))),
    };
    let (vol, warnings) = match &pieces {
        Some(entries) => read_pieces(path, &entries[range])?,
        None => Volume::load(path)?,
    };
    let all: Vec<u32> = (0..vol.mesh.tet_count() as u32).collect();
    let tets = match part {
        Some((part, parts)) => morton_part(&vol, &all, part, parts),
        None => all,
    };
    let key = NodeKey::of(&vol, count == 1);
    let bbox = vol.mesh.bbox();
    Ok((piece(&vol, tets, &key, bbox)?, warnings))
}

/// A `.pvtu`'s pieces (`None` for any other file).
fn pvtu_pieces(path: &Path) -> Result<Option<Vec<Entry>>, Error> {
    let format = format_of_file(path)?;
    if Kind::of_format(format) != Some(Kind::Pvtu) {
        return Ok(None);
    }
    let bytes =
        std::fs::read(path).map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))?;
    Ok(Some(pvtu::entries(&bytes, &path.display().to_string())?))
}

/// The pieces `entries` of the `.pvtu` at `path`, read one after the other and merged.
fn read_pieces(path: &Path, entries: &[Entry]) -> Result<(Volume, Vec<Warning>), Error> {
    let shown = path.display().to_string();
    let mut merge = Merge::new();
    for e in entries {
        let file = path.parent().unwrap_or(Path::new("")).join(&e.file);
        let label = PieceLabel {
            file: file.display().to_string(),
            from: shown.clone(),
            line: e.line,
        };
        let located = |msg: String| Error::from(ParseError::new(&shown, e.line, msg));
        if !file.is_file() {
            let why = if file.exists() {
                "is not a file"
            } else {
                "no such file"
            };
            return Err(located(format!("{}: {why}", label.file)));
        }
        let bytes =
            std::fs::read(&file).map_err(|err| located(format!("{}: {err}", label.file)))?;
        let read = format_to_read(&bytes, &file)?.read.ok_or_else(|| {
            located(format!(
                "{}: a piece of a .pvtu must be a .vtu file",
                label.file
            ))
        })?;
        let desc = read(&bytes, &label.file)?;
        drop(bytes);
        merge.add(desc, label)?;
    }
    let desc = merge
        .finish()
        .ok_or_else(|| Error::Invalid(format!("{shown}: no piece to read")))?;
    let (vol, _, warnings) = build::volume_with_shape(desc)?;
    Ok((vol, warnings))
}

/// `volume FILE` on every rank: each reads its share; an error on any rank is every rank's
/// error; the piece gets the whole's bounding box (the smallest box around every rank's nodes).
pub fn load(comm: &dyn Comm, path: &Path) -> Result<(Volume, Vec<Warning>), String> {
    let local = load_share(path, comm.rank(), comm.size());
    let (mut vol, warnings) = match local {
        Ok(v) => {
            comm.agree(Ok(()))?;
            v
        }
        Err(e) => return Err(comm.agree(Err(e.to_string())).err().unwrap_or_default()),
    };
    agree_on_fields(comm, &vol, path)?;
    let b = vol.mesh.bbox();
    let mut lo = b.min;
    let mut hi = b.max;
    comm.min_f64(&mut lo);
    max_f64(comm, &mut hi);
    std::sync::Arc::make_mut(&mut vol.mesh).set_bbox(Aabb { min: lo, max: hi });
    Ok((vol, warnings))
}

/// The whole's box from every rank's box, for ranks that are not a [`Comm`] (pieces cut in
/// memory): the smallest box around them all.
pub fn union(boxes: impl IntoIterator<Item = Aabb>) -> Aabb {
    boxes
        .into_iter()
        .fold(Aabb::of_points(&[]), |all, b| all.union(&b))
}

/// This rank's fields as the pieces must agree on them: name, type and whether per node or per
/// cell, in their numbering (`"T" double (nodes), "material" int (cells)`).
pub fn fields_signature(vol: &Volume) -> String {
    let list: Vec<String> = vol
        .data
        .fields
        .iter()
        .map(|f| {
            let at = match f.interpolator {
                crate::field::Interpolator::Constant => "cells",
                _ => "nodes",
            };
            format!("\"{}\" {} ({at})", f.name.as_deref().unwrap_or("?"), f.ty)
        })
        .collect();
    if list.is_empty() {
        "no arrays".into()
    } else {
        list.join(", ")
    }
}

/// The ranks' fields must be one process's: each rank merged only its own pieces, so pieces
/// read by different ranks are compared here (every rank sends its fields to every rank, so
/// that all reach the same verdict and message).
fn agree_on_fields(comm: &dyn Comm, vol: &Volume, path: &Path) -> Result<(), String> {
    let mine = fields_signature(vol).into_bytes();
    let all = comm.all_to_all(vec![mine; comm.size()]);
    let parts = all.parts();
    let text = |r: usize| String::from_utf8_lossy(parts[r]).into_owned();
    let pieces = pvtu_pieces(path).ok().flatten().map_or(1, |p| p.len());
    let files = |r: usize| match share(pieces, r, comm.size()) {
        Share::Pieces(range) if range.is_empty() => "no piece".to_string(),
        Share::Pieces(range) => format!("pieces {} … {}", range.start, range.end - 1),
        Share::Part { piece, .. } => format!("piece {piece}"),
    };
    match (1..parts.len()).find(|&r| parts[r] != parts[0]) {
        None => Ok(()),
        Some(r) => Err(format!(
            "{}: the pieces' arrays disagree: rank {r} ({}) has {} but rank 0 ({}) has {}; every piece needs the same point and cell arrays (name, components, type)",
            path.display(),
            files(r),
            text(r),
            files(0),
            text(0)
        )),
    }
}
