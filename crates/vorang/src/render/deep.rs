//! A frame kept as runs instead of pixels: what one rank of a distributed frame renders of its
//! own cells, and the one function that settles a pixel from the runs of every rank
//! (docs/distributed.md).
//!
//! A rank holds only some of the cells, and a ray passes the cells of several ranks in any
//! order along its depth. So a rank renders exactly as one process does — the same sort, tiles,
//! faces and methods — with every pixel in per-pixel order ([`super::runs`]), and stops before
//! compositing: each pixel's runs (maximal stretches of the ray inside this rank's cells, each
//! composed into one map `I ↦ I·θ + b`) leave the tile as [`Stretch`]es. Whoever owns the pixel
//! collects the stretches of all ranks, sorts them by depth (equal ones in rank order) and
//! composites them with the formula one process uses for its runs ([`Resolver::pixel`]). The
//! image then depends on which cells each rank holds, never on the order messages arrive or on
//! threads.
//!
//! Grid lines clip every rank's cells at the nearest line of *any* rank, so the line depths are
//! combined across ranks before the tiles are drawn (the `lines` step of [`render_runs`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use super::approx::Method;
use super::frame::{Backdrop, Frame};
use super::raster::Rect;
use super::runs::{Stretch, back_to_front, by_depth, overlap};
use super::schedule::{
    CANCELLED, Stats, Timing, backdrop, bin_cells, build_frame, line_depth, lit_mapping, map_once,
    non_finite_pixels, place_nodes, sort_cells,
};
use super::settings::{Settings, check_size};
use super::tile::{pixel_out, render_tile_runs};
use crate::error::Error;
use crate::framebuffer::Framebuffer;
use crate::mapping::Mapping;
use crate::scene::View;
use crate::volume::Volume;

/// The edge length of a distributed frame's tiles: the tiles a rank draws are the tiles whose
/// pixels one rank owns, whatever the number of threads.
pub const DEEP_TILE: usize = 64;

/// How many [`DEEP_TILE`] tiles an image has across and down.
pub fn deep_tiles(width: usize, height: usize) -> (usize, usize) {
    (width.div_ceil(DEEP_TILE), height.div_ceil(DEEP_TILE))
}

/// Tile `t`'s pixels (tiles row by row; the last row and column may be cut off by the image).
pub fn deep_rect(t: usize, width: usize, height: usize) -> Rect {
    let tx = width.div_ceil(DEEP_TILE);
    Rect {
        x0: (t % tx) * DEEP_TILE,
        y0: (t / tx) * DEEP_TILE,
        x1: ((t % tx + 1) * DEEP_TILE).min(width),
        y1: ((t / tx + 1) * DEEP_TILE).min(height),
    }
}

/// One tile's runs: per pixel (row by row) how many, and the runs in that order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DeepTile {
    pub counts: Vec<u32>,
    pub stretches: Vec<Stretch>,
}

/// A rank's frame as runs: every tile of the image ([`deep_rect`] order), and what the render
/// counted (`Stats::non_finite` and the overlaps are settled where the pixels are).
pub struct Deep {
    pub tiles: Vec<DeepTile>,
    pub stats: Stats,
    /// The line depths of all ranks the frame was drawn with (for [`Resolver::new`]).
    pub line_depth: Option<Vec<f64>>,
}

/// The step of [`render_runs`] that combines the grid lines of all ranks: given this rank's
/// line depths per pixel (or the error that stopped it before them), it returns the nearest
/// line of any rank per pixel. Called exactly once per frame, from the calling thread, so that
/// a collective operation behind it is reached by every rank — also by one that failed.
pub type LineStep<'a> =
    &'a mut dyn FnMut(Result<Option<Vec<f64>>, Error>) -> Result<Option<Vec<f64>>, Error>;

/// Renders this rank's cells of a frame into runs: [`super::render`]'s steps with every pixel
/// in per-pixel order, the line depths combined by `lines`, and the runs kept per tile.
pub fn render_runs(
    vol: &Volume,
    mapping: &Mapping,
    view: &View,
    settings: &Settings,
    lines: LineStep,
    cancel: &AtomicBool,
) -> Result<Deep, Error> {
    let started = Instant::now();
    let local = check_size(settings.width, settings.height)
        .map_err(Error::Invalid)
        .and_then(|()| place_nodes(vol, view, settings))
        .and_then(|placed| Ok((line_depth(vol, settings, &placed)?, placed)));
    let (depths, placed) = match local {
        Ok((depths, placed)) => (Ok(depths), Some(placed)),
        Err(e) => (Err(e), None),
    };
    let depths = lines(depths)?;
    let placed = placed.ok_or_else(|| Error::Invalid("the line step hid an error".into()))?;
    let lit = lit_mapping(mapping, view, settings, vol.mesh.bbox().center());
    let mapping = lit.as_ref().unwrap_or(mapping);
    let mapped = map_once(vol, mapping, &settings.method);
    let setup = started.elapsed();

    let sorting = Instant::now();
    let sorted = sort_cells(vol, &placed, settings.order, true);
    let sort_time = sorting.elapsed();

    let binning = Instant::now();
    let mut frame = build_frame(vol, mapping, settings, placed, mapped, sorted.rank, depths)?;
    let bins = bin_cells(&frame, sorted.cells, DEEP_TILE);
    let bin_time = binning.elapsed();

    let drawing = Instant::now();
    let mut schedule: Vec<usize> = (0..bins.lists.len()).collect();
    schedule.sort_by_key(|&t| std::cmp::Reverse(bins.lists[t].len()));
    let mut drawn: Vec<(usize, DeepTile, [u64; 2])> = schedule
        .into_par_iter()
        .with_max_len(1)
        .map(|t| {
            if cancel.load(Ordering::Relaxed) {
                return (t, DeepTile::default(), [0; 2]);
            }
            let rect = bins.rect(t, settings.width, settings.height);
            let (counts, stretches, fragments) = draw_tile(&frame, settings, rect, &bins.lists[t]);
            (t, DeepTile { counts, stretches }, fragments)
        })
        .collect();
    if cancel.load(Ordering::Relaxed) {
        return Err(Error::Invalid(CANCELLED.into()));
    }
    drawn.sort_unstable_by_key(|d| d.0);
    let fragments = drawn.iter().map(|d| d.2[0]).sum();
    let lane_fragments = drawn.iter().map(|d| d.2[1]).sum();
    let tiles = drawn.into_iter().map(|d| d.1).collect();
    let stats = Stats {
        cells: vol.mesh.tet_count(),
        drawn: bins.drawn,
        fragments,
        lane_fragments,
        sort: sorted.sort,
        convex: sorted.convex,
        cycle_cells: sorted.cycle_cells,
        per_pixel: true,
        most_runs: 0,
        non_finite: 0,
        first_non_finite: None,
        overlap_pixels: 0,
        overlap_cells: Vec::new(),
        opaque_pixels: 0,
        ranks: Vec::new(),
        timing: Timing {
            setup,
            sort: sort_time,
            bin: bin_time,
            draw: drawing.elapsed(),
            ..Timing::default()
        },
    };
    Ok(Deep {
        tiles,
        stats,
        line_depth: frame.line_depth.take(),
    })
}

/// One tile's runs with the frame's method (monomorphised per method, as the image's tiles).
fn draw_tile(
    frame: &Frame,
    settings: &Settings,
    rect: Rect,
    list: &[u32],
) -> (Vec<u32>, Vec<Stretch>, [u64; 2]) {
    let o = settings.order;
    match &settings.method {
        Method::Exact(m) => render_tile_runs(frame, m, o, rect, list),
        Method::InterpolateCoeff(m) => render_tile_runs(frame, m, o, rect, list),
        Method::InterpolateColor(m) => render_tile_runs(frame, m, o, rect, list),
        Method::Test(m) => render_tile_runs(frame, m, o, rect, list),
    }
}

/// Pixels with a NaN or infinite channel, and the first of them (as one process reports them).
pub fn non_finite(fb: &Framebuffer) -> (usize, Option<(usize, usize)>) {
    non_finite_pixels(fb)
}

/// What settles a pixel from its runs: the background and the grid lines of the frame, and for
/// `test` the surfaces two ranks both drew.
pub struct Resolver {
    width: usize,
    order: super::Order,
    background: Backdrop,
    line_depth: Option<Vec<f64>>,
    surfaces: Option<super::approx::Test>,
}

impl Resolver {
    /// For a frame of `settings`, with the line depths of all ranks combined.
    pub fn new(settings: &Settings, line_depth: Option<Vec<f64>>) -> Result<Resolver, Error> {
        Ok(Resolver {
            width: settings.width,
            order: settings.order,
            background: backdrop(settings)?,
            line_depth,
            surfaces: match &settings.method {
                Method::Test(t) => Some(*t),
                _ => None,
            },
        })
    }

    /// Pixel (x, y) from the runs of every rank, each with the rank that drew it (concatenated
    /// in rank order; sorted here): as one process settles its runs — sorted by depth,
    /// composited back to front over I0 (black on a grid line), alpha `1 − T`. Also whether
    /// two runs overlap along the ray (interpenetrating cells), and whether one process would
    /// have stopped compositing before the last cell ([`Resolver::stops_early`]).
    ///
    /// With `test`, a run that starts where another rank's run ends (the face between their
    /// cells, which both drew) loses its near surface ([`super::approx::Test`]): one process
    /// draws each face once per ray.
    pub fn pixel(
        &self,
        x: usize,
        y: usize,
        stretches: &mut [(Stretch, u32)],
    ) -> ([f32; 4], bool, bool) {
        stretches.sort_by(|(a, _), (b, _)| by_depth((a.near, a.far), (b.near, b.far)));
        let overlapped = stretches
            .windows(2)
            .any(|w| overlap((w[0].0.near, w[0].0.far), (w[1].0.near, w[1].0.far)));
        if let Some(test) = &self.surfaces {
            for k in 1..stretches.len() {
                let ((a, ra), (b, rb)) = (stretches[k - 1], stretches[k]);
                if ra != rb && abut(&a, &b) {
                    (stretches[k].0.b, stretches[k].0.theta) =
                        test.without_near_surface((b.b, b.theta));
                }
            }
        }
        let at = y * self.width + x;
        let line = self.line_depth.as_ref().map_or(f64::INFINITY, |d| d[at]);
        let i0 = if line.is_finite() {
            [0.0; 3]
        } else {
            match &self.background {
                Backdrop::Uniform(c) => *c,
                Backdrop::Image(px) => px[at],
            }
        };
        let (rgb, t) = back_to_front(stretches.iter().map(|(s, _)| (s.b, s.theta)), i0);
        (
            pixel_out(rgb, t, line.is_finite()),
            overlapped,
            self.stops_early(t),
        )
    }

    /// Whether a pixel of transparency `t` may have reached front-to-back compositing's early
    /// termination in one process (`render_ftb`, [`super::EARLY_TERMINATION`]): it stops at
    /// the cell where the transparency falls below the threshold, inside some rank's run,
    /// which the runs cannot reproduce; they composite every cell, as one process does for a
    /// non-convex mesh. A pixel whose transparency stays above it (with room for rounding) was
    /// composited to the end, as here.
    pub fn stops_early(&self, t: f64) -> bool {
        self.order == super::Order::FrontToBack && t < super::EARLY_TERMINATION * (1.0 + 1e-6)
    }
}

/// Whether run `b` (sorted after `a`) starts where `a` ends: at the same face, whose depth
/// both ranks computed from the face alone, or — where the ray passes an edge or node the two
/// share — within rounding ([`super::tile::TOUCH`] of the runs' lengths and depth).
fn abut(a: &Stretch, b: &Stretch) -> bool {
    let scale = (a.far - a.near).max(b.far - b.near) + a.far.abs();
    (b.near - a.far).abs() <= super::tile::TOUCH * scale
}
