//! One frame: bind the maps → render → legend and time label → the messages → the numbered file
//! or the movie's next frame (`render_btf` / `render_ftb`, thesis A.1).
//!
//! The step comes in three parts so that a front end can stand between them: [`Session::prepare`]
//! binds the maps and checks where the image will go, [`Prepared::render`] renders (on any
//! thread: a window shows its tiles, Python waits without the interpreter lock), and
//! [`Session::finish_image`] / [`Session::finish_frame`] add the legend, write the file and say
//! what happened. [`Session::render_frame`] and [`Session::render_image`] do all three.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use super::{Notice, Ranks, Session, display_path, warnings};
use crate::Error;
use crate::distributed::frame::{render_frame, render_virtual};
use crate::framebuffer::{Framebuffer, format_for, numbered, write_image};
use crate::legend::{self, ColorScale};
use crate::mapping::Mapping;
use crate::mapping::{AlphaMap, ColorMap};
use crate::render::{Order, Settings, Stats, TileSink, Watch, render_watched};
use crate::scene::View;
use crate::volume::Volume;

/// What a front end watches of a render while it runs: progress, finished tiles, a cancel flag.
#[derive(Clone, Copy)]
pub struct Hooks<'a> {
    pub progress: Option<&'a (dyn Fn(usize, usize) + Sync)>,
    pub tile: Option<TileSink<'a>>,
    /// Set from another thread (Ctrl-C, a closed window) to stop the render.
    pub cancel: &'a AtomicBool,
}

/// A frame ready to render: the scene bound to its maps, and where its image goes.
pub struct Prepared {
    /// The command the frame was asked by (`render_btf`, `render`), for messages.
    command: &'static str,
    volume: Arc<Volume>,
    mapping: Mapping,
    view: View,
    pub settings: Settings,
    /// The numbered file, when the frame goes to one and no movie is open.
    path: Option<PathBuf>,
    /// Warnings of binding the maps.
    notices: Vec<Notice>,
    /// Which renders it (only the CPU in a build without the GPU backend).
    #[cfg_attr(not(feature = "gpu"), allow(dead_code))]
    backend: super::Backend,
    /// Which ranks render it.
    ranked: Ranked,
}

/// Which ranks render a prepared frame ([`Ranks`]): this process, virtual ranks (every piece,
/// with the maps each binds to its own), or this process as one rank.
enum Ranked {
    One,
    Virtual(Box<(Vec<Arc<Volume>>, ColorMap, AlphaMap)>),
    Comm(Arc<dyn crate::distributed::Comm>),
}

impl Prepared {
    /// The warnings of binding the maps, for a front end that shows them before the render
    /// starts (otherwise they lead the image's notices).
    pub fn take_notices(&mut self) -> Vec<Notice> {
        std::mem::take(&mut self.notices)
    }

    /// Renders the frame; callable from any thread. A rank of a distributed session other than
    /// rank 0 gets an empty image (0 × 0) and its own statistics.
    pub fn render(&self, hooks: &Hooks) -> Result<(Framebuffer, Stats), Error> {
        #[cfg(feature = "gpu")]
        if let super::Backend::Gpu(g) = &self.backend {
            return g.render(&self.volume, &self.mapping, &self.view, &self.settings);
        }
        let (view, settings, cancel) = (&self.view, &self.settings, hooks.cancel);
        match &self.ranked {
            Ranked::One => {}
            Ranked::Virtual(v) => {
                let (pieces, c, a) = &**v;
                return render_virtual(pieces, (c, a), view, settings, cancel);
            }
            Ranked::Comm(comm) => {
                let vol = &self.volume;
                return match render_frame(
                    comm.as_ref(),
                    vol,
                    &self.mapping,
                    view,
                    settings,
                    cancel,
                )? {
                    Some(image) => Ok(image),
                    None => Ok((Framebuffer::try_new(0, 0)?, Stats::empty())),
                };
            }
        }
        let watch = Watch {
            progress: hooks.progress,
            tile: hooks.tile,
            cancel: hooks.cancel,
        };
        render_watched(
            &self.volume,
            &self.mapping,
            &self.view,
            &self.settings,
            &watch,
        )
    }
}

/// A rendered image with its legend, and what the session has to say about it.
pub struct Image {
    pub framebuffer: Framebuffer,
    pub stats: Stats,
    /// Render time (binding and legend not included).
    pub seconds: f64,
    pub notices: Vec<Notice>,
}

/// A frame written to its numbered file or added to the open movie.
pub struct Frame {
    pub image: Image,
    /// The file written (or the movie the frame went to).
    pub written: PathBuf,
    /// The per-frame line: file (or movie frame), size, cells, seconds, largest channel.
    pub summary: String,
}

impl Session {
    /// Binds the maps to the volume and checks where the image will go (`to_file`: a numbered
    /// file or the open movie; otherwise the image is only returned).
    pub fn prepare(
        &mut self,
        command: &'static str,
        order: Order,
        to_file: bool,
    ) -> Result<Prepared, String> {
        let volume = self
            .volume
            .clone()
            .ok_or_else(|| format!("{command}: no volume loaded: use 'volume file' first"))?;
        let bound =
            Mapping::new(&self.colormap, &self.alphamap, &volume).map_err(|e| e.to_string());
        // Bound on every rank's piece: the maps may fit one and not another.
        self.agree(bound.as_ref().map(|_| ()).map_err(String::clone))?;
        let (mapping, w) = bound?;
        let ranked = match &self.ranks {
            Ranks::One => Ranked::One,
            Ranks::Comm(c) => Ranked::Comm(Arc::clone(c)),
            Ranks::Virtual(_) if self.pieces.is_empty() => {
                return Err(format!(
                    "{command}: virtual ranks need a volume read by 'volume FILE' (each rank reads its share)"
                ));
            }
            Ranks::Virtual(_) => Ranked::Virtual(Box::new((
                self.pieces.clone(),
                self.colormap.clone(),
                self.alphamap.clone(),
            ))),
        };
        let mut path = None;
        if to_file && self.movie.is_none() && self.followed_movie().is_none() {
            if self.next_number == u32::MAX {
                return Err(format!(
                    "{command}: the image numbers are used up (the last was {}): use 'set_nr' to start again",
                    u32::MAX - 1
                ));
            }
            let p = numbered(&self.output, self.next_number);
            format_for(&p).map_err(|e| e.to_string())?;
            path = Some(p);
        }
        #[cfg(feature = "gpu")]
        if let super::Backend::Gpu(_) = &self.backend {
            if self.is_distributed() {
                return Err(format!(
                    "{command}: backend gpu renders in one process, not in a distributed session"
                ));
            }
            // What the GPU cannot render is said before the frame starts.
            crate::gpu::frame::check_method(&self.settings.method)
                .and_then(|_| crate::gpu::frame::check_mapping(&mapping, &volume).map(|_| ()))
                .map_err(|e| format!("{command}: backend gpu: {e}"))?;
        }
        let mut notices = warnings(w);
        notices.extend(self.default_notices(command));
        // Count only this render's clamped emission (IDENTITY).
        for l in &self.colormap.lines {
            l.method.take_clamped();
        }
        Ok(Prepared {
            command,
            volume,
            mapping,
            view: self.view.clone(),
            settings: Settings {
                order,
                ..self.settings.clone()
            },
            path,
            notices,
            backend: self.backend.clone(),
            ranked,
        })
    }

    /// Warnings about defaults that silently defeat what the user asked for: maps set while
    /// the method is still the default `test` (which ignores them), and the default camera
    /// stretching the volume to an image of another aspect ratio (once per session).
    fn default_notices(&mut self, command: &str) -> Vec<Notice> {
        let mut notices = Vec::new();
        if !self.method_set
            && matches!(self.settings.method, crate::render::Method::Test(_))
            && (self.colormap_set || self.alphamap_set)
        {
            notices.push(Notice::Warning(format!(
                "{command}: the method is still the default 'test', which ignores the colormap and alphamap; the methods exact, interpolateCoeff and interpolateColor use them (e.g. 'method exact linear 0')"
            )));
        }
        if let Some(stretch) = self.default_camera_stretch()
            && !self.aspect_hinted
            && (stretch - 1.0).abs() > 0.01
        {
            self.aspect_hinted = true;
            notices.push(Notice::Warning(format!(
                "{command}: the default camera stretches the volume by {stretch:.3} (its x/y extent fills the {}×{} image, thesis A.1); 'view_all' frames it undistorted",
                self.settings.width, self.settings.height
            )));
        }
        notices
    }

    /// With no camera set: how much the default camera (the grid's x/y extent on the image)
    /// stretches x against y; `None` with a camera or a flat extent.
    fn default_camera_stretch(&self) -> Option<f64> {
        if self.view.camera.is_some() {
            return None;
        }
        let size = self.volume.as_ref()?.mesh.bbox().size();
        let (w, h) = (self.settings.width as f64, self.settings.height as f64);
        let stretch = (w / h) / (size[0] / size[1]);
        (stretch.is_finite() && stretch > 0.0).then_some(stretch)
    }

    /// The rendered image with its legend and the warnings about it: clamped emission, a legend
    /// that does not fit, non-finite pixels, overlapping cells, visibility cycles.
    pub fn finish_image(
        &self,
        prepared: &mut Prepared,
        result: Result<(Framebuffer, Stats), Error>,
        seconds: f64,
    ) -> Result<Image, String> {
        let command = prepared.command;
        let (mut fb, stats) = result.map_err(|e| format!("{command}: {e}"))?;
        if !self.is_root() {
            // Another rank's image is rank 0's to finish and report.
            return Ok(Image {
                framebuffer: fb,
                stats,
                seconds,
                notices: Vec::new(),
            });
        }
        let mut notices = std::mem::take(&mut prepared.notices);
        let clamped: u64 = self
            .colormap
            .lines
            .iter()
            .map(|l| l.method.take_clamped())
            .sum();
        if clamped > 0 {
            notices.push(Notice::Warning(format!(
                "{command}: IDENTITY clamped {clamped} evaluations with negative components to 0 (emission cannot be negative)"
            )));
        }
        if let Some(place) = self.legend {
            let ranges = self.ranked_ranges.as_deref().map(Vec::as_slice);
            match ColorScale::of_map_over(&self.colormap, &prepared.volume, ranges) {
                Ok(scale) => {
                    if !legend::draw(&mut fb, place, &scale) {
                        notices.push(Notice::Warning(format!(
                            "{command}: the image is too small for a legend (48 pixels at least)"
                        )));
                    }
                }
                Err(e) => notices.push(Notice::Warning(format!("{command}: no legend: {e}"))),
            }
        }
        if let Some(text) = self.label_text() {
            // Clear of the legend: at the bottom where the bar runs along the top.
            legend::label::draw(&mut fb, &text, self.legend == Some(legend::Place::Top));
        }
        Self::stats_notices(command, &stats, &mut notices);
        Ok(Image {
            framebuffer: fb,
            stats,
            seconds,
            notices,
        })
    }

    /// What a render found about the mesh and the pixels: non-finite pixels, overlapping
    /// cells, visibility cycles.
    fn stats_notices(command: &str, stats: &Stats, notices: &mut Vec<Notice>) {
        if let Some((x, y)) = stats.first_non_finite {
            notices.push(Notice::Warning(format!(
                "{command}: {} pixels are NaN or infinite (the first at x {x}, y {y}): an overflow in the data or maps; please report it",
                stats.non_finite
            )));
        }
        if let Some((a, b)) = stats.overlap_cells.first() {
            notices.push(Notice::Warning(format!(
                "{command}: cells overlap other cells along {} rays (e.g. cells {} and {}): the mesh has interpenetrating parts, integrated twice there; 'vorang info --check' lists them",
                stats.overlap_pixels,
                a + 1,
                b + 1
            )));
        }
        if stats.opaque_pixels > 0 {
            notices.push(Notice::Note(format!(
                "{command}: {} pixels turned opaque (transparency below {}): the ranks composited every cell behind that point, where one process stops front to back; these pixels may differ from one process's by less than that transparency (docs/distributed.md)",
                stats.opaque_pixels,
                crate::render::EARLY_TERMINATION
            )));
        }
        if stats.cycle_cells > 0 {
            // Detected and reported; the image is still exact: the order is settled per pixel.
            notices.push(Notice::Note(format!(
                "{command}: {} cells were in visibility cycles; ordered per pixel",
                stats.cycle_cells
            )));
        }
    }

    /// Writes the image to its numbered file (counting up) or adds it to the open movie.
    pub fn finish_frame(&mut self, prepared: Prepared, image: Image) -> Result<Frame, String> {
        let command = prepared.command;
        let Image {
            framebuffer: fb,
            stats,
            seconds,
            notices,
        } = image;
        let followed = if self.is_root() {
            None
        } else {
            self.follow_frame(prepared.path.clone())
        };
        let (shown, written) = match (&mut self.movie, prepared.path) {
            _ if followed.is_some() => followed.unwrap_or_default(),
            (Some(movie), _) => {
                movie.add(&fb).map_err(|e| format!("{command}: {e}"))?;
                self.number_set = false;
                let shown = format!("{} frame {}", display_path(&movie.path), movie.frames());
                (shown, movie.path.clone())
            }
            (None, Some(path)) => {
                write_image(&fb, &path).map_err(|e| e.to_string())?;
                self.next_number += 1;
                self.number_set = false;
                self.written.push(path.clone());
                (display_path(&path), path)
            }
            (None, None) => {
                return Err(format!(
                    "{command}: the frame was prepared without a file to write"
                ));
            }
        };
        let summary = format!(
            "{}  {}×{}  {} cells  {:.3} s  max {}",
            shown,
            fb.width,
            fb.height,
            stats.cells,
            seconds,
            fb.max_channel()
        );
        Ok(Frame {
            image: Image {
                framebuffer: fb,
                stats,
                seconds,
                notices,
            },
            written,
            summary,
        })
    }

    /// Renders the scene into an image without writing it (Python's `render`): every warning
    /// the frame would give, in [`Image::notices`].
    pub fn render_image(&mut self, order: Order, hooks: &Hooks) -> Result<Image, String> {
        let mut prepared = self.prepare("render", order, false)?;
        let started = Instant::now();
        let result = prepared.render(hooks);
        let seconds = started.elapsed().as_secs_f64();
        self.finish_image(&mut prepared, result, seconds)
    }

    /// One frame from scene to file: `render_btf` (back to front) or `render_ftb`.
    pub fn render_frame(
        &mut self,
        command: &'static str,
        order: Order,
        hooks: &Hooks,
    ) -> Result<Frame, String> {
        let mut prepared = self.prepare(command, order, true)?;
        let started = Instant::now();
        let result = prepared.render(hooks);
        let seconds = started.elapsed().as_secs_f64();
        let image = self.finish_image(&mut prepared, result, seconds)?;
        self.finish_frame(prepared, image)
    }
}

/// The `VORANG_TIMING` line of a frame: where its time went.
pub fn timing_line(stats: &Stats) -> String {
    let t = stats.timing;
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    #[cfg(feature = "gpu")]
    if stats.sort == crate::gpu::GPU_SORT {
        return format!(
            "  setup {:.1} ms (nodes, entry lists), upload {:.1} ms (cells, once per mesh), march {:.1} ms on the GPU; {} ray segments ({:.3} G/s)",
            ms(t.setup),
            ms(t.bin),
            ms(t.draw),
            stats.fragments,
            stats.fragments as f64 / t.draw.as_secs_f64().max(1e-9) / 1e9
        );
    }
    format!(
        "  setup {:.1} ms, sort {:.1} ms ({}{}), bin {:.1} ms, draw {:.1} ms; {} ray segments ({:.0} % in SIMD lanes, {}) on {} threads",
        ms(t.setup),
        ms(t.sort),
        stats.sort,
        if stats.per_pixel {
            format!(", per-pixel order: up to {} runs on a ray", stats.most_runs)
        } else {
            String::new()
        },
        ms(t.bin),
        ms(t.draw),
        stats.fragments,
        100.0 * stats.lane_fragments as f64 / stats.fragments.max(1) as f64,
        crate::render::span::kernel().name(),
        rayon::current_num_threads()
    ) + &composite_part(t.composite)
        + &ranks_part(&stats.ranks)
}

/// A distributed frame's load per rank, for the timing line (nothing in one process).
fn ranks_part(ranks: &[crate::render::RankLoad]) -> String {
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    ranks
        .iter()
        .enumerate()
        .map(|(r, l)| {
            format!(
                "; rank {r}: render {:.1} ms, {} ray segments, {} runs, {} bytes sent, composite {:.1} ms",
                ms(l.render),
                l.fragments,
                l.runs,
                l.bytes_sent,
                ms(l.composite)
            )
        })
        .collect()
}

/// A distributed frame's compositing time, for the timing line (nothing in one process).
fn composite_part(composite: Duration) -> String {
    if composite.is_zero() {
        return String::new();
    }
    format!(
        "; composite {:.1} ms (runs exchanged, pixels settled and gathered)",
        composite.as_secs_f64() * 1e3
    )
}
