//! `help ?command?`, generated from the command table and the registries.

use super::{COMMANDS, Call, CommandInfo};
use crate::script::Context;

pub const HELP: CommandInfo = CommandInfo {
    name: "help",
    usage: "?command?",
    summary: "list the VoRANG commands, or describe one",
    details: "All of Tcl 8.6 is available too (set, for, foreach, proc, expr, source …).",
    run: |s: &mut Context, c: &Call| {
        c.expect(0..=1)?;
        let text = match c.args().first() {
            None => overview(),
            Some(name) => describe(name)?,
        };
        s.last_help = Some(text.clone());
        Ok(text)
    },
};

fn overview() -> String {
    let width = COMMANDS.iter().map(|c| c.name.len()).max().unwrap_or(0);
    let mut s =
        String::from("VoRANG commands (help <command> for details; all of Tcl works too):\n");
    for c in COMMANDS {
        s.push_str(&format!("  {:width$}  {}\n", c.name, c.summary));
    }
    s.pop();
    s
}

fn describe(name: &str) -> Result<String, String> {
    let c = COMMANDS
        .iter()
        .find(|c| c.name == name)
        .ok_or_else(|| format!("help: no VoRANG command '{name}' (try 'help')"))?;
    let mut s = format!("{} {}\n  {}", c.name, c.usage, c.summary);
    if !c.details.is_empty() {
        s.push_str(&format!("\n  {}", c.details));
    }
    if name == "colormap" {
        for p in vorang::mapping::PRESETS {
            s.push_str(&format!("\n    {}: {}", p.name, p.summary));
        }
    }
    if name == "colormap" || name == "alphamap" {
        s.push_str(&format!("\n  {}", vorang::mapping::COMPLEX_HELP));
    }
    if name == "method" {
        s.push_str("\n  methods:");
        for m in vorang::render::METHODS {
            s.push_str(&format!("\n    {} {}: {}", m.name, m.usage, m.summary));
        }
        s.push_str("\n  integration rules:");
        for r in vorang::integrate::RULES {
            s.push_str(&format!("\n    {}: {}", r.name, r.summary));
        }
    }
    Ok(s)
}
