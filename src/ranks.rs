//! How this process renders: alone, as virtual ranks (`--virtual-ranks N`), or — in a build
//! with the `mpi` feature started by `mpirun` or `srun` — as one rank of a distributed session
//! (docs/distributed.md). Every rank runs the same scripts; only rank 0 prints and writes.

use std::process::ExitCode;
#[cfg(feature = "mpi")]
use std::sync::Arc;

use vorang::session::Ranks;
use vorang_tcl::script::{Quiet, Reporter, ScriptError, Terminal};

/// This process's place among the ranks.
pub struct Launch {
    virtual_ranks: Option<usize>,
    #[cfg(feature = "mpi")]
    mpi: Option<(vorang_mpi::Universe, Arc<vorang_mpi::Mpi>)>,
}

impl Launch {
    /// Starts MPI if a launcher started this process (a build with the `mpi` feature);
    /// `virtual_ranks` asks for ranks as threads instead.
    pub fn start(virtual_ranks: Option<usize>) -> Result<Launch, String> {
        if virtual_ranks == Some(0) {
            return Err("--virtual-ranks: expected at least 1 rank".into());
        }
        #[cfg(feature = "mpi")]
        {
            let mpi = vorang_mpi::Mpi::start().map(|(u, m)| (u, Arc::new(m)));
            if mpi.is_some() && virtual_ranks.is_some() {
                return Err(
                    "--virtual-ranks: not under an MPI launcher (each process already is a rank)"
                        .into(),
                );
            }
            Ok(Launch { virtual_ranks, mpi })
        }
        #[cfg(not(feature = "mpi"))]
        Ok(Launch { virtual_ranks })
    }

    /// Whether this process prints and writes (rank 0, or the only process).
    pub fn is_root(&self) -> bool {
        #[cfg(feature = "mpi")]
        if let Some((_, m)) = &self.mpi {
            return vorang::distributed::Comm::rank(m.as_ref()) == 0;
        }
        true
    }

    /// Whether this process is one rank of an MPI session.
    pub fn is_rank(&self) -> bool {
        #[cfg(feature = "mpi")]
        if self.mpi.is_some() {
            return true;
        }
        false
    }

    /// Who renders the session's frames.
    pub fn ranks(&self) -> Ranks {
        #[cfg(feature = "mpi")]
        if let Some((_, m)) = &self.mpi {
            return Ranks::Comm(Arc::clone(m) as Arc<dyn vorang::distributed::Comm>);
        }
        match self.virtual_ranks {
            Some(n) => Ranks::Virtual(n),
            None => Ranks::One,
        }
    }

    /// Where the session's messages go: the terminal on rank 0, nowhere on the others.
    pub fn reporter(&self) -> Box<dyn Reporter> {
        if self.is_root() {
            Box::new(Terminal)
        } else {
            Box::new(Quiet)
        }
    }

    /// The end of the scripts: with MPI every rank agrees on the outcome (an error on any rank
    /// fails every rank), and rank 0 prints the error — its own, or the message of the rank
    /// whose script failed. `report` prints a script error.
    pub fn finish(self, result: Result<(), ScriptError>, report: fn(&ScriptError)) -> ExitCode {
        #[cfg(feature = "mpi")]
        if let Some((universe, m)) = self.mpi {
            let agreed = match m.failure() {
                // Every rank left at that agreement: none takes another.
                Some(f) => Err(f.message),
                None => m.finish(result.as_ref().map(|_| ()).map_err(|e| e.to_string())),
            };
            if vorang::distributed::Comm::rank(m.as_ref()) == 0 {
                match (&result, m.failure()) {
                    (_, Some(f)) if f.script && f.rank != 0 => eprintln!("{}", f.message),
                    (Err(e), _) => report(e),
                    (Ok(()), Some(f)) => eprintln!("{}", f.message),
                    (Ok(()), None) => {}
                }
            }
            let code = if result.is_err() || agreed.is_err() {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            };
            drop(m);
            drop(universe);
            return code;
        }
        match result {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                report(&e);
                ExitCode::FAILURE
            }
        }
    }
}
