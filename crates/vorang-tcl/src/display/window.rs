//! The `online` window: a toplevel titled `VoRANG` that shows one photo image at its pixel
//! size (1:1, no border, no scaling), reused by every `online` render and opened again if the
//! user closed it.

use crate::tcl::Interp;
use crate::tk::Tk;
use vorang::render::Rect;

/// The toplevel's Tk path.
pub const TOPLEVEL: &str = ".vorang";
/// The photo image it shows.
pub const PHOTO: &str = "vorang_online";

/// The `online` window, ready for a `width × height` image.
pub struct Window<'a> {
    tk: &'a Tk,
    interp: &'a Interp,
    width: usize,
    height: usize,
}

impl<'a> Window<'a> {
    /// Opens the window (or finds it again), sized and blanked for a new image.
    pub fn open(
        tk: &'a Tk,
        interp: &'a Interp,
        width: usize,
        height: usize,
    ) -> Result<Window<'a>, String> {
        let script = format!(
            r#"
            if {{[lsearch -exact [image names] {PHOTO}] < 0}} {{ image create photo {PHOTO} }}
            if {{![winfo exists {TOPLEVEL}]}} {{
                toplevel {TOPLEVEL} -borderwidth 0 -highlightthickness 0
                wm title {TOPLEVEL} VoRANG
                label {TOPLEVEL}.image -image {PHOTO} -borderwidth 0 -highlightthickness 0 -padx 0 -pady 0
                pack {TOPLEVEL}.image
            }}
            {PHOTO} blank
            {PHOTO} configure -width {width} -height {height}
            update idletasks
            "#
        );
        interp.eval(&script).map_err(|e| e.message)?;
        Ok(Window {
            tk,
            interp,
            width,
            height,
        })
    }

    /// Shows a tile's 8-bit RGBA pixels (row by row) where the tile lies in the image.
    pub fn put(&self, rect: Rect, rgba: &[u8]) -> Result<(), String> {
        self.tk.put(
            self.interp,
            PHOTO,
            (rect.x0, rect.y0),
            (rect.x1 - rect.x0, rect.y1 - rect.y0),
            rgba,
        )
    }

    /// Shows a whole image.
    pub fn put_all(&self, rgba: &[u8]) -> Result<(), String> {
        self.put(
            Rect {
                x0: 0,
                y0: 0,
                x1: self.width,
                y1: self.height,
            },
            rgba,
        )
    }

    /// Lets Tk handle its events (redraws, window manager, user input).
    pub fn update(&self) {
        // `update` fails only if an event handler of the user's script fails; Tk reports that
        // through `bgerror` itself.
        let _ = self.interp.eval("update");
    }
}
