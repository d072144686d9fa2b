//! Time steps: the session's collection ([`Series`]) and the step it shows.
//!
//! `volume FILE` on a collection (`.pvd`, `.pvtu`, `.vtm`, `.series`) loads step 0 and keeps
//! the series; `timestep` shows another step. Unlike `volume`, a new step keeps the whole
//! scene — camera, transforms, maps, method, image settings: only the data change, as in a
//! solver's output, so that an animation is a loop over the steps (docs/formats.md, "Time
//! series and collections"). A step with the same points and cells as the one shown is built on
//! its mesh (only its fields are new). A volume that is no collection counts as one step at
//! time 0.
//!
//! The label (`label "t = %.3g s"`) prints the shown step's time into every image
//! ([`crate::legend::label`]).

use std::path::Path;
use std::sync::Arc;

use super::{Notice, Session, fields, warnings};
use crate::formats::collection::{self, FieldRanges, Series, StepVolume};
use crate::info::num;
use crate::legend::label;

/// A collection and the step the session shows.
pub(super) struct Shown {
    pub(super) series: Arc<Series>,
    pub(super) step: StepVolume,
    /// Each field's range over all steps, where a front end has them (Python's `Series`): the
    /// preset maps then span them, so that a colour means the same value in every frame.
    pub(super) ranges: Option<Arc<FieldRanges>>,
}

impl Session {
    /// `volume COLLECTION`: step 0 of a collection, with `volume`'s resets; `None` where `path`
    /// is a single mesh file.
    pub(super) fn load_collection(
        &mut self,
        path: &Path,
    ) -> Result<Option<(String, Vec<Notice>)>, String> {
        let Some((series, first, w)) = collection::open(path).map_err(|e| e.to_string())? else {
            return Ok(None);
        };
        let vol = &first.volume;
        let (t0, t1) = series.time_range();
        let steps = series.len();
        let summary = format!(
            "{} nodes, {} tetrahedra, {}; {steps} time step{}, t = {} … {}",
            vol.mesh.node_count(),
            vol.mesh.tet_count(),
            fields(vol.data.fields.len()),
            if steps == 1 { "" } else { "s" },
            num(t0),
            num(t1)
        );
        let mut notices = warnings(w);
        notices.extend(self.set_step(Arc::new(series), first));
        Ok(Some((summary, notices)))
    }

    /// A collection and one of its loaded steps, with `volume`'s resets (Python's
    /// `render(series, step=…)`).
    pub fn set_step(&mut self, series: Arc<Series>, step: StepVolume) -> Option<Notice> {
        let notice = self.set_volume(Arc::clone(&step.volume));
        self.series = Some(Shown {
            series,
            step,
            ranges: None,
        });
        notice
    }

    /// The fields' ranges over all steps of the shown collection ([`Series::ranges`]): the
    /// preset maps ([`Session::use_preset_maps`]) span them instead of the shown step's.
    pub fn set_series_ranges(&mut self, ranges: Arc<FieldRanges>) {
        if let Some(shown) = &mut self.series {
            shown.ranges = Some(ranges);
        }
    }

    /// The range of field `i` per component: over all steps where the session has them,
    /// else the shown volume's.
    pub(super) fn range_of(
        &self,
        vol: &crate::volume::Volume,
        i: usize,
    ) -> Option<Vec<(f64, f64)>> {
        let ranges = self.ranked_ranges.as_ref();
        match ranges.or(self.series.as_ref().and_then(|s| s.ranges.as_ref())) {
            Some(ranges) => ranges.get(i).cloned().flatten(),
            None => vol.field_range(i),
        }
    }

    /// The collection the shown volume belongs to, if any.
    pub fn series(&self) -> Option<&Arc<Series>> {
        self.series.as_ref().map(|s| &s.series)
    }

    /// The shown step's number and time: `(0, 0.0)` for a volume that is no collection; `None`
    /// without a volume.
    pub fn timestep(&self) -> Option<(usize, f64)> {
        if let Some(shown) = self.ranked_step() {
            return Some(shown);
        }
        match &self.series {
            Some(s) => Some((s.step.index, s.series.steps[s.step.index].time)),
            None => self.volume.as_ref().map(|_| (0, 0.0)),
        }
    }

    /// Every step's time (`[0.0]` for a volume that is no collection, none without a volume).
    pub fn timesteps(&self) -> Vec<f64> {
        if let Some(series) = self.ranked_series() {
            return series.times();
        }
        match &self.series {
            Some(s) => s.series.times(),
            None => self.volume.iter().map(|_| 0.0).collect(),
        }
    }

    /// The number of the step nearest time `t` (the earlier one on a tie).
    pub fn nearest_timestep(&self, t: f64) -> Result<usize, String> {
        self.need_volume("timestep")?;
        if !t.is_finite() {
            return Err(format!("timestep: the time {t} is not a finite number"));
        }
        if let Some(series) = self.ranked_series() {
            return Ok(series.nearest(t));
        }
        Ok(self.series.as_ref().map_or(0, |s| s.series.nearest(t)))
    }

    /// The number of the last step.
    pub fn last_timestep(&self) -> Result<usize, String> {
        self.need_volume("timestep")?;
        if let Some(series) = self.ranked_series() {
            return Ok(series.len() - 1);
        }
        Ok(self.series.as_ref().map_or(0, |s| s.series.len() - 1))
    }

    /// `timestep N`: shows step `index`; camera, transforms, maps, method and image settings
    /// stay. The maps and grid lines are checked against the step's fields: on an error the
    /// shown step stays.
    pub fn set_timestep(&mut self, index: usize) -> Result<Vec<Notice>, String> {
        self.need_volume("timestep")?;
        if let Some(shown) = self.show_ranked_step(index) {
            return shown;
        }
        self.whole_volume_only("timestep")?;
        let Some(shown) = &self.series else {
            return match index {
                0 => Ok(Vec::new()),
                _ => Err(format!(
                    "timestep: step {index} is out of range: the volume is one step (0 … 0); load a collection (.pvd, .series) or a file with time steps (Exodus II, XDMF, VTKHDF) for more"
                )),
            };
        };
        if index >= shown.series.len() {
            return Err(format!(
                "timestep: step {index} is out of range: {} has {}",
                super::display_path(Path::new(&shown.series.source)),
                shown.series.range_text()
            ));
        }
        if index == shown.step.index {
            return Ok(Vec::new());
        }
        let (step, w) = shown
            .series
            .load_step(index, Some(&shown.step))
            .map_err(|e| format!("timestep: {e}"))?;
        let mut notices = warnings(w);
        notices.extend(self.show_step(step)?);
        Ok(notices)
    }

    /// Shows a step of the shown collection loaded elsewhere (Python's `Series` loads its
    /// steps itself), as `timestep` would: the scene stays; the maps and grid lines are checked
    /// against the step's fields, and on an error the shown step stays.
    pub fn show_step(&mut self, step: StepVolume) -> Result<Vec<Notice>, String> {
        let index = step.index;
        let Some(shown) = &self.series else {
            return Err(format!(
                "timestep {index}: the volume is no collection's step"
            ));
        };
        if index >= shown.series.len() {
            return Err(format!(
                "timestep: step {index} is out of range: {} has {}",
                super::display_path(Path::new(&shown.series.source)),
                shown.series.range_text()
            ));
        }
        crate::mapping::Mapping::new(&self.colormap, &self.alphamap, &step.volume)
            .map_err(|e| e.to_string())
            .and_then(|_| self.check_lines(&step))
            .map_err(|e| format!("timestep {index}: {e}"))?;
        self.volume = Some(Arc::clone(&step.volume));
        if let Some(shown) = &mut self.series {
            shown.step = step;
        }
        Ok(Vec::new())
    }

    /// `label FORMAT` (`Some`) or `label off` (`None`): the shown step's time in every image.
    pub fn set_label(&mut self, format: Option<String>) -> Result<(), String> {
        if let Some(f) = &format {
            label::format(f, 0.0, 0).map_err(|e| format!("label: {e}"))?;
        }
        self.label = format;
        Ok(())
    }

    /// The label's format, if one is set.
    pub fn label(&self) -> Option<&str> {
        self.label.as_deref()
    }

    /// The label's text for the shown step.
    pub(super) fn label_text(&self) -> Option<String> {
        let format = self.label.as_ref()?;
        let (index, time) = self.timestep().unwrap_or((0, 0.0));
        label::format(format, time, index).ok()
    }

    fn check_lines(&self, step: &StepVolume) -> Result<(), String> {
        if let crate::render::LineDraw::Cells { .. } = &self.settings.lines {
            crate::render::lines::edges(&step.volume, &self.settings.lines)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }
}
