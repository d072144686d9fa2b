//! One frame on every rank (docs/distributed.md): this rank's cells rendered into runs
//! ([`crate::render::deep`]), the runs sent to the owners of their pixels, the owned pixels
//! settled, the image gathered on rank 0.
//!
//! The collective steps, in the order every rank takes them: agree that the frame could be set
//! up, combine the grid lines' depths; agree that the runs were drawn; the all-to-all of the
//! runs; agree that the pixels were settled; the gather of the pixels; the gather of every
//! rank's statistics and load. A rank that fails before one of the agreements still takes it (with its error),
//! so every rank leaves at the same step with the same message.

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use super::Comm;
use super::exchange::{assemble, pack, settle};
use crate::error::Error;
use crate::framebuffer::{Background, Framebuffer};
use crate::mapping::Mapping;
use crate::render::deep::{Resolver, non_finite, render_runs};
use crate::render::{LineDraw, RankLoad, Settings, Stats};
use crate::scene::View;
use crate::volume::Volume;

/// `result` on every rank if every rank passed `Ok`, else every rank's error is the message of
/// the lowest failing rank.
pub fn agreed<T>(comm: &dyn Comm, result: Result<T, Error>) -> Result<T, Error> {
    match result {
        Ok(v) => {
            comm.agree(Ok(())).map_err(Error::Invalid)?;
            Ok(v)
        }
        Err(e) => Err(Error::Invalid(
            comm.agree(Err(e.to_string())).err().unwrap_or_default(),
        )),
    }
}

/// Renders one frame of a distributed session: `vol` is this rank's piece, `mapping` bound to
/// it. Rank 0 gets the image and the statistics of all ranks; the others `None`. An error on
/// any rank is every rank's error.
pub fn render_frame(
    comm: &dyn Comm,
    vol: &Volume,
    mapping: &Mapping,
    view: &View,
    settings: &Settings,
    cancel: &AtomicBool,
) -> Result<Option<(Framebuffer, Stats)>, Error> {
    let size = (settings.width, settings.height);
    // Set when the line step's agreement failed: every rank left there.
    let mut left = false;
    let mut lines = |local: Result<Option<Vec<f64>>, Error>| {
        let local = agreed(comm, local).inspect_err(|_| left = true)?;
        if settings.lines == LineDraw::Off {
            return Ok(None);
        }
        let mut depths = local.unwrap_or_else(|| vec![f64::INFINITY; size.0 * size.1]);
        comm.min_f64(&mut depths);
        Ok(Some(depths))
    };
    let drawn = render_runs(vol, mapping, view, settings, &mut lines, cancel);
    if left {
        return Err(drawn.err().unwrap_or_else(|| Error::Invalid(String::new())));
    }
    let ready = drawn.and_then(|mut deep| {
        let resolver = Resolver::new(settings, deep.line_depth.take())?;
        Ok((deep, resolver))
    });
    let (deep, resolver) = agreed(comm, ready)?;
    let started = Instant::now();
    let (rank, ranks) = (comm.rank(), comm.size());
    let runs: u64 = deep.tiles.iter().map(|t| t.stretches.len() as u64).sum();
    let messages = pack(deep.tiles, ranks);
    let bytes_sent: u64 = messages
        .iter()
        .enumerate()
        .filter(|(to, _)| *to != rank)
        .map(|(_, m)| m.len() as u64)
        .sum();
    let incoming = comm.all_to_all(messages);
    let settled = agreed(
        comm,
        settle(&incoming.parts(), rank, ranks, size, &resolver),
    )?;
    drop(incoming);
    let gathered = comm.gather(settled);
    let s = &deep.stats;
    let t = s.timing;
    let render = t.setup + t.sort + t.bin + t.draw;
    // Every rank's numbers to rank 0: the sums of the statistics, and each rank's load.
    let mine = [
        s.cells as u64,
        s.drawn as u64,
        s.fragments,
        s.lane_fragments,
        s.cycle_cells as u64,
        render.as_nanos() as u64,
        runs,
        bytes_sent,
        started.elapsed().as_nanos() as u64,
    ];
    let loads = comm.gather(mine.iter().flat_map(|v| v.to_le_bytes()).collect());
    let (Some(gathered), Some(loads)) = (gathered, loads) else {
        return Ok(None);
    };
    let loads: Vec<[u64; 9]> = loads
        .iter()
        .map(|b| {
            std::array::from_fn(|k| {
                b.get(8 * k..8 * k + 8)
                    .and_then(|v| v.try_into().ok())
                    .map_or(0, u64::from_le_bytes)
            })
        })
        .collect();
    let sums: [u64; 5] = std::array::from_fn(|k| loads.iter().map(|l| l[k]).sum());
    let (mut fb, [overlap_pixels, most, opaque_pixels]) = assemble(&gathered, size)?;
    fb.transparent = matches!(settings.background, Background::None);
    let (non_finite, first_non_finite) = non_finite(&fb);
    let mut timing = s.timing;
    timing.composite = started.elapsed();
    let stats = Stats {
        cells: sums[0] as usize,
        drawn: sums[1] as usize,
        fragments: sums[2],
        lane_fragments: sums[3],
        sort: s.sort,
        convex: false,
        cycle_cells: sums[4] as usize,
        per_pixel: true,
        most_runs: most as usize,
        non_finite,
        first_non_finite,
        overlap_pixels: overlap_pixels as usize,
        overlap_cells: Vec::new(),
        opaque_pixels: opaque_pixels as usize,
        timing,
        ranks: loads
            .iter()
            .map(|l| RankLoad {
                render: Duration::from_nanos(l[5]),
                fragments: l[2],
                runs: l[6],
                bytes_sent: l[7],
                composite: Duration::from_nanos(l[8]),
            })
            .collect(),
    };
    Ok(Some((fb, stats)))
}

/// A frame rendered by virtual ranks: one thread per piece (rank r holds `pieces[r]`), each
/// binding the maps to its piece and taking the very steps of [`render_frame`] through
/// [`Threads`](super::Threads) — what `mpirun -np N` renders, in one process. Returns rank 0's
/// image and statistics.
pub fn render_virtual(
    pieces: &[std::sync::Arc<Volume>],
    maps: (&crate::mapping::ColorMap, &crate::mapping::AlphaMap),
    view: &View,
    settings: &Settings,
    cancel: &AtomicBool,
) -> Result<(Framebuffer, Stats), Error> {
    let ranks = super::Threads::group(pieces.len());
    let results: Vec<Result<Option<(Framebuffer, Stats)>, Error>> = std::thread::scope(|s| {
        let handles: Vec<_> = ranks
            .iter()
            .zip(pieces)
            .map(|(comm, vol)| {
                s.spawn(move || {
                    let bound = Mapping::new(maps.0, maps.1, vol).map_err(Error::from);
                    let (mapping, _) = agreed(comm, bound)?;
                    render_frame(comm, vol, &mapping, view, settings, cancel)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err(Error::Invalid("a virtual rank panicked".into())))
            })
            .collect()
    });
    match results.into_iter().next() {
        Some(Ok(Some(image))) => Ok(image),
        Some(Err(e)) => Err(e),
        _ => Err(Error::Invalid("rank 0 returned no image".into())),
    }
}

/// The pieces rank by rank for `ranks` ranks, of a whole volume cut into `pieces` in memory
/// (each a list of its tets, as a `.pvtu`'s pieces would hold them): every rank's cells
/// ([`super::partition::rank_tets`]) as a volume with the whole's box, nodes numbered by `key`.
pub fn split(
    vol: &Volume,
    pieces: &[Vec<u32>],
    ranks: usize,
    key: &super::partition::NodeKey,
) -> Result<Vec<std::sync::Arc<Volume>>, Error> {
    (0..ranks)
        .map(|r| {
            let tets = super::partition::rank_tets(vol, pieces, r, ranks);
            super::partition::piece(vol, tets, key, vol.mesh.bbox()).map(std::sync::Arc::new)
        })
        .collect()
}
