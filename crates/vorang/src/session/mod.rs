//! The session: one typed scene and the step that renders it — the layer below every front end.
//!
//! The thesis's script commands (thesis 4.2, appendix A.1) edit a scene — the volume, the colour
//! and alpha maps, the camera and transforms, the method, the image settings, lights, legend and
//! the numbering of the images — and `render_btf`/`render_ftb` turn it into a numbered image.
//! [`Session`] is that scene as typed state with setters that validate (the names follow the
//! commands), and [`Session::render_frame`] is the one step from scene to file: bind the maps →
//! render → legend → the messages → the numbered file or the movie's next frame.
//!
//! Every front end is a thin caller: the Tcl commands parse their words and call a setter, the
//! Python module and the viewer call the setters directly, and [`Session::script`] prints the
//! scene back as script commands (the viewer's `p`). The session prints nothing: what it has to
//! say comes back as [`Notice`]s, which each front end shows in its own idiom (standard error,
//! Python's `warnings`), so every front end shows the same texts.
//!
//! ```
//! use std::sync::Arc;
//! use std::sync::atomic::AtomicBool;
//! use vorang::render::{Method, Order};
//! use vorang::session::{Hooks, Session};
//!
//! let mut session = Session::new();
//! session.set_volume(Arc::new(vorang::volume::jittered_box(48, 0.0, 1)));
//! session.set_image_size(32, 24).unwrap();
//! session.set_method(Method::parse(&["exact", "linear", "0", "1"]).unwrap());
//! session.view_all().unwrap();
//! let cancel = AtomicBool::new(false);
//! let hooks = Hooks { progress: None, tile: None, cancel: &cancel };
//! let image = session.render_image(Order::BackToFront, &hooks).unwrap();
//! assert_eq!((image.framebuffer.width, image.framebuffer.height), (32, 24));
//! // The default maps are in use and the method is not the default: nothing to warn about.
//! assert!(image.notices.is_empty(), "{:?}", image.notices);
//! ```

mod frame;
mod ranks;
mod script;
mod series;

pub use script::{commands_for, method_command};

use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use frame::{Frame, Hooks, Image, Prepared, timing_line};
pub use ranks::Ranks;

use crate::formats::hypermesh::{self, Encoding, WriteOptions};
use crate::framebuffer::{Background, BackgroundImage, format_for};
use crate::legend::Place;
use crate::mapping::{AlphaMap, ColorMap, Mapping};
use crate::movie::{Movie, MovieFormat};
use crate::render::{LineDraw, Method, Settings};
use crate::scene::{Camera, Light, LookAt, TransformOp, View};
use crate::volume::Volume;

/// Something the session has to tell the user: a warning (a default or an input that may defeat
/// what the user asked for) or a note (what happened, e.g. cells ordered per pixel).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Notice {
    Warning(String),
    Note(String),
}

impl Notice {
    pub fn text(&self) -> &str {
        match self {
            Notice::Warning(t) | Notice::Note(t) => t,
        }
    }
}

/// Warnings of the core (file readers, map binding) as notices.
fn warnings(list: impl IntoIterator<Item = crate::Warning>) -> Vec<Notice> {
    list.into_iter()
        .map(|w| Notice::Warning(w.to_string()))
        .collect()
}

/// The GPU backend: the one already open, or a newly opened device.
#[cfg(feature = "gpu")]
fn open_gpu(current: &Backend) -> Result<Backend, String> {
    if let Backend::Gpu(g) = current {
        return Ok(Backend::Gpu(g.clone()));
    }
    crate::gpu::Gpu::open()
        .map(|g| Backend::Gpu(Arc::new(g)))
        .map_err(|e| format!("backend gpu: {e}"))
}

#[cfg(not(feature = "gpu"))]
fn open_gpu(_: &Backend) -> Result<Backend, String> {
    Err("backend gpu: this vorang was built without the GPU backend (build it with 'cargo build --release --features gpu')".into())
}

/// A path for messages: relative to the current folder when it lies inside it.
pub fn display_path(path: &Path) -> String {
    if path.is_absolute()
        && let Ok(cwd) = std::env::current_dir()
        && let Ok(rel) = path.strip_prefix(&cwd)
    {
        return rel.display().to_string();
    }
    path.display().to_string()
}

/// "a", "a and b", "a, b and c".
fn and_list(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => one.to_string(),
        [head @ .., last] => format!("{} and {last}", head.join(", ")),
    }
}

/// "1 field", "2 fields".
fn fields(n: usize) -> String {
    format!("{n} field{}", if n == 1 { "" } else { "s" })
}

/// The scene the commands edit, and the numbering of the images it renders.
pub struct Session {
    volume: Option<Arc<Volume>>,
    colormap: ColorMap,
    alphamap: AlphaMap,
    view: View,
    /// Image size, method, grid lines, background, lights (the compositing order is chosen per
    /// frame).
    settings: Settings,
    /// `output base.fmt`: the numbered images' base name and format.
    output: PathBuf,
    /// The number of the next image (the first is 1).
    next_number: u32,
    /// `legend on ?position?`: where the colour legend goes (none by default).
    legend: Option<Place>,
    /// `movie FILE`: while open, frames go to it instead of numbered images.
    movie: Option<Movie>,
    /// Files written, in order.
    written: Vec<PathBuf>,
    /// What the user set since the scene began, for the warnings about defaults that would
    /// silently defeat it: `set_nr` since the last image, the maps and the method since the
    /// last `volume`.
    number_set: bool,
    colormap_set: bool,
    alphamap_set: bool,
    method_set: bool,
    /// The default camera's distortion is pointed out once per session.
    aspect_hinted: bool,
    /// Who renders the frames: this process, virtual ranks, or this process as one rank.
    ranks: Ranks,
    /// Virtual ranks: every rank's piece, rank 0's first (also `volume`).
    pieces: Vec<Arc<Volume>>,
    /// A rank that does not write (not rank 0): the movie rank 0 writes, and its frames.
    movie_elsewhere: Option<(PathBuf, usize)>,
    /// The collection the volume is a step of (`volume` on a `.pvd`, `.pvtu`, `.vtm`,
    /// `.series`), with the step shown.
    series: Option<series::Shown>,
    /// A distributed session's time series whose steps are `.pvtu` grids: the steps, and the
    /// one the ranks show (each rank holds its share of it).
    ranked_steps: Option<(Arc<crate::formats::collection::Series>, usize)>,
    /// A distributed session's fields' data ranges over every rank's cells (the legend, the
    /// preset maps).
    ranked_ranges: Option<Arc<crate::formats::collection::FieldRanges>>,
    /// `label FORMAT`: the step's time printed into every image.
    label: Option<String>,
    /// `backend`: which renders the frames.
    backend: Backend,
}

/// Which renders a frame (`backend cpu|gpu`): the front ends never learn which.
#[derive(Debug, Clone, Default)]
pub enum Backend {
    #[default]
    Cpu,
    /// The GPU backend (feature `gpu`), opened once and shared.
    #[cfg(feature = "gpu")]
    Gpu(Arc<crate::gpu::Gpu>),
}

impl Backend {
    /// Renders one frame with this backend: on the GPU the whole frame at once (no tiles for
    /// `watch`, not cancelled midway), on the CPU through `watch`.
    pub fn render(
        &self,
        vol: &Arc<Volume>,
        mapping: &Mapping,
        view: &View,
        settings: &Settings,
        watch: &crate::render::Watch,
    ) -> Result<(crate::framebuffer::Framebuffer, crate::render::Stats), crate::error::Error> {
        #[cfg(feature = "gpu")]
        if let Backend::Gpu(g) = self {
            return g.render(vol, mapping, view, settings);
        }
        crate::render::render_watched(vol, mapping, view, settings, watch)
    }

    /// Whether frames go to the GPU.
    pub fn is_gpu(&self) -> bool {
        !matches!(self, Backend::Cpu)
    }

    /// `cpu` or `gpu <adapter>`.
    pub fn describe(&self) -> String {
        match self {
            Backend::Cpu => "cpu".into(),
            #[cfg(feature = "gpu")]
            Backend::Gpu(g) => format!("gpu {}", g.name()),
        }
    }
}

impl Default for Session {
    fn default() -> Self {
        Session::new()
    }
}

impl Session {
    /// The thesis's defaults (appendix A.1): no volume, red emission, absorption 2, the default
    /// camera, 512 × 512, `test 0.5`, grid lines on, white background, `vorang.tiff`.
    pub fn new() -> Session {
        Session {
            volume: None,
            colormap: ColorMap::default_map(),
            alphamap: AlphaMap::default_map(),
            view: View::default(),
            settings: Settings::default(),
            output: PathBuf::from("vorang.tiff"),
            next_number: 1,
            legend: None,
            movie: None,
            written: Vec::new(),
            number_set: false,
            colormap_set: false,
            alphamap_set: false,
            method_set: false,
            aspect_hinted: false,
            ranks: Ranks::One,
            pieces: Vec::new(),
            movie_elsewhere: None,
            series: None,
            ranked_steps: None,
            ranked_ranges: None,
            label: None,
            backend: Backend::Cpu,
        }
    }

    /// The backend that renders the frames.
    pub fn backend(&self) -> &Backend {
        &self.backend
    }

    /// `backend cpu|gpu`: switches the renderer. `gpu` opens the first Vulkan adapter with
    /// 64-bit floats (once per session) or says what is missing — never a silent fallback.
    /// Returns the backend's description (`cpu`, `gpu ADAPTER`).
    pub fn set_backend(&mut self, name: &str) -> Result<String, String> {
        match name {
            "cpu" => self.backend = Backend::Cpu,
            "gpu" => self.backend = open_gpu(&self.backend)?,
            other => {
                return Err(format!(
                    "backend: unknown backend '{other}': expected cpu or gpu"
                ));
            }
        }
        Ok(self.backend.describe())
    }

    pub fn volume(&self) -> Option<&Arc<Volume>> {
        self.volume.as_ref()
    }
    pub fn colormap(&self) -> &ColorMap {
        &self.colormap
    }
    pub fn alphamap(&self) -> &AlphaMap {
        &self.alphamap
    }
    pub fn view(&self) -> &View {
        &self.view
    }
    pub fn settings(&self) -> &Settings {
        &self.settings
    }
    pub fn output(&self) -> &Path {
        &self.output
    }
    pub fn next_number(&self) -> u32 {
        self.next_number
    }
    pub fn legend(&self) -> Option<Place> {
        self.legend
    }
    /// The open movie's file, if one is open.
    pub fn movie(&self) -> Option<&Path> {
        self.movie.as_ref().map(|m| m.path.as_path())
    }
    /// Files written by frames, saves and closed movies, in order.
    pub fn written(&self) -> &[PathBuf] {
        &self.written
    }

    /// The volume, or the error of a command that needs one.
    fn need_volume(&self, command: &str) -> Result<Arc<Volume>, String> {
        self.volume
            .clone()
            .ok_or_else(|| format!("{command}: no volume loaded: use 'volume file' first"))
    }

    // --- data (thesis A.1 „Angaben zu den Daten“) ---

    /// `volume FILE`: loads a grid with its data; maps, transforms and camera return to their
    /// defaults (thesis A.1). On an error the previous volume stays. Returns the summary
    /// ("N nodes, M tetrahedra, K fields"). A collection (`.pvd`, `.pvtu`, `.vtm`, `.series`)
    /// loads its step 0, and the summary adds its steps and their time range.
    pub fn load_volume(&mut self, path: &Path) -> Result<(String, Vec<Notice>), String> {
        if let Some(loaded) = self.load_share(path)? {
            return Ok(loaded);
        }
        if let Some(loaded) = self.load_collection(path)? {
            return Ok(loaded);
        }
        let (vol, w) = Volume::load(path).map_err(|e| e.to_string())?;
        let summary = format!(
            "{} nodes, {} tetrahedra, {}",
            vol.mesh.node_count(),
            vol.mesh.tet_count(),
            fields(vol.data.fields.len())
        );
        let mut notices = warnings(w);
        notices.extend(self.set_volume(Arc::new(vol)));
        Ok((summary, notices))
    }

    /// A volume built elsewhere (Python's arrays, a PyVista grid), with the same resets as
    /// [`Session::load_volume`]: a warning names the maps and camera set before that the new
    /// volume dropped (a thesis-era script sets them after `volume`; one that sets them before
    /// would silently lose them).
    pub fn set_volume(&mut self, vol: Arc<Volume>) -> Option<Notice> {
        let mut dropped = Vec::new();
        if self.colormap_set {
            dropped.push("colormap");
        }
        if self.alphamap_set {
            dropped.push("alphamap");
        }
        if self.view.camera.is_some() {
            dropped.push("camera");
        }
        if !self.view.transforms.is_empty() {
            dropped.push("vol_* transforms");
        }
        if self.view.look_at != View::default().look_at {
            dropped.push("look_at");
        }
        self.volume = Some(vol);
        self.pieces.clear();
        self.series = None;
        self.ranked_steps = None;
        self.ranked_ranges = None;
        self.colormap = ColorMap::default_map();
        self.alphamap = AlphaMap::default_map();
        self.view = View::default();
        self.colormap_set = false;
        self.alphamap_set = false;
        (!dropped.is_empty()).then(|| {
            Notice::Warning(format!(
                "volume: a new volume resets the {} set before it to the defaults (thesis A.1): set them after 'volume'",
                and_list(&dropped)
            ))
        })
    }

    /// `data ?+? FILE`: the fields of a data-only file onto the grid: replacing all fields (and
    /// resetting the maps) or, with `append`, adding them. On an error nothing changes.
    pub fn load_data(
        &mut self,
        path: &Path,
        append: bool,
    ) -> Result<(String, Vec<Notice>), String> {
        self.whole_volume_only("data")?;
        let vol = self.need_volume("data")?;
        let (next, w) = crate::formats::load_data(&vol, path, append).map_err(|e| e.to_string())?;
        let n = next.data.fields.len();
        self.volume = Some(Arc::new(next));
        if !append {
            self.colormap = ColorMap::default_map();
            self.alphamap = AlphaMap::default_map();
            self.colormap_set = false;
            self.alphamap_set = false;
        }
        Ok((fields(n), warnings(w)))
    }

    /// `save_volume FILE ?binary|ascii? ?small?`: the volume in the format of the file's
    /// extension; `opts` given explicitly (`explicit`) only apply to HyperMesh.
    pub fn save_volume(
        &self,
        path: &Path,
        opts: WriteOptions,
        explicit: bool,
    ) -> Result<Vec<Notice>, String> {
        self.whole_volume_only("save_volume")?;
        let vol = self
            .volume
            .as_ref()
            .ok_or("save_volume: no volume loaded: use 'volume file' first")?;
        let format = crate::formats::format_for_writing(path);
        if format.name != "HyperMesh" && explicit {
            return Err(format!(
                "save_volume: binary/ascii/small choose the HyperMesh encoding; {} is written as {} (binary appended, zlib)",
                path.display(),
                format.name
            ));
        }
        let w = crate::formats::save_volume(vol, path, opts).map_err(|e| e.to_string())?;
        Ok(warnings(w))
    }

    /// `save_subset FILE FIELD ?binary|ascii?`: the cells where the Constant field is not zero.
    pub fn save_subset(&self, path: &Path, field: usize, encoding: Encoding) -> Result<(), String> {
        self.whole_volume_only("save_subset")?;
        let vol = self
            .volume
            .as_ref()
            .ok_or("save_subset: no volume loaded: use 'volume file' first")?;
        hypermesh::save_subset(vol, path, field, encoding).map_err(|e| e.to_string())
    }

    // --- maps and display (thesis A.1 „Angaben zu Beleuchtung und Darstellung“) ---

    /// Binds the maps now if a volume is loaded, so that a mismatch is reported at the command.
    fn check_maps(&self, color: &ColorMap, alpha: &AlphaMap) -> Result<(), String> {
        self.on_every_piece(|vol| {
            Mapping::new(color, alpha, vol)
                .map(|_| ())
                .map_err(|e| e.to_string())
        })
    }

    /// `colormap`: the colour mapping (checked against the volume, if one is loaded).
    pub fn set_colormap(&mut self, map: ColorMap) -> Result<(), String> {
        self.check_maps(&map, &self.alphamap)?;
        self.colormap = map;
        self.colormap_set = true;
        Ok(())
    }

    /// `alphamap`: the alpha mapping (checked against the volume, if one is loaded).
    pub fn set_alphamap(&mut self, map: AlphaMap) -> Result<(), String> {
        self.check_maps(&self.colormap, &map)?;
        self.alphamap = map;
        self.alphamap_set = true;
        Ok(())
    }

    /// The first picture `vorang info` suggests, for front ends that render without maps
    /// (`vorang view FILE`, Python): a colour preset (`viridis`) and an absorption ramp over the first
    /// scalar field's range (over all steps of a time series where [`Session::set_series_ranges`]
    /// gave them), χ rising to 4 / the bounding box's diagonal (the densest part then
    /// lets about e⁻⁴ of the light through across the volume). Returns that χ_max — the
    /// brightness at which opaque parts show the preset's colours — and a note saying what was
    /// chosen; `None` (and no change) when no field varies.
    pub fn use_preset_maps(
        &mut self,
        command: &str,
        preset: &str,
    ) -> Result<Option<(f64, Notice)>, String> {
        let vol = self.need_volume(command)?;
        let size = vol.mesh.bbox().size();
        let diagonal = size.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(diagonal > 0.0 && diagonal.is_finite()) {
            return Ok(None);
        }
        let chi = 4.0 / diagonal;
        let found =
            (0..vol.data.fields.len()).find_map(|i| match self.range_of(&vol, i)?.as_slice() {
                [(lo, hi)] if lo < hi && lo.is_finite() && hi.is_finite() => Some((i, *lo, *hi)),
                _ => None,
            });
        let Some((i, lo, hi)) = found else {
            return Ok(None);
        };
        let field = i.to_string();
        let colormap = crate::mapping::preset_colormap(preset, lo, hi, Some(&field))?;
        let alphamap = crate::mapping::ramp_alphamap(lo, hi, chi, Some(&field))?;
        self.check_maps(&colormap, &alphamap)?;
        self.colormap = colormap;
        self.alphamap = alphamap;
        let name = vol.data.fields[i]
            .name
            .as_deref()
            .map(|n| format!(" \"{n}\""))
            .unwrap_or_default();
        let note = Notice::Note(format!(
            "{command}: no maps given: the {preset} preset and an absorption ramp up to χ = {} over field {i}{name}, [{}, {}] (as 'vorang info' suggests)",
            crate::info::num(chi),
            crate::info::num(lo),
            crate::info::num(hi)
        ));
        Ok(Some((chi, note)))
    }

    /// `linedraw`: which grid edges are drawn (a field's values are checked against the volume).
    pub fn set_lines(&mut self, lines: LineDraw) -> Result<(), String> {
        if let LineDraw::Cells { .. } = &lines {
            self.on_every_piece(|vol| {
                crate::render::lines::edges(vol, &lines)
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            })?;
        }
        self.settings.lines = lines;
        Ok(())
    }

    /// `legend on ?place?` (`Some`) or `legend off` (`None`).
    pub fn set_legend(&mut self, place: Option<Place>) {
        self.legend = place;
    }

    /// `addlight r g b dx dy dz`: returns the light's number (1, 2, …).
    pub fn add_light(&mut self, light: Light) -> Result<usize, String> {
        if light.direction == [0.0; 3] {
            return Err("addlight: the direction must not be zero".into());
        }
        self.settings.lights.push(light);
        Ok(self.settings.lights.len())
    }

    /// `removelight n` (1 = the first added).
    pub fn remove_light(&mut self, n: usize) -> Result<(), String> {
        if n == 0 || n > self.settings.lights.len() {
            return Err(format!(
                "removelight: there is no light {n} ({} added)",
                self.settings.lights.len()
            ));
        }
        self.settings.lights.remove(n - 1);
        Ok(())
    }

    // --- camera and transforms (thesis A.1; docs/camera.md) ---

    /// `persp_camera` / `ortho_camera`.
    pub fn set_camera(&mut self, camera: Camera) -> Result<(), String> {
        camera.validate()?;
        self.view.camera = Some(camera);
        Ok(())
    }

    /// `view_all`: a camera of the current kind that frames the transformed volume.
    pub fn view_all(&mut self) -> Result<(), String> {
        let vol = self
            .volume
            .clone()
            .ok_or("view_all: no volume loaded (use 'volume FILE' first)")?;
        let centre = vol.mesh.bbox().center();
        if !self.is_distributed() {
            return self.view.fit(
                vol.mesh.nodes(),
                centre,
                self.settings.width,
                self.settings.height,
            );
        }
        // Every rank's nodes: the extremes are minima, combined over the ranks.
        let view = &self.view;
        let extremes = self.min_over_pieces(|piece| {
            view.fit_extremes(piece.mesh.nodes(), centre)
                .map(|e| e.to_vec())
        })?;
        let extremes: [f64; crate::scene::FIT_EXTREMES] = extremes
            .try_into()
            .map_err(|_| "view_all: the ranks disagree".to_string())?;
        self.view
            .fit_to(&extremes, centre, self.settings.width, self.settings.height)
    }

    /// Zooms the camera by `factor` (> 1: closer) about the image centre: an orthographic window
    /// shrinks by the factor, a perspective field of view narrows so that its tangent does. A
    /// session without a camera gets the one `view_all` would choose first.
    pub fn zoom(&mut self, factor: f64) -> Result<(), String> {
        if !(factor > 0.0 && factor.is_finite()) {
            return Err(format!("zoom: expected a factor > 0, found {factor}"));
        }
        if self.view.camera.is_none() {
            self.view_all()?;
        }
        let camera = match self.view.camera {
            Some(Camera::Ortho {
                left,
                right,
                bottom,
                top,
                front,
                back,
            }) => {
                let (cx, cy) = ((left + right) / 2.0, (bottom + top) / 2.0);
                let (hx, hy) = ((right - left) / 2.0 / factor, (top - bottom) / 2.0 / factor);
                Camera::Ortho {
                    left: cx - hx,
                    right: cx + hx,
                    bottom: cy - hy,
                    top: cy + hy,
                    front,
                    back,
                }
            }
            Some(Camera::Persp {
                fovy,
                aspect,
                near,
                far,
            }) => Camera::Persp {
                fovy: 2.0
                    * ((fovy.to_radians() / 2.0).tan() / factor)
                        .atan()
                        .to_degrees(),
                aspect,
                near,
                far,
            },
            None => return Ok(()),
        };
        self.set_camera(camera)
    }

    /// `vol_scale`, `vol_translate`, `vol_rotate`: one more transform after those so far.
    pub fn transform(&mut self, op: TransformOp) -> Result<(), String> {
        match op {
            TransformOp::Scale(v) if v.contains(&0.0) => {
                Err("vol_scale: a scale factor of 0 would flatten the volume".into())
            }
            TransformOp::Rotate { axis, .. } if axis == [0.0; 3] => {
                Err("vol_rotate: the rotation axis must not be zero".into())
            }
            op => {
                self.view.transforms.push(op);
                Ok(())
            }
        }
    }

    /// `look_at`: eye, reference point and up direction.
    pub fn set_look_at(&mut self, look_at: LookAt) {
        self.view.look_at = look_at;
    }

    /// The whole view at once (the viewer hands back where the user left it).
    pub fn set_view(&mut self, view: View) {
        self.view = view;
    }

    // --- method and image (thesis A.1 „Berechnungsmethoden“, „Bildangaben“) ---

    /// `method`.
    pub fn set_method(&mut self, method: Method) {
        self.settings.method = method;
        self.method_set = true;
    }

    /// `imagesize width height`.
    pub fn set_image_size(&mut self, width: usize, height: usize) -> Result<(), String> {
        crate::render::check_size(width, height).map_err(|e| format!("imagesize: {e}"))?;
        self.settings.width = width;
        self.settings.height = height;
        Ok(())
    }

    /// `background`: uniform white (default), none (transparent), a colour or an image.
    pub fn set_background(&mut self, background: Background) -> Result<(), String> {
        if let Background::Color(rgb) = &background
            && rgb.iter().any(|v| *v < 0.0)
        {
            return Err("background: colour components must be ≥ 0".into());
        }
        self.settings.background = background;
        Ok(())
    }

    /// `background FILE`: an image under the volume.
    pub fn load_background(&mut self, path: &Path) -> Result<(), String> {
        let img = BackgroundImage::load(path).map_err(|e| e.to_string())?;
        self.settings.background = Background::Image(Arc::new(img));
        Ok(())
    }

    /// `output base.fmt`. A new base name starts a new series at 1; the same base again, also in
    /// another format, keeps counting. A `set_nr` since the last image holds whatever `output`
    /// says (thesis A.1: `set_nr` sets the number of the next image).
    pub fn set_output(&mut self, path: PathBuf) -> Result<(), String> {
        format_for(&path).map_err(|e| e.to_string())?;
        if path.with_extension("") != self.output.with_extension("") && !self.number_set {
            self.next_number = 1;
        }
        self.output = path;
        Ok(())
    }

    /// `set_nr n`: the number the next image gets.
    pub fn set_number(&mut self, n: usize) -> Result<(), String> {
        // The largest number leaves room for the count-up after the render.
        self.next_number = u32::try_from(n)
            .ok()
            .filter(|&n| n < u32::MAX)
            .ok_or_else(|| format!("set_nr: {n} is too large (at most {})", u32::MAX - 1))?;
        self.number_set = true;
        Ok(())
    }

    /// `movie FILE ?fps?`: the following frames go to an animation. An open movie is closed
    /// first (its note is returned).
    pub fn open_movie(&mut self, path: &Path, fps: f64) -> Result<Vec<Notice>, String> {
        MovieFormat::for_path(path).map_err(|e| format!("movie: {e}"))?;
        let mut notes = Vec::new();
        if let Some((_, note)) = self.close_movie()? {
            notes.push(note);
        }
        if !self.is_root() {
            self.follow_movie(path);
            return Ok(notes);
        }
        self.movie = Some(Movie::open(path, fps).map_err(|e| format!("movie: {e}"))?);
        Ok(notes)
    }

    /// `movie close` (also a new `movie` and the session's end): writes the open movie, if any;
    /// the note names the file and its frames.
    pub fn close_movie(&mut self) -> Result<Option<(PathBuf, Notice)>, String> {
        if let Some((path, _)) = self.movie_elsewhere.take() {
            return Ok(Some((path.clone(), Notice::Note(display_path(&path)))));
        }
        let Some(movie) = self.movie.take() else {
            return Ok(None);
        };
        let frames = movie.frames();
        let fps = movie.fps;
        let path = movie.finish().map_err(|e| e.to_string())?;
        let msg = format!(
            "{}  {frames} frame{} at {fps} fps",
            display_path(&path),
            if frames == 1 { "" } else { "s" }
        );
        self.written.push(path.clone());
        Ok(Some((path, Notice::Note(msg))))
    }

    /// Drops the open movie without writing it (a front end's animation that failed half-way);
    /// its frames are removed.
    pub fn discard_movie(&mut self) {
        if let Some(movie) = self.movie.take() {
            movie.discard();
        }
    }

    /// Writes `fb` as the next numbered image, as a frame would (the viewer's `s`).
    pub fn save_numbered(
        &mut self,
        fb: &crate::framebuffer::Framebuffer,
    ) -> Result<Notice, String> {
        if self.next_number == u32::MAX {
            return Err("the image numbers are used up: use 'set_nr' to start again".into());
        }
        let path = crate::framebuffer::numbered(&self.output, self.next_number);
        format_for(&path).map_err(|e| e.to_string())?;
        crate::framebuffer::write_image(fb, &path).map_err(|e| e.to_string())?;
        self.next_number += 1;
        self.number_set = false;
        let note = Notice::Note(format!(
            "{}  {}×{}  saved from the viewer",
            display_path(&path),
            fb.width,
            fb.height
        ));
        self.written.push(path);
        Ok(note)
    }
}
