//! The tile loop: one screen tile's cells, in compositing order, drawn into the tile's own
//! buffer (thesis 6.3; where its time goes: `docs/performance.md`).
//!
//! Per cell: its footprint ([`super::footprint`]); the ray intervals from its faces
//! ([`super::faces`]), clipped to the camera's depth range and to a grid line in front; the
//! method's `(b, θ)` per pixel ([`super::approx`]), composited in the sort's order or kept in
//! per-pixel runs ([`super::runs`]). Whole unclipped cells go through the SIMD span kernels
//! ([`super::span`]) where the method allows. Tiles share nothing but the frame, so any number
//! of them run in parallel and every pixel sees the same cells in the same order.

use super::approx::{Approx, Pixel, Scratch};
use super::cell::{CellRays, EyeCell, Interval};
use super::composite::{EARLY_TERMINATION, Order, composite};
use super::faces::{CellFaces, FaceHit};
use super::footprint::{Footprint, footprint_into};
use super::frame::Frame;
use super::gouraud::Fan;
use super::raster::{Rect, rasterize, rasterize_convex, rasterize_convex_rows};
use super::runs::{self, Runs};
use super::span;
use crate::mesh::NO_NEIGHBOR;
use crate::scene::Projector;

/// A ray interval shorter than this fraction of the cell's depth extent only touches the cell
/// (for `test`'s surfaces, and near-plane-clipped cells).
pub const TOUCH: f64 = 1e-9;

/// Asks the processor to bring `value` into the first-level cache: a hint, it reads nothing.
#[inline(always)]
pub(super) fn prefetch<T>(value: &T) {
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
pub(super) type Overlaps = (usize, Vec<(u32, u32)>);

/// How a tile keeps its pixels: composited straight in the sort's order (exact for MPVO on a
/// convex mesh), or in per-pixel runs settled by depth ([`runs`]).
enum Pixels {
    Direct(Vec<([f64; 3], f64)>),
    Runs(Runs),
}

/// Renders the cells `list` (in compositing order) into one tile; also returns the number of
/// pixel–cell pairs integrated (all, and in the span kernels) and the most runs one pixel held.
pub(super) fn render_tile<A: Approx>(
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
