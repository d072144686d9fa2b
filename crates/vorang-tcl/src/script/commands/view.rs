//! `view`: the interactive viewer on the current scene.

use super::{Call, CommandInfo};
use crate::script::Context;

pub const VIEW: CommandInfo = CommandInfo {
    name: "view",
    usage: "",
    summary: "open the interactive viewer on the current scene; returns when it is closed, keeping its view and method for the next render",
    details: "Drag turns the volume about its centre, shift-drag pans, the wheel zooms; keys 1–4 choose exact, interpolateCoeff, interpolateColor, test; + and − change the brightness; r resets; s saves the image (numbered like a render); p prints the commands that reproduce the view; q quits. Needs a display (X11).",
    run: |s: &mut Context, c: &Call| {
        c.expect(0..=0)?;
        if s.session.volume().is_none() {
            return Err("view: no volume loaded: use 'volume file' first".into());
        }
        let tk = s.display.need_tk(c.interp())?;
        crate::display::viewer::run(&mut s.session, s.reporter.as_mut(), tk, c.interp())
    },
};
