//! The `vorang` program: renders volume scripts and converts/inspects HyperMesh files.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use vorang::hypermesh::{self, Encoding, Layout, WriteOptions};
use vorang::{Error, Volume, info};

#[derive(Parser)]
#[command(
    name = "vorang",
    version,
    about = "Direct volume rendering of fields on tetrahedral meshes"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
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
        /// Write BINARY instead of ASCII.
        #[arg(long)]
        binary: bool,
        /// Full layout (triangles, tetrahedra by triangles) instead of the small one.
        #[arg(long)]
        full: bool,
    },
    /// Print what a HyperMesh file holds: counts, bounding box, boundary, materials, fields.
    Info {
        /// A HyperMesh file (ASCII or BINARY; volume or data-only).
        file: PathBuf,
    },
    /// Convert a HyperMesh file between ASCII and BINARY, full and small layout (bin2Asc).
    Convert {
        input: PathBuf,
        output: PathBuf,
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
}

fn print_warnings(w: &[vorang::Warning]) {
    for w in w {
        eprintln!("{w}");
    }
}

fn run(cli: Cli) -> Result<(), Error> {
    match cli.command {
        Command::Generate {
            output,
            tets,
            jitter,
            seed,
            binary,
            full,
        } => {
            if !(0.0..=0.15).contains(&jitter) {
                return Err(Error::Invalid(format!(
                    "--jitter {jitter}: expected a value in 0 … 0.15"
                )));
            }
            let vol = vorang::volume::jittered_box(tets, jitter, seed);
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
        Command::Info { file } => {
            let f = hypermesh::read_file(&file)?;
            print_warnings(&f.warnings);
            let text = if f.geometry.is_some() {
                let encoding = format!("{} {}", f.encoding.keyword(), f.version);
                let vol = Volume::from_file(f)?;
                info::describe_volume(&vol, &encoding)
            } else {
                info::describe_data_file(&f)
            };
            print!("{text}");
        }
        Command::Convert {
            input,
            output,
            binary,
            small,
            ..
        } => {
            let (vol, warnings) = Volume::load(&input)?;
            print_warnings(&warnings);
            let opts = WriteOptions {
                encoding: if binary {
                    Encoding::Binary
                } else {
                    Encoding::Ascii
                },
                layout: if small { Layout::Small } else { Layout::Full },
            };
            hypermesh::save_volume(&vol, &output, opts)?;
            eprintln!(
                "wrote {} ({} {}, {} nodes, {} tetrahedra, {} fields)",
                output.display(),
                opts.encoding.keyword(),
                if small { "small" } else { "full" },
                vol.mesh.node_count(),
                vol.mesh.tet_count(),
                vol.data.fields.len()
            );
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("vorang: {e}");
            ExitCode::FAILURE
        }
    }
}
