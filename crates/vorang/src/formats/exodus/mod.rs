//! Exodus II (`.e`, `.exo`, `.ex2`, and the `-s0002` continuation files a solver starts when
//! the mesh changes): the netCDF layout of the SEACAS tools, Cubit, MOOSE and meshio, in its
//! netCDF-4 (HDF5) and classic (CDF-1, CDF-2) forms — docs/formats.md, "Exodus II".
//!
//! Read through the pure-Rust `netcdf-reader` crate, which reads both forms behind one
//! interface. The points are `coordx`/`coordy`/`coordz` (or `coord`); the cells are the element
//! blocks `connect1`, `connect2`, … with their `elem_type` and 1-based node numbers
//! ([`blocks`]); each block's id (`eb_prop1`) becomes the byte cell array `block`; nodal
//! variables (`name_nod_var` with `vals_nod_var1`, … or the older `vals_nod_var[time, var,
//! node]`) become point arrays, element variables (`name_elem_var`, `vals_elem_var{i}eb{j}`
//! where `elem_var_tab` has them) cell arrays; `time_whole` gives the steps' times.

mod blocks;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use netcdf_reader::{
    NcFile, NcFormat, NcOpenOptions, NcReadable, NcSliceInfo, NcSliceInfoElem, NcType,
};

use super::{Array, ArrayValues, FileStep, MeshDescription};
use crate::error::ParseError;

/// Whether a file's head is Exodus: netCDF classic (`CDF\x01`, `CDF\x02`: VoRANG reads no
/// other netCDF), or HDF5 whose root group carries Exodus's global attributes
/// (`floating_point_word_size`, `api_version`, written first, so within the head); an HDF5
/// file without them is decided by its extension.
pub fn sniff(head: &[u8]) -> bool {
    let has = |name: &[u8]| head.windows(name.len()).any(|w| w == name);
    head.starts_with(b"CDF\x01")
        || head.starts_with(b"CDF\x02")
        || (super::hdf::is_hdf5(head) && (has(b"floating_point_word_size") || has(b"api_version")))
}

/// An open Exodus file and its name for messages.
pub(super) struct Exo {
    nc: NcFile,
    name: String,
    /// How many bytes a variable read whole may claim (see `native`): the file's length for
    /// a classic file, 1100 times that for netCDF-4, whose data may be compressed (deflate
    /// expands at most about 1032-fold).
    limit: u64,
}

/// How a netCDF-4 file is opened: no chunk cache — a mesh's variables are read once each, and
/// with a cache `hdf5-reader` also keeps a copy of every chunked variable up to 32 MiB for as
/// long as the file is open, which made a deflated file's load peak at 2.4× its volume
/// (docs/formats.md, "Speed and memory") — and no read larger than `limit` bytes, checked
/// before anything is allocated for it.
fn nc4_options(limit: u64) -> NcOpenOptions {
    NcOpenOptions {
        chunk_cache_bytes: 0,
        max_read_bytes: usize::try_from(limit).unwrap_or(usize::MAX),
        ..NcOpenOptions::default()
    }
}

/// At most this many groups in a netCDF-4 file (an Exodus file has one).
const MAX_GROUPS: usize = 4096;

/// The groups of a netCDF-4 file form a tree, as netCDF's data model has them: no group is
/// reached twice from the root (HDF5 links can make a group its own member, and
/// `netcdf-reader` would then follow it without end until the stack overflows: found by
/// fuzzing), and there are at most [`MAX_GROUPS`]. An HDF5 layer that cannot be read is left to
/// `netcdf-reader`, which says why.
fn check_groups(
    file: Result<hdf5_reader::Hdf5File, hdf5_reader::error::Error>,
    name: &str,
) -> Result<(), ParseError> {
    let Ok(root) = file.and_then(|f| f.root_group()) else {
        return Ok(());
    };
    let bad = |m: String| ParseError::new(name, 0, format!("not a readable netCDF file: {m}"));
    let mut seen = std::collections::HashSet::from([root.address()]);
    let mut open = vec![root];
    while let Some(group) = open.pop() {
        let Ok(children) = group.groups() else {
            continue;
        };
        for child in children {
            if !seen.insert(child.address()) {
                return Err(bad(format!(
                    "group '{}' is reached twice (the groups do not form a tree)",
                    child.name()
                )));
            }
            if seen.len() > MAX_GROUPS {
                return Err(bad(format!("more than {MAX_GROUPS} groups")));
            }
            open.push(child);
        }
    }
    Ok(())
}

/// How many bytes a netCDF-4 variable read whole may claim: its data may be compressed, and
/// deflate expands at most about 1032-fold.
fn nc4_limit(len: u64) -> u64 {
    len.saturating_mul(1100)
}

impl Exo {
    fn open(path: &Path, name: &str) -> Result<Exo, ParseError> {
        let bad = |e: &dyn std::fmt::Display| {
            ParseError::new(name, 0, format!("not a readable netCDF file: {e}"))
        };
        let mut file = std::fs::File::open(path).map_err(|e| bad(&e))?;
        let len = file.metadata().map_err(|e| bad(&e))?.len();
        let mut magic = [0u8; 4];
        let classic =
            std::io::Read::read_exact(&mut file, &mut magic).is_ok() && magic.starts_with(b"CDF");
        if classic {
            // netcdf-reader maps classic files itself and reads from the map.
            let nc = NcFile::open(path).map_err(|e| bad(&e))?;
            return Ok(Exo::classic(nc, name, len));
        }
        // A netCDF-4 file is mapped here and read from the map, so that a variable is copied
        // once, into its vector (netcdf-reader's own `open` reads each range into a buffer
        // first, which doubles a connectivity while it is read: docs/formats.md, "Speed and
        // memory").
        // SAFETY: the map is only read; as for every mapped file, another program truncating
        // the file meanwhile is not guarded against (netcdf-reader maps classic files the same
        // way).
        let map = unsafe { memmap2::Mmap::map(&file) }.map_err(|e| bad(&e))?;
        Exo::nc4(Arc::new(netcdf_reader::MmapStorage::new(map)), name, len)
    }

    fn from_bytes(bytes: &[u8], name: &str) -> Result<Exo, ParseError> {
        let len = bytes.len() as u64;
        if bytes.starts_with(b"CDF") {
            let nc = NcFile::from_bytes(bytes).map_err(|e| {
                ParseError::new(name, 0, format!("not a readable netCDF file: {e}"))
            })?;
            return Ok(Exo::classic(nc, name, len));
        }
        // One copy of the bytes, shared by the group check and the reader.
        let storage = hdf5_reader::storage::BytesStorage::new(bytes.to_vec());
        Exo::nc4(Arc::new(storage), name, len)
    }

    fn classic(nc: NcFile, name: &str, len: u64) -> Exo {
        Exo {
            nc,
            name: name.to_string(),
            limit: len,
        }
    }

    /// A netCDF-4 file from its bytes: the groups checked ([`check_groups`]), then opened.
    fn nc4(storage: netcdf_reader::DynStorage, name: &str, len: u64) -> Result<Exo, ParseError> {
        let hdf5 = hdf5_reader::Hdf5File::from_storage_with_options(
            Arc::clone(&storage),
            hdf5_reader::OpenOptions {
                chunk_cache_bytes: 0,
                ..hdf5_reader::OpenOptions::default()
            },
        );
        check_groups(hdf5, name)?;
        let nc = NcFile::from_storage_with_options(storage, nc4_options(nc4_limit(len)))
            .map_err(|e| ParseError::new(name, 0, format!("not a readable netCDF file: {e}")))?;
        Ok(Exo {
            nc,
            name: name.to_string(),
            limit: nc4_limit(len),
        })
    }

    /// Whether the file is netCDF-4 (HDF5, read through `hdf5-reader`: [`nc4_options`]).
    fn is_nc4(&self) -> bool {
        matches!(self.nc.format(), NcFormat::Nc4 | NcFormat::Nc4Classic)
    }

    pub(super) fn error(&self, what: &str, message: impl std::fmt::Display) -> ParseError {
        ParseError::new(&self.name, 0, format!("{what}: {message}"))
    }

    pub(super) fn has(&self, var: &str) -> bool {
        self.nc.variable(var).is_ok()
    }

    /// The size of a dimension (0 if absent).
    pub(super) fn dim(&self, name: &str) -> usize {
        self.nc.dimension(name).map_or(0, |d| d.size as usize)
    }

    /// How many dimensions the file declares.
    pub(super) fn dimensions(&self) -> usize {
        self.nc.dimensions().map_or(0, |d| d.len())
    }

    /// A variable's shape.
    pub(super) fn shape(&self, var: &str) -> Result<Vec<u64>, ParseError> {
        self.nc
            .variable(var)
            .map(|v| v.shape())
            .map_err(|e| self.error(&format!("variable {var}"), e))
    }

    /// A text attribute of a variable.
    pub(super) fn text_attr(&self, var: &str, attr: &str) -> Option<String> {
        let v = self.nc.variable(var).ok()?;
        v.attribute(attr)?.value.as_string()
    }

    /// A whole variable, or one index of its first dimensions (`at`: the time step, then the
    /// variable for the old `vals_nod_var`), in the variable's own number type. `float`,
    /// `double`, `int` and `int64` variables are read as they are stored (no copy through
    /// `f64`: the coordinates and values of a large mesh are read once).
    pub(super) fn read(&self, var: &str, at: &[u64]) -> Result<ArrayValues, ParseError> {
        let what = format!("variable {var}");
        let v = self.nc.variable(var).map_err(|e| self.error(&what, e))?;
        let shape = v.shape();
        for (k, (&i, &n)) in at.iter().zip(&shape).enumerate() {
            if i >= n {
                return Err(self.error(
                    &what,
                    format!("index {i} of dimension {k} is past its {n} entries"),
                ));
            }
        }
        let mut selections: Vec<NcSliceInfoElem> =
            at.iter().map(|&i| NcSliceInfoElem::Index(i)).collect();
        selections.resize(
            shape.len(),
            NcSliceInfoElem::Slice {
                start: 0,
                end: u64::MAX,
                step: 1,
            },
        );
        let selection = NcSliceInfo { selections };
        let all = at.is_empty();
        let err = |e: netcdf_reader::Error| self.error(&what, e);
        Ok(match v.dtype() {
            NcType::Float => ArrayValues::F32(self.native(var, all, &selection).map_err(err)?),
            NcType::Double => ArrayValues::F64(self.native(var, all, &selection).map_err(err)?),
            NcType::Int => {
                let values: Vec<i32> = self.native(var, all, &selection).map_err(err)?;
                ArrayValues::Int(values.into_iter().map(i64::from).collect())
            }
            NcType::Int64 => ArrayValues::Int(self.native(var, all, &selection).map_err(err)?),
            NcType::Byte
            | NcType::UByte
            | NcType::Short
            | NcType::UShort
            | NcType::UInt
            | NcType::UInt64 => {
                let values = if all {
                    self.nc.read_variable_as_f64(var)
                } else {
                    self.nc.read_variable_slice_as_f64(var, &selection)
                }
                .map_err(err)?;
                ArrayValues::Int(values.into_iter().map(|x| x as i64).collect())
            }
            other => return Err(self.error(&what, format!("expected numbers, found {other:?}"))),
        })
    }

    /// A variable's values in its own type `T` (the whole variable, or `selection`), as a
    /// vector. A whole variable of a classic file is read straight into a vector of its size
    /// (no array to copy from, no bytes decoded on the side: a large connectivity exists once)
    /// when the file can hold that many values (`limit`), so that a corrupt shape cannot
    /// reserve memory. Otherwise the reader's own array is taken: for netCDF-4 it is built in
    /// place from the chunks, once (reading into a vector of ours would leave `hdf5-reader` a
    /// copy of a chunked variable), and the reader refuses reads beyond `limit`.
    fn native<T: NcReadable + Clone + Default>(
        &self,
        var: &str,
        all: bool,
        selection: &NcSliceInfo,
    ) -> Result<Vec<T>, netcdf_reader::Error> {
        let size = self.nc.variable(var).ok().and_then(|v| {
            v.shape()
                .iter()
                .try_fold(1u64, |n, &d| n.checked_mul(d))
                .and_then(|n| n.checked_mul(std::mem::size_of::<T>() as u64))
        });
        if all && !self.is_nc4() && size.is_some_and(|b| b <= self.limit) {
            let n = size.unwrap_or(0) as usize / std::mem::size_of::<T>().max(1);
            let mut values = vec![T::default(); n];
            self.nc.read_variable_into(var, &mut values)?;
            return Ok(values);
        }
        let a = if all {
            self.nc.read_variable::<T>(var)?
        } else {
            self.nc.read_variable_slice::<T>(var, selection)?
        };
        Ok(super::hdf::into_vec(a))
    }

    /// A connectivity variable: its node numbers as stored (`int` or `int64`; other number
    /// types converted), without widening 32-bit numbers.
    pub(super) fn read_nodes(&self, var: &str) -> Result<Nodes, ParseError> {
        let what = format!("variable {var}");
        let v = self.nc.variable(var).map_err(|e| self.error(&what, e))?;
        let all = NcSliceInfo {
            selections: Vec::new(),
        };
        let err = |e: netcdf_reader::Error| self.error(&what, e);
        Ok(match v.dtype() {
            NcType::Int => Nodes::I32(self.native(var, true, &all).map_err(err)?),
            _ => match self.read(var, &[])? {
                ArrayValues::Int(v) => Nodes::I64(v),
                other => Nodes::I64((0..other.len()).map(|i| other.get(i) as i64).collect()),
            },
        })
    }

    /// The names of a `name_*_var` text variable (empty if absent).
    pub(super) fn names(&self, var: &str) -> Result<Vec<String>, ParseError> {
        if !self.has(var) {
            return Ok(Vec::new());
        }
        let names = self
            .nc
            .read_variable_as_strings(var)
            .map_err(|e| self.error(&format!("variable {var}"), e))?;
        Ok(names
            .into_iter()
            .map(|s| s.trim_end_matches('\0').trim().to_string())
            .collect())
    }
}

/// The node numbers of a block's connectivity, as the file stores them.
pub(super) enum Nodes {
    I32(Vec<i32>),
    I64(Vec<i64>),
}

impl Nodes {
    pub(super) fn len(&self) -> usize {
        match self {
            Nodes::I32(v) => v.len(),
            Nodes::I64(v) => v.len(),
        }
    }

    pub(super) fn get(&self, i: usize) -> i64 {
        match self {
            Nodes::I32(v) => i64::from(v[i]),
            Nodes::I64(v) => v[i],
        }
    }
}

/// Step 0 of an Exodus file held in memory.
pub fn read(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    describe(&Exo::from_bytes(bytes, name)?, 0)
}

/// The steps of the file at `path` and of its continuation files (`path-s0002`, … in the same
/// folder, in the order of their numbers), each file's steps from its `time_whole`.
pub fn steps(path: &Path, name: &str) -> Result<Vec<FileStep>, ParseError> {
    let mut out = Vec::new();
    for (k, file) in std::iter::once(path.to_path_buf())
        .chain(continuations(path))
        .enumerate()
    {
        let shown = if k == 0 {
            name.to_string()
        } else {
            file.display().to_string()
        };
        let exo = Exo::open(&file, &shown)?;
        let times = times(&exo)?;
        out.extend(times.into_iter().enumerate().map(|(index, time)| FileStep {
            time,
            file: file.clone(),
            index,
        }));
    }
    Ok(out)
}

/// Step `index` of the file at `path` (a continuation file holds its own steps).
pub fn read_step(path: &Path, name: &str, index: usize) -> Result<MeshDescription, ParseError> {
    describe(&Exo::open(path, name)?, index)
}

/// The continuation files of `path`: `NAME-sNNNN` beside it with NNNN ≥ 2, by number.
fn continuations(path: &Path) -> Vec<PathBuf> {
    let Some(base) = path.file_name().and_then(|n| n.to_str()) else {
        return Vec::new();
    };
    let folder = path.parent().unwrap_or(Path::new(""));
    let prefix = format!("{base}-s");
    let listing = std::fs::read_dir(if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    });
    let mut found: Vec<(u64, PathBuf)> = listing
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|entry| {
            let name = entry.file_name().into_string().ok()?;
            let digits = name.strip_prefix(&prefix)?;
            if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
                return None;
            }
            let n: u64 = digits.parse().ok()?;
            (n >= 2).then(|| (n, folder.join(&name)))
        })
        .collect();
    found.sort();
    found.into_iter().map(|(_, p)| p).collect()
}

/// The times of a file's steps (`time_whole`); a file without steps is one step at 0.
fn times(exo: &Exo) -> Result<Vec<f64>, ParseError> {
    if !exo.has("time_whole") || exo.shape("time_whole")?.first().is_none_or(|&n| n == 0) {
        return Ok(vec![0.0]);
    }
    let t = exo.read("time_whole", &[])?;
    let times: Vec<f64> = (0..t.len()).map(|i| t.get(i)).collect();
    if let Some(bad) = times.iter().position(|t| !t.is_finite()) {
        return Err(exo.error(
            "variable time_whole",
            format!("step {bad}: the time is not finite"),
        ));
    }
    Ok(times)
}

/// The description of step `index`.
fn describe(exo: &Exo, index: usize) -> Result<MeshDescription, ParseError> {
    let steps = times(exo)?.len();
    if index >= steps {
        return Err(exo.error(
            "variable time_whole",
            format!("has {steps} steps, not step {index}"),
        ));
    }
    let stored = exo.has("time_whole") && exo.dim("time_step") > 0;
    let mut desc = MeshDescription {
        source: exo.name.clone(),
        format: "Exodus II".into(),
        ..MeshDescription::default()
    };
    let (nodes, float) = coordinates(exo)?;
    desc.nodes = nodes;
    desc.float_coordinates = float;
    let blocks = blocks::read(exo, desc.nodes.len(), &mut desc.cells, &mut desc.warnings)?;
    desc.cell_arrays.push(blocks::ids_array(&blocks));
    if stored {
        desc.point_arrays = nodal(exo, index, desc.nodes.len())?;
        desc.cell_arrays
            .extend(blocks::element_arrays(exo, &blocks, index)?);
    }
    Ok(desc)
}

/// The points: `coordx`, `coordy`, `coordz` (missing axes 0), or `coord[dim, node]`.
fn coordinates(exo: &Exo) -> Result<(Vec<[f64; 3]>, bool), ParseError> {
    let n = exo.dim("num_nodes");
    let mut axes = Vec::new();
    let float;
    if exo.has("coordx") {
        for var in ["coordx", "coordy", "coordz"] {
            if exo.has(var) {
                axes.push(exo.read(var, &[])?);
            }
        }
        float = axes.iter().all(|a| matches!(a, ArrayValues::F32(_)));
    } else if exo.has("coord") {
        let all = exo.read("coord", &[])?;
        let dims = exo.shape("coord")?;
        let per = dims.get(1).copied().unwrap_or(0) as usize;
        let axes_in_file = dims.first().copied().unwrap_or(0) as usize;
        if dims.len() != 2 || Some(all.len()) != axes_in_file.checked_mul(per) {
            return Err(exo.error(
                "variable coord",
                format!("expected [num_dim, num_nodes] values, found shape {dims:?}"),
            ));
        }
        for d in 0..axes_in_file.min(3) {
            let values: Vec<f64> = (0..per).map(|i| all.get(d * per + i)).collect();
            axes.push(ArrayValues::F64(values));
        }
        float = matches!(all, ArrayValues::F32(_));
    } else {
        return Err(exo.error(
            "variable coordx",
            "not in the file: no coordinates (coordx or coord)",
        ));
    }
    finish_axes(exo, n, axes, float)
}

fn finish_axes(
    exo: &Exo,
    n: usize,
    axes: Vec<ArrayValues>,
    float: bool,
) -> Result<(Vec<[f64; 3]>, bool), ParseError> {
    if axes.is_empty() {
        return Err(exo.error("coordinates", "no axis"));
    }
    if let Some(a) = axes.iter().find(|a| a.len() != n) {
        return Err(exo.error(
            "coordinates",
            format!("{} values for num_nodes = {n}", a.len()),
        ));
    }
    let nodes = (0..n)
        .map(|i| {
            let c = |k: usize| axes.get(k).map_or(0.0, |a| a.get(i));
            [c(0), c(1), c(2)]
        })
        .collect();
    Ok((nodes, float && !axes.is_empty()))
}

/// The nodal variables of step `index` as point arrays.
fn nodal(exo: &Exo, index: usize, points: usize) -> Result<Vec<Array>, ParseError> {
    let names = exo.names("name_nod_var")?;
    let combined = exo.has("vals_nod_var");
    let mut out = Vec::new();
    for (i, name) in names.into_iter().enumerate() {
        let (var, at) = if combined {
            ("vals_nod_var".to_string(), vec![index as u64, i as u64])
        } else {
            (format!("vals_nod_var{}", i + 1), vec![index as u64])
        };
        if !exo.has(&var) {
            return Err(exo.error(
                &format!("variable {var}"),
                format!("not in the file: nodal variable \"{name}\" has no values"),
            ));
        }
        let values = exo.read(&var, &at)?;
        if values.len() != points {
            return Err(exo.error(
                &format!("variable {var}"),
                format!("{} values for {points} nodes", values.len()),
            ));
        }
        out.push(Array {
            name,
            components: 1,
            values,
            line: 0,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sniffing_knows_classic_and_netcdf4() {
        assert!(sniff(b"CDF\x01\0\0\0\0"));
        assert!(sniff(b"CDF\x02\0\0\0\0"));
        assert!(!sniff(b"CDF\x05"));
        let mut h = super::super::hdf::MAGIC.to_vec();
        h.extend_from_slice(b".....floating_point_word_size...");
        assert!(sniff(&h));
        assert!(!sniff(super::super::hdf::MAGIC));
    }

    #[test]
    fn bad_bytes_are_an_error_naming_the_file() {
        let e = read(b"CDF\x01garbage", "x.exo").unwrap_err();
        assert!(e.to_string().starts_with("x.exo: "), "{e}");
    }
}
