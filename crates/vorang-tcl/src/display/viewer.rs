//! The interactive viewer: `vorang view FILE` and the `view` script command.
//!
//! One thread runs Tcl and Tk (Tk is single-threaded): it builds the window, turns Tk's mouse
//! and key events — collected by Tcl bindings into a list variable — into changes of the
//! [`Orbit`], and puts finished frames into the photo. Renders run on a thread of their own,
//! one at a time: while the view moves, a fast preview (`interpolateColor` at reduced
//! resolution, scaled up); once it has been still for [`SETTLE`], the chosen method at full
//! size, its tiles shown over the preview as they finish. A refined frame made stale by a change
//! is cancelled through the renderer's cancel flag, so the window follows the mouse and never
//! waits for a frame nobody will see.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use super::controls::{self, Action, Controls, parse_event};
use super::frames::{self, Done, Job, Tile};
use super::legend::{self, Legend};
use super::orbit::Orbit;
use super::rgba8;
use crate::report::Reporter;
use crate::tcl::Interp;
use crate::tk::Tk;
use vorang::framebuffer::Framebuffer;
use vorang::mapping::Mapping;
use vorang::render::approx::{InterpolateCoeff, InterpolateColor};
use vorang::render::{CANCELLED, Method, Order, Settings};
use vorang::session::{Notice, Session, method_command};
use vorang::volume::Volume;

/// How long the view must stay still before the chosen method refines the preview.
pub const SETTLE: Duration = Duration::from_millis(150);
/// How often the Tcl thread looks for events and frames.
const POLL: Duration = Duration::from_millis(8);
/// The preview has at most about this many pixels.
const PREVIEW_PIXELS: usize = 192 * 192;

const TOPLEVEL: &str = ".vorang_view";
const PHOTO: &str = "vorang_view";
const LEGEND: &str = "vorang_legend";
const EVENTS: &str = "::vorang::view_events";

/// The reduction of the preview: at least 2, more for large images.
pub fn preview_factor(width: usize, height: usize) -> usize {
    let f = ((width * height) as f64 / PREVIEW_PIXELS as f64)
        .sqrt()
        .ceil() as usize;
    f.max(2)
}

/// The window: image, legend, status line; bindings that append events to [`EVENTS`].
fn open_window(interp: &Interp, width: usize, height: usize) -> Result<(), String> {
    let script = format!(
        r#"
        namespace eval ::vorang {{ variable view_events {{}}; variable view_status {{}}; variable view_range {{}} }}
        catch {{ destroy {TOPLEVEL} }}
        foreach p {{{PHOTO} {LEGEND}}} {{ if {{[lsearch -exact [image names] $p] < 0}} {{ image create photo $p }} }}
        {PHOTO} blank
        {PHOTO} configure -width {width} -height {height}
        {LEGEND} blank
        {LEGEND} configure -width {width} -height {lh}
        toplevel {TOPLEVEL} -borderwidth 0 -highlightthickness 0
        wm title {TOPLEVEL} {{VoRANG view}}
        label {TOPLEVEL}.image -image {PHOTO} -borderwidth 0 -highlightthickness 0 -padx 0 -pady 0
        label {TOPLEVEL}.legend -image {LEGEND} -borderwidth 0 -highlightthickness 0 -padx 0 -pady 0
        label {TOPLEVEL}.range -textvariable ::vorang::view_range -anchor w -justify left -font TkSmallCaptionFont -wraplength {wrap}
        label {TOPLEVEL}.status -textvariable ::vorang::view_status -anchor w -justify left -font TkSmallCaptionFont -wraplength {wrap}
        pack {TOPLEVEL}.image {TOPLEVEL}.legend -side top -anchor nw
        pack {TOPLEVEL}.range {TOPLEVEL}.status -side top -fill x
        set w {TOPLEVEL}.image
        bind $w <ButtonPress-1> {{lappend {EVENTS} [list press %x %y %s]}}
        bind $w <B1-Motion> {{lappend {EVENTS} [list motion %x %y]}}
        bind $w <ButtonRelease-1> {{lappend {EVENTS} release}}
        bind $w <MouseWheel> {{lappend {EVENTS} [list wheel %D]}}
        bind $w <Button-4> {{lappend {EVENTS} {{wheel 120}}}}
        bind $w <Button-5> {{lappend {EVENTS} {{wheel -120}}}}
        bind {TOPLEVEL} <KeyPress> {{lappend {EVENTS} [list key %K]}}
        wm protocol {TOPLEVEL} WM_DELETE_WINDOW {{lappend {EVENTS} {{key q}}}}
        update idletasks
        focus -force {TOPLEVEL}
        "#,
        lh = legend::HEIGHT,
        // Text wraps at the image's width, so that the window is as wide as the image.
        wrap = width.max(240)
    );
    interp.eval(&script).map(|_| ()).map_err(|e| e.message)
}

/// Nearest-neighbour enlargement of a preview to the window's size.
fn enlarge(small: &[u8], sw: usize, sh: usize, width: usize, height: usize) -> Vec<u8> {
    let mut out = Vec::with_capacity(width * height * 4);
    for y in 0..height {
        let sy = (y * sh / height).min(sh - 1);
        for x in 0..width {
            let sx = (x * sw / width).min(sw - 1);
            out.extend_from_slice(&small[(sy * sw + sx) * 4..][..4]);
        }
    }
    out
}

/// Shows `rgba` (the window's size) in the image.
fn show(tk: &Tk, interp: &Interp, (width, height): (usize, usize), rgba: &[u8]) {
    // A failure here (out of memory in Tk) leaves the old picture: nothing else to do.
    let _ = tk.put(interp, PHOTO, (0, 0), (width, height), rgba);
}

/// The window's legend strip and range line: the maps as a function of one scalar, if they are.
fn show_legend(tk: &Tk, interp: &Interp, mapping: &Mapping, vol: &Volume, width: usize) {
    match legend::legend(mapping, vol, width) {
        Some(Legend {
            rgba,
            min,
            max,
            chi_max,
            ..
        }) => {
            let _ = tk.put(interp, LEGEND, (0, 0), (width, legend::HEIGHT), &rgba);
            interp.set_var(
                "::vorang::view_range",
                &format!("{min:.4} … {max:.4}   (colour: η scaled; bars: χ up to {chi_max:.3})"),
            );
        }
        None => {
            interp.set_var(
                "::vorang::view_range",
                "no legend: the maps are not a function of one scalar field",
            );
            let _ = interp.eval(&format!("pack forget {TOPLEVEL}.legend"));
        }
    }
}

/// Runs the viewer on the session's scene until the user quits (`q`, or closing the window).
/// The session keeps the final view and method, so a render after `view` shows what the
/// viewer showed.
pub fn run(
    session: &mut Session,
    reporter: &mut dyn Reporter,
    tk: Tk,
    interp: &Interp,
) -> Result<String, String> {
    let vol = session
        .volume()
        .cloned()
        .ok_or("view: no volume loaded: use 'volume file' first")?;
    let (mapping, warnings) =
        Mapping::new(session.colormap(), session.alphamap(), &vol).map_err(|e| e.to_string())?;
    for w in warnings {
        reporter.warn(&w.to_string());
    }
    let (width, height) = (session.settings().width, session.settings().height);
    let orbit = Orbit::new(session.view(), &vol, width, height)?;
    let method = session.settings().method;
    open_window(interp, width, height).map_err(|e| format!("view: {e}"))?;
    show_legend(&tk, interp, &mapping, &vol, width);

    let (job_send, job_receive) = mpsc::channel::<Job>();
    let (done_send, done_receive) = mpsc::channel::<Done>();
    // A refined frame's tiles as they finish: shown over the preview, so a slow method visibly
    // makes progress (the thesis's `online` picture).
    let (tile_send, tile_receive) = mpsc::channel::<Tile>();
    std::thread::scope(|scope| {
        let (vol, mapping, backend) = (&vol, &mapping, session.backend().clone());
        scope.spawn(move || {
            frames::render(&backend, vol, mapping, job_receive, done_send, tile_send)
        });
        let mut viewer = Viewer {
            session,
            reporter,
            tk,
            interp,
            size: (width, height),
            factor: preview_factor(width, height),
            cells: vol.mesh.tet_count(),
            orbit,
            method,
            generation: 0,
            changed_at: Instant::now(),
            in_flight: None,
            shown: None,
            refined: None,
            controls: Controls::default(),
            save: false,
            quit: false,
            preview_ms: f64::NAN,
            refined_ms: f64::NAN,
            error: None,
            times: (Vec::new(), Vec::new()),
        };
        let result = loop {
            viewer.poll_events();
            viewer.show_tiles(&tile_receive);
            viewer.receive_frames(&done_receive);
            viewer.save_if_asked();
            // A save waits for the refined frame, unless that cannot be rendered.
            if viewer.quit && (!viewer.save || viewer.error.is_some()) {
                break Ok(String::new());
            }
            if let Err(e) = viewer.schedule(&job_send) {
                break Err(e);
            }
            viewer.show_status();
            std::thread::sleep(POLL);
        };
        if let Some((_, _, cancel)) = &viewer.in_flight {
            cancel.store(true, Ordering::Relaxed);
        }
        drop(job_send);
        viewer.close();
        result
    })
}

/// The viewer's state between polls: the view the mouse made, what is being rendered and
/// what the window shows.
struct Viewer<'a> {
    session: &'a mut Session,
    reporter: &'a mut dyn Reporter,
    tk: Tk,
    interp: &'a Interp,
    size: (usize, usize),
    /// The preview's reduction.
    factor: usize,
    cells: usize,
    orbit: Orbit,
    method: Method,
    /// Counts the view's changes; a frame of an older generation is stale.
    generation: u64,
    changed_at: Instant,
    /// The job being rendered: its generation, whether refined, its cancel flag.
    in_flight: Option<(u64, bool, Arc<AtomicBool>)>,
    /// The generation and kind of the frame on the screen.
    shown: Option<(u64, bool)>,
    /// The last refined frame, for `s`.
    refined: Option<(u64, Framebuffer)>,
    controls: Controls,
    save: bool,
    quit: bool,
    preview_ms: f64,
    refined_ms: f64,
    error: Option<String>,
    /// Frame times in seconds (previews, refined), for the VORANG_TIMING summary.
    times: (Vec<f64>, Vec<f64>),
}

impl Viewer<'_> {
    /// Tk's events since the last poll, applied to the view; a change cancels a stale
    /// refinement.
    fn poll_events(&mut self) {
        let interp = self.interp;
        interp.eval("update").ok();
        if interp
            .eval(&format!("winfo exists {TOPLEVEL}"))
            .is_ok_and(|v| v != "1")
        {
            self.quit = true;
            self.save = false;
        }
        let events = interp
            .eval(&format!("set e ${EVENTS}; set {EVENTS} {{}}; set e"))
            .unwrap_or_default();
        let mut moved = false;
        for e in interp.split_list(&events).unwrap_or_default() {
            let Some(input) = parse_event(interp, &e) else {
                continue;
            };
            match self
                .controls
                .apply(input, &mut self.orbit, &mut self.method)
            {
                Action::None => {}
                Action::Moved => moved = true,
                Action::Save => self.save = true,
                Action::Print => self.print(),
                Action::Quit => self.quit = true,
            }
        }
        if moved {
            // A new view may well render where the last one failed (e.g. a method's step).
            self.error = None;
            self.generation += 1;
            self.changed_at = Instant::now();
            if let Some((_, true, cancel)) = &self.in_flight {
                cancel.store(true, Ordering::Relaxed);
            }
        }
    }

    /// `p`: the session, holding the viewer's view and method, prints itself as commands.
    fn print(&mut self) {
        self.session.set_view(self.orbit.view());
        self.session.set_method(self.method);
        let lines = self.session.script();
        self.reporter.info(&format!(
            "# view: the commands for this image (after loading the volume and maps)\n{}",
            lines.join("\n")
        ));
    }

    /// A refined frame's finished tiles, over the preview.
    fn show_tiles(&mut self, tiles: &mpsc::Receiver<Tile>) {
        while let Ok((g, rect, rgba)) = tiles.try_recv() {
            if g == self.generation && self.shown != Some((g, true)) {
                let size = (rect.x1 - rect.x0, rect.y1 - rect.y0);
                let _ = self
                    .tk
                    .put(self.interp, PHOTO, (rect.x0, rect.y0), size, &rgba);
            }
        }
    }

    /// Finished frames: a refined frame of the current view replaces the picture; a preview
    /// is enlarged to the window.
    fn receive_frames(&mut self, done: &mpsc::Receiver<Done>) {
        let (width, height) = self.size;
        while let Ok(done) = done.try_recv() {
            if self
                .in_flight
                .as_ref()
                .is_some_and(|f| (f.0, f.1) == (done.generation, done.refined))
            {
                self.in_flight = None;
            }
            let fb = match done.frame {
                Ok(fb) => fb,
                Err(e) if e == CANCELLED => continue,
                Err(e) => {
                    self.error = Some(e);
                    continue;
                }
            };
            if done.refined && done.generation != self.generation {
                continue;
            }
            let rgba = rgba8(&fb.pixels, fb.transparent);
            if done.refined {
                show(&self.tk, self.interp, self.size, &rgba);
                self.refined_ms = done.seconds * 1e3;
                self.times.1.push(done.seconds);
                self.refined = Some((done.generation, fb));
            } else {
                let big = enlarge(&rgba, fb.width, fb.height, width, height);
                show(&self.tk, self.interp, self.size, &big);
                self.preview_ms = done.seconds * 1e3;
                self.times.0.push(done.seconds);
            }
            self.shown = Some((done.generation, done.refined));
            self.error = None;
        }
    }

    /// `s`: once the refined frame of the current view is there, it is written as the next
    /// numbered image, as a render would.
    fn save_if_asked(&mut self) {
        let generation = self.generation;
        let Some((_, fb)) = self
            .refined
            .as_ref()
            .filter(|(g, _)| self.save && *g == generation)
        else {
            return;
        };
        self.save = false;
        match self.session.save_numbered(fb) {
            Ok(Notice::Warning(t)) => self.reporter.warn(&t),
            Ok(Notice::Note(t)) => self.reporter.info(&t),
            Err(e) => self.reporter.warn(&format!("view: {e}")),
        }
    }

    /// With nothing in flight: a preview of a changed view at once, the chosen method at full
    /// size once the view has been still for [`SETTLE`].
    fn schedule(&mut self, jobs: &mpsc::Sender<Job>) -> Result<(), String> {
        if self.in_flight.is_some() || self.error.is_some() {
            return Ok(());
        }
        let generation = self.generation;
        let refine = matches!(self.shown, Some((g, false)) if g == generation)
            && self.changed_at.elapsed() >= SETTLE;
        let preview = self.shown.is_none_or(|(g, _)| g != generation);
        if !(preview || refine) {
            return Ok(());
        }
        let (width, height) = self.size;
        let mut settings = Settings {
            method: self.method,
            order: Order::BackToFront,
            ..self.session.settings().clone()
        };
        if preview {
            let brightness = controls::brightness(&self.method);
            // The GPU previews with the method it has that is closest to interpolateColor's
            // speed: interpolateCoeff linear (crates/vorang/src/gpu/frame.rs).
            settings.method = if self.session.backend().is_gpu() {
                Method::InterpolateCoeff(InterpolateCoeff {
                    rule: vorang::integrate::find("linear").ok_or("view: no linear rule")?,
                    brightness,
                })
            } else {
                Method::InterpolateColor(InterpolateColor { brightness })
            };
            settings.width = width.div_ceil(self.factor);
            settings.height = height.div_ceil(self.factor);
        }
        let cancel = Arc::new(AtomicBool::new(false));
        self.in_flight = Some((generation, refine, Arc::clone(&cancel)));
        let job = Job {
            generation,
            refined: refine,
            view: self.orbit.view(),
            settings,
            cancel,
        };
        jobs.send(job)
            .map_err(|_| "view: the render thread stopped".to_string())
    }

    /// The status line: method, cells, state and frame times, and the keys.
    fn show_status(&self) {
        let ms = |v: f64| {
            if v.is_nan() {
                "–".to_string()
            } else {
                format!("{v:.0} ms")
            }
        };
        let state = match (&self.error, self.shown) {
            (Some(e), _) => format!("error: {e}"),
            (None, Some((g, true))) if g == self.generation => "refined".to_string(),
            _ => "preview".to_string(),
        };
        self.interp.set_var(
            "::vorang::view_status",
            &format!(
                "{}  ·  {} cells  ·  {state}  ·  preview {} (1/{} size), refined {}\ndrag: turn · shift-drag: pan · wheel: zoom · 1–4 method · +/− brightness · r reset · s save · p print · q quit",
                method_command(&self.method).trim_start_matches("method "),
                self.cells,
                ms(self.preview_ms),
                self.factor,
                ms(self.refined_ms)
            ),
        );
    }

    /// Closes the window and hands the final view and method back to the session.
    fn close(mut self) {
        let (width, height) = self.size;
        let _ = self
            .interp
            .eval(&format!("catch {{destroy {TOPLEVEL}}}; update"));
        if std::env::var_os("VORANG_TIMING").is_some() {
            let (pw, ph) = (width.div_ceil(self.factor), height.div_ceil(self.factor));
            self.reporter.info(&format!(
                "view: {} previews {pw}×{ph} {}: {}; {} refined {width}×{height} {}: {}",
                self.times.0.len(),
                if self.session.backend().is_gpu() {
                    "interpolateCoeff linear (GPU)"
                } else {
                    "interpolateColor"
                },
                summary(&mut self.times.0),
                self.times.1.len(),
                method_command(&self.method).trim_start_matches("method "),
                summary(&mut self.times.1)
            ));
        }
        self.session.set_view(self.orbit.view());
        self.session.set_method(self.method);
    }
}

/// "median 41 ms (24.4 frames/s), 35…60 ms" of frame times in seconds.
fn summary(times: &mut [f64]) -> String {
    if times.is_empty() {
        return "none".into();
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    format!(
        "median {:.0} ms ({:.1} frames/s), {:.0}…{:.0} ms",
        median * 1e3,
        1.0 / median,
        times[0] * 1e3,
        times[times.len() - 1] * 1e3
    )
}

#[cfg(test)]
mod tests {
    use crate::display::controls::{BRIGHTNESS_STEP, scale_brightness};
    use crate::display::orbit::Orbit;

    use vorang::render::{LineDraw, Method};
    use vorang::scene::View;
    use vorang::session::commands_for;

    fn unit_box() -> vorang::volume::Volume {
        vorang::volume::jittered_box(48, 0.0, 1)
    }

    #[test]
    /// What `p` prints, run by Tcl, builds the very same view and method (shortest round-trip
    /// numbers read back exactly).
    fn printed_commands_build_the_same_view_and_method() {
        let vol = unit_box();
        let mut runner = crate::script::Runner::new(Box::new(crate::script::Collect::default()));
        let mut o = Orbit::new(&View::default(), &vol, 64, 48).unwrap();
        o.rotate(37.0, -11.0);
        o.zoom_by(1.1 * 1.1);
        o.pan(3.0, 7.0);
        let method = Method::parse(&["exact", "linear", "0", "1.3"]).unwrap();
        let method = scale_brightness(&method, BRIGHTNESS_STEP);
        let view = o.view();
        let script = commands_for(&view, &method, &LineDraw::Off, (64, 48)).join("\n");
        runner.session().set_volume(std::sync::Arc::new(vol));
        runner.run_string(&script, "-e").unwrap();
        let s = runner.session();
        assert_eq!(*s.view(), view);
        assert_eq!(s.settings().method, method);
        assert_eq!((s.settings().width, s.settings().height), (64, 48));
        assert_eq!(s.settings().lines, LineDraw::Off);
    }
}
