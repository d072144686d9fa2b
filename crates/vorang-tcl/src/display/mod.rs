//! Windows on the screen: the thesis's `online` display, which shows a render
//! growing tile by tile ([`online`]), and the interactive viewer ([`viewer`]).
//!
//! Tk is single-threaded, so every Tk call stays on the thread that runs the Tcl interpreter;
//! renders run on threads of their own and hand finished pixels back through channels. What a
//! window shows is converted exactly as the 8-bit image files are ([`rgba8`]), so the window and
//! the written file agree pixel for pixel.

pub mod controls;
mod frames;
pub mod legend;
pub mod online;
pub mod orbit;
pub mod viewer;
mod window;

pub use window::Window;

use crate::tcl::Interp;
use crate::tk::Tk;
use vorang::framebuffer::{output_pixel, to_u8};

/// Tk for one session, loaded on first use.
#[derive(Debug, Default)]
pub struct Display {
    tk: Option<Result<Tk, String>>,
}

impl Display {
    /// Tk, loaded into `interp` on the first call. `Err(Some(message))` the first time Tk cannot
    /// be loaded (no display): the caller warns once; `Err(None)` on later calls, which stay
    /// silent.
    pub fn tk(&mut self, interp: &Interp) -> Result<&Tk, Option<String>> {
        let first = self.tk.is_none();
        match self.tk.get_or_insert_with(|| Tk::load(interp)) {
            Ok(tk) => Ok(tk),
            Err(message) if first => Err(Some(message.clone())),
            Err(_) => Err(None),
        }
    }

    /// Tk for a window that cannot go without one (the viewer): without it an error that says
    /// why.
    pub fn need_tk(&mut self, interp: &Interp) -> Result<Tk, String> {
        self.tk(interp).copied().map_err(|why| {
            format!(
                "view: no window can be opened{}",
                why.map(|w| format!(" ({})", w.lines().next().unwrap_or_default()))
                    .unwrap_or_default()
            )
        })
    }
}

/// Float pixels as the 8-bit RGBA a window shows: what an 8-bit file of a framebuffer that is
/// `transparent` or not holds ([`vorang::framebuffer::Framebuffer::to_rgba8`]), but opaque — a
/// window has nothing to show through, so straight colour is shown as it is.
pub fn rgba8(pixels: &[[f32; 4]], transparent: bool) -> Vec<u8> {
    pixels
        .iter()
        .flat_map(|p| {
            let o = output_pixel(p, transparent);
            [to_u8(o[0]), to_u8(o[1]), to_u8(o[2]), 255]
        })
        .collect()
}
