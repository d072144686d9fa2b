//! A session of many ranks (docs/distributed.md): every rank runs the same script on its own
//! session, holding its own cells of the volume; the frames are rendered together
//! ([`crate::distributed`]) and only rank 0 writes images and movies.
//!
//! The session stands between a script and the collective steps: `volume` reads this rank's
//! share; a command whose outcome can depend on the rank's cells (binding the maps, the grid
//! lines' field, writing on rank 0) ends in an agreement, so that an error on any rank is every
//! rank's error; commands that would need the whole volume on one rank (`data`, `save_volume`,
//! `view_all`, time steps, …) say so.
//!
//! [`Ranks::Virtual`] runs the same steps with ranks as threads of this process, each with its
//! own piece: `vorang --virtual-ranks N` renders what `mpirun -np N vorang` renders.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{Notice, Session, fields, warnings};
use crate::distributed::{self, Comm, Threads};
use crate::volume::Volume;

/// Who renders a session's frames.
#[derive(Clone, Default)]
pub enum Ranks {
    /// This process alone (the default).
    #[default]
    One,
    /// This many ranks as threads of this process, each holding its own piece.
    Virtual(usize),
    /// This process as one rank of a distributed session (MPI).
    Comm(Arc<dyn Comm>),
}

impl Session {
    /// Makes the session one of many ranks (or virtual ranks); set before the first `volume`.
    pub fn set_ranks(&mut self, ranks: Ranks) {
        self.ranks = ranks;
    }

    /// This rank and the number of ranks: `(0, 1)` for one process.
    pub fn rank(&self) -> (usize, usize) {
        match &self.ranks {
            Ranks::One => (0, 1),
            Ranks::Virtual(n) => (0, *n),
            Ranks::Comm(c) => (c.rank(), c.size()),
        }
    }

    /// Whether this rank writes the images, movies and per-frame lines (rank 0, or one process).
    pub fn is_root(&self) -> bool {
        self.rank().0 == 0
    }

    /// Whether the frames are rendered by ranks (real or virtual) rather than one process.
    pub fn is_distributed(&self) -> bool {
        !matches!(self.ranks, Ranks::One)
    }

    /// `outcome` on every rank if every rank's is `Ok`, else every rank's error is the first
    /// failing rank's (one process: `outcome` itself).
    pub fn agree(&self, outcome: Result<(), String>) -> Result<(), String> {
        match &self.ranks {
            Ranks::Comm(c) => c.agree(outcome),
            _ => outcome,
        }
    }

    /// `check` on every rank's piece (virtual ranks: every piece in this process), agreed: the
    /// first failing rank's error. Without a volume nothing is checked.
    pub(super) fn on_every_piece(
        &self,
        check: impl Fn(&Volume) -> Result<(), String>,
    ) -> Result<(), String> {
        match &self.ranks {
            Ranks::Virtual(_) => self.pieces.iter().try_for_each(|p| check(p)),
            _ => self.agree(self.volume.as_deref().map_or(Ok(()), check)),
        }
    }

    /// The error of a command that needs the whole volume on one rank.
    pub(super) fn whole_volume_only(&self, command: &str) -> Result<(), String> {
        if self.is_distributed() {
            return Err(format!(
                "{command}: not available in a distributed session (each rank holds part of the volume; docs/distributed.md)"
            ));
        }
        Ok(())
    }

    /// `volume FILE` of a distributed session: this rank's share (virtual ranks: every
    /// rank's), the whole's box agreed on; `None` for one process.
    pub(super) fn load_share(
        &mut self,
        path: &Path,
    ) -> Result<Option<(String, Vec<Notice>)>, String> {
        let (vol, w, pieces) = match &self.ranks {
            Ranks::One => return Ok(None),
            Ranks::Comm(c) => {
                let (vol, w) = distributed::load(c.as_ref(), path)?;
                (Arc::new(vol), w, Vec::new())
            }
            Ranks::Virtual(n) => {
                let group = Threads::group(*n);
                let loaded: Vec<Result<_, String>> = std::thread::scope(|s| {
                    let handles: Vec<_> = group
                        .iter()
                        .map(|comm| s.spawn(move || distributed::load(comm, path)))
                        .collect();
                    handles
                        .into_iter()
                        .map(|h| h.join().unwrap_or_else(|_| Err("a rank panicked".into())))
                        .collect()
                });
                let mut pieces = Vec::new();
                let mut first = None;
                for l in loaded {
                    let (vol, w) = l?;
                    first.get_or_insert(w);
                    pieces.push(Arc::new(vol));
                }
                (pieces[0].clone(), first.unwrap_or_default(), pieces)
            }
        };
        let (rank, ranks) = self.rank();
        let summary = format!(
            "{} nodes, {} tetrahedra, {} on rank {rank} of {ranks}",
            vol.mesh.node_count(),
            vol.mesh.tet_count(),
            fields(vol.data.fields.len()),
        );
        let mut notices = warnings(w);
        notices.extend(self.set_volume(vol));
        self.pieces = pieces;
        Ok(Some((summary, notices)))
    }

    /// `movie FILE` on a rank that does not write: the movie is rank 0's; this rank only
    /// follows it (its name and frames), so that every rank's script sees the same results.
    pub(super) fn follow_movie(&mut self, path: &Path) {
        self.movie_elsewhere = Some((path.to_path_buf(), 0));
    }

    /// A frame on a rank that does not write: what rank 0 writes (the file, or the movie's
    /// next frame) as this rank shows it, the numbers counted alike; `None` without either.
    pub(super) fn follow_frame(&mut self, path: Option<PathBuf>) -> Option<(String, PathBuf)> {
        self.number_set = false;
        if let Some((movie, frames)) = &mut self.movie_elsewhere {
            *frames += 1;
            return Some((
                format!("{} frame {frames}", super::display_path(movie)),
                movie.clone(),
            ));
        }
        let path = path?;
        self.next_number += 1;
        Some((super::display_path(&path), path))
    }

    /// The movie rank 0 writes, as followed by another rank.
    pub(super) fn followed_movie(&self) -> Option<&(PathBuf, usize)> {
        self.movie_elsewhere.as_ref()
    }
}
