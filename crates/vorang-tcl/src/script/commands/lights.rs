//! `addlight`, `removelight` (thesis A.1): the lights the colour method `LIT_EMITTER` shades
//! with ([`vorang::scene::light`]).

use super::{Call, CommandInfo};
use crate::script::Context;
use vorang::scene::Light;

pub const ADDLIGHT: CommandInfo = CommandInfo {
    name: "addlight",
    usage: "r g b dx dy dz",
    summary: "add a light of colour (r, g, b) at infinity in direction (dx, dy, dz) from the origin (world coordinates)",
    details: "The result is the light's number (1, 2, …). Lights shade the colour method LIT_EMITTER: table colour × (ka + Σ light colour × (kd·max(0, n·l) + ks·max(0, n·h)^shininess)), n = −∇f/|∇f|, l towards the light, h the half vector with the direction towards the viewer. Without lights one white light sits at the camera, shining from the eye towards the volume's centre; the first addlight replaces it. Other methods ignore lights.",
    run: |s: &mut Context, c: &Call| {
        c.expect(6..=6)?;
        let [r, g, b, dx, dy, dz] = c.numbers(0, ["r", "g", "b", "dx", "dy", "dz"])?;
        let n = s.session.add_light(Light {
            color: [r, g, b],
            direction: [dx, dy, dz],
        })?;
        Ok(n.to_string())
    },
};

pub const REMOVELIGHT: CommandInfo = CommandInfo {
    name: "removelight",
    usage: "n",
    summary: "remove the n-th added light (1 = the first)",
    details: "Lights keep their numbers in the order added: removing light 1 makes light 2 the new light 1. With the last light removed, the default white light at the camera is back.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=1)?;
        s.session.remove_light(c.count(0, "n")?)?;
        Ok(String::new())
    },
};
