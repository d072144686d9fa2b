//! The script language (thesis 4.2 and appendix A; docs/commands.md): real Tcl 8.6 extended by
//! the VoRANG commands.
//!
//! Commands are thin: they parse their words and call a setter of the core's [`Session`];
//! `render_btf` and `render_ftb` call its one frame step (bind the maps, render, legend, write
//! the image) and show the notices it returns. Errors stop the script
//! with `file:line: message`, also inside procs and loop bodies: failing VoRANG commands locate
//! themselves with `info frame`; for errors Tcl raises itself the `errorInfo` trace is walked
//! back to a file line (procedure bodies are located when they are defined).

mod commands;
pub mod complete;
pub mod interrupt;
mod locate;
mod nearest;
pub mod reference;

use std::cell::RefCell;
use std::path::Path;
use std::rc::Rc;

pub use commands::{COMMANDS, CommandInfo};

pub use crate::report::{Collect, Quiet, Reporter, Terminal};
use crate::tcl::Interp;
pub use crate::{tcl, tk};
use vorang::session::{Notice, Session};

/// What the script commands work on: the core's [`Session`] (the typed scene), and what only a
/// script run has — where messages go, the last `help` text, Tk for the windows.
pub struct Context {
    pub session: Session,
    pub reporter: Box<dyn Reporter>,
    /// What `help` last returned: `vorang -e 'help …'` and piped scripts print their result
    /// when it is this text (other results, such as a render's file name, stay quiet).
    pub last_help: Option<String>,
    /// Tk for the `online` window and the viewer, loaded on first use.
    pub display: crate::display::Display,
}

impl Context {
    pub fn new(reporter: Box<dyn Reporter>) -> Context {
        Context {
            session: Session::new(),
            reporter,
            last_help: None,
            display: crate::display::Display::default(),
        }
    }

    /// Shows the session's notices: warnings on the warning channel, notes on the other.
    pub fn report(&mut self, notices: impl IntoIterator<Item = Notice>) {
        for n in notices {
            match n {
                Notice::Warning(t) => self.reporter.warn(&t),
                Notice::Note(t) => self.reporter.info(&t),
            }
        }
    }
}

impl Drop for Context {
    /// A script that ends with a movie open still gets its movie.
    fn drop(&mut self) {
        match self.session.close_movie() {
            Ok(Some((_, note))) => self.report([note]),
            Ok(None) => {}
            Err(e) => self.reporter.warn(&e),
        }
    }
}

/// A path for messages: relative to the current folder when inside it.
pub fn locate_display(path: &Path) -> String {
    vorang::session::display_path(path)
}

/// A script error located in a file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScriptError {
    /// The script file (or `-e`, `<stdin>`) and line of the failing command.
    pub file: String,
    pub line: usize,
    pub message: String,
    /// Tcl's stack trace (`errorInfo`).
    pub trace: String,
}

impl std::fmt::Display for ScriptError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.file, self.line, self.message)
    }
}

impl std::error::Error for ScriptError {}

/// A Tcl interpreter with the VoRANG commands, sharing one session.
pub struct Runner {
    interp: Interp,
    context: Rc<RefCell<Context>>,
    /// Where the last failing VoRANG command was called from: (message, file, line).
    last_failure: Rc<RefCell<Option<(String, String, usize)>>>,
}

/// Tcl set up before any script runs: procedure bodies are recorded where they are defined,
/// so that errors inside them can be traced to a file line.
const PRELUDE: &str = r#"
namespace eval ::vorang { variable procline }
proc ::vorang::proc_defined {cmd op} {
    set f [info frame -2]
    if {![dict exists $f file] || ![dict exists $f line] || ![dict exists $f cmd]} return
    set body [lindex $cmd end]
    set src [dict get $f cmd]
    set at [string last $body $src]
    set skip [expr {$at <= 0 ? 0 : [regexp -all "\n" [string range $src 0 [expr {$at - 1}]]]}]
    set ::vorang::procline([namespace tail [lindex $cmd 1]]) [list [dict get $f file] [expr {[dict get $f line] + $skip}]]
}
trace add execution proc enter ::vorang::proc_defined
# Paths in a script are relative to its folder (docs/scripts.md), for `source` too.
rename ::source ::vorang::tcl_source
proc ::source {args} {
    set path [lindex $args end]
    set here [info script]
    if {$here ne "" && [file pathtype $path] eq "relative"} {
        set path [file join [file dirname $here] $path]
    }
    uplevel 1 [list ::vorang::tcl_source {*}[lrange $args 0 end-1] $path]
}
# An unknown command names the nearest known one ("did you mean …?").
rename ::unknown ::vorang::tcl_unknown
proc ::unknown {args} {
    set code [catch {uplevel 1 [list ::vorang::tcl_unknown {*}$args]} result opts]
    if {$code == 1 && [string match "invalid command name *" $result]} {
        set near [::vorang::nearest [lindex $args 0] [info commands]]
        if {$near ne ""} {
            append result "; did you mean \"$near\"?"
        }
        return -code error -errorcode [dict get $opts -errorcode] $result
    }
    dict incr opts -level
    return -options $opts $result
}
"#;

impl Runner {
    pub fn new(reporter: Box<dyn Reporter>) -> Runner {
        let mut interp = Interp::new();
        let context = Rc::new(RefCell::new(Context::new(reporter)));
        let last_failure = Rc::new(RefCell::new(None));
        interp.register(
            "::vorang::nearest",
            Box::new(|interp: &Interp, words: &[String]| {
                let [_, name, list] = words else {
                    return Err(
                        "wrong # args: should be \"::vorang::nearest name commands\"".into(),
                    );
                };
                let known = interp.split_list(list).map_err(|e| e.to_string())?;
                Ok(nearest::nearest(name, known.iter().map(String::as_str))
                    .unwrap_or("")
                    .to_string())
            }),
        );
        // The prelude is a fixed, valid script.
        let _ = interp.eval(PRELUDE);
        for info in COMMANDS {
            let context = Rc::clone(&context);
            let failure = Rc::clone(&last_failure);
            let run = info.run;
            interp.register(
                info.name,
                Box::new(move |interp: &Interp, words: &[String]| {
                    let call = commands::Call::new(info, interp, words);
                    let result = match context.try_borrow_mut() {
                        Ok(mut s) => run(&mut s, &call),
                        Err(_) => Err(format!(
                            "{} cannot run while another VoRANG command is running",
                            info.name
                        )),
                    };
                    if let Err(message) = &result {
                        let (file, line) = locate::caller(interp);
                        *failure.borrow_mut() = Some((message.clone(), file, line));
                    }
                    result
                }),
            );
        }
        Runner {
            interp,
            context,
            last_failure,
        }
    }

    /// The session the commands edit.
    pub fn session(&self) -> std::cell::RefMut<'_, Session> {
        std::cell::RefMut::map(self.context.borrow_mut(), |c| &mut c.session)
    }

    /// The session with the script run's own state (reporter, `help`, Tk).
    pub fn context(&self) -> std::cell::RefMut<'_, Context> {
        self.context.borrow_mut()
    }

    /// The interpreter (for front ends that open a window on it, e.g. `vorang view`).
    pub fn interp(&self) -> &Interp {
        &self.interp
    }

    /// Runs a script file. Relative paths in it are relative to its folder.
    pub fn run_file(&mut self, path: &Path) -> Result<(), ScriptError> {
        if !path.is_file() {
            return Err(ScriptError {
                file: path.display().to_string(),
                line: 0,
                message: if path.exists() {
                    "not a file".into()
                } else {
                    "no such script file".into()
                },
                trace: String::new(),
            });
        }
        *self.last_failure.borrow_mut() = None;
        self.interp
            .eval_file(path)
            .map(|_| ())
            .map_err(|e| self.locate(e, &path.display().to_string()))
    }

    /// Evaluates a string (`vorang -e`, the prompt); `label` names it in messages.
    pub fn run_string(&mut self, script: &str, label: &str) -> Result<String, ScriptError> {
        *self.last_failure.borrow_mut() = None;
        self.interp.eval(script).map_err(|e| self.locate(e, label))
    }

    fn locate(&self, e: tcl::TclError, label: &str) -> ScriptError {
        let ours = self.last_failure.borrow_mut().take();
        let (file, line) = match ours {
            Some((msg, file, line)) if msg == e.message => (
                if file.is_empty() {
                    label.to_string()
                } else {
                    file
                },
                line,
            ),
            _ => locate::from_trace(&e, label, |name| {
                let entry = self
                    .interp
                    .get_var(&format!("::vorang::procline({name})"))?;
                let parts = self.interp.split_list(&entry).ok()?;
                Some((parts.first()?.clone(), parts.get(1)?.parse().ok()?))
            }),
        };
        ScriptError {
            file: locate::display_path(&file),
            line,
            message: e.message,
            trace: e.info,
        }
    }

    /// True if `text` is a complete Tcl command (for the interactive prompt).
    pub fn is_complete(text: &str) -> bool {
        Interp::complete(text)
    }
}
