//! Distributed rendering: every rank renders its own cells with the one-process renderer, and
//! the pixels are settled where they are owned (docs/distributed.md).
//!
//! - [`partition`]: which cells a rank holds — a contiguous range of a `.pvtu`'s pieces, or,
//!   with more ranks than pieces, a part of one piece in the Morton order of its cells — and the
//!   piece as a volume whose nodes are numbered by a key every rank shares.
//! - [`load`]: `volume FILE` on one rank: its share read, the whole's bounding box agreed on.
//! - [`exchange`]: the runs each rank sends to the owners of the pixels, and what the owners
//!   send to rank 0 (the bytes of one all-to-all and one gather).
//! - [`frame`]: one frame on every rank: the runs of this rank's cells
//!   ([`crate::render::deep`]), the exchange, the owned pixels settled, the image on rank 0.
//! - [`write`]: a volume written as a `.pvtu` of pieces (input for the ranks).
//!
//! The ranks talk through [`Comm`]: MPI in the `vorang` program built with the `mpi` feature
//! (the `vorang-mpi` crate), or [`Threads`] — ranks as threads of one process, the "virtual
//! ranks" that let the tests and `vorang --virtual-ranks N` run the very same steps without MPI.
//! Every step that can fail on some ranks only ends in [`Comm::agree`], so that an error on any
//! rank stops all of them with its message and none waits forever for the others.

pub mod exchange;
pub mod frame;
pub mod load;
pub mod partition;
mod threads;
pub mod write;

pub use frame::render_frame;
pub use load::load;
pub use threads::Threads;

/// The collective operations a distributed session needs. Every rank calls the same operations
/// in the same order (the same script); each call returns once every rank has made it.
pub trait Comm: Send + Sync {
    /// This rank (0 … size − 1).
    fn rank(&self) -> usize;
    /// How many ranks there are.
    fn size(&self) -> usize;
    /// Every rank's outcome of a step: `Ok` on every rank only if every rank passed `Ok`,
    /// otherwise every rank gets the message of the lowest failing rank.
    fn agree(&self, outcome: Result<(), String>) -> Result<(), String>;
    /// The elementwise minimum over all ranks, in place (every rank passes the same length).
    fn min_f64(&self, values: &mut [f64]);
    /// The elementwise sum over all ranks, in place.
    fn sum_u64(&self, values: &mut [u64]);
    /// `send[d]` goes to rank `d` (one entry per rank); returns what each rank sent to this
    /// one, by sending rank.
    fn all_to_all(&self, send: Vec<Vec<u8>>) -> Received;
    /// Rank 0 gets every rank's bytes, by rank; the others get `None`.
    fn gather(&self, mine: Vec<u8>) -> Option<Vec<Vec<u8>>>;
}

/// What an all-to-all brought: every rank's message, one after the other in one buffer (by
/// sending rank), so that a large exchange is not held twice.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Received {
    pub bytes: Vec<u8>,
    /// Where each rank's message lies in `bytes`.
    pub ranges: Vec<std::ops::Range<usize>>,
}

impl Received {
    /// Messages one after the other.
    pub fn concat(parts: Vec<Vec<u8>>) -> Received {
        let mut out = Received::default();
        for p in parts {
            let at = out.bytes.len();
            out.bytes.extend_from_slice(&p);
            out.ranges.push(at..out.bytes.len());
        }
        out
    }

    /// Each rank's message.
    pub fn parts(&self) -> Vec<&[u8]> {
        self.ranges.iter().map(|r| &self.bytes[r.clone()]).collect()
    }
}

/// The elementwise maximum over all ranks, through [`Comm::min_f64`].
pub fn max_f64(comm: &dyn Comm, values: &mut [f64]) {
    for v in values.iter_mut() {
        *v = -*v;
    }
    comm.min_f64(values);
    for v in values.iter_mut() {
        *v = -*v;
    }
}
