//! `addlight`, `removelight` (thesis A.1): lights are stored and listed; no shading method uses
//! them yet (the thesis reserved them too).

use super::{Call, CommandInfo};
use crate::script::{Light, Session};

pub const ADDLIGHT: CommandInfo = CommandInfo {
    name: "addlight",
    usage: "r g b dx dy dz",
    summary: "add a light at infinity shining from direction (dx, dy, dz)",
    details: "Lights are stored (the result is their number) but no shading method uses them yet: the gradient-shaded method that will is planned. Without lights a default light sits at the camera.",
    run: |s: &mut Session, c: &Call| {
        c.expect(6..=6)?;
        let [r, g, b, dx, dy, dz] = c.numbers(0, ["r", "g", "b", "dx", "dy", "dz"])?;
        if [dx, dy, dz] == [0.0; 3] {
            return Err("addlight: the direction must not be zero".into());
        }
        s.lights.push(Light {
            color: [r, g, b],
            direction: [dx, dy, dz],
        });
        Ok(s.lights.len().to_string())
    },
};

pub const REMOVELIGHT: CommandInfo = CommandInfo {
    name: "removelight",
    usage: "n",
    summary: "remove the n-th added light (1 = the first)",
    details: "The default light at the camera has no number.",
    run: |s: &mut Session, c: &Call| {
        c.expect(1..=1)?;
        let n = c.count(0, "n")?;
        if n == 0 || n > s.lights.len() {
            return Err(format!(
                "removelight: there is no light {n} ({} added)",
                s.lights.len()
            ));
        }
        s.lights.remove(n - 1);
        Ok(String::new())
    },
};
