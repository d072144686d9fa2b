//! One frame: node positions to eye space and screen, the visibility sort, the cells binned into
//! screen tiles, the tiles drawn in parallel ([`super::tile`]) and gathered into the image, and
//! what happened on the way ([`Stats`]). The steps 1–4 of the renderer ([`super`]).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use super::approx::{Method, check_step};
use super::composite::Order;
use super::footprint::footprint;
use super::frame::{Backdrop, Frame};
use super::lines;
use super::raster::Rect;
use super::settings::{Settings, TILE, check_size};
use super::tile::{Overlaps, render_tile};
use crate::cache::prefetch;
use crate::error::Error;
use crate::framebuffer::{Background, Framebuffer};
use crate::mapping::{CategoryTransfers, Mapping, Transfer1D};
use crate::predicates::entry_sign;
use crate::scene::{Lighting, Projector, View};
use crate::sort::{self, SortInput};
use crate::volume::Volume;

/// The edge length of the screen tiles when [`Settings::tile`] is [`TILE`]: the largest of 128,
/// 64 and 32 pixels that still gives at least eight tiles per thread. A cell that straddles a
/// tile border is set up once per tile it touches, so large tiles save set-up work (measured,
/// one thread, CPU time: 128 against 64 saved 5 % at 150k cells / 512², 8.5 % at 1M / 1024²
/// and 8.5 % for interpolateColor), while enough tiles per thread keep the threads busy to the
/// end (tiles go largest first).
pub fn auto_tile(width: usize, height: usize, threads: usize) -> usize {
    [128, 64]
        .into_iter()
        .find(|&t| width.div_ceil(t) * height.div_ceil(t) >= 8 * threads.max(1))
        .unwrap_or(32)
}

/// What happened during a render.
#[derive(Debug, Clone, PartialEq)]
pub struct Stats {
    pub cells: usize,
    /// Cells whose footprint's bounding box reaches the screen.
    pub drawn: usize,
    /// Pixel–cell pairs integrated (ray segments).
    pub fragments: u64,
    /// Of those, the ones integrated in the SIMD span kernels ([`super::span`]).
    pub lane_fragments: u64,
    /// The visibility sort used and whether the mesh is convex.
    pub sort: &'static str,
    pub convex: bool,
    /// Cells that had to be released from a visibility cycle (0: the sort's order is exact).
    pub cycle_cells: usize,
    /// The order was settled per pixel (non-convex mesh or broken cycle; see [`super::runs`]).
    pub per_pixel: bool,
    /// The most runs (separate stretches of mesh along one ray) a pixel held.
    pub most_runs: usize,
    /// Pixels with a NaN or infinite channel (0 unless something overflowed: reported, not
    /// hidden), and the first of them.
    pub non_finite: usize,
    pub first_non_finite: Option<(usize, usize)>,
    /// Pixels whose ray passes cells that overlap along it (interpenetrating parts of the
    /// mesh, integrated twice), and sorted example pairs of such cells.
    pub overlap_pixels: usize,
    pub overlap_cells: Vec<(u32, u32)>,
    /// A distributed `render_ftb` frame: pixels whose transparency fell below
    /// [`super::EARLY_TERMINATION`]. One process would have stopped compositing there (on a
    /// convex mesh); the ranks composited every cell, so these pixels may differ from one
    /// process's image by less than that transparency times the light behind.
    pub opaque_pixels: usize,
    pub timing: Timing,
    /// A distributed frame (on rank 0): what each rank did, by rank; empty in one process.
    pub ranks: Vec<RankLoad>,
}

/// One rank's share of a distributed frame (`VORANG_TIMING`, benches/distributed.sh).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RankLoad {
    /// Rendering its cells into runs (setup, sort, binning, drawing).
    pub render: Duration,
    /// Pixel–cell pairs it integrated (ray segments).
    pub fragments: u64,
    /// The runs it sent to the owners of their pixels (its own tiles' included).
    pub runs: u64,
    /// The bytes it sent to the other ranks in the all-to-all (its own tiles' not counted).
    pub bytes_sent: u64,
    /// From the all-to-all to the gathered image (rank 0) or to its pixels sent (the others).
    pub composite: Duration,
}

impl Stats {
    /// Nothing rendered (a rank of a distributed frame that gets no image).
    pub fn empty() -> Stats {
        Stats {
            cells: 0,
            drawn: 0,
            fragments: 0,
            lane_fragments: 0,
            sort: "",
            convex: false,
            cycle_cells: 0,
            per_pixel: false,
            most_runs: 0,
            non_finite: 0,
            first_non_finite: None,
            overlap_pixels: 0,
            overlap_cells: Vec::new(),
            opaque_pixels: 0,
            timing: Timing::default(),
            ranks: Vec::new(),
        }
    }
}

/// Where a render's time went (wall clock).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timing {
    /// Node transforms and projection, mapping preparation.
    pub setup: Duration,
    /// The visibility sort.
    pub sort: Duration,
    /// Grid lines, background and binning cells into tiles.
    pub bin: Duration,
    /// Scan conversion, integration and compositing of all tiles.
    pub draw: Duration,
    /// A distributed frame: exchanging the runs, settling the pixels and gathering the image
    /// (zero in one process).
    pub composite: Duration,
}

/// Renders one image. `progress(done, total)` is called as tiles finish.
pub fn render(
    vol: &Volume,
    mapping: &Mapping,
    view: &View,
    settings: &Settings,
    progress: Option<&(dyn Fn(usize, usize) + Sync)>,
) -> Result<(Framebuffer, Stats), Error> {
    render_cancellable(
        vol,
        mapping,
        view,
        settings,
        progress,
        &std::sync::atomic::AtomicBool::new(false),
    )
}

/// The message of a render stopped through its `cancel` flag.
pub const CANCELLED: &str = "the render was cancelled";

/// [`render`] that stops early once `cancel` is set (from another thread, e.g. on Ctrl-C): tiles
/// not yet started are skipped and the result is an error ([`CANCELLED`]), never a partial
/// image.
pub fn render_cancellable(
    vol: &Volume,
    mapping: &Mapping,
    view: &View,
    settings: &Settings,
    progress: Option<&(dyn Fn(usize, usize) + Sync)>,
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<(Framebuffer, Stats), Error> {
    render_watched(
        vol,
        mapping,
        view,
        settings,
        &Watch {
            progress,
            tile: None,
            cancel,
        },
    )
}

/// A finished tile as [`Watch::tile`] sees it: where it lies in the image and its pixels, row by
/// row (`rect.x1 − rect.x0` per row), as they will be in the framebuffer.
pub type TileSink<'a> = &'a (dyn Fn(Rect, &[[f32; 4]]) + Sync);

/// What a caller may see of, and do to, a render while it runs (from the render's threads).
pub struct Watch<'a> {
    /// `progress(done, total)` as tiles finish.
    pub progress: Option<&'a (dyn Fn(usize, usize) + Sync)>,
    /// Each finished tile, so that a window can show the picture growing (the thesis's `online`).
    pub tile: Option<TileSink<'a>>,
    /// Set from another thread to stop the render (see [`render_cancellable`]).
    pub cancel: &'a std::sync::atomic::AtomicBool,
}

/// [`render_cancellable`] that also hands every finished tile to [`Watch::tile`].
pub fn render_watched(
    vol: &Volume,
    mapping: &Mapping,
    view: &View,
    settings: &Settings,
    watch: &Watch,
) -> Result<(Framebuffer, Stats), Error> {
    let started = Instant::now();
    check_size(settings.width, settings.height).map_err(Error::Invalid)?;
    let placed = place_nodes(vol, view, settings)?;
    let lit = lit_mapping(mapping, view, settings, vol.mesh.bbox().center());
    let mapping = lit.as_ref().unwrap_or(mapping);
    let mapped = map_once(vol, mapping, &settings.method);
    let setup = started.elapsed();

    let sorting = Instant::now();
    let sorted = sort_cells(vol, &placed, settings.order, false);
    let sort_time = sorting.elapsed();

    let binning = Instant::now();
    let line_depth = line_depth(vol, settings, &placed)?;
    let frame = build_frame(
        vol,
        mapping,
        settings,
        placed,
        mapped,
        sorted.rank,
        line_depth,
    )?;
    let bins = bin_cells(&frame, sorted.cells, settings.tile);
    let bin_time = binning.elapsed();

    let drawing = Instant::now();
    let (fb, tiles) = draw_tiles(&frame, settings, &bins, sorted.per_pixel, watch)?;
    let fragments = tiles.iter().map(|t| t.0[0]).sum();
    let lane_fragments = tiles.iter().map(|t| t.0[1]).sum();
    let most_runs = tiles.iter().map(|t| t.1).max().unwrap_or(0);
    let overlap_pixels = tiles.iter().map(|t| t.2.0).sum();
    let mut overlap_cells: Vec<(u32, u32)> = tiles.into_iter().flat_map(|t| t.2.1).collect();
    overlap_cells.sort_unstable();
    overlap_cells.dedup();
    let draw_time = drawing.elapsed();
    let (non_finite, first_non_finite) = non_finite_pixels(&fb);
    Ok((
        fb,
        Stats {
            cells: vol.mesh.tet_count(),
            drawn: bins.drawn,
            fragments,
            lane_fragments,
            sort: sorted.sort,
            convex: sorted.convex,
            cycle_cells: sorted.cycle_cells,
            per_pixel: sorted.per_pixel,
            most_runs,
            non_finite,
            first_non_finite,
            overlap_pixels,
            overlap_cells,
            opaque_pixels: 0,
            timing: Timing {
                setup,
                sort: sort_time,
                bin: bin_time,
                draw: draw_time,
                composite: Duration::ZERO,
            },
            ranks: Vec::new(),
        },
    ))
}

/// The nodes of a frame in eye space and on screen, and how they were put there.
pub(crate) struct Placed {
    /// The transform to eye space has a negative determinant: a mirror turns every
    /// orientation around, accounted for once (the sort's faces, [`Frame::entry_sign`]).
    pub mirrored: bool,
    pub projector: Projector,
    pub eye_nodes: Vec<[f64; 3]>,
    pub screen: Vec<[f64; 2]>,
}

/// Step 1: node positions to eye space (model from `vol_*`, view from `look_at`) and to
/// screen. Refuses a singular volume transform, and an `exact` step that would cut a ray into
/// more pieces than the method allows, which needs the eye-space nodes ([`check_step`]).
pub(crate) fn place_nodes(vol: &Volume, view: &View, settings: &Settings) -> Result<Placed, Error> {
    let bbox = vol.mesh.bbox();
    let model = view.model(bbox.center()).ok_or_else(|| {
        Error::Invalid(
            "the volume transform is singular (a zero vol_scale factor or a zero vol_rotate axis)"
                .into(),
        )
    })?;
    let to_eye = view.view_matrix().after(&model);
    let mirrored = to_eye.determinant() < 0.0;
    let (width, height) = (settings.width, settings.height);
    let projector = Projector::new(view.camera.as_ref(), bbox.size(), width, height)?;
    let eye_nodes: Vec<[f64; 3]> = vol
        .mesh
        .nodes()
        .par_iter()
        .map(|&p| to_eye.apply(p))
        .collect();
    if let Method::Exact(m) = &settings.method {
        check_step(m.step, &eye_nodes)?;
    }
    let screen: Vec<[f64; 2]> = eye_nodes.par_iter().map(|&p| projector.screen(p)).collect();
    Ok(Placed {
        mirrored,
        projector,
        eye_nodes,
        screen,
    })
}

/// `LIT_EMITTER`: the mapping with this frame's lights (the default light follows the camera,
/// so it is set per frame); `None` where the mapping is not lit or there is no light.
pub(super) fn lit_mapping(
    mapping: &Mapping,
    view: &View,
    settings: &Settings,
    center: [f64; 3],
) -> Option<Mapping> {
    match Lighting::new(&settings.lights, view, center) {
        Some(lighting) if mapping.is_lit() => Some(mapping.lit(lighting)),
        _ => None,
    }
}

/// The mapping in the forms the fast paths read, prepared once per frame ([`Frame::transfer`],
/// [`Frame::category_transfers`], [`Frame::node_mapped`]).
pub(super) struct Mapped {
    transfer: Option<Transfer1D>,
    category_transfers: Option<CategoryTransfers>,
    node_mapped: Option<Vec<([f64; 3], f64)>>,
}

/// The mapping as one merged transfer function where it has that form, else per category of
/// cells; and mapped at every node for the methods that map at the nodes
/// (`interpolateColor`, `interpolateCoeff`), once per frame instead of once per cell and node.
pub(super) fn map_once(vol: &Volume, mapping: &Mapping, method: &Method) -> Mapped {
    let transfer = mapping.transfer(vol);
    let category_transfers = match transfer {
        None => mapping.category_transfers(vol),
        Some(_) => None,
    };
    let node_mapped = match (&transfer, method) {
        (Some(t), Method::InterpolateColor(_) | Method::InterpolateCoeff(_)) => {
            t.map_nodes(vol.mesh.node_count())
        }
        _ => None,
    };
    Mapped {
        transfer,
        category_transfers,
        node_mapped,
    }
}

/// The cells in compositing order, and what the sort found.
pub(super) struct Sorted {
    pub(super) cells: Vec<u32>,
    /// Each cell's place in `cells`, for the per-pixel runs (empty in the sort's order).
    pub(super) rank: Vec<u32>,
    pub(super) sort: &'static str,
    pub(super) convex: bool,
    pub(super) cycle_cells: usize,
    /// The order is settled per pixel ([`super::runs`]).
    pub(super) per_pixel: bool,
}

/// Step 2: the visibility order ([`crate::sort`]), back to front or reversed. MPVO's order is
/// exact for a convex mesh without cycles; anything else — and every frame that keeps its runs
/// (`runs`: a rank's part of a distributed frame) — is settled per pixel, for which each cell's
/// place in the order is kept.
pub(super) fn sort_cells(vol: &Volume, placed: &Placed, order: Order, runs: bool) -> Sorted {
    let mesh = &vol.mesh;
    let convex = mesh.is_convex();
    let sorter = sort::choose(convex);
    let input = SortInput {
        mesh,
        eye_nodes: &placed.eye_nodes,
        screen: &placed.screen,
        perspective: placed.projector.is_perspective(),
        mirrored: placed.mirrored,
    };
    let sorted = (sorter.sort)(&input);
    let per_pixel = runs || !convex || sorted.cycle_cells > 0;
    let mut cells = sorted.back_to_front;
    if order == Order::FrontToBack {
        cells.reverse();
    }
    let mut rank = Vec::new();
    if per_pixel {
        rank = vec![0u32; mesh.tet_count()];
        for (i, &c) in cells.iter().enumerate() {
            rank[c as usize] = i as u32;
        }
    }
    Sorted {
        cells,
        rank,
        sort: sorter.name,
        convex,
        cycle_cells: sorted.cycle_cells,
        per_pixel,
    }
}

/// The depth of the nearest grid line per pixel (`None`: no line is drawn).
pub(super) fn line_depth(
    vol: &Volume,
    settings: &Settings,
    placed: &Placed,
) -> Result<Option<Vec<f64>>, Error> {
    let edges = lines::edges(vol, &settings.lines)?;
    if edges.is_empty() {
        return Ok(None);
    }
    let (width, height) = (settings.width, settings.height);
    let depths = lines::depth_buffer(&edges, &placed.eye_nodes, &placed.projector, width, height)?;
    Ok(Some(depths))
}

/// The background intensity I0 the settings ask for.
pub(super) fn backdrop(settings: &Settings) -> Result<Backdrop, Error> {
    Ok(match &settings.background {
        Background::Color(c) => Backdrop::Uniform(*c),
        Background::None => Backdrop::Uniform([0.0; 3]),
        other => Backdrop::Image(other.pixels(settings.width, settings.height)?),
    })
}

/// What every tile shares: the placed nodes and the prepared mapping, with the grid lines'
/// depth per pixel and the background, which the tiles read pixel by pixel.
pub(super) fn build_frame<'a>(
    vol: &'a Volume,
    mapping: &'a Mapping,
    settings: &Settings,
    placed: Placed,
    mapped: Mapped,
    rank: Vec<u32>,
    line_depth: Option<Vec<f64>>,
) -> Result<Frame<'a>, Error> {
    let (width, height) = (settings.width, settings.height);
    let background = backdrop(settings)?;
    Ok(Frame {
        vol,
        mapping,
        transfer: mapped.transfer,
        category_transfers: mapped.category_transfers,
        node_mapped: mapped.node_mapped,
        projector: placed.projector,
        width,
        height,
        eye_nodes: placed.eye_nodes,
        screen: placed.screen,
        background,
        line_depth,
        entry_sign: entry_sign(placed.mirrored),
        rank,
        span_kernels: settings.span_kernels,
    })
}

/// The screen tiles and the cells each one draws, in compositing order.
pub(super) struct Bins {
    /// Tile → its cells (tiles row by row, `tx` per row).
    pub(super) lists: Vec<Vec<u32>>,
    /// The tiles' edge length and how many there are across and down.
    pub(super) tile: usize,
    pub(super) tx: usize,
    pub(super) ty: usize,
    /// Cells whose footprint's bounding box reaches the screen.
    pub(super) drawn: usize,
}

impl Bins {
    /// Tile `t`'s pixels (the last row and column of tiles may be cut off by the image).
    pub(super) fn rect(&self, t: usize, width: usize, height: usize) -> Rect {
        let (tile, tx) = (self.tile, self.tx);
        Rect {
            x0: (t % tx) * tile,
            y0: (t / tx) * tile,
            x1: ((t % tx + 1) * tile).min(width),
            y1: ((t / tx + 1) * tile).min(height),
        }
    }
}

/// Step 3: the ordered cells binned into the tiles their footprint's bounding box touches
/// (`tile`: the edge length, or [`TILE`] to choose per frame, [`auto_tile`]). In parallel: each
/// chunk of the order lists its cells per tile, then each tile joins its chunks' lists in chunk
/// order — the same order as one pass over all cells, whatever the number of threads.
pub(super) fn bin_cells(frame: &Frame, cells: Vec<u32>, tile: usize) -> Bins {
    let (width, height) = (frame.width, frame.height);
    let tile = match tile {
        TILE => auto_tile(width, height, rayon::current_num_threads()),
        t => t,
    };
    let (tx, ty) = (width.div_ceil(tile), height.div_ceil(tile));
    let chunk = (cells.len() / (4 * rayon::current_num_threads())).max(4096);
    let parts: Vec<(Vec<Vec<u32>>, usize)> = cells
        .par_chunks(chunk)
        .map(|cs| bin_chunk(frame, cs, tile, tx, ty))
        .collect();
    drop(cells);
    let drawn = parts.iter().map(|p| p.1).sum();
    let lists: Vec<Vec<u32>> = (0..tx * ty)
        .into_par_iter()
        .map(|t| {
            let mut list = Vec::with_capacity(parts.iter().map(|p| p.0[t].len()).sum());
            for p in &parts {
                list.extend_from_slice(&p.0[t]);
            }
            list
        })
        .collect();
    drop(parts);
    Bins {
        lists,
        tile,
        tx,
        ty,
        drawn,
    }
}

/// One chunk of the order: its cells listed per tile, and how many reach the screen.
fn bin_chunk(
    frame: &Frame,
    cs: &[u32],
    tile: usize,
    tx: usize,
    ty: usize,
) -> (Vec<Vec<u32>>, usize) {
    let mut lists = vec![Vec::new(); tx * ty];
    let mut drawn = 0;
    let tets = frame.vol.mesh.tets();
    for (i, &c) in cs.iter().enumerate() {
        // As in the tile loop: the visibility order is scattered over the mesh.
        if let Some(&later) = cs.get(i + 8) {
            prefetch(&tets[later as usize]);
        }
        if let Some(&next) = cs.get(i + 4) {
            for n in tets[next as usize] {
                prefetch(&frame.screen[n as usize]);
            }
        }
        if let Some(r) = tile_range(frame, c as usize, tile, tx, ty) {
            drawn += 1;
            for y in r[1]..=r[3] {
                for x in r[0]..=r[2] {
                    lists[y as usize * tx + x as usize].push(c);
                }
            }
        }
    }
    (lists, drawn)
}

/// What one tile counted: pixel–cell pairs integrated (all, and in the span kernels), the
/// most runs one pixel held, and the overlaps its runs found.
type TileCounts = ([u64; 2], usize, Overlaps);

/// Step 4: the tiles in parallel, those with the most cells first so that no long tile is left
/// for the end, each copied into the image as it finishes (only the tiles in flight exist
/// besides it) and handed to the watcher. A cancelled render is an error, never a partial
/// image.
fn draw_tiles(
    frame: &Frame,
    settings: &Settings,
    bins: &Bins,
    per_pixel: bool,
    watch: &Watch,
) -> Result<(Framebuffer, Vec<TileCounts>), Error> {
    let (progress, cancel) = (watch.progress, watch.cancel);
    let (width, height) = (settings.width, settings.height);
    let done = AtomicUsize::new(0);
    let total = bins.tx * bins.ty;
    let mut schedule: Vec<usize> = (0..total).collect();
    schedule.sort_by_key(|&t| std::cmp::Reverse(bins.lists[t].len()));
    let fb = std::sync::Mutex::new(Framebuffer::try_new(width, height)?);
    let tiles: Vec<TileCounts> = schedule
        .into_par_iter()
        .with_max_len(1)
        .map(|t| {
            let rect = bins.rect(t, width, height);
            if cancel.load(Ordering::Relaxed) {
                return ([0, 0], 0, (0, Vec::new()));
            }
            let (out, fragments, most, overlaps) =
                draw_tile(frame, settings, per_pixel, rect, &bins.lists[t]);
            if let Some(sink) = watch.tile {
                sink(rect, &out);
            }
            {
                let mut fb = fb.lock().unwrap_or_else(|e| e.into_inner());
                let w = rect.x1 - rect.x0;
                for (row, chunk) in out.chunks(w).enumerate() {
                    let at = (rect.y0 + row) * width + rect.x0;
                    fb.pixels[at..at + w].copy_from_slice(chunk);
                }
            }
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if let Some(p) = progress {
                p(n, total);
            }
            (fragments, most, overlaps)
        })
        .collect();
    if cancel.load(Ordering::Relaxed) {
        return Err(Error::Invalid(CANCELLED.into()));
    }
    let mut fb = fb.into_inner().unwrap_or_else(|e| e.into_inner());
    fb.transparent = matches!(settings.background, Background::None);
    Ok((fb, tiles))
}

/// One tile with the frame's method: [`render_tile`] monomorphised per method, so the method is
/// chosen once per tile and its per-pixel code has no dispatch in it.
fn draw_tile(
    frame: &Frame,
    settings: &Settings,
    per_pixel: bool,
    rect: Rect,
    list: &[u32],
) -> (Vec<[f32; 4]>, [u64; 2], usize, Overlaps) {
    let (o, pp) = (settings.order, per_pixel);
    match &settings.method {
        Method::Exact(m) => render_tile(frame, m, o, pp, rect, list),
        Method::InterpolateCoeff(m) => render_tile(frame, m, o, pp, rect, list),
        Method::InterpolateColor(m) => render_tile(frame, m, o, pp, rect, list),
        Method::Test(m) => render_tile(frame, m, o, pp, rect, list),
    }
}

/// Pixels with a NaN or infinite channel (0 unless something overflowed: reported, not
/// hidden), and the first of them.
pub(super) fn non_finite_pixels(fb: &Framebuffer) -> (usize, Option<(usize, usize)>) {
    let mut non_finite = 0;
    let mut first_non_finite = None;
    for (i, p) in fb.pixels.iter().enumerate() {
        if !p.iter().all(|v| v.is_finite()) {
            non_finite += 1;
            first_non_finite.get_or_insert((i % fb.width, i / fb.width));
        }
    }
    (non_finite, first_non_finite)
}

/// The tiles `[x0, y0, x1, y1]` (inclusive) a cell's footprint touches, if any. The bounding
/// box of the four projected nodes is the footprint's, except for a cell reaching in front of a
/// perspective near plane, whose clipped footprint is computed.
fn tile_range(f: &Frame, cell: usize, tile: usize, tx: usize, ty: usize) -> Option<[u32; 4]> {
    // Only a perspective view needs the eye-space corners (the near-plane test): the
    // orthographic bins read the screen corners alone, half the scattered node reads.
    let near_clipped = match f.projector {
        Projector::Persp { depth, .. } => {
            let eye = f.eye_corners(cell);
            eye.iter().any(|p| -p[2] < depth.0).then_some(eye)
        }
        _ => None,
    };
    let b = match near_clipped {
        Some(eye) => footprint(
            f.vol.mesh.tets()[cell],
            &eye,
            &f.screen_corners(cell),
            &f.projector,
        )?
        .bbox()?,
        None => {
            let s = f.screen_corners(cell);
            let mut b = [s[0][0], s[0][1], s[0][0], s[0][1]];
            for p in &s[1..] {
                b = [
                    b[0].min(p[0]),
                    b[1].min(p[1]),
                    b[2].max(p[0]),
                    b[3].max(p[1]),
                ];
            }
            b
        }
    };
    // Pixel centres i + ½ inside [min, max].
    let lo = |m: f64| (m - 0.5).ceil().max(0.0);
    let hi = |m: f64, n: usize| (m - 0.5).floor().min(n as f64 - 1.0);
    let (x0, y0, x1, y1) = (lo(b[0]), lo(b[1]), hi(b[2], f.width), hi(b[3], f.height));
    if !(x0 <= x1 && y0 <= y1) {
        return None;
    }
    let t = |v: f64| (v as usize / tile) as u32;
    let r = [t(x0), t(y0), t(x1), t(y1)];
    (r[2] < tx as u32 && r[3] < ty as u32).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::auto_tile;

    #[test]
    fn tiles_are_large_while_every_thread_gets_eight() {
        assert_eq!(auto_tile(512, 512, 2), 128);
        assert_eq!(auto_tile(1024, 1024, 2), 128);
        assert_eq!(auto_tile(512, 512, 4), 64);
        assert_eq!(auto_tile(512, 512, 16), 32);
        assert_eq!(auto_tile(100, 60, 1), 32);
        assert_eq!(auto_tile(0, 0, 0), 32);
    }
}
