//! `method`, `render_btf`, `render_ftb` (thesis A.1 „Berechnungsmethoden“).

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::Instant;

use super::{Call, CommandInfo};
use crate::display::online::show_while_rendering;
use crate::display::{Window, rgba8};
use vorang::framebuffer::{Background, format_for, numbered, write_image};
use vorang::legend::{self, ColorScale};
use vorang::mapping::Mapping;
use vorang::render::{Method, Order, Settings, TileSink, Watch, render_watched};
use crate::script::Session;

pub const METHOD: CommandInfo = CommandInfo {
    name: "method",
    usage: "name ?parameters?",
    summary: "the approximation method: exact integration step brightness | interpolateCoeff integration brightness | interpolateColor brightness | test opacity",
    details: "Default: test 0.5. Integration rules: trapez, constEA, weightedConstEA, linear. 'step' is the largest distance between samples in world units (0: the whole cell interval); 'brightness' scales all emission. The thesis's short names interpolCoeff and interpolColor are accepted for interpolateCoeff and interpolateColor.",
    run: |s: &mut Session, c: &Call| {
        let words: Vec<&str> = c.args().iter().map(String::as_str).collect();
        s.settings.method = Method::parse(&words).map_err(|e| format!("method: {e}"))?;
        Ok(String::new())
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

fn render_command(s: &mut Session, c: &Call, order: Order) -> Result<String, String> {
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
    let vol = s
        .volume
        .clone()
        .ok_or_else(|| format!("{}: no volume loaded: use 'volume file' first", c.info.name))?;
    let (mapping, warnings) =
        Mapping::new(&s.colormap, &s.alphamap, &vol).map_err(|e| e.to_string())?;
    for w in warnings {
        s.reporter.warn(&w.to_string());
    }
    if s.movie.is_none() && s.next_number == u32::MAX {
        return Err(format!(
            "{}: the image numbers are used up (the last was {}): use 'set_nr' to start again",
            c.info.name,
            u32::MAX - 1
        ));
    }
    let path = numbered(&s.output, s.next_number);
    format_for(&path).map_err(|e| e.to_string())?;
    let settings = Settings {
        order,
        ..s.settings.clone()
    };
    let progress = Progress::new();
    let started = Instant::now();
    let tk = if online {
        match s.display.tk(c.interp()) {
            Ok(tk) => Some(tk),
            Err(first) => {
                // Issue 14 Decision: one warning, the file only, the exit status unchanged.
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
    } else {
        None
    };
    let view = &s.view;
    // Count only this render's clamped emission (IDENTITY).
    for l in &s.colormap.lines {
        l.method.take_clamped();
    }
    // Ctrl-C cancels the render and keeps the session (script::interrupt).
    let run = |tile: Option<TileSink>| {
        let watch = Watch {
            progress: Some(&|d, t| progress.update(d, t)),
            tile,
            cancel: &crate::script::interrupt::CANCEL,
        };
        let rendering = crate::script::interrupt::Rendering::start();
        let result = render_watched(&vol, &mapping, view, &settings, &watch);
        drop(rendering);
        result
    };
    // A window that cannot be opened (e.g. the script destroyed Tk's main window) costs the
    // picture on the screen, not the render: warn and write the file as without a display.
    let window = tk.and_then(
        |tk| match Window::open(tk, c.interp(), settings.width, settings.height) {
            Ok(w) => Some(w),
            Err(e) => {
                s.reporter.warn(&format!(
                    "{}: the online window cannot be opened ({e}); the image is written to its file only",
                    c.info.name
                ));
                None
            }
        },
    );
    let result = match &window {
        Some(window) => {
            let transparent = matches!(settings.background, Background::None);
            let result = show_while_rendering(window, transparent, |sink| run(Some(sink)))
                .map_err(|e| format!("{}: {e}", c.info.name))?;
            // The tiles covered the image; the whole frame once more makes sure the window
            // holds exactly the file's pixels.
            if let Ok((fb, _)) = &result {
                // Only fails if the photo image was deleted meanwhile: nothing left to show.
                let _ = window.put_all(&rgba8(&fb.pixels, fb.transparent));
                window.update();
            }
            result
        }
        None => run(None),
    };
    progress.clear();
    let (mut fb, stats) = result.map_err(|e| format!("{}: {e}", c.info.name))?;
    let clamped: u64 = s
        .colormap
        .lines
        .iter()
        .map(|l| l.method.take_clamped())
        .sum();
    if clamped > 0 {
        s.reporter.warn(&format!(
            "{}: IDENTITY clamped {clamped} evaluations with negative components to 0 (emission cannot be negative)",
            c.info.name
        ));
    }
    let seconds = started.elapsed().as_secs_f64();
    if let Some(place) = s.legend {
        match ColorScale::of_map(&s.colormap, &vol) {
            Ok(scale) => {
                if !legend::draw(&mut fb, place, &scale) {
                    s.reporter.warn(&format!(
                        "{}: the image is too small for a legend (48 pixels at least)",
                        c.info.name
                    ));
                }
            }
            Err(e) => s.reporter.warn(&format!("{}: no legend: {e}", c.info.name)),
        }
        // The window shows what the file holds, legend included.
        if let Some(window) = &window {
            let _ = window.put_all(&rgba8(&fb.pixels, fb.transparent));
            window.update();
        }
    }
    // While a movie is open the frame goes to it; otherwise the next numbered image.
    let (shown, written) = match &mut s.movie {
        Some(movie) => {
            movie
                .add(&fb)
                .map_err(|e| format!("{}: {e}", c.info.name))?;
            let shown = format!(
                "{} frame {}",
                crate::script::locate_display(&movie.path),
                movie.frames()
            );
            (shown, movie.path.clone())
        }
        None => {
            write_image(&fb, &path).map_err(|e| e.to_string())?;
            s.next_number += 1;
            s.written.push(path.clone());
            (crate::script::locate_display(&path), path)
        }
    };
    if let Some((x, y)) = stats.first_non_finite {
        s.reporter.warn(&format!(
            "{}: {} pixels are NaN or infinite (the first at x {x}, y {y}): an overflow in the data or maps; please report it",
            c.info.name, stats.non_finite
        ));
    }
    if let Some((a, b)) = stats.overlap_cells.first() {
        s.reporter.warn(&format!(
            "{}: cells overlap other cells along {} rays (e.g. cells {} and {}): the mesh has interpenetrating parts, integrated twice there; 'vorang info --check' lists them",
            c.info.name,
            stats.overlap_pixels,
            a + 1,
            b + 1
        ));
    }
    if stats.cycle_cells > 0 {
        // SPEC §4: detect and report. The image is still exact: the order is settled per pixel.
        s.reporter.info(&format!(
            "{}: {} cells were in visibility cycles; ordered per pixel",
            c.info.name, stats.cycle_cells
        ));
    }
    s.reporter.info(&format!(
        "{}  {}×{}  {} cells  {:.3} s  max {}",
        shown,
        fb.width,
        fb.height,
        stats.cells,
        seconds,
        fb.max_channel()
    ));
    if std::env::var_os("VORANG_TIMING").is_some() {
        let t = stats.timing;
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        s.reporter.info(&format!(
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
            vorang::render::span::kernel().name(),
            rayon::current_num_threads()
        ));
    }
    Ok(written.display().to_string())
}

pub const RENDER_BTF: CommandInfo = CommandInfo {
    name: "render_btf",
    usage: "?online|remote?",
    summary: "render back to front and write the next numbered image; prints the file, size, cells, seconds and the largest channel value",
    details: "The largest R/G/B value helps tune the brightness factor: above 1, 8-bit formats clip. 'online' also shows the image in a window titled VoRANG while it renders (1:1, reused by the next online render; Tk and a display needed — without them one warning, and the file is written as always).",
    run: |s: &mut Session, c: &Call| render_command(s, c, Order::BackToFront),
};

pub const RENDER_FTB: CommandInfo = CommandInfo {
    name: "render_ftb",
    usage: "?online|remote?",
    summary: "render front to back (stops early where the volume turns opaque) and write the next numbered image",
    details: "Same image as render_btf up to the early-termination threshold (transparency below 1e-6).",
    run: |s: &mut Session, c: &Call| render_command(s, c, Order::FrontToBack),
};
