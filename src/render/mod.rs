//! The renderer: projected tetrahedra with exact per-pixel ray intervals (thesis chapters 2, 4,
//! 6.3; SPEC §2–6).
//!
//! 1. Node positions to eye space (model from `vol_*`, view from `look_at`).
//! 2. Visibility order of the cells ([`crate::sort`]).
//! 3. Cells are binned, in that order, into the 32×32 screen tiles their footprint touches.
//! 4. Tiles are rendered in parallel, each into its own buffer: per cell, its footprint is
//!    scan-converted; per covered pixel the ray's interval in the cell is clipped to the camera's
//!    depth range and to a grid line in front, the approximation method gives the cell's
//!    `(b, θ)`, and that is composited back to front (`I = I·θ + b`) or front to back.
//!
//! Every pixel sees the same cells in the same order whatever the number of threads, so the image
//! is bit-identical on any machine.

pub mod approx;
pub mod cell;
pub mod footprint;
pub mod frame;
pub mod lines;
pub mod project;
pub mod raster;

use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

pub use approx::{METHODS, Method};
pub use lines::LineDraw;

use approx::{Approx, Pixel, Scratch};
use cell::EyeCell;
use footprint::footprint;
use frame::Frame;
use raster::{Rect, rasterize};

use crate::error::Error;
use crate::framebuffer::{Background, Framebuffer};
use crate::mapping::Mapping;
use crate::scene::{Projector, View};
use crate::sort::{self, SortInput};
use crate::volume::Volume;

/// Default edge length of a screen tile in pixels.
pub const TILE: usize = 32;

/// Front-to-back compositing stops for a pixel once its accumulated transparency falls below
/// this: what lies behind can change the pixel by at most this fraction of its background.
pub const EARLY_TERMINATION: f64 = 1e-6;

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
    /// Edge length of the screen tiles rendered in parallel (any value gives the same image).
    pub tile: usize,
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
        }
    }
}

/// What happened during a render.
#[derive(Debug, Clone, PartialEq)]
pub struct Stats {
    pub cells: usize,
    /// Cells with a footprint on screen.
    pub drawn: usize,
    /// The visibility sort used and whether the mesh is convex.
    pub sort: &'static str,
    pub convex: bool,
    /// Cells that had to be released from a visibility cycle (0: the order is exact).
    pub cycle_cells: usize,
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
    let to_eye = view.view_matrix().after(&model);
    let projector = Projector::new(view.camera.as_ref(), bbox.size(), width, height)?;
    let eye_nodes: Vec<[f64; 3]> = mesh.nodes().par_iter().map(|&p| to_eye.apply(p)).collect();
    let screen: Vec<[f64; 2]> = eye_nodes.par_iter().map(|&p| projector.screen(p)).collect();

    let convex = sort::is_convex(mesh);
    let sorter = sort::choose(convex);
    let input = SortInput {
        mesh,
        eye_nodes: &eye_nodes,
        perspective: projector.is_perspective(),
    };
    let order = (sorter.sort)(&input);
    let mut cells = order.back_to_front;
    if settings.order == Order::FrontToBack {
        cells.reverse();
    }

    let edges = lines::edges(vol, &settings.lines)?;
    let line_depth = lines::depth_buffer(&edges, &eye_nodes, &projector, width, height);
    let frame = Frame {
        vol,
        mapping,
        projector,
        width,
        height,
        eye_nodes,
        screen,
        background: settings.background.pixels(width, height),
        line_depth,
    };

    // Bin the ordered cells into tiles (CSR: tile → cells in order).
    let tile = settings.tile.max(1);
    let (tx, ty) = (width.div_ceil(tile), height.div_ceil(tile));
    let ranges: Vec<Option<[u32; 4]>> = cells
        .par_iter()
        .map(|&c| tile_range(&frame, c as usize, tile, tx, ty))
        .collect();
    let mut start = vec![0u32; tx * ty + 1];
    for r in ranges.iter().flatten() {
        for y in r[1]..=r[3] {
            for x in r[0]..=r[2] {
                start[y as usize * tx + x as usize + 1] += 1;
            }
        }
    }
    for i in 0..tx * ty {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut binned = vec![0u32; start[tx * ty] as usize];
    for (&c, r) in cells.iter().zip(&ranges) {
        if let Some(r) = r {
            for y in r[1]..=r[3] {
                for x in r[0]..=r[2] {
                    let t = y as usize * tx + x as usize;
                    binned[fill[t] as usize] = c;
                    fill[t] += 1;
                }
            }
        }
    }
    drop(fill);
    let drawn = ranges.iter().filter(|r| r.is_some()).count();

    let done = AtomicUsize::new(0);
    let total = tx * ty;
    let tiles: Vec<Vec<[f32; 4]>> = (0..total)
        .into_par_iter()
        .map(|t| {
            let rect = Rect {
                x0: (t % tx) * tile,
                y0: (t / tx) * tile,
                x1: ((t % tx + 1) * tile).min(width),
                y1: ((t / tx + 1) * tile).min(height),
            };
            let list = &binned[start[t] as usize..start[t + 1] as usize];
            let out = match &settings.method {
                Method::Exact(m) => render_tile(&frame, m, settings.order, rect, list),
                Method::InterpolateCoeff(m) => render_tile(&frame, m, settings.order, rect, list),
                Method::InterpolateColor(m) => render_tile(&frame, m, settings.order, rect, list),
                Method::Test(m) => render_tile(&frame, m, settings.order, rect, list),
            };
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if let Some(p) = progress {
                p(n, total);
            }
            out
        })
        .collect();

    let mut fb = Framebuffer::new(width, height);
    for (t, pixels) in tiles.iter().enumerate() {
        let (x0, y0) = ((t % tx) * tile, (t / tx) * tile);
        let w = (x0 + tile).min(width) - x0;
        for (row, chunk) in pixels.chunks(w).enumerate() {
            let at = (y0 + row) * width + x0;
            fb.pixels[at..at + w].copy_from_slice(chunk);
        }
    }
    Ok((
        fb,
        Stats {
            cells: mesh.tet_count(),
            drawn,
            sort: sorter.name,
            convex,
            cycle_cells: order.cycle_cells,
        },
    ))
}

/// The tiles `[x0, y0, x1, y1]` (inclusive) a cell's footprint touches, if any.
fn tile_range(f: &Frame, cell: usize, tile: usize, tx: usize, ty: usize) -> Option<[u32; 4]> {
    let fp = footprint(
        f.vol.mesh.tets()[cell],
        &f.eye_corners(cell),
        &f.screen_corners(cell),
        &f.projector,
    )?;
    let b = fp.bbox()?;
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

/// Renders the cells `list` (in compositing order) into one tile.
fn render_tile<A: Approx>(
    f: &Frame,
    method: &A,
    order: Order,
    rect: Rect,
    list: &[u32],
) -> Vec<[f32; 4]> {
    let tw = rect.x1 - rect.x0;
    let n = tw * (rect.y1 - rect.y0);
    let (dmin, dmax) = f.projector.depth();
    let pixel_index = |x: usize, y: usize| y * f.width + x;
    let has_line = |x: usize, y: usize| f.line_depth[pixel_index(x, y)].is_finite();
    let i0 = |x: usize, y: usize| {
        if has_line(x, y) {
            [0.0; 3]
        } else {
            f.background[pixel_index(x, y)]
        }
    };
    // Per pixel: intensity (back to front) or accumulated colour (front to back), and the
    // volume's transparency.
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
    let mut scratch = Scratch::default();
    let tets = f.vol.mesh.tets();
    for &cell in list {
        let cell = cell as usize;
        let eye = f.eye_corners(cell);
        let Some(ec) = EyeCell::new(&eye) else {
            continue;
        };
        let Some(fp) = footprint(tets[cell], &eye, &f.screen_corners(cell), &f.projector) else {
            continue;
        };
        let mut prepared: Option<A::Cell> = None;
        for k in 0..fp.count {
            let corners = fp.corners[k];
            rasterize(&fp.tris[k], rect, |x, y, weights| {
                let a = &mut acc[(y - rect.y0) * tw + (x - rect.x0)];
                if order == Order::FrontToBack && a.1 < EARLY_TERMINATION {
                    return;
                }
                let ray = f.projector.ray(x, y);
                let Some(iv) = ec.interval(&ray) else { return };
                let (mut near, mut far) = (iv.near, iv.far);
                if method.clips() {
                    near = near.max(dmin);
                    far = far.min(dmax);
                }
                far = far.min(f.line_depth[pixel_index(x, y)]);
                if near >= far {
                    return;
                }
                if prepared.is_none() {
                    prepared = Some(method.prepare(f, cell, &ec, &fp, &mut scratch));
                }
                let Some(c) = prepared.as_ref() else { return };
                let px = Pixel {
                    ray,
                    iv,
                    near,
                    far,
                    corners,
                    weights,
                };
                let (b, theta) = method.pixel(f, cell, c, &px, &mut scratch);
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
            });
        }
    }
    let mut out = Vec::with_capacity(n);
    let mut k = 0;
    for y in rect.y0..rect.y1 {
        for x in rect.x0..rect.x1 {
            let (c, t) = acc[k];
            k += 1;
            let rgb = match order {
                Order::BackToFront => c,
                Order::FrontToBack => {
                    let bg = i0(x, y);
                    [0, 1, 2].map(|ch| c[ch] + t * bg[ch])
                }
            };
            let alpha = if has_line(x, y) { 1.0 } else { 1.0 - t };
            out.push([rgb[0] as f32, rgb[1] as f32, rgb[2] as f32, alpha as f32]);
        }
    }
    out
}
