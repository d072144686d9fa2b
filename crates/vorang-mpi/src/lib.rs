//! VoRANG on MPI: the ranks of `mpirun -np N vorang script.tcl` (or `srun`) as the core's
//! [`Comm`] (docs/distributed.md).
//!
//! Every rank runs the same script on its own session; the session calls the collective steps
//! ([`vorang::distributed`]) and this crate carries them over MPI-3.1 collectives on
//! `MPI_COMM_WORLD`: `MPI_Allreduce` for the agreements and reductions, `MPI_Bcast` for an
//! error's message, `MPI_Alltoall(v)` for the runs and `MPI_Gather(v)` for the pixels. All calls
//! come from the thread that runs the script (MPI is initialised for serialised calls; the
//! renderer's own threads never call MPI).
//!
//! A process started without a launcher is no rank: [`Mpi::start`] then returns `None` and the
//! program runs as the build without MPI does.
//!
//! Ranks that share a node divide its cores among their render threads ([`cores`]).

use std::sync::Mutex;

pub mod cores;

use mpi::Count;
use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::traits::*;

pub use mpi::environment::Universe;
use vorang::distributed::{Comm, Received};

/// Environment variables that a launcher (Open MPI's `mpirun`, PMI/PMIx as `srun` and MPICH
/// set them) gives the processes it starts.
const LAUNCHED: &[&str] = &[
    "OMPI_COMM_WORLD_SIZE",
    "PMIX_RANK",
    "PMI_RANK",
    "PMI_SIZE",
    "MPI_LOCALNRANKS",
];

/// This process as a rank of `MPI_COMM_WORLD`.
pub struct Mpi {
    rank: usize,
    size: usize,
    /// The first failure the ranks agreed on: the failing rank, whether its script had ended
    /// ([`Mpi::finish`]) rather than one command failed, and the message.
    failure: Mutex<Option<Failure>>,
}

/// A failure the ranks agreed on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Failure {
    pub rank: usize,
    /// The failing rank's script had stopped (its error came from [`Mpi::finish`]).
    pub script: bool,
    pub message: String,
}

/// What an agreement carries besides the message: whether it is a script's end.
const COMMAND: u8 = b'C';
const SCRIPT: u8 = b'S';

impl Mpi {
    /// Initialises MPI when a launcher started this process; `None` (MPI untouched) otherwise.
    /// The universe finalises MPI when dropped: keep it until the program ends. Sizes rayon's
    /// pool to this rank's part of its node's cores ([`cores`]): call it before any rayon work.
    pub fn start() -> Option<(Universe, Mpi)> {
        if !LAUNCHED.iter().any(|v| std::env::var_os(v).is_some()) {
            return None;
        }
        let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Serialized)?;
        let world = universe.world();
        cores::divide(&world);
        let mpi = Mpi {
            rank: world.rank() as usize,
            size: world.size() as usize,
            failure: Mutex::new(None),
        };
        Some((universe, mpi))
    }

    fn world(&self) -> SimpleCommunicator {
        SimpleCommunicator::world()
    }

    /// The failure the ranks agreed on, if any.
    pub fn failure(&self) -> Option<Failure> {
        self.failure.lock().ok().and_then(|f| f.clone())
    }

    /// The end of this rank's script, the last agreement of every rank: `outcome` is `Ok` if
    /// the script ran to its end, else its error. A rank that already took part in a failed
    /// agreement must not call it (every rank left at that agreement).
    pub fn finish(&self, outcome: Result<(), String>) -> Result<(), String> {
        self.agree_as(outcome, SCRIPT)
    }

    fn agree_as(&self, outcome: Result<(), String>, kind: u8) -> Result<(), String> {
        let world = self.world();
        let mine = match &outcome {
            Ok(()) => self.size as i32,
            Err(_) => self.rank as i32,
        };
        let mut first = 0i32;
        world.all_reduce_into(&mine, &mut first, SystemOperation::min());
        let first = first as usize;
        if first >= self.size {
            return Ok(());
        }
        // The lowest failing rank tells every rank its message (length first).
        let mut bytes = match &outcome {
            Err(m) if self.rank == first => {
                let mut b = vec![kind];
                b.extend_from_slice(m.as_bytes());
                b
            }
            _ => Vec::new(),
        };
        let mut len = bytes.len() as u64;
        let root = world.process_at_rank(first as i32);
        root.broadcast_into(&mut len);
        let len = len as usize;
        bytes.resize(len + 1, 0);
        root.broadcast_into(&mut bytes[..len]);
        bytes.truncate(len);
        let failure = Failure {
            rank: first,
            script: bytes.first() == Some(&SCRIPT),
            message: String::from_utf8_lossy(bytes.get(1..).unwrap_or_default()).into_owned(),
        };
        let message = failure.message.clone();
        if let Ok(mut f) = self.failure.lock() {
            f.get_or_insert(failure);
        }
        Err(message)
    }
}

/// Counts and displacements (in bytes) of `lens`, as MPI takes them; `None` above 2 GiB in
/// all.
fn layout(lens: impl Iterator<Item = usize>) -> Option<(Vec<Count>, Vec<Count>)> {
    let mut counts = Vec::new();
    let mut displs = Vec::new();
    let mut at: usize = 0;
    for n in lens {
        counts.push(Count::try_from(n).ok()?);
        displs.push(Count::try_from(at).ok()?);
        at = at.checked_add(n)?;
    }
    Count::try_from(at).ok()?;
    Some((counts, displs))
}

/// `len` bytes in a buffer that is never empty: an empty `Vec`'s address is 1, which Open MPI
/// takes for `MPI_IN_PLACE` (and refuses in an all-to-all), so every buffer holds one byte more
/// than it passes.
fn buffer(len: usize) -> Vec<u8> {
    vec![0u8; len + 1]
}

/// A message too large for one MPI call ends the program on every rank (MPI_Abort): no rank is
/// left waiting.
fn too_large(world: &SimpleCommunicator) -> ! {
    eprintln!(
        "vorang: a distributed frame's message is larger than 2 GiB (an MPI count); use more ranks or a smaller image"
    );
    world.abort(1)
}

impl Comm for Mpi {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    fn agree(&self, outcome: Result<(), String>) -> Result<(), String> {
        self.agree_as(outcome, COMMAND)
    }

    fn min_f64(&self, values: &mut [f64]) {
        let send = values.to_vec();
        self.world()
            .all_reduce_into(&send[..], values, SystemOperation::min());
    }

    fn sum_u64(&self, values: &mut [u64]) {
        let send = values.to_vec();
        self.world()
            .all_reduce_into(&send[..], values, SystemOperation::sum());
    }

    fn all_to_all(&self, send: Vec<Vec<u8>>) -> Received {
        let world = self.world();
        let Some((counts, displs)) = layout(send.iter().map(Vec::len)) else {
            too_large(&world)
        };
        let mut recv_counts = vec![0 as Count; self.size];
        world.all_to_all_into(&counts[..], &mut recv_counts[..]);
        let Some((rcounts, rdispls)) = layout(recv_counts.iter().map(|&c| c as usize)) else {
            too_large(&world)
        };
        let sent: usize = send.iter().map(Vec::len).sum();
        // Each rank's part freed as it is copied: the runs are not held twice.
        let mut flat = Vec::with_capacity(sent + 1);
        for part in send {
            flat.extend_from_slice(&part);
        }
        flat.push(0);
        let total = rcounts.iter().map(|&c| c as usize).sum();
        let mut recv = buffer(total);
        {
            let out = Partition::new(&flat[..sent], &counts[..], &displs[..]);
            let mut into = PartitionMut::new(&mut recv[..total], &rcounts[..], &rdispls[..]);
            world.all_to_all_varcount_into(&out, &mut into);
        }
        recv.truncate(total);
        Received {
            bytes: recv,
            ranges: rcounts
                .iter()
                .zip(&rdispls)
                .map(|(&c, &d)| d as usize..(d + c) as usize)
                .collect(),
        }
    }

    fn gather(&self, mine: Vec<u8>) -> Option<Vec<Vec<u8>>> {
        let world = self.world();
        let root = world.process_at_rank(0);
        let Ok(len) = Count::try_from(mine.len()) else {
            too_large(&world)
        };
        let n = mine.len();
        let mut mine = mine;
        mine.push(0);
        if self.rank != 0 {
            root.gather_into(&len);
            root.gather_varcount_into(&mine[..n]);
            return None;
        }
        let mut lens = vec![0 as Count; self.size];
        root.gather_into_root(&len, &mut lens[..]);
        let Some((counts, displs)) = layout(lens.iter().map(|&c| c as usize)) else {
            too_large(&world)
        };
        let total = counts.iter().map(|&c| c as usize).sum();
        let mut all = buffer(total);
        {
            let mut into = PartitionMut::new(&mut all[..total], &counts[..], &displs[..]);
            root.gather_varcount_into_root(&mine[..n], &mut into);
        }
        Some(
            counts
                .iter()
                .zip(&displs)
                .map(|(&c, &d)| all[d as usize..(d + c) as usize].to_vec())
                .collect(),
        )
    }
}
