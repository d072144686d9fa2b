//! A session of many ranks (docs/distributed.md): every rank runs the same script on its own
//! session, holding its own cells of the volume; the frames are rendered together
//! ([`crate::distributed`]) and only rank 0 writes images and movies.
//!
//! The session stands between a script and the collective steps: `volume` reads this rank's
//! share; a command whose outcome can depend on the rank's cells (binding the maps, the grid
//! lines' field, writing on rank 0) ends in an agreement, so that an error on any rank is every
//! rank's error. What depends on the whole volume is combined over the ranks: `view_all` from
//! every rank's extremes, the fields' data ranges (legend, preset maps) at `volume`, and a time
//! series of `.pvtu` steps is read step by step, each rank its share. Commands that would need
//! the whole volume on one rank (`data`, `save_volume`, `save_subset`) say so.
//!
//! [`Ranks::Virtual`] runs the same steps with ranks as threads of this process, each with its
//! own piece: `vorang --virtual-ranks N` renders what `mpirun -np N vorang` renders.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{Notice, Session, fields, warnings};
use crate::distributed::{self, Comm, Threads};
use crate::error::Warning;
use crate::formats::collection::{FieldRanges, Kind, Series};
use crate::volume::Volume;

/// A rank's share of a volume: its piece, the warnings, and with virtual ranks every rank's
/// piece (rank 0's first).
type Share = (Arc<Volume>, Vec<Warning>, Vec<Arc<Volume>>);

/// A time series whose every step is one `.pvtu` grid (a `.pvd`, a `.series` listing
/// `.pvtu` files), which ranks read step by step; `None` for any other file.
fn pvtu_steps(path: &Path) -> Result<Option<Series>, String> {
    let format = crate::formats::format_of_file(path).map_err(|e| e.to_string())?;
    match Kind::of_format(format) {
        None | Some(Kind::Pvtu) | Some(Kind::Steps(_)) => return Ok(None),
        Some(_) => {}
    }
    let series = Series::read(path).map_err(|e| e.to_string())?;
    let pvtu = |p: &std::path::PathBuf| {
        p.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("pvtu"))
    };
    let all = series
        .steps
        .iter()
        .all(|s| matches!(s.parts.as_slice(), [p] if p.within.is_none() && pvtu(&p.path)));
    Ok((all && !series.steps.is_empty()).then_some(series))
}

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

    /// The elementwise minimum of `local` over every rank's piece (virtual ranks: every piece
    /// in this process; one process: its volume), agreed: an error on any rank is every
    /// rank's. Every rank passes numbers of the same length.
    pub(super) fn min_over_pieces(
        &self,
        local: impl Fn(&Volume) -> Result<Vec<f64>, String>,
    ) -> Result<Vec<f64>, String> {
        let fold = |all: Vec<Vec<f64>>| {
            all.into_iter().reduce(|mut a, b| {
                for (x, y) in a.iter_mut().zip(b) {
                    *x = x.min(y);
                }
                a
            })
        };
        match &self.ranks {
            Ranks::Virtual(_) => {
                let all = self
                    .pieces
                    .iter()
                    .map(|p| local(p))
                    .collect::<Result<Vec<_>, _>>()?;
                fold(all).ok_or_else(|| "no rank holds a piece".into())
            }
            Ranks::Comm(c) => {
                let mine = self.volume.as_deref().map(&local);
                let mine = match mine {
                    Some(Ok(v)) => Ok(v),
                    Some(Err(e)) => Err(e),
                    None => Err("no volume loaded (use 'volume FILE' first)".into()),
                };
                c.agree(mine.as_ref().map(|_| ()).map_err(Clone::clone))?;
                // The same length on every rank: the same command on every rank's piece.
                let mut values = mine?;
                c.min_f64(&mut values);
                Ok(values)
            }
            Ranks::One => self.volume.as_deref().map_or_else(
                || Err("no volume loaded (use 'volume FILE' first)".into()),
                local,
            ),
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
    /// rank's), the whole's box agreed on; `None` for one process. A time series whose steps
    /// are `.pvtu` grids (a `.pvd`, a `.series`) shows step 0, each rank reading its share;
    /// `timestep` reads another step's share ([`Session::show_ranked_step`]).
    pub(super) fn load_share(
        &mut self,
        path: &Path,
    ) -> Result<Option<(String, Vec<Notice>)>, String> {
        if matches!(self.ranks, Ranks::One) {
            return Ok(None);
        }
        let steps = self.agree_on(pvtu_steps(path))?;
        let file = steps
            .as_ref()
            .map_or_else(|| path.to_path_buf(), |s| s.steps[0].parts[0].path.clone());
        let (vol, w, pieces) = self.read_share(&file)?;
        let (rank, ranks) = self.rank();
        let mut summary = format!(
            "{} nodes, {} tetrahedra, {} on rank {rank} of {ranks}",
            vol.mesh.node_count(),
            vol.mesh.tet_count(),
            fields(vol.data.fields.len()),
        );
        if let Some(s) = &steps {
            let (t0, t1) = s.time_range();
            summary += &format!(
                "; {} time steps, t = {} … {}",
                s.len(),
                crate::info::num(t0),
                crate::info::num(t1)
            );
        }
        let mut notices = warnings(w);
        notices.extend(self.set_volume(vol));
        self.pieces = pieces;
        self.ranked_steps = steps.map(|s| (Arc::new(s), 0));
        self.ranked_ranges = Some(Arc::new(self.agreed_ranges()?));
        Ok(Some((summary, notices)))
    }

    /// `local` on every rank, agreed: the value where every rank's is `Ok`, else every rank's
    /// error is the first failing rank's.
    fn agree_on<T>(&self, local: Result<T, String>) -> Result<T, String> {
        self.agree(local.as_ref().map(|_| ()).map_err(Clone::clone))?;
        local
    }

    /// This rank's share of `file` (virtual ranks: every rank's, rank 0's first), read by
    /// every rank together.
    fn read_share(&self, file: &Path) -> Result<Share, String> {
        match &self.ranks {
            Ranks::One => Err("one process reads the whole volume".into()),
            Ranks::Comm(c) => {
                let (vol, w) = distributed::load(c.as_ref(), file)?;
                Ok((Arc::new(vol), w, Vec::new()))
            }
            Ranks::Virtual(n) => {
                let group = Threads::group(*n);
                let loaded: Vec<Result<_, String>> = std::thread::scope(|s| {
                    let handles: Vec<_> = group
                        .iter()
                        .map(|comm| s.spawn(move || distributed::load(comm, file)))
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
                Ok((pieces[0].clone(), first.unwrap_or_default(), pieces))
            }
        }
    }

    /// `timestep N` of a distributed time series: every rank reads its share of step `index`;
    /// the scene stays, the maps and grid lines are checked on every rank's share, and on an
    /// error the shown step stays. `None` where the session shows no such series.
    pub(super) fn show_ranked_step(&mut self, index: usize) -> Option<Result<Vec<Notice>, String>> {
        let (series, shown) = self.ranked_steps.clone()?;
        if index >= series.len() {
            return Some(Err(format!(
                "timestep: step {index} is out of range: {} has {}",
                super::display_path(Path::new(&series.source)),
                series.range_text()
            )));
        }
        if index == shown {
            return Some(Ok(Vec::new()));
        }
        let file = series.steps[index].parts[0].path.clone();
        Some(self.read_share(&file).and_then(|(vol, w, pieces)| {
            let old = (
                self.volume.replace(vol),
                std::mem::replace(&mut self.pieces, pieces),
            );
            let checked = self.check_maps(&self.colormap, &self.alphamap);
            if let Err(e) = checked {
                (self.volume, self.pieces) = old;
                return Err(format!("timestep {index}: {e}"));
            }
            self.ranked_steps = Some((series, index));
            self.ranked_ranges = Some(Arc::new(self.agreed_ranges()?));
            Ok(warnings(w))
        }))
    }

    /// Every field's data range per component over every rank's cells (each rank samples
    /// its cells as [`Volume::field_range`] does; the minima and maxima combine exactly).
    fn agreed_ranges(&self) -> Result<FieldRanges, String> {
        let vol = self.volume.clone().ok_or("no volume loaded")?;
        let components: Vec<usize> = vol.data.fields.iter().map(|f| f.components()).collect();
        let width = components.iter().sum::<usize>() * 2;
        let local = |piece: &Volume| {
            let mut out = Vec::with_capacity(width);
            for (i, &k) in components.iter().enumerate() {
                let r = piece.field_range(i).unwrap_or_default();
                for c in 0..k {
                    let (lo, hi) = r
                        .get(c)
                        .copied()
                        .unwrap_or((f64::INFINITY, f64::NEG_INFINITY));
                    out.extend([lo, -hi]);
                }
            }
            Ok(out)
        };
        let all = self.min_over_pieces(local)?;
        let mut at = 0;
        Ok(components
            .iter()
            .map(|&k| {
                let r: Vec<(f64, f64)> = (0..k)
                    .map(|c| (all[at + 2 * c], -all[at + 2 * c + 1]))
                    .collect();
                at += 2 * k;
                Some(r)
            })
            .collect())
    }

    /// The distributed time series' step shown and its time.
    pub(super) fn ranked_step(&self) -> Option<(usize, f64)> {
        self.ranked_steps
            .as_ref()
            .map(|(s, k)| (*k, s.steps[*k].time))
    }

    /// The distributed time series, if the session shows one.
    pub(super) fn ranked_series(&self) -> Option<&Arc<Series>> {
        self.ranked_steps.as_ref().map(|(s, _)| s)
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
