//! HDF5 files for the VTKHDF and XDMF readers, through the pure-Rust `hdf5-reader` crate (no
//! system library; chunked and deflate-compressed datasets, every superblock and layout version
//! that h5py, netCDF-4, dolfinx and VTK write). This module only adapts it: datasets become
//! [`ArrayValues`] of the file's own number type (so that a field's type is the one it has in a
//! `.vtu`), attributes become numbers or text, and every failure becomes a [`ParseError`] that
//! names the file and the object (`flow.vtkhdf: dataset /VTKHDF/Points: …`), never a panic.
//!
//! A file on disk is read by ranges from the open file: a step of a long time series reads
//! only its own slices.

use std::path::Path;

use hdf5_reader::{Datatype, Hdf5File, OpenOptions, SliceInfo, SliceInfoElem};

use super::ArrayValues;
use crate::error::ParseError;

/// An open HDF5 file and the name it is reported under.
pub struct H5 {
    file: Hdf5File,
    /// The file name as given, for messages.
    pub name: String,
}

/// The 8 bytes every HDF5 file starts with (at offset 0, or after a user block of 512 · 2^k
/// bytes).
pub const MAGIC: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// Whether `head` (a file's first bytes) is an HDF5 file without a user block.
pub fn is_hdf5(head: &[u8]) -> bool {
    head.starts_with(MAGIC)
}

/// The most one read may decode: a corrupt size field must not ask for terabytes. Compressed
/// data may grow far beyond the file's size, so the bound is generous.
fn read_limit(file_len: usize) -> usize {
    file_len.saturating_mul(4096).max(256 << 20)
}

/// No chunk cache: a mesh's datasets are read once each, and with a cache `hdf5-reader` also
/// keeps a copy of every chunked dataset up to 32 MiB for as long as the file is open (the
/// peak of a load: docs/formats.md, "Speed and memory").
fn options(file_len: usize) -> OpenOptions {
    OpenOptions {
        chunk_cache_bytes: 0,
        ..OpenOptions::default()
    }
    .with_max_read_bytes(read_limit(file_len))
}

impl H5 {
    /// Opens (memory-maps) the file at `path`.
    pub fn open(path: &Path, name: &str) -> Result<H5, ParseError> {
        let len = std::fs::metadata(path)
            .map_err(|e| ParseError::new(name, 0, e.to_string()))?
            .len();
        let bad = |e: &dyn std::fmt::Display| {
            ParseError::new(name, 0, format!("not a readable HDF5 file: {e}"))
        };
        // Mapped and read from the map, so that a contiguous dataset is copied once, into its
        // array (`hdf5-reader`'s own `open` reads each range into a buffer first).
        let f = std::fs::File::open(path).map_err(|e| bad(&e))?;
        // SAFETY: the map is only read; as for every mapped file, another program truncating
        // the file meanwhile is not guarded against.
        let map = unsafe { memmap2::Mmap::map(&f) }.map_err(|e| bad(&e))?;
        let storage: hdf5_reader::storage::DynStorage =
            std::sync::Arc::new(hdf5_reader::storage::MmapStorage::new(map));
        let file = Hdf5File::from_storage_with_options(storage, options(len as usize))
            .map_err(|e| bad(&e))?;
        Ok(H5 {
            file,
            name: name.to_string(),
        })
    }

    /// The file held in memory.
    pub fn from_bytes(bytes: &[u8], name: &str) -> Result<H5, ParseError> {
        let file = Hdf5File::from_bytes_with_options(bytes, options(bytes.len()))
            .map_err(|e| ParseError::new(name, 0, format!("not a readable HDF5 file: {e}")))?;
        Ok(H5 {
            file,
            name: name.to_string(),
        })
    }

    fn error(&self, what: &str, message: impl std::fmt::Display) -> ParseError {
        ParseError::new(&self.name, 0, format!("{what}: {message}"))
    }

    /// Whether a group or dataset exists at `path`.
    pub fn has(&self, path: &str) -> bool {
        self.file.dataset(path).is_ok() || self.file.group(path).is_ok()
    }

    /// The shape of the dataset at `path`.
    pub fn shape(&self, path: &str) -> Result<Vec<u64>, ParseError> {
        let ds = self.dataset(path)?;
        Ok(ds.shape().to_vec())
    }

    fn dataset(&self, path: &str) -> Result<hdf5_reader::Dataset, ParseError> {
        self.file
            .dataset(path)
            .map_err(|e| self.error(&format!("dataset {path}"), missing(e)))
    }

    /// The names of a group's members: (groups, datasets).
    pub fn members(&self, path: &str) -> Result<(Vec<String>, Vec<String>), ParseError> {
        let group = self
            .file
            .group(path)
            .map_err(|e| self.error(&format!("group {path}"), missing(e)))?;
        group
            .member_names()
            .map_err(|e| self.error(&format!("group {path}"), e))
    }

    /// A whole dataset, flattened in C order.
    pub fn read(&self, path: &str) -> Result<ArrayValues, ParseError> {
        self.read_rows(path, None)
    }

    /// Rows `start .. start + count` of a dataset (its first dimension), or all of it.
    pub fn read_rows(
        &self,
        path: &str,
        rows: Option<(u64, u64)>,
    ) -> Result<ArrayValues, ParseError> {
        let ds = self.dataset(path)?;
        let what = format!("dataset {path}");
        let shape = ds.shape().to_vec();
        let selection = match rows {
            None => None,
            Some((start, count)) => {
                let end = start
                    .checked_add(count)
                    .filter(|&e| shape.first().is_some_and(|&n| e <= n));
                let Some(end) = end else {
                    return Err(self.error(
                        &what,
                        format!(
                            "rows {start} … {} asked for, it has {}",
                            start.saturating_add(count).saturating_sub(1),
                            shape.first().copied().unwrap_or(0)
                        ),
                    ));
                };
                let mut s = SliceInfo::all(shape.len());
                s.selections[0] = SliceInfoElem::Slice {
                    start,
                    end,
                    step: 1,
                };
                Some(s)
            }
        };
        read_typed(&ds, selection.as_ref()).map_err(|e| self.error(&what, e))
    }

    /// A whole dataset as integers (connectivity, offsets, types).
    pub fn read_ints(&self, path: &str) -> Result<Vec<i64>, ParseError> {
        self.read_int_rows(path, None)
    }

    /// [`H5::read_rows`] as integers: an error for a floating-point dataset.
    pub fn read_int_rows(
        &self,
        path: &str,
        rows: Option<(u64, u64)>,
    ) -> Result<Vec<i64>, ParseError> {
        match self.read_rows(path, rows)? {
            ArrayValues::Int(v) => Ok(v),
            _ => Err(self.error(
                &format!("dataset {path}"),
                "expected integers, found floating-point numbers",
            )),
        }
    }

    /// An attribute of the group or dataset at `path` as numbers (`None` if absent).
    pub fn attr_numbers(&self, path: &str, name: &str) -> Option<Vec<f64>> {
        let a = self.attribute(path, name)?;
        a.read_1d::<f64>()
            .or_else(|_| {
                a.read_1d::<i64>()
                    .map(|v| v.into_iter().map(|x| x as f64).collect())
            })
            .or_else(|_| {
                a.read_1d::<i32>()
                    .map(|v| v.into_iter().map(f64::from).collect())
            })
            .or_else(|_| {
                a.read_1d::<f32>()
                    .map(|v| v.into_iter().map(f64::from).collect())
            })
            .or_else(|_| a.read_scalar::<f64>().map(|v| vec![v]))
            .or_else(|_| a.read_scalar::<i64>().map(|v| vec![v as f64]))
            .ok()
    }

    /// An attribute as text (fixed or variable length; `None` if absent or not text).
    pub fn attr_text(&self, path: &str, name: &str) -> Option<String> {
        let a = self.attribute(path, name)?;
        a.read_string()
            .ok()
            .or_else(|| a.read_strings().ok().and_then(|v| v.into_iter().next()))
            .map(|s| s.trim_end_matches('\0').trim().to_string())
    }

    fn attribute(&self, path: &str, name: &str) -> Option<hdf5_reader::Attribute> {
        match self.file.group(path) {
            Ok(g) => g.attribute(name).ok(),
            Err(_) => self.file.dataset(path).ok()?.attribute(name).ok(),
        }
    }
}

/// The reason a path was not found, without the crate's internal wording where it is plain.
fn missing(e: hdf5_reader::error::Error) -> String {
    let text = e.to_string();
    if text.contains("not found") {
        "not in the file".to_string()
    } else {
        text
    }
}

/// An array's values in C order as a vector: the array's own buffer where it is one (as
/// `hdf5-reader` and `netcdf-reader` build them), so that a large dataset is not copied.
pub(super) fn into_vec<T: Clone>(a: ndarray::ArrayD<T>) -> Vec<T> {
    if !a.is_standard_layout() {
        return a.iter().cloned().collect();
    }
    let n = a.len();
    let (mut values, offset) = a.into_raw_vec_and_offset();
    values.drain(..offset.unwrap_or(0).min(values.len()));
    values.truncate(n);
    values
}

/// Reads a dataset (or a selection of it) in its own number type.
fn read_typed(
    ds: &hdf5_reader::Dataset,
    selection: Option<&SliceInfo>,
) -> Result<ArrayValues, String> {
    macro_rules! read {
        ($t:ty) => {
            match selection {
                Some(s) => ds.read_slice::<$t>(s),
                None => ds.read_array::<$t>(),
            }
            .map(into_vec)
            .map_err(|e| e.to_string())
        };
    }
    let ints = |v: Vec<i64>| ArrayValues::Int(v);
    Ok(match ds.dtype() {
        Datatype::FloatingPoint { size: 4, .. } => ArrayValues::F32(read!(f32)?),
        Datatype::FloatingPoint { size: 8, .. } => ArrayValues::F64(read!(f64)?),
        Datatype::FixedPoint { size, signed, .. } => match (size, signed) {
            (1, true) => ints(read!(i8)?.into_iter().map(i64::from).collect()),
            (1, false) => ints(read!(u8)?.into_iter().map(i64::from).collect()),
            (2, true) => ints(read!(i16)?.into_iter().map(i64::from).collect()),
            (2, false) => ints(read!(u16)?.into_iter().map(i64::from).collect()),
            (4, true) => ints(read!(i32)?.into_iter().map(i64::from).collect()),
            (4, false) => ints(read!(u32)?.into_iter().map(i64::from).collect()),
            (8, true) => ints(read!(i64)?),
            // Beyond i64::MAX no index or count is meaningful: saturate, the checks that
            // follow report it as out of range.
            (8, false) => ints(
                read!(u64)?
                    .into_iter()
                    .map(|v| i64::try_from(v).unwrap_or(i64::MAX))
                    .collect(),
            ),
            _ => return Err(format!("{size}-byte integers are not supported")),
        },
        other => return Err(format!("expected numbers, found {}", type_name(other))),
    })
}

fn type_name(t: &Datatype) -> String {
    match t {
        Datatype::String { .. } => "text".into(),
        Datatype::FloatingPoint { size, .. } => {
            format!("{}-bit floating point", u64::from(*size).saturating_mul(8))
        }
        Datatype::Compound { .. } => "a compound type".into(),
        other => format!("{other:?}")
            .split([' ', '{', '('])
            .next()
            .unwrap_or("data")
            .to_lowercase(),
    }
}
