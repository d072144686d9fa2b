//! The VoRANG commands (thesis A.1; docs/commands.md), one table: name, usage, summary, handler. The
//! Tcl registration, `help`, and the "wrong # args" messages all come from it. Commands are
//! grouped in files by what they set.

mod camera;
mod data;
mod help;
mod image;
mod lights;
mod maps;
mod ranks;
mod rendering;
mod series;
mod view;

use std::path::{Path, PathBuf};

use super::Context;
use crate::tcl::Interp;

/// A command handler: edits the session, returns the Tcl result or an error message.
pub type Run = fn(&mut Context, &Call) -> Result<String, String>;

/// One entry of the command table.
pub struct CommandInfo {
    pub name: &'static str,
    /// The arguments, as in `wrong # args: should be "name usage"`.
    pub usage: &'static str,
    pub summary: &'static str,
    /// More help: defaults, choices.
    pub details: &'static str,
    pub run: Run,
}

/// Every VoRANG command, in the order of the thesis's appendix A.
pub const COMMANDS: &[CommandInfo] = &[
    image::IMAGESIZE,
    image::OUTPUT,
    image::SET_NR,
    image::BACKGROUND,
    image::MOVIE,
    data::VOLUME,
    data::DATA,
    data::SAVE_VOLUME,
    data::SAVE_SUBSET,
    series::TIMESTEP,
    series::TIMESTEPS,
    lights::ADDLIGHT,
    lights::REMOVELIGHT,
    maps::COLORMAP,
    maps::ALPHAMAP,
    maps::LINEDRAW,
    maps::LEGEND,
    maps::LABEL,
    camera::PERSP_CAMERA,
    camera::ORTHO_CAMERA,
    camera::VIEW_ALL,
    camera::VOL_SCALE,
    camera::VOL_TRANSLATE,
    camera::VOL_ROTATE,
    camera::LOOK_AT,
    rendering::METHOD,
    rendering::BACKEND,
    rendering::RENDER_BTF,
    rendering::RENDER_FTB,
    ranks::RANK,
    view::VIEW,
    help::HELP,
];

/// One invocation: the words, and access to the interpreter (for list splitting and the
/// current script's folder).
pub struct Call<'a> {
    pub info: &'static CommandInfo,
    interp: &'a Interp,
    words: &'a [String],
}

impl<'a> Call<'a> {
    pub fn new(info: &'static CommandInfo, interp: &'a Interp, words: &'a [String]) -> Call<'a> {
        Call {
            info,
            interp,
            words,
        }
    }

    /// The interpreter running the command (for Tk: the `online` window and the viewer).
    pub fn interp(&self) -> &Interp {
        self.interp
    }

    /// The arguments (without the command name).
    pub fn args(&self) -> &[String] {
        self.words.get(1..).unwrap_or(&[])
    }

    /// `wrong # args: should be "name usage"`.
    pub fn wrong_args(&self) -> String {
        if self.info.usage.is_empty() {
            format!("wrong # args: should be \"{}\"", self.info.name)
        } else {
            format!(
                "wrong # args: should be \"{} {}\"",
                self.info.name, self.info.usage
            )
        }
    }

    /// Checks the number of arguments.
    pub fn expect(&self, counts: impl std::ops::RangeBounds<usize>) -> Result<(), String> {
        if counts.contains(&self.args().len()) {
            Ok(())
        } else {
            Err(self.wrong_args())
        }
    }

    /// Argument `i` as a finite number; the message names the argument `what`.
    pub fn number(&self, i: usize, what: &str) -> Result<f64, String> {
        let word = self.args().get(i).map_or("", |w| w.as_str());
        vorang::numbers::parse_f64(word.trim()).ok_or_else(|| {
            format!(
                "{}: expected a number for \"{what}\" but got \"{word}\"",
                self.info.name
            )
        })
    }

    /// Argument `i` as a whole number ≥ 0.
    pub fn count(&self, i: usize, what: &str) -> Result<usize, String> {
        let word = self.args().get(i).map_or("", |w| w.as_str());
        word.trim().parse::<usize>().map_err(|_| {
            format!(
                "{}: expected a whole number ≥ 0 for \"{what}\" but got \"{word}\"",
                self.info.name
            )
        })
    }

    /// Arguments `start..start+N` as numbers named by `names`.
    pub fn numbers<const N: usize>(
        &self,
        start: usize,
        names: [&str; N],
    ) -> Result<[f64; N], String> {
        let mut out = [0.0; N];
        for (k, name) in names.iter().enumerate() {
            out[k] = self.number(start + k, name)?;
        }
        Ok(out)
    }

    /// Argument `i` as a Tcl list.
    pub fn list(&self, i: usize) -> Result<Vec<String>, String> {
        let word = self.args().get(i).map_or("", |w| w.as_str());
        self.interp
            .split_list(word)
            .map_err(|e| format!("{}: {e}", self.info.name))
    }

    /// The folder of the script being run (the current folder for strings and the prompt).
    pub fn script_dir(&self) -> PathBuf {
        match self.interp.eval("info script") {
            Ok(s) if !s.is_empty() => Path::new(&s)
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default(),
            _ => PathBuf::new(),
        }
    }

    /// Argument `i` as a path, relative to the script's folder (docs/scripts.md).
    pub fn path(&self, i: usize) -> PathBuf {
        let word = self.args().get(i).map_or("", |w| w.as_str());
        let p = Path::new(word);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.script_dir().join(p)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn command_names_are_unique() {
        let mut names: Vec<&str> = COMMANDS.iter().map(|c| c.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), COMMANDS.len());
    }
}
