//! `render` and `animate`: a fresh [`Session`] with the data (a `Volume`, or a step of a
//! `Series`) and the scene from the keywords ([`Scene`]), then one frame into an array, or one
//! frame per step into a movie (the core's movie code: `.gif`, `.apng`, and `.mp4`, `.webm`,
//! `.mkv`, `.mov` through ffmpeg).

use std::path::PathBuf;
use std::sync::Arc;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use vorang::render::Order;
use vorang::session::{Image, Notice, Session};

use crate::scene::{Scene, Vec3, render_interruptible, session_err};
use crate::series::PySeries;
use crate::{PyVolume, warn_all};

/// Puts `data` into the session: a `Volume`, or the step of a `Series` that `step` or `time`
/// choose (with the fields' ranges over all steps where the preset maps will span them).
fn set_data(
    py: Python<'_>,
    session: &mut Session,
    data: &Bound<'_, PyAny>,
    (step, time): (Option<isize>, Option<f64>),
    preset: bool,
) -> PyResult<()> {
    if let Ok(vol) = data.cast::<PyVolume>() {
        if step.is_some() || time.is_some() {
            return Err(PyValueError::new_err(
                "step and time choose a step of a vorang.Series; this is a Volume",
            ));
        }
        session.set_volume(Arc::clone(&vol.get().inner));
        return Ok(());
    }
    let series = data.cast::<PySeries>().map_err(|_| {
        PyValueError::new_err(format!(
            "expected a vorang.Volume or a vorang.Series, found {}",
            data.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    })?;
    let series = series.get();
    let index = series.index(step, time)?;
    let shown = series.step(py, index)?;
    session.set_step(Arc::clone(&series.inner), shown);
    if preset {
        session.set_series_ranges(series.ranges(py)?);
    }
    Ok(())
}

/// Renders the session's frame (to the open movie with `to_movie`), its notices added to
/// `notices`.
fn frame(
    py: Python<'_>,
    session: &mut Session,
    progress: Option<Bound<'_, PyAny>>,
    to_movie: bool,
    notices: &mut Vec<Notice>,
) -> PyResult<Option<Image>> {
    let command = if to_movie { "animate" } else { "render" };
    let mut prepared = session
        .prepare(command, Order::BackToFront, to_movie)
        .map_err(session_err)?;
    notices.extend(prepared.take_notices());
    let started = std::time::Instant::now();
    let result = render_interruptible(py, &prepared, progress)?;
    let seconds = started.elapsed().as_secs_f64();
    let mut image = session
        .finish_image(&mut prepared, result, seconds)
        .map_err(session_err)?;
    notices.append(&mut image.notices);
    if !to_movie {
        return Ok(Some(image));
    }
    session.finish_frame(prepared, image).map_err(session_err)?;
    Ok(None)
}

/// Shows each notice once, in order (an animation's frames repeat theirs).
fn warn_once(py: Python<'_>, notices: &[Notice]) -> PyResult<()> {
    let mut seen = std::collections::HashSet::new();
    warn_all(
        py,
        notices
            .iter()
            .map(|n| n.text().to_string())
            .filter(|t| seen.insert(t.clone())),
    )
}

/// render(volume, *, size=(512, 512), colormap=None, alphamap=None, method="exact linear 0",
/// persp=None, ortho=None, look_at=None, rotate=(), scale=None, translate=None,
/// background="white", linedraw="off", lights=(), view_all=True, zoom=1.0, legend=None,
/// brightness=None, label=None, step=None, time=None, progress=None, backend="cpu")
///
/// Renders back to front and returns a float32 array of shape (h, w, 4), first row at the top:
/// RGB exactly as the PFM output of the equivalent script holds it, plus alpha (the volume's
/// opacity 1 − T). `volume` is a Volume or a Series (`step`: its number, `time`: the nearest
/// step; default step 0). The volume transforms are applied as the script commands
/// `vol_scale`, `vol_rotate` (each of `rotate`, in order), `vol_translate` given in that order.
/// `lights` are `(r, g, b, dx, dy, dz)` tuples, each an `addlight` (they shade `LIT_EMITTER`
/// colormaps; none: one white light at the camera). `label`: the step's time printed into the
/// image (`label "t = %.3g s"`). `backend`: "cpu" or "gpu" (`backend gpu`).
#[pyfunction]
#[pyo3(signature = (volume, *, size=(512, 512), colormap=None, alphamap=None, method="exact linear 0", persp=None, ortho=None, look_at=None, rotate=Vec::new(), scale=None, translate=None, background=None, linedraw="off", lights=Vec::new(), view_all=true, zoom=1.0, legend=None, brightness=None, label=None, step=None, time=None, progress=None, backend="cpu"))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn render<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    size: (usize, usize),
    colormap: Option<Bound<'py, PyAny>>,
    alphamap: Option<Bound<'py, PyAny>>,
    method: &str,
    persp: Option<[f64; 4]>,
    ortho: Option<[f64; 6]>,
    look_at: Option<(Vec3, Vec3, Vec3)>,
    rotate: Vec<[f64; 4]>,
    scale: Option<Vec3>,
    translate: Option<Vec3>,
    background: Option<Bound<'py, PyAny>>,
    linedraw: &str,
    lights: Vec<[f64; 6]>,
    view_all: bool,
    zoom: f64,
    legend: Option<String>,
    brightness: Option<f64>,
    label: Option<String>,
    step: Option<isize>,
    time: Option<f64>,
    progress: Option<Bound<'py, PyAny>>,
    backend: &str,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let scene = Scene {
        size,
        colormap,
        alphamap,
        method: method.to_string(),
        persp,
        ortho,
        look_at,
        rotate,
        scale,
        translate,
        background,
        linedraw: linedraw.to_string(),
        lights,
        view_all,
        zoom,
        legend,
        brightness,
        label,
    };
    // The session every front end uses: same setters, same defaults, same checks and messages
    // as the script commands.
    let mut session = Session::new();
    // `backend="gpu"`: the GPU renders (an error naming what is missing, never the CPU instead).
    session.set_backend(backend).map_err(session_err)?;
    set_data(py, &mut session, volume, (step, time), scene.uses_preset()?)?;
    let mut notices = scene.apply(&mut session)?;
    let image = frame(py, &mut session, progress, false, &mut notices)?
        .ok_or_else(|| PyRuntimeError::new_err("render: no image"))?;
    warn_once(py, &notices)?;
    let fb = image.framebuffer;
    let (w, h) = (fb.width, fb.height);
    let flat: Vec<f32> = fb.pixels.into_iter().flatten().collect();
    let arr = Array3::from_shape_vec((h, w, 4), flat)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(arr.into_pyarray(py))
}

/// animate(series, path, *, fps=10.0, label=None, progress=None, **render's keywords) -> str
///
/// Renders every step of `series` into the movie `path` (by extension: .gif, .apng or .png,
/// and .mp4, .webm, .mkv, .mov through the ffmpeg program) with one scene: the maps (default:
/// the preset over each field's range over all steps), camera (framed on step 0), transforms
/// and settings stay from frame to frame, as after the script's `timestep`. `label` prints
/// each step's time into its frame (`"t = %.3g s"`). `progress(done, total)` is called after
/// each frame (or a tqdm-like object's update(1)). Returns the movie's path.
#[pyfunction]
#[pyo3(signature = (series, path, *, fps=10.0, size=(512, 512), colormap=None, alphamap=None, method="exact linear 0", persp=None, ortho=None, look_at=None, rotate=Vec::new(), scale=None, translate=None, background=None, linedraw="off", lights=Vec::new(), view_all=true, zoom=1.0, legend=None, brightness=None, label=None, progress=None, backend="cpu"))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn animate<'py>(
    py: Python<'py>,
    series: &Bound<'py, PySeries>,
    path: PathBuf,
    fps: f64,
    size: (usize, usize),
    colormap: Option<Bound<'py, PyAny>>,
    alphamap: Option<Bound<'py, PyAny>>,
    method: &str,
    persp: Option<[f64; 4]>,
    ortho: Option<[f64; 6]>,
    look_at: Option<(Vec3, Vec3, Vec3)>,
    rotate: Vec<[f64; 4]>,
    scale: Option<Vec3>,
    translate: Option<Vec3>,
    background: Option<Bound<'py, PyAny>>,
    linedraw: &str,
    lights: Vec<[f64; 6]>,
    view_all: bool,
    zoom: f64,
    legend: Option<String>,
    brightness: Option<f64>,
    label: Option<String>,
    progress: Option<Bound<'py, PyAny>>,
    backend: &str,
) -> PyResult<String> {
    let scene = Scene {
        size,
        colormap,
        alphamap,
        method: method.to_string(),
        persp,
        ortho,
        look_at,
        rotate,
        scale,
        translate,
        background,
        linedraw: linedraw.to_string(),
        lights,
        view_all,
        zoom,
        legend,
        brightness,
        label,
    };
    let mut session = Session::new();
    // `backend="gpu"`: the GPU renders (an error naming what is missing, never the CPU instead).
    session.set_backend(backend).map_err(session_err)?;
    set_data(
        py,
        &mut session,
        series.as_any(),
        (None, None),
        scene.uses_preset()?,
    )?;
    let mut notices = scene.apply(&mut session)?;
    notices.extend(session.open_movie(&path, fps).map_err(session_err)?);
    let steps = series.get().inner.len();
    let frames = (0..steps).try_for_each(|i| {
        if i > 0 {
            let step = series.get().step(py, i)?;
            notices.extend(session.show_step(step).map_err(session_err)?);
        }
        frame(py, &mut session, None, true, &mut notices)?;
        report_frame(progress.as_ref(), i + 1, steps)
    });
    if let Err(e) = frames {
        session.discard_movie();
        return Err(e);
    }
    let written = session.close_movie().map_err(session_err)?;
    warn_once(py, &notices)?;
    let (written, _) = written.ok_or_else(|| PyRuntimeError::new_err("animate: no movie"))?;
    Ok(written.display().to_string())
}

/// `progress(done, total)` after a frame, or a tqdm-like object's `total` and `update(1)`.
fn report_frame(progress: Option<&Bound<'_, PyAny>>, done: usize, total: usize) -> PyResult<()> {
    let Some(p) = progress else {
        return Ok(());
    };
    if p.hasattr("update")? {
        if done == 1 {
            // A bar without a total still counts; only the total's display is lost.
            let _ = p.setattr("total", total);
        }
        p.call_method1("update", (1,))?;
    } else {
        p.call1((done, total))?;
    }
    Ok(())
}
