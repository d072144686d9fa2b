//! The renderer: projected tetrahedra with exact per-pixel ray intervals (thesis chapters 2, 4,
//! 6.3; SPEC §2–6).
//!
//! 1. Node positions to eye space (model from `vol_*`, view from `look_at`), and to screen on a
//!    2⁻²⁸ px grid ([`crate::scene::SUBPIXEL`]), so that views degenerate up to rounding are
//!    the degenerate views.
//! 2. Visibility order of the cells ([`crate::sort`]), with a mirroring transform accounted for.
//! 3. Cells are binned, in that order, into the 64×64 screen tiles their footprint's bounding
//!    box touches.
//! 4. Tiles are rendered in parallel (the ones with the most cells first), each into its own
//!    buffer. Per cell: its footprint's outline is scan-converted by rows; per covered pixel the
//!    entry and exit face and their depths give the ray's interval in the cell
//!    ([`faces::CellFaces`]: exact predicates, one depth per face and pixel shared by both of
//!    its cells, so intervals along a ray meet without gap or overlap); the interval is clipped
//!    to the camera's depth range and to a grid line in front, the approximation method gives
//!    the cell's `(b, θ)`, and that is composited back to front (`I = I·θ + b`) or front to
//!    back. A cell reaching in front of a perspective near plane keeps the per-cell clip
//!    ([`cell::CellRays`]). `interpolateColor` on unclipped cells needs no ray at all: it shades
//!    the outline with [`gouraud::Fan`].
//! 5. Where the sort is not exact (non-convex meshes, broken cycles) pixels keep per-pixel runs
//!    of face-adjacent cells ([`runs`]), composited by depth at the end: exact per pixel for any
//!    mesh.
//!
//! Every pixel sees the same cells in the same order whatever the number of threads, so the image
//! is bit-identical on any machine. Where the time goes: `docs/performance.md`.

pub mod approx;
pub mod cell;
pub mod faces;
pub mod footprint;
pub mod frame;
pub mod gouraud;
pub mod lines;
pub mod project;
pub mod raster;
pub mod rows;
pub mod runs;
pub mod span;

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;

pub use approx::{METHODS, Method};
pub use lines::LineDraw;

use approx::{Approx, Pixel, Scratch};
use cell::{CellRays, EyeCell, Interval};
use faces::{CellFaces, FaceHit};
use footprint::{Footprint, footprint, footprint_into};
use frame::{Backdrop, Frame};
use gouraud::Fan;
pub use raster::Rect;
use raster::{rasterize, rasterize_convex, rasterize_convex_rows};
use runs::Runs;

use crate::error::Error;
use crate::framebuffer::{Background, Framebuffer};
use crate::mapping::Mapping;
use crate::mesh::NO_NEIGHBOR;
use crate::scene::{Lighting, Projector, View};
use crate::sort::{self, SortInput};
use crate::volume::Volume;

/// [`Settings::tile`] for "choose per frame" ([`auto_tile`]).
pub const TILE: usize = 0;

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

/// Front-to-back compositing stops for a pixel once its accumulated transparency falls below
/// this: what lies behind can change the pixel by at most this fraction of its background.
pub const EARLY_TERMINATION: f64 = 1e-6;

/// A ray interval shorter than this fraction of the cell's depth extent only touches the cell
/// (for `test`'s surfaces, and near-plane-clipped cells).
pub const TOUCH: f64 = 1e-9;

/// The largest image, in pixels (2^27: a 2 GiB float framebuffer).
pub const MAX_PIXELS: usize = 1 << 27;

/// Compositing order: `render_btf` or `render_ftb`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Order {
    #[default]
    BackToFront,
    FrontToBack,
}

/// Everything a render needs besides the volume, the mapping and the view.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub width: usize,
    pub height: usize,
    pub method: Method,
    pub order: Order,
    pub lines: LineDraw,
    pub background: Background,
    /// Edge length of the screen tiles rendered in parallel (any value gives the same image);
    /// [`TILE`] (0): chosen per frame by [`auto_tile`].
    pub tile: usize,
    /// Let whole cells go through the SIMD span kernels where they apply ([`span`]); off, every
    /// pixel takes the scalar reference path (for tests and comparisons).
    pub span_kernels: bool,
    /// `addlight`: the lights of the scene, for `LIT_EMITTER` ([`crate::scene::light`]); none
    /// = one white light at the camera.
    pub lights: Vec<crate::scene::Light>,
}

impl Default for Settings {
    /// 512 × 512, `test 0.5`, back to front, all grid lines, white background (thesis A.1).
    fn default() -> Self {
        Settings {
            width: 512,
            height: 512,
            method: Method::default(),
            order: Order::BackToFront,
            lines: LineDraw::All,
            background: Background::default(),
            tile: TILE,
            span_kernels: true,
            lights: Vec::new(),
        }
    }
}

/// What happened during a render.
#[derive(Debug, Clone, PartialEq)]
pub struct Stats {
    pub cells: usize,
    /// Cells whose footprint's bounding box reaches the screen.
    pub drawn: usize,
    /// Pixel–cell pairs integrated (ray segments).
    pub fragments: u64,
    /// Of those, the ones integrated in the SIMD span kernels ([`span`]).
    pub lane_fragments: u64,
    /// The visibility sort used and whether the mesh is convex.
    pub sort: &'static str,
    pub convex: bool,
    /// Cells that had to be released from a visibility cycle (0: the sort's order is exact).
    pub cycle_cells: usize,
    /// The order was settled per pixel (non-convex mesh or broken cycle; see [`runs`]).
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
    pub timing: Timing,
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
}

/// The most pieces `exact` may cut one ray through the whole volume into.
pub const MAX_PIECES: f64 = 1e6;

/// Refuses an `exact` step so small that a ray through the volume would need more than
/// [`MAX_PIECES`] pieces (the frame would take days and its cut lists terabytes): every cell
/// interval is at most the diagonal of the transformed volume's bounding box.
fn check_step(step: f64, eye_nodes: &[[f64; 3]]) -> Result<(), Error> {
    if step <= 0.0 {
        return Ok(());
    }
    let size = crate::mesh::Aabb::of_points(eye_nodes).size();
    let diagonal = (size[0] * size[0] + size[1] * size[1] + size[2] * size[2]).sqrt();
    if diagonal / step > MAX_PIECES {
        return Err(Error::Invalid(format!(
            "method exact: a step of {step:e} would cut a ray through the volume (diagonal {diagonal:.3e}) into more than {MAX_PIECES:e} pieces; use a step of at least {:.3e}, or 0 for one piece per cell",
            diagonal / MAX_PIECES
        )));
    }
    Ok(())
}

/// Checks an image size: at least 1 × 1 and at most [`MAX_PIXELS`].
pub fn check_size(width: usize, height: usize) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!(
            "the image size must be at least 1 × 1, found {width} × {height}"
        ));
    }
    if width.saturating_mul(height) > MAX_PIXELS || width > 1 << 20 || height > 1 << 20 {
        return Err(format!(
            "an image of {width} × {height} pixels is too large (at most {MAX_PIXELS} pixels, i.e. 2 GiB of float framebuffer)"
        ));
    }
    Ok(())
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
    let (progress, cancel) = (watch.progress, watch.cancel);
    let started = Instant::now();
    let (width, height) = (settings.width, settings.height);
    check_size(width, height).map_err(Error::Invalid)?;
    let mesh = &vol.mesh;
    let bbox = mesh.bbox();
    let model = view.model(bbox.center()).ok_or_else(|| {
        Error::Invalid(
            "the volume transform is singular (a zero vol_scale factor or a zero vol_rotate axis)"
                .into(),
        )
    })?;
    // LIT_EMITTER: the lights of this frame (the default light follows the camera).
    let lit;
    let mapping = match Lighting::new(&settings.lights, view, bbox.center()) {
        Some(lighting) if mapping.is_lit() => {
            lit = mapping.lit(lighting);
            &lit
        }
        _ => mapping,
    };
    let to_eye = view.view_matrix().after(&model);
    // A mirror turns every orientation around; accounted for once, here.
    let mirrored = to_eye.determinant() < 0.0;
    let projector = Projector::new(view.camera.as_ref(), bbox.size(), width, height)?;
    let eye_nodes: Vec<[f64; 3]> = mesh.nodes().par_iter().map(|&p| to_eye.apply(p)).collect();
    if let Method::Exact(m) = &settings.method {
        check_step(m.step, &eye_nodes)?;
    }
    let screen: Vec<[f64; 2]> = eye_nodes.par_iter().map(|&p| projector.screen(p)).collect();
    let transfer = mapping.transfer(vol);
    let category_transfers = match transfer {
        None => mapping.category_transfers(vol),
        Some(_) => None,
    };
    let node_mapped = match (&transfer, &settings.method) {
        (Some(t), Method::InterpolateColor(_) | Method::InterpolateCoeff(_)) => {
            t.map_nodes(mesh.node_count())
        }
        _ => None,
    };
    let setup = started.elapsed();

    let sorting = Instant::now();
    let convex = mesh.is_convex();
    let sorter = sort::choose(convex);
    let input = SortInput {
        mesh,
        eye_nodes: &eye_nodes,
        screen: &screen,
        perspective: projector.is_perspective(),
        mirrored,
    };
    let order = (sorter.sort)(&input);
    // MPVO's order is exact for a convex mesh without cycles; anything else is settled per
    // pixel.
    let per_pixel = !convex || order.cycle_cells > 0;

    let mut cells = order.back_to_front;
    if settings.order == Order::FrontToBack {
        cells.reverse();
    }
    // Each cell's place in the compositing order, for the per-pixel runs.
    let mut rank = Vec::new();
    if per_pixel {
        rank = vec![0u32; mesh.tet_count()];
        for (i, &c) in cells.iter().enumerate() {
            rank[c as usize] = i as u32;
        }
    }
    let sort_time = sorting.elapsed();

    let binning = Instant::now();
    let edges = lines::edges(vol, &settings.lines)?;
    let line_depth = if edges.is_empty() {
        None
    } else {
        Some(lines::depth_buffer(
            &edges, &eye_nodes, &projector, width, height,
        )?)
    };
    let background = match &settings.background {
        Background::Color(c) => Backdrop::Uniform(*c),
        Background::None => Backdrop::Uniform([0.0; 3]),
        other => Backdrop::Image(other.pixels(width, height)?),
    };
    let frame = Frame {
        vol,
        mapping,
        transfer,
        category_transfers,
        node_mapped,
        projector,
        width,
        height,
        eye_nodes,
        screen,
        background,
        line_depth,
        entry_sign: crate::predicates::entry_sign(mirrored),
        rank,
        span_kernels: settings.span_kernels,
    };

    // Bin the ordered cells into tiles (CSR: tile → cells in order).
    let tile = match settings.tile {
        TILE => auto_tile(width, height, rayon::current_num_threads()),
        t => t,
    };
    let (tx, ty) = (width.div_ceil(tile), height.div_ceil(tile));
    // In parallel: each chunk of the order lists its cells per tile, then each tile joins
    // its chunks' lists in chunk order — the same order as one pass over all cells.
    let chunk = (cells.len() / (4 * rayon::current_num_threads())).max(4096);
    let parts: Vec<(Vec<Vec<u32>>, usize)> = cells
        .par_chunks(chunk)
        .map(|cs| {
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
                if let Some(r) = tile_range(&frame, c as usize, tile, tx, ty) {
                    drawn += 1;
                    for y in r[1]..=r[3] {
                        for x in r[0]..=r[2] {
                            lists[y as usize * tx + x as usize].push(c);
                        }
                    }
                }
            }
            (lists, drawn)
        })
        .collect();
    drop(cells);
    let drawn = parts.iter().map(|p| p.1).sum();
    let binned: Vec<Vec<u32>> = (0..tx * ty)
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
    let bin_time = binning.elapsed();

    let drawing = Instant::now();
    let done = AtomicUsize::new(0);
    let total = tx * ty;
    // Tiles with the most cells first, so that no long tile is left for the end.
    let mut schedule: Vec<usize> = (0..total).collect();
    schedule.sort_by_key(|&t| std::cmp::Reverse(binned[t].len()));
    // The image, filled in as tiles finish: only the tiles in flight exist besides it.
    let fb = std::sync::Mutex::new(Framebuffer::try_new(width, height)?);
    let tiles: Vec<([u64; 2], usize, Overlaps)> = schedule
        .into_par_iter()
        .with_max_len(1)
        .map(|t| {
            let rect = Rect {
                x0: (t % tx) * tile,
                y0: (t / tx) * tile,
                x1: ((t % tx + 1) * tile).min(width),
                y1: ((t / tx + 1) * tile).min(height),
            };
            if cancel.load(Ordering::Relaxed) {
                return ([0, 0], 0, (0, Vec::new()));
            }
            let list = &binned[t];
            let (o, pp) = (settings.order, per_pixel);
            let (out, fragments, most, overlaps) = match &settings.method {
                Method::Exact(m) => render_tile(&frame, m, o, pp, rect, list),
                Method::InterpolateCoeff(m) => render_tile(&frame, m, o, pp, rect, list),
                Method::InterpolateColor(m) => render_tile(&frame, m, o, pp, rect, list),
                Method::Test(m) => render_tile(&frame, m, o, pp, rect, list),
            };
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
    let fragments = tiles.iter().map(|t| t.0[0]).sum();
    let lane_fragments = tiles.iter().map(|t| t.0[1]).sum();
    let most_runs = tiles.iter().map(|t| t.1).max().unwrap_or(0);
    let overlap_pixels = tiles.iter().map(|t| t.2.0).sum();
    let mut overlap_cells: Vec<(u32, u32)> = tiles.into_iter().flat_map(|t| t.2.1).collect();
    overlap_cells.sort_unstable();
    overlap_cells.dedup();
    let draw_time = drawing.elapsed();
    let mut non_finite = 0;
    let mut first_non_finite = None;
    for (i, p) in fb.pixels.iter().enumerate() {
        if !p.iter().all(|v| v.is_finite()) {
            non_finite += 1;
            first_non_finite.get_or_insert((i % width, i / width));
        }
    }
    Ok((
        fb,
        Stats {
            cells: mesh.tet_count(),
            drawn,
            fragments,
            lane_fragments,
            sort: sorter.name,
            convex,
            cycle_cells: order.cycle_cells,
            per_pixel,
            most_runs,
            non_finite,
            first_non_finite,
            overlap_pixels,
            overlap_cells,
            timing: Timing {
                setup,
                sort: sort_time,
                bin: bin_time,
                draw: draw_time,
            },
        },
    ))
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

/// Composites a cell's `(b, θ)` onto a pixel's state: back to front the intensity becomes
/// `I·θ + b`; front to back the colour gains `T·b`. Either way the transparency `T` becomes `T·θ`.
#[inline]
pub(crate) fn composite(order: Order, a: &mut ([f64; 3], f64), (b, theta): ([f64; 3], f64)) {
    match order {
        Order::BackToFront => {
            for ch in 0..3 {
                a.0[ch] = a.0[ch] * theta + b[ch];
            }
        }
        Order::FrontToBack => {
            for ch in 0..3 {
                a.0[ch] += a.1 * b[ch];
            }
        }
    }
    a.1 *= theta;
}

/// Asks the processor to bring `value` into the first-level cache: a hint, it reads nothing.
#[inline(always)]
fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing and cannot fault; the address is of a live reference.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            (value as *const T).cast::<i8>(),
        )
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// Pixels whose runs overlap along the ray, and example pairs of cells.
type Overlaps = (usize, Vec<(u32, u32)>);

/// How a tile keeps its pixels: composited straight in the sort's order (exact for MPVO on a
/// convex mesh), or in per-pixel runs settled by depth ([`runs`]).
enum Pixels {
    Direct(Vec<([f64; 3], f64)>),
    Runs(Runs),
}

/// Renders the cells `list` (in compositing order) into one tile; also returns the number of
/// pixel–cell pairs integrated (all, and in the span kernels) and the most runs one pixel held.
fn render_tile<A: Approx>(
    f: &Frame,
    method: &A,
    order: Order,
    per_pixel: bool,
    rect: Rect,
    list: &[u32],
) -> (Vec<[f32; 4]>, [u64; 2], usize, Overlaps) {
    let tw = rect.x1 - rect.x0;
    let n = tw * (rect.y1 - rect.y0);
    let (dmin, dmax) = f.projector.depth();
    let has_line = |x: usize, y: usize| f.line_at(x, y).is_finite();
    let i0 = |x: usize, y: usize| {
        if has_line(x, y) {
            [0.0; 3]
        } else {
            f.background_at(x, y)
        }
    };
    // The nearest line in the tile: cells behind it need no per-pixel line test.
    let mut nearest_line = f64::INFINITY;
    if f.line_depth.is_some() {
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                nearest_line = nearest_line.min(f.line_at(x, y));
            }
        }
    }
    // Per pixel: intensity (back to front) or accumulated colour (front to back), and the
    // volume's transparency; or the pixel's runs.
    let mut pixels = if per_pixel {
        Pixels::Runs(Runs::new(n))
    } else {
        let mut acc: Vec<([f64; 3], f64)> = Vec::with_capacity(n);
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let c = if order == Order::BackToFront {
                    i0(x, y)
                } else {
                    [0.0; 3]
                };
                acc.push((c, 1.0));
            }
        }
        Pixels::Direct(acc)
    };
    let mut scratch = Scratch::default();
    if A::FACES {
        scratch.faces = vec![[f64::NAN; 2]; n];
    }
    let mut fragments = 0u64;
    // Cells may go through the span kernel: composited in the sort's order, or (per-pixel
    // order) each pixel's result added to its runs.
    let span_frame = f.span_kernels && A::SPAN;
    let ray_planes = f.projector.ray_planes();
    let ray_dirs = f.projector.is_perspective().then(|| {
        let d = ray_planes.dir;
        [d[0][0], d[0][1], d[1][0], d[1][2]]
    });
    let mut span_buf = span::SpanBuffer::default();
    let mut span_pieces = span::SpanPieces::empty();
    // Reused from cell to cell, written in place (see `footprint_into`, `Fan::build`).
    let mut fp = Footprint::empty();
    let mut fan = Fan::default();
    let mut lane_fragments = 0u64;
    let tets = f.vol.mesh.tets();
    let neighbors = f.vol.mesh.neighbors();
    let perspective = f.projector.is_perspective();
    let field: &[f64] = f.transfer.as_ref().map_or(&[], |t| &t.node_values);
    for (i, &cell) in list.iter().enumerate() {
        // The cells come in visibility order, scattered over the mesh: ask for the data of the
        // cells a few places ahead while this one is drawn (a hint, no value changes).
        if let Some(&later) = list.get(i + 8) {
            prefetch(&tets[later as usize]);
            prefetch(&neighbors[later as usize]);
        }
        if let Some(&next) = list.get(i + 4) {
            for n in tets[next as usize] {
                let n = n as usize;
                prefetch(&f.eye_nodes[n]);
                prefetch(&f.screen[n]);
                if let Some(v) = field.get(n) {
                    prefetch(v);
                }
            }
        }
        let cell = cell as usize;
        let eye = f.eye_corners(cell);
        // A flat cell has nothing to draw; its barycentric functions ([`EyeCell`]) only where
        // rays are followed through it (screen-space shading needs none).
        if !EyeCell::is_proper(&eye) {
            continue;
        }
        // Built at most once: the span path and the per-ray path may both ask for it.
        let eye_once = std::cell::OnceCell::new();
        let eye_cell = || *eye_once.get_or_init(|| EyeCell::new(&eye));
        let screen = f.screen_corners(cell);
        if !footprint_into(tets[cell], &eye, &screen, &f.projector, &mut fp) {
            continue;
        }
        let fp = &fp;
        let depth = eye.map(|p| -p[2]);
        // Along every ray τ is the depth, so the cell's depth range bounds every interval:
        // inside the camera's range and before every line, no pixel needs clipping.
        let (lo, hi) = depth
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &d| {
                (lo.min(d), hi.max(d))
            });
        // Depths closer than this are the same point for `test`'s shared faces.
        let touch = TOUCH * (hi - lo);
        let camera_clips = method.clips() && (lo < dmin || hi > dmax);
        let line_clips = hi > nearest_line;
        let unclipped = !camera_clips && !line_clips;
        // A whole projection: every pixel's interval from the faces (watertight); a cell
        // reaching in front of a perspective near plane keeps the per-cell clip.
        // The fan of a screen-space method needs them only to chain runs.
        let fan_only = A::SCREEN_SPACE && unclipped && !per_pixel;
        let cell_faces = || {
            fp.projection
                .is_some()
                .then(|| CellFaces::new(tets[cell], &screen, &depth, f.entry_sign, perspective))
        };
        let faces = if fan_only { None } else { cell_faces() };
        let nb = &neighbors[cell];
        // Whether a neighbour came before this cell in the compositing order.
        let earlier = |n: u32| n != NO_NEIGHBOR && f.rank[n as usize] < f.rank[cell];
        // A fragment of this cell for a pixel's runs, entering from neighbour `en` and leaving
        // to `xn` between depths `near` and `far`.
        let link = |en: u32, xn: u32, near: f64, far: f64| runs::Link {
            cell: cell as u32,
            entry_neighbor: en,
            exit_neighbor: xn,
            entry_earlier: earlier(en),
            exit_earlier: earlier(xn),
            near,
            far,
        };
        let hull = fp.hull();
        // Span kernel: the whole cell's pixels at once.
        if span_frame
            && unclipped
            && let (Some((v, count)), Some(cf), Some(ec)) = (hull, &faces, eye_cell())
        {
            let geometry = span::SpanGeometry {
                rays: CellRays::new(&ec, &f.projector),
                extent: hi - lo,
                length: (hi - lo) * ray_planes.max_speed,
                screen,
            };
            if method.span_cell(f, cell, &geometry, &mut scratch, &mut span_pieces) {
                let sc = &mut span_pieces;
                for piece in &mut sc.cells[..sc.count] {
                    piece.rays = ray_dirs;
                }
                let acc = match &mut pixels {
                    Pixels::Direct(acc) => Some(&mut acc[..]),
                    Pixels::Runs(_) => None,
                };
                let drawn = span::draw(
                    sc,
                    &screen,
                    &v[..count],
                    cf,
                    rect,
                    &mut span_buf,
                    acc,
                    order,
                );
                if let Pixels::Runs(runs) = &mut pixels {
                    // Each pixel's fragment chained through the faces its run enters and
                    // leaves by, as on the per-pixel path below.
                    let b = &span_buf;
                    for &[first, len, entry, exit] in &b.runs {
                        let (en, xn) = (nb[entry as usize], nb[exit as usize]);
                        for i in first as usize..(first + len) as usize {
                            let l = link(en, xn, b.near[i], b.far[i]);
                            let piece = ([b.b[0][i], b.b[1][i], b.b[2][i]], b.theta[i]);
                            runs.add(b.slot[i] as usize, l, piece);
                        }
                    }
                }
                fragments += drawn;
                lane_fragments += drawn;
                continue;
            }
        }
        let mut prepared: Option<A::Cell> = None;
        // Screen-space methods on unclipped cells: Gouraud shading over the outline.
        if A::SCREEN_SPACE
            && unclipped
            && let Some((v, count)) = hull
        {
            let c = method.prepare(f, cell, fp, &mut scratch);
            if method
                .fan_values(&c)
                .is_some_and(|values| fan.build(fp, &values))
            {
                if let (Some(brightness), true, Pixels::Direct(acc)) =
                    (method.gouraud_brightness(), f.span_kernels, &mut pixels)
                {
                    let drawn = span::draw_fan(
                        &fan,
                        brightness,
                        &screen,
                        &v[..count],
                        rect,
                        &mut span_buf,
                        acc,
                        order,
                    );
                    fragments += drawn;
                    lane_fragments += drawn;
                    continue;
                }
                rasterize_convex(&v[..count], rect, |x, y| {
                    let slot = (y - rect.y0) * tw + (x - rect.x0);
                    let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                    let piece = || method.screen_pixel(fan.at(px, py));
                    match &mut pixels {
                        Pixels::Direct(acc) => {
                            let a = &mut acc[slot];
                            if order == Order::FrontToBack && a.1 < EARLY_TERMINATION {
                                return;
                            }
                            fragments += 1;
                            composite(order, a, piece());
                        }
                        Pixels::Runs(runs) => {
                            let Some(h) = faces.as_ref().and_then(|c| c.hit(px, py)) else {
                                return;
                            };
                            fragments += 1;
                            let (en, xn) = (nb[h.entry_face], nb[h.exit_face]);
                            runs.add(slot, link(en, xn, h.near, h.far), piece());
                        }
                    }
                });
                continue;
            }
            prepared = Some(c);
        }
        // No fan after all (a method without one): per ray, from the faces.
        let faces = if fan_only { cell_faces() } else { faces };
        let interval_link = |iv: &Interval| {
            let entry = if faces.is_none() && iv.near <= dmin {
                NO_NEIGHBOR
            } else {
                nb[iv.entry_face]
            };
            link(entry, nb[iv.exit_face], iv.near, iv.far)
        };
        // Everything else per ray: over the outline where the method needs no fan triangle.
        let Some(ec) = eye_cell() else {
            continue;
        };
        let rays = CellRays::new(&ec, &f.projector);
        let hull = if A::SCREEN_SPACE { None } else { hull };
        let parts = if hull.is_some() { 1 } else { fp.count };
        for k in 0..parts {
            let corners = fp.corners[k];
            let mut draw = |x: usize, y: usize, weights: [f64; 3], hit: Option<FaceHit>| {
                let slot = (y - rect.y0) * tw + (x - rect.x0);
                if let Pixels::Direct(acc) = &pixels
                    && order == Order::FrontToBack
                    && acc[slot].1 < EARLY_TERMINATION
                {
                    return;
                }
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let iv = match (&faces, hit) {
                    (Some(_), None) => return,
                    (Some(_), Some(h)) => {
                        let (a, b) = rays.line(px, py);
                        Interval {
                            near: h.near,
                            // Rounding can put a face crossing ~1e-16 past the other one.
                            far: h.far.max(h.near),
                            entry_face: h.entry_face,
                            exit_face: h.exit_face,
                            a,
                            b,
                        }
                    }
                    (None, _) => {
                        let Some(iv) = rays.interval(px, py).filter(|iv| iv.far - iv.near > touch)
                        else {
                            return;
                        };
                        iv
                    }
                };
                let (mut near, mut far) = (iv.near, iv.far);
                if camera_clips {
                    near = near.max(dmin);
                    far = far.min(dmax);
                }
                if line_clips {
                    far = far.min(f.line_at(x, y));
                }
                let clipped_away = near >= far;
                if clipped_away {
                    // Nothing to integrate; a run still passes through the cell.
                    if let Pixels::Runs(runs) = &mut pixels {
                        runs.add(slot, interval_link(&iv), ([0.0; 3], 1.0));
                    }
                    return;
                }
                let c = prepared.get_or_insert_with(|| method.prepare(f, cell, fp, &mut scratch));
                let speed = match f.projector {
                    Projector::Ortho { .. } => 1.0,
                    Projector::Persp { .. } => f.projector.ray(x, y).speed(),
                };
                let entry_on = faces.as_ref().is_some_and(|cf| cf.edge_on(iv.entry_face));
                let exit_on = faces.as_ref().is_some_and(|cf| cf.edge_on(iv.exit_face));
                let px = Pixel {
                    speed,
                    iv,
                    near,
                    far,
                    corners,
                    weights,
                    slot,
                    touch,
                    edge_on: [entry_on, exit_on],
                };
                fragments += 1;
                let piece = method.pixel(f, cell, c, &px, &mut scratch);
                match &mut pixels {
                    Pixels::Direct(acc) => composite(order, &mut acc[slot], piece),
                    Pixels::Runs(runs) => runs.add(slot, interval_link(&iv), piece),
                }
            };
            let at = |x: usize, y: usize| {
                faces
                    .as_ref()
                    .and_then(|cf| cf.hit(x as f64 + 0.5, y as f64 + 0.5))
            };
            match (hull, &faces) {
                (Some((v, count)), Some(cf)) => {
                    // Rows: the inner edges are settled once per row, not per pixel.
                    rasterize_convex_rows(&v[..count], rect, |y, from, to| {
                        let row = cf.row(y, from, to);
                        for x in from..to {
                            draw(x, y, [0.0; 3], cf.hit_in_row(&row, x, y));
                        }
                    });
                }
                (Some((v, count)), None) => {
                    rasterize_convex(&v[..count], rect, |x, y| draw(x, y, [0.0; 3], None));
                }
                (None, _) if A::SCREEN_SPACE => {
                    rasterize::<true>(&fp.tris[k], rect, |x, y, w| draw(x, y, w, at(x, y)));
                }
                (None, _) => {
                    rasterize::<false>(&fp.tris[k], rect, |x, y, w| draw(x, y, w, at(x, y)));
                }
            }
        }
    }
    let mut out = Vec::with_capacity(n);
    let mut k = 0;
    let most = match &pixels {
        Pixels::Runs(r) => r.most,
        Pixels::Direct(_) => 1,
    };
    let mut overlaps = (0, Vec::new());
    for y in rect.y0..rect.y1 {
        for x in rect.x0..rect.x1 {
            let bg = i0(x, y);
            let (rgb, t) = match &mut pixels {
                Pixels::Runs(runs) => runs.resolve(k, bg),
                Pixels::Direct(acc) => {
                    let (c, t) = acc[k];
                    match order {
                        Order::BackToFront => (c, t),
                        Order::FrontToBack => ([0, 1, 2].map(|ch| c[ch] + t * bg[ch]), t),
                    }
                }
            };
            k += 1;
            let alpha = if has_line(x, y) { 1.0 } else { 1.0 - t };
            // A finite value beyond the float range saturates; NaN and infinities stay, to be
            // counted and reported.
            let f = |v: f64| {
                let m = f64::from(f32::MAX);
                if v.is_finite() {
                    v.clamp(-m, m) as f32
                } else {
                    v as f32
                }
            };
            out.push([f(rgb[0]), f(rgb[1]), f(rgb[2]), alpha as f32]);
        }
    }
    if let Pixels::Runs(r) = pixels {
        overlaps = (r.overlaps, r.overlap_cells);
    }
    (out, [fragments, lane_fragments], most, overlaps)
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
