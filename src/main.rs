//! The `vorang` program: runs VoRANG scripts (Tcl with the VoRANG commands), offers an
//! interactive prompt, and inspects, converts and generates HyperMesh files.

use std::io::{IsTerminal, Read};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use vorang::hypermesh::{self, Encoding, Layout, WriteOptions};
use vorang::mapping::{AlphaShading, ColorShading, read_map};
use vorang::render::{LineDraw, Method};
use vorang::session::Notice;
use vorang::{Error, Volume, info};
use vorang_tcl::script::{Runner, ScriptError, Terminal};

mod ranks;

/// Direct volume rendering of fields on tetrahedral meshes.
///
/// `vorang SCRIPT…` runs scripts; `vorang` alone is an interactive prompt (or reads a script from
/// standard input); `vorang -e 'commands'` runs a string. Scripts are Tcl 8.6 with the VoRANG
/// commands — type `help` at the prompt for the list.
#[derive(Parser)]
#[command(name = "vorang", version, args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Commands to run before the scripts (may be given several times).
    #[arg(short = 'e', long = "eval", value_name = "COMMANDS")]
    eval: Vec<String>,
    /// Scripts to run, in order, in one session.
    scripts: Vec<PathBuf>,
    /// Render every frame as N ranks, threads of this process, each holding its own share of
    /// the volume: the image `mpirun -np N vorang` gives (docs/distributed.md).
    #[arg(long, value_name = "N")]
    virtual_ranks: Option<usize>,
}

#[derive(Subcommand)]
enum Command {
    /// Print what a mesh file holds: counts, bounding box, boundary, materials, fields (by
    /// number and name, with their ranges).
    Info {
        /// A HyperMesh (ASCII or BINARY; volume or data-only), .vtu, .vtk or .msh file.
        file: PathBuf,
        /// Also look for cells that interpenetrate without sharing a face (exact tests on
        /// candidate pairs from a grid, at most 200 per cell); exit status 1 if any are found.
        #[arg(long)]
        check: bool,
    },
    /// Convert a mesh file: any readable format to HyperMesh (ASCII or BINARY, full or small
    /// layout; bin2Asc) or, for an output named *.vtu, to VTK XML (binary appended, zlib); for
    /// *.pvtu, a parallel grid of --pieces .vtu files (input for `mpirun -np N vorang`).
    Convert {
        input: PathBuf,
        output: PathBuf,
        /// For a .pvtu output: this many pieces, cut in the Morton order of the cells.
        #[arg(long, value_name = "N")]
        pieces: Option<usize>,
        /// Write ASCII (the default).
        #[arg(long, conflicts_with = "binary")]
        ascii: bool,
        /// Write BINARY (big-endian).
        #[arg(long)]
        binary: bool,
        /// Small layout: nodes, tetrahedra by nodes, data-carrying elements only.
        #[arg(long)]
        small: bool,
    },
    /// Open the interactive viewer on a mesh: drag turns it, shift-drag pans, the wheel zooms;
    /// keys 1–4 method, +/− brightness, r reset, s save, p print the commands, q quit.
    View {
        /// A mesh file (HyperMesh, .vtu, .vtk, .msh).
        file: PathBuf,
        /// A colormap file (without --colormap and --alphamap: the viridis preset and an
        /// absorption ramp over the first field's range, as `vorang info` suggests).
        #[arg(long, value_name = "FILE")]
        colormap: Option<PathBuf>,
        /// An alphamap file.
        #[arg(long, value_name = "FILE")]
        alphamap: Option<PathBuf>,
        /// The method and its parameters, as for the `method` command (e.g. "exact linear 0
        /// 1"); the keys 1–4 switch it in the window. Default: interpolateCoeff linear, with
        /// brightness 1 (with the preset maps: their χ_max, so that opaque parts show the
        /// preset's colours).
        #[arg(long, value_name = "METHOD")]
        method: Option<String>,
        /// The image size in pixels.
        #[arg(long, num_args = 2, value_names = ["W", "H"])]
        size: Option<Vec<usize>>,
        /// Render on the GPU (`backend gpu`: a build with `--features gpu` and a Vulkan
        /// adapter with 64-bit floats); the default method is then exact linear 0.
        #[arg(long)]
        gpu: bool,
        /// Where `s` saves, numbered like `output` (view.0001.png, …).
        #[arg(long, value_name = "FILE", default_value = "view.png")]
        output: PathBuf,
        /// Draw the grid's edges (off by default in the viewer: on large meshes they hide the
        /// volume).
        #[arg(long)]
        lines: bool,
    },
    /// Write a generated test volume: a jittered box of tetrahedra with a smooth scalar field.
    Generate {
        output: PathBuf,
        /// About how many tetrahedra (6 per cube of an n×n×n grid).
        #[arg(long, default_value_t = 20_000)]
        tets: usize,
        /// Move interior nodes by up to this fraction of a cube (0 … 0.15).
        #[arg(long, default_value_t = 0.1)]
        jitter: f64,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Remove this fraction of the cells at random (0 … 0.5): a non-convex mesh.
        #[arg(long, default_value_t = 0.0)]
        holes: f64,
        /// Write BINARY instead of ASCII.
        #[arg(long)]
        binary: bool,
        /// Full layout (triangles, tetrahedra by triangles) instead of the small one.
        #[arg(long)]
        full: bool,
    },
}

fn print_warnings(w: &[vorang::Warning]) {
    for w in w {
        eprintln!("{w}");
    }
}

/// Runs a subcommand; `Ok(false)` where it found problems to report by the exit status.
fn data_command(command: Command) -> Result<bool, Error> {
    match command {
        Command::Info { file, check } => {
            let (described, warnings) = vorang::formats::describe_file(&file)?;
            print_warnings(&warnings);
            let (text, clean) = info::describe(&described, check);
            print!("{text}");
            if !clean {
                return Ok(false);
            }
        }
        Command::Convert {
            input,
            output,
            pieces,
            ascii,
            binary,
            small,
        } => {
            let (vol, warnings) = Volume::load(&input)?;
            print_warnings(&warnings);
            if output.extension().is_some_and(|e| e == "pvtu") {
                let n = pieces.unwrap_or(1).max(1);
                let cut = vorang::distributed::write::morton_pieces(&vol, n);
                let w = vorang::distributed::write::write_pvtu(&vol, &output, &cut)?;
                print_warnings(&w);
                eprintln!(
                    "wrote {} ({n} piece{}, {} tetrahedra)",
                    output.display(),
                    if n == 1 { "" } else { "s" },
                    vol.mesh.tet_count()
                );
                return Ok(true);
            }
            if pieces.is_some() {
                return Err(Error::Invalid(format!(
                    "--pieces: only a .pvtu output is written in pieces, not {}",
                    output.display()
                )));
            }
            let format = vorang::formats::format_for_writing(&output);
            let hypermesh_out = format.name == "HyperMesh";
            if !hypermesh_out && (ascii || binary || small) {
                return Err(Error::Invalid(format!(
                    "--ascii, --binary and --small choose the HyperMesh encoding and layout; {} is written as {} (binary appended, zlib)",
                    output.display(),
                    format.name
                )));
            }
            let opts = WriteOptions {
                encoding: if binary {
                    Encoding::Binary
                } else {
                    Encoding::Ascii
                },
                layout: if small { Layout::Small } else { Layout::Full },
            };
            let warnings = vorang::formats::save_volume(&vol, &output, opts)?;
            print_warnings(&warnings);
            let how = if hypermesh_out {
                format!(
                    "{} {}",
                    opts.encoding.keyword(),
                    if small { "small" } else { "full" }
                )
            } else {
                format.name.to_string()
            };
            eprintln!(
                "wrote {} ({how}, {} nodes, {} tetrahedra, {} fields)",
                output.display(),
                vol.mesh.node_count(),
                vol.mesh.tet_count(),
                vol.data.fields.len()
            );
        }
        // The viewer runs script commands: `main` hands it to a script runner.
        Command::View { .. } => unreachable!("vorang view is run by main"),
        Command::Generate {
            output,
            tets,
            jitter,
            seed,
            holes,
            binary,
            full,
        } => {
            if !(0.0..=0.15).contains(&jitter) {
                return Err(Error::Invalid(format!(
                    "--jitter {jitter}: expected a value in 0 … 0.15"
                )));
            }
            if !(0.0..=0.5).contains(&holes) {
                return Err(Error::Invalid(format!(
                    "--holes {holes}: expected a fraction in 0 … 0.5"
                )));
            }
            let vol = vorang::volume::jittered_box_with_holes(tets, jitter, seed, holes);
            let opts = WriteOptions {
                encoding: if binary {
                    Encoding::Binary
                } else {
                    Encoding::Ascii
                },
                layout: if full { Layout::Full } else { Layout::Small },
            };
            hypermesh::save_volume(&vol, &output, opts)?;
            eprintln!(
                "wrote {} ({} nodes, {} tetrahedra)",
                output.display(),
                vol.mesh.node_count(),
                vol.mesh.tet_count()
            );
        }
    }
    Ok(true)
}

/// `file:line: message`, then Tcl's trace where it says more: the calls (procedures, sourced
/// files, loop bodies) that led there, without repeating the message or the failing command
/// the first line already locates.
fn report(e: &ScriptError) {
    eprintln!("{e}");
    let trace = e.trace.strip_prefix(e.message.as_str()).unwrap_or(&e.trace);
    if trace.contains("invoked from within") {
        eprintln!("Tcl trace:");
        for line in trace.lines().filter(|l| !l.trim().is_empty()) {
            eprintln!("    {line}");
        }
    }
}

/// Tab completion at the prompt: command names where a command starts, file names elsewhere.
struct PromptHelper {
    /// Tcl's and VoRANG's commands, refreshed before each line (procs appear as defined).
    commands: Vec<String>,
    files: rustyline::completion::FilenameCompleter,
}

impl rustyline::completion::Completer for PromptHelper {
    type Candidate = rustyline::completion::Pair;

    fn complete(
        &self,
        line: &str,
        pos: usize,
        ctx: &rustyline::Context<'_>,
    ) -> rustyline::Result<(usize, Vec<Self::Candidate>)> {
        let names = self.commands.iter().map(String::as_str);
        match vorang_tcl::script::complete::commands_at(line, pos, names) {
            Some((start, found)) => Ok((
                start,
                found
                    .into_iter()
                    .map(|n| rustyline::completion::Pair {
                        display: n.clone(),
                        replacement: n,
                    })
                    .collect(),
            )),
            None => self.files.complete(line, pos, ctx),
        }
    }
}

impl rustyline::hint::Hinter for PromptHelper {
    type Hint = String;
}
impl rustyline::highlight::Highlighter for PromptHelper {}
impl rustyline::validate::Validator for PromptHelper {}
impl rustyline::Helper for PromptHelper {}

/// Ctrl-C during a render cancels it; otherwise it ends the program (exit status 130, as the
/// default action would report it).
#[cfg(unix)]
extern "C" fn interrupted(_: libc::c_int) {
    if !vorang_tcl::script::interrupt::on_interrupt() {
        // SAFETY: _exit is async-signal-safe.
        unsafe { libc::_exit(130) };
    }
}

#[cfg(unix)]
fn catch_interrupts() {
    let handler = interrupted as extern "C" fn(libc::c_int);
    // SAFETY: the handler only touches atomics and calls _exit.
    unsafe { libc::signal(libc::SIGINT, handler as libc::sighandler_t) };
}

#[cfg(not(unix))]
fn catch_interrupts() {}

/// What the prompt asks of its line-editing thread.
enum Ask {
    /// Read a line with this prompt, completing these command names.
    Line(&'static str, Vec<String>),
    History(String),
}

/// How often the prompt lets Tcl handle events while it waits for a line.
const PROMPT_EVENTS: std::time::Duration = std::time::Duration::from_millis(30);

/// The interactive prompt: commands and Tcl, with line editing, history and tab completion.
///
/// The line editor runs on a thread of its own, so that while it waits for the user this
/// (the Tcl) thread keeps handling Tcl's and Tk's events: an `online` window or a viewer left
/// open stays drawn, and `after` timers fire.
fn prompt(runner: &mut Runner) -> ExitCode {
    println!(
        "VoRANG {} — Tcl with the VoRANG commands; 'help' lists them, 'exit' quits.",
        env!("CARGO_PKG_VERSION")
    );
    let (ask, asked) = std::sync::mpsc::channel::<Ask>();
    let (answer, answers) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut editor =
            match rustyline::Editor::<PromptHelper, rustyline::history::DefaultHistory>::new() {
                Ok(e) => e,
                Err(e) => {
                    let _ = answer.send(Err(e));
                    return;
                }
            };
        editor.set_helper(Some(PromptHelper {
            commands: Vec::new(),
            files: rustyline::completion::FilenameCompleter::new(),
        }));
        for a in asked {
            match a {
                Ask::Line(prompt, commands) => {
                    if let Some(helper) = editor.helper_mut() {
                        helper.commands = commands;
                    }
                    if answer.send(editor.readline(prompt)).is_err() {
                        return;
                    }
                }
                Ask::History(entry) => {
                    let _ = editor.add_history_entry(entry);
                }
            }
        }
    });
    catch_interrupts();
    let mut buffer = String::new();
    loop {
        // Tcl's and VoRANG's commands, refreshed before each line (procs appear as defined).
        let commands = runner
            .run_string("info commands", "<prompt>")
            .map(|list| list.split_whitespace().map(str::to_string).collect())
            .unwrap_or_default();
        let _ = ask.send(Ask::Line(
            if buffer.is_empty() {
                "vorang> "
            } else {
                "   ...> "
            },
            commands,
        ));
        let line = loop {
            match answers.recv_timeout(PROMPT_EVENTS) {
                Ok(line) => break line,
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                    // Errors of event handlers are Tcl's to report (bgerror).
                    let _ = runner.run_string("update", "<prompt>");
                }
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                    eprintln!("vorang: the prompt stopped");
                    return ExitCode::FAILURE;
                }
            }
        };
        match line {
            Ok(line) => {
                buffer.push_str(&line);
                buffer.push('\n');
                if !Runner::is_complete(&buffer) {
                    continue;
                }
                let _ = ask.send(Ask::History(buffer.trim_end().to_string()));
                match runner.run_string(&buffer, "<prompt>") {
                    Ok(result) if !result.is_empty() => println!("{result}"),
                    Ok(_) => {}
                    Err(e) => eprintln!("{e}"),
                }
                buffer.clear();
            }
            Err(rustyline::error::ReadlineError::Interrupted) => buffer.clear(),
            Err(rustyline::error::ReadlineError::Eof) => return ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("vorang: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
}

/// `vorang view`: the options set on the session directly, then the viewer on it (the CLI is
/// one more front end of the same session).
fn view(runner: &Runner, command: &Command) -> Result<(), String> {
    let Command::View {
        file,
        colormap,
        alphamap,
        method,
        size,
        gpu,
        output,
        lines,
    } = command
    else {
        return Ok(());
    };
    let mut context = runner.context();
    if *gpu {
        context.session.set_backend("gpu")?;
    }
    let (_, notices) = context.session.load_volume(file)?;
    context.report(notices);
    let mut brightness = 1.0;
    if colormap.is_none()
        && alphamap.is_none()
        && let Some((chi, note)) = context.session.use_preset_maps("view", "viridis")?
    {
        brightness = chi;
        context.report([note]);
    }
    if let Some(path) = colormap {
        let (map, w) = read_map::<dyn ColorShading>(path).map_err(|e| e.to_string())?;
        context.session.set_colormap(map)?;
        context.report(w.iter().map(|w| Notice::Warning(w.to_string())));
    }
    if let Some(path) = alphamap {
        let (map, w) = read_map::<dyn AlphaShading>(path).map_err(|e| e.to_string())?;
        context.session.set_alphamap(map)?;
        context.report(w.iter().map(|w| Notice::Warning(w.to_string())));
    }
    let default_method = if *gpu {
        format!("exact linear 0 {brightness}")
    } else {
        format!("interpolateCoeff linear {brightness}")
    };
    let words: Vec<&str> = method
        .as_deref()
        .unwrap_or(&default_method)
        .split_whitespace()
        .collect();
    context
        .session
        .set_method(Method::parse(&words).map_err(|e| format!("method: {e}"))?);
    if let Some([w, h]) = size.as_deref() {
        context.session.set_image_size(*w, *h)?;
    }
    context.session.set_output(output.clone())?;
    context
        .session
        .set_lines(if *lines { LineDraw::All } else { LineDraw::Off })?;
    let context = &mut *context;
    let tk = context.display.need_tk(runner.interp())?;
    vorang_tcl::display::viewer::run(
        &mut context.session,
        context.reporter.as_mut(),
        tk,
        runner.interp(),
    )
    .map(|_| ())
}

/// `vorang -e 'help method'` and `echo 'help method' | vorang` print the help: the result of
/// such a script is printed when it is what `help` returned (a render's file name is not).
fn print_help_result(runner: &Runner, result: &str) {
    if !result.is_empty() && runner.context().last_help.as_deref() == Some(result) {
        println!("{result}");
    }
}

/// glibc's malloc gives every thread that allocates its own arena (up to eight per core), and
/// memory freed in one arena serves only that arena's threads: the frame's arrays (main thread)
/// and the tiles' buffers (the rayon workers) each keep their own peak resident. One arena per
/// core lets them reuse each other's freed memory: a 1M-cell frame peaked 5 MB lower on two
/// cores, at the same speed (docs/performance.md "Memory"). `MALLOC_ARENA_MAX` in the
/// environment still decides (glibc reads it itself).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn limit_malloc_arenas() {
    if std::env::var_os("MALLOC_ARENA_MAX").is_some() {
        return;
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let arenas = libc::c_int::try_from(cores).unwrap_or(libc::c_int::MAX);
    // SAFETY: mallopt only sets a tunable of the allocator; called before any other thread
    // exists, and glibc ignores values it does not take.
    unsafe {
        libc::mallopt(libc::M_ARENA_MAX, arenas);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn limit_malloc_arenas() {}

fn main() -> ExitCode {
    limit_malloc_arenas();
    let cli = Cli::parse();
    if let Some(command @ Command::View { .. }) = &cli.command {
        let runner = Runner::new(Box::new(Terminal));
        return match view(&runner, command) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("vorang: {e}");
                ExitCode::FAILURE
            }
        };
    }
    if let Some(command) = cli.command {
        return match data_command(command) {
            Ok(true) => ExitCode::SUCCESS,
            Ok(false) => ExitCode::FAILURE,
            Err(e) => {
                eprintln!("vorang: {e}");
                ExitCode::FAILURE
            }
        };
    }
    let launch = match ranks::Launch::start(cli.virtual_ranks) {
        Ok(launch) => launch,
        Err(e) => {
            eprintln!("vorang: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut runner = Runner::new(launch.reporter());
    runner.context().session.set_ranks(launch.ranks());
    let root = launch.is_root();
    if cli.eval.is_empty() && cli.scripts.is_empty() {
        if launch.is_rank() {
            // The launcher gives standard input to one rank only.
            eprintln!(
                "vorang: a rank of an MPI session runs script files or -e: give the script as a file"
            );
            return ExitCode::FAILURE;
        }
        if std::io::stdin().is_terminal() {
            return prompt(&mut runner);
        }
        let mut script = String::new();
        if let Err(e) = std::io::stdin().read_to_string(&mut script) {
            eprintln!("vorang: cannot read standard input: {e}");
            return ExitCode::FAILURE;
        }
        let result = runner
            .run_string(&script, "<stdin>")
            .map(|result| print_help_result(&runner, &result));
        return launch.finish(result, report);
    }
    let mut run = || -> Result<(), ScriptError> {
        for script in &cli.eval {
            let result = runner.run_string(script, "-e")?;
            if root {
                print_help_result(&runner, &result);
            }
        }
        for path in &cli.scripts {
            runner.run_file(path)?;
        }
        Ok(())
    };
    let result = run();
    launch.finish(result, report)
}
