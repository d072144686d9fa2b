//! A scene from Python's keywords: the maps, camera, transforms, method and image settings that
//! `render` and `animate` take, set on a [`Session`] with the same setters (and so the same
//! checks and messages) as the script commands — no script text is written or run
//! (docs/architecture.md, "Front ends are thin") — and the render itself, on a worker thread
//! while Python waits without the interpreter lock.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyString;

use vorang::framebuffer::{Background, Framebuffer};
use vorang::mapping::{AlphaMap, AlphaShading, ColorMap, ColorShading, parse_map, read_map};
use vorang::render::{LineDraw, Method};
use vorang::scene::{Camera, Light, LookAt, TransformOp};
use vorang::session::{Hooks, Notice, Prepared, Session};

use crate::py_err;

/// A map argument: None (the script's default), a path, map text ("# VoRANG …") or an object
/// with a `text` attribute (vorang.Colormap / vorang.Alphamap).
enum MapArg {
    Default,
    Path(PathBuf),
    Text(String),
}

fn map_arg(obj: Option<&Bound<'_, PyAny>>, what: &str) -> PyResult<MapArg> {
    let Some(obj) = obj else {
        return Ok(MapArg::Default);
    };
    if obj.is_none() {
        return Ok(MapArg::Default);
    }
    if let Ok(s) = obj.cast::<PyString>() {
        let s = s.to_string();
        let t = s.trim_start_matches('\u{feff}').trim_start();
        if t.starts_with("# VoRANG") || t.starts_with("#VoRANG") {
            return Ok(MapArg::Text(s));
        }
        return Ok(MapArg::Path(PathBuf::from(s)));
    }
    if let Ok(text) = obj.getattr("text") {
        return Ok(MapArg::Text(text.extract()?));
    }
    if let Ok(p) = obj.extract::<PathBuf>() {
        return Ok(MapArg::Path(p));
    }
    Err(PyValueError::new_err(format!(
        "{what}: expected a map file path, a map text ('# VoRANG …') or a vorang map object, found {}",
        obj.get_type().name()?
    )))
}

/// A map with the warnings of reading it (`None`: the session keeps its default).
type MapRead<T> = Option<(T, Vec<vorang::Warning>)>;

fn load_color(arg: MapArg) -> PyResult<MapRead<ColorMap>> {
    match arg {
        MapArg::Default => Ok(None),
        MapArg::Path(p) => read_map::<dyn ColorShading>(&p).map(Some).map_err(py_err),
        MapArg::Text(t) => parse_map::<dyn ColorShading>(t.as_bytes(), "<colormap>")
            .map(Some)
            .map_err(|e| PyValueError::new_err(e.to_string())),
    }
}

fn load_alpha(arg: MapArg) -> PyResult<MapRead<AlphaMap>> {
    match arg {
        MapArg::Default => Ok(None),
        MapArg::Path(p) => read_map::<dyn AlphaShading>(&p).map(Some).map_err(py_err),
        MapArg::Text(t) => parse_map::<dyn AlphaShading>(t.as_bytes(), "<alphamap>")
            .map(Some)
            .map_err(|e| PyValueError::new_err(e.to_string())),
    }
}

fn is_none(obj: Option<&Bound<'_, PyAny>>) -> bool {
    obj.is_none_or(|o| o.is_none())
}

/// A colormap argument that names a built-in preset (`"viridis"`, `"magma"`, …) rather than a
/// file or map text.
fn preset_name(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<String>> {
    let Some(s) = obj.and_then(|o| o.cast::<PyString>().ok()) else {
        return Ok(None);
    };
    let s = s.to_string();
    let known = vorang::mapping::PRESETS.iter().any(|p| p.name == s);
    Ok((known && !Path::new(&s).exists()).then_some(s))
}

/// The method string, its last parameter (brightness, or `test`'s opacity) optional in Python:
/// `"exact linear 0"` renders at `brightness` (the preset's χ_max when the preset maps are in
/// use, so that opaque parts show its colours; else 1), `"test"` at opacity 0.5.
fn parse_method(method: &str, brightness: f64) -> PyResult<Method> {
    let mut words: Vec<String> = method.split_whitespace().map(str::to_string).collect();
    let Some(name) = words.first() else {
        return Err(PyValueError::new_err("method: empty method string"));
    };
    let name = match name.as_str() {
        "interpolCoeff" => "interpolateCoeff",
        "interpolColor" => "interpolateColor",
        other => other,
    };
    if let Some(info) = vorang::render::approx::METHODS
        .iter()
        .find(|m| m.name == name)
    {
        let params: Vec<&str> = info.usage.split_whitespace().collect();
        if words.len() == params.len() {
            words.push(match params.last() {
                Some(&"opacity") => "0.5".to_string(),
                _ => format!("{brightness:?}"),
            });
        }
    }
    let words: Vec<&str> = words.iter().map(String::as_str).collect();
    Method::parse(&words).map_err(|e| session_err(format!("method: {e}")))
}

/// A session's error message as the Python exception a user expects: a missing file is an
/// `OSError`, everything else a `ValueError`.
pub(crate) fn session_err(message: String) -> PyErr {
    if message.contains("No such file") || message.contains("no such file") {
        PyOSError::new_err(message)
    } else {
        PyValueError::new_err(message)
    }
}

/// `linedraw="on" | "off" | "FIELD {v1 v2 …}"` (commas separate values too, as the thesis
/// writes them), as the `linedraw` command reads it.
fn parse_linedraw(text: &str) -> PyResult<LineDraw> {
    let words: Vec<&str> = text.split_whitespace().collect();
    match words.as_slice() {
        ["on"] => Ok(LineDraw::All),
        ["off"] => Ok(LineDraw::Off),
        [field, rest @ ..] if !rest.is_empty() => {
            let field: usize = field.parse().map_err(|_| {
                PyValueError::new_err(format!(
                    "linedraw: expected a whole number ≥ 0 for \"field\" but got \"{field}\""
                ))
            })?;
            let values = rest
                .join(" ")
                .split(|c: char| c.is_whitespace() || matches!(c, ',' | '{' | '}'))
                .filter(|v| !v.is_empty())
                .map(|v| {
                    vorang::numbers::parse_f64(v).ok_or_else(|| {
                        PyValueError::new_err(format!(
                            "linedraw: expected numbers in the value list, found \"{v}\""
                        ))
                    })
                })
                .collect::<PyResult<Vec<f64>>>()?;
            Ok(LineDraw::Cells { field, values })
        }
        _ => Err(PyValueError::new_err(
            "wrong # args: should be \"linedraw on|off|field {values}\"",
        )),
    }
}

/// The background argument: "white"/"clear", "none"/"transparent", an (r, g, b) tuple or an
/// image path.
fn set_background(session: &mut Session, b: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
    let Some(b) = b.filter(|b| !b.is_none()) else {
        return Ok(());
    };
    if let Ok(s) = b.cast::<PyString>() {
        let s = s.to_string();
        return match s.as_str() {
            "white" | "clear" => session.set_background(Background::default()),
            "none" | "transparent" => session.set_background(Background::None),
            path => session.load_background(Path::new(path)),
        }
        .map_err(session_err);
    }
    if let Ok(rgb) = b.extract::<Vec3>() {
        return session
            .set_background(Background::Color(rgb))
            .map_err(session_err);
    }
    if let Ok(p) = b.extract::<PathBuf>() {
        return session.load_background(&p).map_err(session_err);
    }
    Err(PyValueError::new_err(
        "background: expected \"white\", \"clear\", \"none\", an (r, g, b) tuple or an image path",
    ))
}

pub(crate) type Vec3 = [f64; 3];

/// Everything `render` and `animate` set besides the volume, as their keywords give it.
pub(crate) struct Scene<'py> {
    pub size: (usize, usize),
    pub colormap: Option<Bound<'py, PyAny>>,
    pub alphamap: Option<Bound<'py, PyAny>>,
    pub method: String,
    pub persp: Option<[f64; 4]>,
    pub ortho: Option<[f64; 6]>,
    pub look_at: Option<(Vec3, Vec3, Vec3)>,
    pub rotate: Vec<[f64; 4]>,
    pub scale: Option<Vec3>,
    pub translate: Option<Vec3>,
    pub background: Option<Bound<'py, PyAny>>,
    pub linedraw: String,
    pub lights: Vec<[f64; 6]>,
    pub view_all: bool,
    pub zoom: f64,
    pub legend: Option<String>,
    pub brightness: Option<f64>,
    /// `label`: the time step's label format (`"t = %.3g s"`).
    pub label: Option<String>,
}

impl Scene<'_> {
    /// Whether the scene renders with the preset maps (no maps given, or a preset's name as
    /// the colormap).
    pub(crate) fn uses_preset(&self) -> PyResult<bool> {
        Ok(preset_name(self.colormap.as_ref())?.is_some()
            || (is_none(self.colormap.as_ref()) && is_none(self.alphamap.as_ref())))
    }

    /// Sets the scene on `session`, whose volume is set: the maps' warnings are returned.
    pub(crate) fn apply(&self, session: &mut Session) -> PyResult<Vec<Notice>> {
        if self.persp.is_some() && self.ortho.is_some() {
            return Err(PyValueError::new_err(
                "give persp or ortho, not both (one camera)",
            ));
        }
        session
            .set_image_size(self.size.0, self.size.1)
            .map_err(session_err)?;
        // No maps (or a preset's name as the colormap): the first picture `vorang info` suggests.
        let preset = preset_name(self.colormap.as_ref())?;
        let mut default_brightness = self.brightness.unwrap_or(1.0);
        if self.uses_preset()?
            && let Some((chi, _)) = session
                .use_preset_maps("render", preset.as_deref().unwrap_or("viridis"))
                .map_err(session_err)?
        {
            default_brightness = self.brightness.unwrap_or(chi);
        }
        session.set_method(parse_method(&self.method, default_brightness)?);
        if let Some(place) = &self.legend {
            session.set_legend(Some(vorang::legend::Place::parse(place).ok_or_else(
                || {
                    PyValueError::new_err(format!(
                        "legend: expected a position {}, found '{place}'",
                        vorang::legend::Place::NAMES.join(", ")
                    ))
                },
            )?));
        }
        session.set_label(self.label.clone()).map_err(session_err)?;
        self.apply_view(session)?;
        set_background(session, self.background.as_ref())?;
        session
            .set_lines(parse_linedraw(&self.linedraw)?)
            .map_err(session_err)?;
        for &[r, g, b, dx, dy, dz] in &self.lights {
            session
                .add_light(Light {
                    color: [r, g, b],
                    direction: [dx, dy, dz],
                })
                .map_err(session_err)?;
        }
        if self.view_all && self.persp.is_none() && self.ortho.is_none() {
            session.view_all().map_err(session_err)?;
        }
        if self.zoom != 1.0 {
            session.zoom(self.zoom).map_err(session_err)?;
        }
        let mut notices = Vec::new();
        let colormap = if preset.is_some() {
            None
        } else {
            self.colormap.as_ref()
        };
        if let Some((map, w)) = load_color(map_arg(colormap, "colormap")?)? {
            session.set_colormap(map).map_err(session_err)?;
            notices.extend(w.iter().map(|w| Notice::Warning(w.to_string())));
        }
        if let Some((map, w)) = load_alpha(map_arg(self.alphamap.as_ref(), "alphamap")?)? {
            session.set_alphamap(map).map_err(session_err)?;
            notices.extend(w.iter().map(|w| Notice::Warning(w.to_string())));
        }
        Ok(notices)
    }

    /// The camera, `look_at` and the volume transforms (`vol_scale`, each `vol_rotate`,
    /// `vol_translate`, in that order).
    fn apply_view(&self, session: &mut Session) -> PyResult<()> {
        if let Some([fovy, aspect, near, far]) = self.persp {
            session
                .set_camera(Camera::Persp {
                    fovy,
                    aspect,
                    near,
                    far,
                })
                .map_err(session_err)?;
        }
        if let Some([left, right, bottom, top, front, back]) = self.ortho {
            session
                .set_camera(Camera::Ortho {
                    left,
                    right,
                    bottom,
                    top,
                    front,
                    back,
                })
                .map_err(session_err)?;
        }
        if let Some((eye, reference, up)) = self.look_at {
            session.set_look_at(LookAt { eye, reference, up });
        }
        let mut ops: Vec<TransformOp> = self.scale.map(TransformOp::Scale).into_iter().collect();
        ops.extend(
            self.rotate
                .iter()
                .map(|&[x, y, z, degrees]| TransformOp::Rotate {
                    axis: [x, y, z],
                    degrees,
                }),
        );
        ops.extend(self.translate.map(TransformOp::Translate));
        for op in ops {
            session.transform(op).map_err(session_err)?;
        }
        Ok(())
    }
}

/// Why a render stopped early (carried by an unwind out of the progress callback).
struct Stop;

/// Renders on a worker thread while this (the main) thread waits without the GIL, checking
/// for signals every 20 ms: Ctrl-C (KeyboardInterrupt) or an exception of the progress
/// callback sets the render's cancel flag (tiles not yet started are skipped) and the
/// exception is raised here.
/// `progress` is called as progress(done, total), or, for a tqdm-like object (one with
/// `update`), as `total` set once and update(n) per finished tile.
pub(crate) fn render_interruptible(
    py: Python<'_>,
    prepared: &Prepared,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Result<(Framebuffer, vorang::render::Stats), vorang::Error>> {
    use std::sync::atomic::{AtomicBool, Ordering};
    let stop = AtomicBool::new(false);
    let error: Mutex<Option<PyErr>> = Mutex::new(None);
    let tqdm = progress
        .as_ref()
        .is_some_and(|p| p.hasattr("update").unwrap_or(false));
    let progress: Option<Py<PyAny>> = progress.map(Bound::unbind);
    let started_total = AtomicBool::new(false);
    let callback = |done: usize, total: usize| {
        if let Some(p) = &progress {
            Python::attach(|py| {
                let p = p.bind(py);
                let r = if tqdm {
                    let first = !started_total.swap(true, Ordering::Relaxed);
                    let set = if first {
                        p.setattr("total", total)
                            .and_then(|_| p.call_method0("refresh").map(|_| ()))
                            .or(Ok::<(), PyErr>(()))
                    } else {
                        Ok(())
                    };
                    set.and_then(|_| p.call_method1("update", (1,)).map(|_| ()))
                } else {
                    p.call1((done, total)).map(|_| ())
                };
                if let Err(e) = r {
                    if let Ok(mut slot) = error.lock() {
                        slot.get_or_insert(e);
                    }
                    stop.store(true, Ordering::Relaxed);
                }
            });
        }
        if stop.load(Ordering::Relaxed) {
            std::panic::resume_unwind(Box::new(Stop));
        }
    };
    let result = py.detach(|| {
        std::thread::scope(|scope| {
            let worker = scope.spawn(|| {
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    prepared.render(&Hooks {
                        progress: Some(&callback),
                        tile: None,
                        cancel: &stop,
                    })
                }))
            });
            while !worker.is_finished() {
                std::thread::sleep(std::time::Duration::from_millis(20));
                let checked = Python::attach(|py| py.check_signals());
                if let Err(e) = checked {
                    if let Ok(mut slot) = error.lock() {
                        slot.get_or_insert(e);
                    }
                    stop.store(true, Ordering::Relaxed);
                }
            }
            worker.join()
        })
    });
    if let Some(e) = error.lock().ok().and_then(|mut slot| slot.take()) {
        return Err(e);
    }
    match result {
        Ok(Ok(r)) => Ok(r),
        Ok(Err(payload)) | Err(payload) => {
            if payload.is::<Stop>() {
                Err(PyRuntimeError::new_err("the render was stopped"))
            } else {
                std::panic::resume_unwind(payload)
            }
        }
    }
}
