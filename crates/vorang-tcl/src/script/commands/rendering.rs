//! `method`, `render_btf`, `render_ftb` (thesis A.1 „Berechnungsmethoden“).

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::Instant;

use super::{Call, CommandInfo};
use crate::display::online::show_while_rendering;
use crate::display::{Window, rgba8};
use crate::script::Context;
use crate::tk::Tk;
use vorang::framebuffer::Background;
use vorang::render::{Method, Order, TileSink};
use vorang::session::{Frame, Hooks, timing_line};

pub const METHOD: CommandInfo = CommandInfo {
    name: "method",
    usage: "name ?parameters?",
    summary: "the approximation method: exact integration step brightness | interpolateCoeff integration brightness | interpolateColor brightness | test opacity",
    details: "Default: test 0.5. Integration rules: trapez, constEA, weightedConstEA, linear. 'step' is the largest distance between samples in world units (0: the whole cell interval); 'brightness' scales all emission. The thesis's short names interpolCoeff and interpolColor are accepted for interpolateCoeff and interpolateColor.",
    run: |s: &mut Context, c: &Call| {
        let words: Vec<&str> = c.args().iter().map(String::as_str).collect();
        let method = Method::parse(&words).map_err(|e| format!("method: {e}"))?;
        s.session.set_method(method);
        Ok(String::new())
    },
};

pub const BACKEND: CommandInfo = CommandInfo {
    name: "backend",
    usage: "?cpu|gpu?",
    summary: "which renders the frames: the CPU (default) or the GPU; without an argument returns the current backend and adapter",
    details: "'backend gpu' renders 'exact linear 0 B', 'interpolateCoeff linear B' and 'interpolateColor B' with 64-bit floats in Vulkan compute shaders (a build with '--features gpu' and a Vulkan adapter with shaderFloat64, e.g. lavapipe from mesa-vulkan-drivers); the image is the CPU's up to rounding. Without such an adapter, or in a build without the feature, it is an error saying what is missing. Methods the GPU does not render yet are refused at render time; 'backend cpu' switches back.",
    run: |s: &mut Context, c: &Call| {
        c.expect(0..=1)?;
        match c.args() {
            [] => Ok(s.session.backend().describe()),
            [name] => s.session.set_backend(name),
            _ => unreachable!("at most one argument"),
        }
    },
};

/// A progress bar on standard error, shown for renders running longer than a second when
/// standard error is a terminal.
struct Progress {
    start: Instant,
    shown: Mutex<Option<usize>>,
    enabled: bool,
}

impl Progress {
    fn new() -> Progress {
        Progress {
            start: Instant::now(),
            shown: Mutex::new(None),
            enabled: std::io::stderr().is_terminal(),
        }
    }

    fn update(&self, done: usize, total: usize) {
        if !self.enabled || self.start.elapsed().as_secs_f64() < 1.0 || total == 0 {
            return;
        }
        let percent = done * 100 / total;
        let Ok(mut shown) = self.shown.lock() else {
            return;
        };
        if *shown == Some(percent) {
            return;
        }
        *shown = Some(percent);
        let bar = "#".repeat(percent / 4) + &" ".repeat(25 - percent / 4);
        eprint!("\rrendering [{bar}] {percent:3}%");
        let _ = std::io::stderr().flush();
    }

    fn clear(&self) {
        if self.shown.lock().is_ok_and(|s| s.is_some()) {
            eprint!("\r{}\r", " ".repeat(40));
        }
    }
}

/// Tk for the `online` window: without Tk or a display one warning (the first time), and the
/// image is written to its file as always.
fn online_tk(s: &mut Context, c: &Call) -> Option<Tk> {
    match s.display.tk(c.interp()) {
        Ok(tk) => Some(*tk),
        Err(first) => {
            if let Some(why) = first {
                s.reporter.warn(&format!(
                    "{}: no window for 'online' ({}); the images are written to their files only",
                    c.info.name,
                    why.lines().next().unwrap_or_default()
                ));
            }
            None
        }
    }
}

/// The `online` window, opened for the session's image size.
fn online_window<'a>(s: &mut Context, c: &'a Call, tk: &'a Tk) -> Option<Window<'a>> {
    // A window that cannot be opened (e.g. the script destroyed Tk's main window) costs the
    // picture on the screen, not the render: warn and write the file as without a display.
    let (width, height) = (s.session.settings().width, s.session.settings().height);
    match Window::open(tk, c.interp(), width, height) {
        Ok(w) => Some(w),
        Err(e) => {
            s.reporter.warn(&format!(
                "{}: the online window cannot be opened ({e}); the image is written to its file only",
                c.info.name
            ));
            None
        }
    }
}

/// `render_btf` / `render_ftb`: the session's frame step, with a progress bar, Ctrl-C and,
/// for `online`, the window showing the tiles as they finish.
fn render_command(s: &mut Context, c: &Call, order: Order) -> Result<String, String> {
    c.expect(0..=1)?;
    let online = match c.args().first().map(String::as_str) {
        None | Some("remote") => false,
        Some("online") => true,
        Some(other) => {
            return Err(format!(
                "{}: expected online or remote, found '{other}'",
                c.info.name
            ));
        }
    };
    let mut prepared = s.session.prepare(c.info.name, order, true)?;
    let notices = prepared.take_notices();
    s.report(notices);
    let tk = if online { online_tk(s, c) } else { None };
    let window = tk.as_ref().and_then(|tk| online_window(s, c, tk));
    let progress = Progress::new();
    let started = Instant::now();
    // Ctrl-C cancels the render and keeps the session (script::interrupt).
    let run = |tile: Option<TileSink>| {
        let hooks = Hooks {
            progress: Some(&|d, t| progress.update(d, t)),
            tile,
            cancel: &crate::script::interrupt::CANCEL,
        };
        let rendering = crate::script::interrupt::Rendering::start();
        let result = prepared.render(&hooks);
        drop(rendering);
        result
    };
    let result = match &window {
        Some(window) => {
            let transparent = matches!(prepared.settings.background, Background::None);
            show_while_rendering(window, transparent, |sink| run(Some(sink)))
                .map_err(|e| format!("{}: {e}", c.info.name))?
        }
        None => run(None),
    };
    progress.clear();
    let seconds = started.elapsed().as_secs_f64();
    let image = s.session.finish_image(&mut prepared, result, seconds)?;
    // The window shows exactly what the file holds, legend included.
    if let Some(window) = &window {
        let fb = &image.framebuffer;
        // Only fails if the photo image was deleted meanwhile: nothing left to show.
        let _ = window.put_all(&rgba8(&fb.pixels, fb.transparent));
        window.update();
    }
    let frame = s.session.finish_frame(prepared, image)?;
    let Frame {
        image,
        written,
        summary,
    } = frame;
    s.report(image.notices);
    s.reporter.info(&summary);
    if std::env::var_os("VORANG_TIMING").is_some() {
        s.reporter.info(&timing_line(&image.stats));
    }
    Ok(written.display().to_string())
}

pub const RENDER_BTF: CommandInfo = CommandInfo {
    name: "render_btf",
    usage: "?online|remote?",
    summary: "render back to front and write the next numbered image; prints the file, size, cells, seconds and the largest channel value",
    details: "The largest R/G/B value helps tune the brightness factor: above 1, 8-bit formats clip. 'online' also shows the image in a window titled VoRANG while it renders (1:1, reused by the next online render; Tk and a display needed — without them one warning, and the file is written as always).",
    run: |s: &mut Context, c: &Call| render_command(s, c, Order::BackToFront),
};

pub const RENDER_FTB: CommandInfo = CommandInfo {
    name: "render_ftb",
    usage: "?online|remote?",
    summary: "render front to back (stops early where the volume turns opaque) and write the next numbered image",
    details: "Same image as render_btf up to the early-termination threshold (transparency below 1e-6).",
    run: |s: &mut Context, c: &Call| render_command(s, c, Order::FrontToBack),
};
