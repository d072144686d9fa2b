//! `vorang.Series`: a collection or time series (`.pvd`, `.pvtu`, `.vtm`, `.series`, or an
//! Exodus II, XDMF or VTKHDF file with its time steps) as the
//! core reads it ([`vorang::formats::collection::Series`]): its times, its steps as `Volume`s
//! loaded when asked for (each on the mesh of the step loaded before it when the points and
//! cells are the same), and each field's range over all steps, so that an animation's colours
//! mean the same value in every frame (docs/formats.md, "Time series and collections").

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;

use vorang::formats::collection::{FieldRanges, Series, StepVolume};

use crate::scene::session_err;
use crate::{PyVolume, warn_all};

/// A collection of mesh files with its time steps.
#[pyclass(name = "Series", module = "vorang", frozen)]
pub(crate) struct PySeries {
    pub(crate) inner: Arc<Series>,
    /// The step loaded last: the next one shares its mesh when its points and cells are the
    /// same.
    last: Mutex<Option<StepVolume>>,
    /// Each field's range over all steps, once asked for.
    ranges: Mutex<Option<Arc<FieldRanges>>>,
}

impl PySeries {
    /// Step `index`, loaded on the mesh of the step loaded last (without the interpreter lock);
    /// the loading's warnings go to Python's `warnings`.
    pub(crate) fn step(&self, py: Python<'_>, index: usize) -> PyResult<StepVolume> {
        let previous = self.last.lock().ok().and_then(|last| last.clone());
        if let Some(p) = previous.as_ref().filter(|p| p.index == index) {
            return Ok(p.clone());
        }
        let series = &self.inner;
        let (step, warnings) = py
            .detach(|| series.load_step(index, previous.as_ref()))
            .map_err(|e| session_err(e.to_string()))?;
        warn_all(py, warnings.iter().map(|w| w.to_string()))?;
        if let Ok(mut last) = self.last.lock() {
            *last = Some(step.clone());
        }
        Ok(step)
    }

    /// Each field's range over all steps (computed once: every step is loaded).
    pub(crate) fn ranges(&self, py: Python<'_>) -> PyResult<Arc<FieldRanges>> {
        if let Some(r) = self.ranges.lock().ok().and_then(|r| r.clone()) {
            return Ok(r);
        }
        let first = self.step(py, 0)?;
        let series = &self.inner;
        let ranges = Arc::new(
            py.detach(|| series.ranges(&first))
                .map_err(|e| session_err(e.to_string()))?,
        );
        if let Ok(mut slot) = self.ranges.lock() {
            *slot = Some(Arc::clone(&ranges));
        }
        Ok(ranges)
    }

    /// The step `step` (a number, negative from the end) or `time` (the nearest, the earlier
    /// on a tie) choose; step 0 without either.
    pub(crate) fn index(&self, step: Option<isize>, time: Option<f64>) -> PyResult<usize> {
        match (step, time) {
            (Some(_), Some(_)) => Err(PyValueError::new_err(
                "give step or time, not both (one step)",
            )),
            (Some(i), None) => self.checked(i),
            (None, Some(t)) if t.is_finite() => Ok(self.inner.nearest(t)),
            (None, Some(t)) => Err(PyValueError::new_err(format!(
                "time: {t} is not a finite number"
            ))),
            (None, None) => Ok(0),
        }
    }

    /// A step number, negative ones counted from the end as Python counts.
    fn checked(&self, i: isize) -> PyResult<usize> {
        let n = self.inner.len();
        let k = if i < 0 { i + n as isize } else { i };
        usize::try_from(k).ok().filter(|&k| k < n).ok_or_else(|| {
            PyIndexError::new_err(format!(
                "step {i} is out of range: {} has {}",
                self.inner.source,
                self.inner.range_text()
            ))
        })
    }
}

#[pymethods]
impl PySeries {
    /// Series.read(path): a `.pvd` or `.series` time series, an Exodus II (`.e`, `.exo`), XDMF
    /// (`.xdmf`) or VTKHDF (`.vtkhdf`) file with its time steps, or a `.pvtu` / `.vtm` (one
    /// step of merged pieces or blocks). The file names inside are relative to the collection; a
    /// missing one is an OSError naming the collection's line. Steps are loaded when indexed.
    #[staticmethod]
    fn read(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let series = py
            .detach(|| Series::read(&path))
            .map_err(|e| session_err(e.to_string()))?;
        Ok(PySeries {
            inner: Arc::new(series),
            last: Mutex::new(None),
            ranges: Mutex::new(None),
        })
    }

    /// The steps' times, in order.
    #[getter]
    fn times(&self) -> Vec<f64> {
        self.inner.times()
    }

    /// The collection file.
    #[getter]
    fn source(&self) -> String {
        self.inner.source.clone()
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    /// series[i]: step i as a Volume (negative i from the end), loaded now; a step with the
    /// points and cells of the step loaded before it shares that step's mesh.
    fn __getitem__(&self, py: Python<'_>, i: isize) -> PyResult<PyVolume> {
        let index = self.checked(i)?;
        Ok(PyVolume {
            inner: self.step(py, index)?.volume,
        })
    }

    /// nearest(time) -> int: the step whose time is nearest (the earlier one on a tie).
    fn nearest(&self, time: f64) -> PyResult<usize> {
        self.index(None, Some(time))
    }

    /// range(field) -> (lo, hi): the range of a scalar field (a name or a number, as step 0
    /// numbers them) over all steps (every step is loaded the first time); ValueError for
    /// vector fields and unknown names.
    fn range(&self, py: Python<'_>, field: &Bound<'_, PyAny>) -> PyResult<(f64, f64)> {
        let first = self.step(py, 0)?;
        let i = crate::field_number(&first.volume, field)?;
        let ranges = self.ranges(py)?;
        match ranges.get(i).cloned().flatten().as_deref() {
            Some([(lo, hi)]) => Ok((*lo, *hi)),
            Some(r) => Err(PyValueError::new_err(format!(
                "field {i} has {} components: give a scalar field",
                r.len()
            ))),
            None => Err(PyValueError::new_err(format!(
                "no field {i} ({} fields)",
                first.volume.data.fields.len()
            ))),
        }
    }

    fn __repr__(&self) -> String {
        let (t0, t1) = self.inner.time_range();
        format!(
            "vorang.Series({}: {}, t = {} … {})",
            self.inner.source,
            self.inner.range_text(),
            vorang::info::num(t0),
            vorang::info::num(t1)
        )
    }
}
