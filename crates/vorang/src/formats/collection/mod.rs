//! Collections of mesh files and time series: ParaView's `.pvd` collections, parallel
//! `.pvtu` grids, `.vtm` multi-block data sets and `.series` file series.
//!
//! Solvers rarely write one file: a parallel run writes a grid in pieces, a coupled one in
//! blocks, a transient one a file per step, and a collection file lists them. A [`Series`] is
//! that list as VoRANG sees it: steps in the order of their time, each made of one or more
//! files (parts) that together are the step's grid. `.pvd` and `.series` files are time series;
//! a `.pvtu` or `.vtm` is one step (at time 0) whose files are its pieces or blocks. The file
//! names inside are relative to the collection file. `volume` loads step 0 ([`open`]); the
//! session keeps the series and its current step, and `timestep` loads another
//! ([`Series::load_step`]) on the mesh of the step before it when the points and cells are the
//! same (docs/formats.md, "Time series and collections").
//!
//! One module per format parses its file into entries (time, file, line) — `pvd`, `pvtu`,
//! `vtm`, `series_json` — on a shared XML walk (`xml`); `merge` joins a step's pieces into one
//! description, and `step` reads and builds a step. The registry ([`crate::formats::FORMATS`])
//! lists the four formats; their entries load step 0, so `data`, `vorang info` and Python's
//! `Volume.read` take a collection too.

mod merge;
pub mod multi;
pub mod pvd;
pub mod pvtu;
pub mod series_json;
mod step;
pub mod vtm;
mod xml;

use std::path::Path;

pub use merge::{GHOST_ARRAY, Merge, PieceLabel};
pub use multi::{EXODUS, Multi, VTKHDF, XDMF};
pub use step::StepVolume;
pub(crate) use xml::vtk_type;

use super::{Described, DescribedFile, Format, Loaded, format_to_read, read_bytes_of};
use crate::error::{Error, ParseError, Warning};
use std::path::PathBuf;

/// Per field, its range per component (`None` for a field without one): what
/// [`Series::ranges`] gives over all steps.
pub type FieldRanges = Vec<Option<Vec<(f64, f64)>>>;

/// One file a collection lists: the time it belongs to, its name as written, and the line.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub time: f64,
    pub file: String,
    pub line: usize,
}

/// The four collection formats, and the formats whose files hold time steps themselves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Pvd,
    Pvtu,
    Vtm,
    SeriesJson,
    /// Exodus II, XDMF, VTKHDF ([`multi`]).
    Steps(Multi),
}

impl Kind {
    /// The collection kind of a registry entry (`None`: a single mesh file).
    pub fn of_format(format: &Format) -> Option<Kind> {
        [
            (PVD.name, Kind::Pvd),
            (PVTU.name, Kind::Pvtu),
            (VTM.name, Kind::Vtm),
            (SERIES.name, Kind::SeriesJson),
        ]
        .into_iter()
        .find(|(name, _)| *name == format.name)
        .map(|(_, k)| k)
        .or_else(|| Multi::of_format(format).map(Kind::Steps))
    }

    /// What a file of this kind is called in messages.
    pub fn noun(self) -> &'static str {
        match self {
            Kind::Pvd => ".pvd collection",
            Kind::Pvtu => ".pvtu grid",
            Kind::Vtm => ".vtm multi-block data set",
            Kind::SeriesJson => ".series file series",
            Kind::Steps(m) => m.noun(),
        }
    }
}

/// One file of a step, and where the collection lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// The file (relative to the current folder, or absolute).
    pub path: PathBuf,
    /// The line of the collection that lists it (1 for a `.pvtu` or `.vtm`, which is itself
    /// the step's only part).
    pub line: usize,
    /// The step's number inside the file, for files that hold steps themselves (Exodus II,
    /// XDMF, VTKHDF); `None`: the whole file is the part.
    pub within: Option<usize>,
}

impl Part {
    /// The file, and the step inside it where it has several, for `vorang info`.
    pub fn label(&self) -> String {
        match self.within {
            Some(k) => format!("{} [step {k}]", self.path.display()),
            None => self.path.display().to_string(),
        }
    }
}

/// A time step: its time and its files.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub time: f64,
    pub parts: Vec<Part>,
}

/// A collection: its steps in the order of their time (the file's order among equal times).
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// The collection file as given, for messages.
    pub source: String,
    pub kind: Kind,
    pub steps: Vec<Step>,
}

impl Series {
    /// Reads the collection file at `path` (its files are not read yet; a file a time series
    /// names that does not exist is an error at its line).
    pub fn read(path: &Path) -> Result<Series, Error> {
        if let Some(Kind::Steps(multi)) = Kind::of_format(super::format_of_file(path)?) {
            return Ok(Series::of_steps(path, multi)?);
        }
        let bytes = read_bytes_of(path)?;
        let format = format_to_read(&bytes, path)?;
        let kind = Kind::of_format(format).ok_or_else(|| {
            Error::Invalid(format!(
                "{}: this is a {} file, not a collection or time series (.pvd, .pvtu, .vtm, .series, Exodus II, XDMF, VTKHDF)",
                path.display(),
                format.name
            ))
        })?;
        let series = Series::parse(&bytes, path, kind)?;
        series.check_files()?;
        Ok(series)
    }

    /// The series of a file that holds time steps itself, read from disk (its readers open
    /// it themselves: an HDF5 file is memory-mapped, not read whole).
    fn of_steps(path: &Path, multi: Multi) -> Result<Series, ParseError> {
        Ok(Series {
            source: path.display().to_string(),
            kind: Kind::Steps(multi),
            steps: multi.steps(path)?,
        })
    }

    /// The collection of `kind` in `bytes`, its files relative to `path`'s folder.
    pub fn parse(bytes: &[u8], path: &Path, kind: Kind) -> Result<Series, ParseError> {
        let source = path.display().to_string();
        let whole = |line| Step {
            time: 0.0,
            parts: vec![Part {
                path: path.to_path_buf(),
                line,
                within: None,
            }],
        };
        let steps = match kind {
            Kind::Pvd => steps_of(pvd::entries(bytes, &source)?, path, true),
            Kind::SeriesJson => steps_of(series_json::entries(bytes, &source)?, path, false),
            // The file is checked now, read piece by piece when the step loads.
            Kind::Pvtu => {
                pvtu::entries(bytes, &source)?;
                vec![whole(1)]
            }
            Kind::Vtm => {
                vtm::leaves(bytes, &source)?;
                vec![whole(1)]
            }
            Kind::Steps(multi) => multi.steps(path)?,
        };
        Ok(Series {
            source,
            kind,
            steps,
        })
    }

    /// Every file a time series names exists (a missing one is named at its line).
    fn check_files(&self) -> Result<(), ParseError> {
        if matches!(self.kind, Kind::Pvtu | Kind::Vtm | Kind::Steps(_)) {
            return Ok(());
        }
        for part in self.steps.iter().flat_map(|s| &s.parts) {
            if !part.path.is_file() {
                let why = if part.path.exists() {
                    "is not a file"
                } else {
                    "no such file"
                };
                return Err(ParseError::new(
                    &self.source,
                    part.line,
                    format!("{}: {why}", part.path.display()),
                ));
            }
        }
        Ok(())
    }

    pub fn len(&self) -> usize {
        self.steps.len()
    }

    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// The steps' times.
    pub fn times(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.time).collect()
    }

    /// The step whose time is nearest `t` (the earlier one on a tie).
    pub fn nearest(&self, t: f64) -> usize {
        let mut best = 0;
        for (i, s) in self.steps.iter().enumerate() {
            if (s.time - t).abs() < (self.steps[best].time - t).abs() {
                best = i;
            }
        }
        best
    }

    /// "3 time steps (0 … 2)" — the steps' numbers, for messages.
    pub fn range_text(&self) -> String {
        let n = self.steps.len();
        format!(
            "{n} time step{} (0 … {})",
            if n == 1 { "" } else { "s" },
            n.saturating_sub(1)
        )
    }

    /// The first and last step's times.
    pub fn time_range(&self) -> (f64, f64) {
        let t = |s: Option<&Step>| s.map_or(0.0, |s| s.time);
        (t(self.steps.first()), t(self.steps.last()))
    }
}

/// Steps from entries: sorted by time (stable); entries of equal time are the parts of one
/// step when `merge_equal` (`.pvd`), separate steps otherwise (`.series`).
fn steps_of(mut entries: Vec<Entry>, path: &Path, merge_equal: bool) -> Vec<Step> {
    entries.sort_by(|a, b| a.time.total_cmp(&b.time));
    let mut steps: Vec<Step> = Vec::new();
    for e in entries {
        let part = Part {
            path: step::resolve(path, &e.file),
            line: e.line,
            within: None,
        };
        match steps.last_mut() {
            Some(last) if merge_equal && last.time == e.time => last.parts.push(part),
            _ => steps.push(Step {
                time: e.time,
                parts: vec![part],
            }),
        }
    }
    steps
}

/// A collection opened by `volume`: the series, its step 0, and the warnings of reading it.
pub type Opened = (Series, StepVolume, Vec<Warning>);

/// Opens `path` if it is a collection: reads it and loads step 0. `None` for a single mesh
/// file (its format's own loader reads it).
pub fn open(path: &Path) -> Result<Option<Opened>, Error> {
    let format = super::format_of_file(path)?;
    if Kind::of_format(format).is_none() {
        return Ok(None);
    }
    let series = Series::read(path)?;
    let (first, warnings) = series.load_step(0, None)?;
    Ok(Some((series, first, warnings)))
}

/// A collection's step 0, for the registry's `load`.
fn load_first(path: &Path) -> Result<Loaded, Error> {
    let series = Series::read(path)?;
    let (first, warnings) = series.load_step(0, None)?;
    Ok((unshared(first.volume), warnings))
}

/// A collection held in memory (its files relative to `name`'s folder): step 0.
fn load_first_bytes(bytes: &[u8], name: &str) -> Result<Loaded, ParseError> {
    let path = Path::new(name);
    let kind = Kind::of_format(format_to_read(bytes, path)?)
        .ok_or_else(|| ParseError::new(name, 1, "not a collection (.pvd, .pvtu, .vtm, .series)"))?;
    let series = Series::parse(bytes, path, kind)?;
    series.check_files()?;
    let (first, warnings) = series.load_step(0, None).map_err(|e| match e {
        Error::Parse(p) => p,
        other => ParseError::new(name, 1, other.to_string()),
    })?;
    Ok((unshared(first.volume), warnings))
}

fn unshared(vol: std::sync::Arc<crate::volume::Volume>) -> crate::volume::Volume {
    std::sync::Arc::try_unwrap(vol).unwrap_or_else(|shared| (*shared).clone())
}

/// `vorang info COLLECTION`: step 0 with the series and every field's range over all steps.
fn describe(path: &Path) -> Result<DescribedFile, Error> {
    let series = Series::read(path)?;
    let (first, warnings) = series.load_step(0, None)?;
    let ranges = series.ranges(&first)?;
    Ok((
        Described::Series {
            volume: unshared(first.volume),
            series,
            ranges,
        },
        warnings,
    ))
}

/// `data ?+? COLLECTION`: step 0's fields.
fn load_data(vol: &crate::volume::Volume, path: &Path, append: bool) -> Result<Loaded, Error> {
    let (other, warnings) = load_first(path)?;
    let mut next = vol.clone();
    next.attach_fields_of(other, append)?;
    Ok((next, warnings))
}

fn sniff_attr(head: &[u8], ty: &str) -> bool {
    vtk_type(head).is_some_and(|t| t == ty)
}

fn sniff_series(head: &[u8]) -> bool {
    let head = head.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(head);
    let text = String::from_utf8_lossy(&head[..head.len().min(4096)]);
    text.trim_start().starts_with('{') && text.contains("\"file-series-version\"")
}

/// The registry entry of a collection format: every operation starts from step 0.
macro_rules! collection_format {
    ($name:expr, $extensions:expr, $sniff:expr) => {
        Format {
            name: $name,
            extensions: $extensions,
            sniff: $sniff,
            read: None,
            load: load_first,
            load_bytes: load_first_bytes,
            load_data,
            describe,
            write: None,
        }
    };
}

pub const PVD: Format = collection_format!("ParaView collection", &["pvd"], |h| sniff_attr(
    h,
    "Collection"
));
pub const PVTU: Format = collection_format!("parallel VTK XML UnstructuredGrid", &["pvtu"], |h| {
    sniff_attr(h, "PUnstructuredGrid")
});
pub const VTM: Format = collection_format!("VTK XML multi-block", &["vtm"], |h| sniff_attr(
    h,
    "vtkMultiBlockDataSet"
));
pub const SERIES: Format = collection_format!("ParaView file series", &["series"], sniff_series);

#[cfg(test)]
mod tests {
    use super::*;

    fn series(times: &[f64]) -> Series {
        Series {
            source: "s.pvd".into(),
            kind: Kind::Pvd,
            steps: times
                .iter()
                .map(|&time| Step {
                    time,
                    parts: Vec::new(),
                })
                .collect(),
        }
    }

    #[test]
    fn nearest_takes_the_earlier_step_on_a_tie() {
        let s = series(&[0.0, 1.0, 2.0, 4.0]);
        assert_eq!(s.nearest(-5.0), 0);
        assert_eq!(s.nearest(0.5), 0);
        assert_eq!(s.nearest(0.51), 1);
        assert_eq!(s.nearest(3.0), 2);
        assert_eq!(s.nearest(99.0), 3);
        assert_eq!(s.range_text(), "4 time steps (0 … 3)");
    }

    #[test]
    fn pvd_steps_are_sorted_and_parts_of_one_time_merged() {
        let text = br#"<VTKFile type="Collection"><Collection>
<DataSet timestep="1" file="b1.vtu"/>
<DataSet timestep="0" file="a0.vtu"/>
<DataSet timestep="1" file="c1.vtu"/>
</Collection></VTKFile>"#;
        let s = Series::parse(text, Path::new("dir/x.pvd"), Kind::Pvd).unwrap();
        assert_eq!(s.times(), [0.0, 1.0]);
        let parts: Vec<_> = s.steps[1]
            .parts
            .iter()
            .map(|p| (p.path.clone(), p.line))
            .collect();
        assert_eq!(
            parts,
            [
                (PathBuf::from("dir/b1.vtu"), 2),
                (PathBuf::from("dir/c1.vtu"), 4)
            ]
        );
        let json = br#"{"file-series-version": "1.0", "files": [{"name": "b", "time": 1}, {"name": "a", "time": 1}]}"#;
        let s = Series::parse(json, Path::new("x.series"), Kind::SeriesJson).unwrap();
        assert_eq!(s.len(), 2);
    }

    #[test]
    fn the_formats_are_recognised_by_content() {
        let detect =
            |text: &[u8], name: &str| super::super::detect(text, Path::new(name)).map(|f| f.name);
        assert_eq!(
            detect(
                b"<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">",
                "a.vtu"
            ),
            Some("ParaView collection")
        );
        assert_eq!(
            detect(b"<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\">", "a"),
            Some("parallel VTK XML UnstructuredGrid")
        );
        assert_eq!(
            detect(b"<VTKFile type=\"vtkMultiBlockDataSet\">", "a"),
            Some("VTK XML multi-block")
        );
        assert_eq!(
            detect(
                b"{\n \"file-series-version\" : \"1.0\", \"files\": []}",
                "a"
            ),
            Some("ParaView file series")
        );
        assert_eq!(
            detect(b"<VTKFile type=\"UnstructuredGrid\">", "a.pvd"),
            Some("VTK XML UnstructuredGrid")
        );
    }
}
