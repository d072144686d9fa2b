//! Time series: `timestep`, `timesteps` (the steps of a collection loaded by `volume`,
//! docs/formats.md "Time series and collections").

use super::{Call, CommandInfo};
use crate::script::Context;

/// `{index time}`: the shown step as a Tcl list (times in shortest round-trip form).
fn shown(s: &Context) -> Result<String, String> {
    let (index, time) = s
        .session
        .timestep()
        .ok_or("timestep: no volume loaded: use 'volume file' first")?;
    Ok(format!("{index} {time}"))
}

pub const TIMESTEP: CommandInfo = CommandInfo {
    name: "timestep",
    usage: "?N|last|-time T?",
    summary: "show time step N (0-based) of the collection 'volume' loaded, the last one, or the one nearest time T; returns {index time}",
    details: "Camera, transforms, maps, method and image settings stay (unlike 'volume'); a step with the same points and cells reuses the mesh and loads only its fields. Without arguments returns the shown step as {index time}. On a tie '-time' takes the earlier step. A volume that is no collection is one step at time 0. The maps and linedraw are checked against the new step's fields: on an error the shown step stays.",
    run: |s: &mut Context, c: &Call| {
        c.expect(0..=2)?;
        let index = match c.args() {
            [] => return shown(s),
            [flag, _] if flag == "-time" => {
                let t = c.number(1, "T")?;
                s.session.nearest_timestep(t)?
            }
            [word] if word == "last" => s.session.last_timestep()?,
            [word] => word.trim().parse::<usize>().map_err(|_| {
                let steps = s.session.timesteps().len();
                format!(
                    "timestep: expected a step number 0 … {}, 'last' or '-time T', found \"{word}\"",
                    steps.saturating_sub(1)
                )
            })?,
            _ => return Err(c.wrong_args()),
        };
        let notices = s.session.set_timestep(index)?;
        s.report(notices);
        shown(s)
    },
};

pub const TIMESTEPS: CommandInfo = CommandInfo {
    name: "timesteps",
    usage: "",
    summary: "the times of the steps of the collection 'volume' loaded, as a Tcl list ({0} for a single file)",
    details: "'llength [timesteps]' is the number of steps; 'foreach t [timesteps] {timestep -time $t; render_btf}' renders them all.",
    run: |s: &mut Context, c: &Call| {
        c.expect(0..=0)?;
        if s.session.volume().is_none() {
            return Err("timesteps: no volume loaded: use 'volume file' first".into());
        }
        let times: Vec<String> = s.session.timesteps().iter().map(f64::to_string).collect();
        Ok(times.join(" "))
    },
};
