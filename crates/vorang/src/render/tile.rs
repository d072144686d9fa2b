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
use crate::cache::prefetch;
use crate::mesh::NO_NEIGHBOR;
use crate::scene::Projector;

/// A ray interval shorter than this fraction of the cell's depth extent only touches the cell
/// (for `test`'s surfaces, and near-plane-clipped cells).
pub const TOUCH: f64 = 1e-9;

/// Pixels whose runs overlap along the ray, and example pairs of cells.
pub(super) type Overlaps = (usize, Vec<(u32, u32)>);

/// How a tile keeps its pixels: composited straight in the sort's order (exact for MPVO on a
/// convex mesh), or in per-pixel runs settled by depth ([`runs`]).
enum Pixels {
    Direct(Vec<([f64; 3], f64)>),
    Runs(Runs),
}

/// A tile's pixels while its cells are drawn, and what drawing them counted.
struct Canvas {
    /// Per pixel: intensity (back to front) or accumulated colour (front to back), and the
    /// volume's transparency; or the pixel's runs.
    pixels: Pixels,
    /// Pixel–cell pairs integrated, and of those the ones integrated in the span kernels.
    fragments: u64,
    lane_fragments: u64,
}

/// What the tile loop reuses from cell to cell, written in place, so that drawing a cell
/// allocates nothing: the method's scratch space, the span kernels' buffer and pieces, the
/// Gouraud fan (see [`Fan::build`]).
struct Reused {
    scratch: Scratch,
    span_buf: span::SpanBuffer,
    span_pieces: span::SpanPieces,
    fan: Fan,
}

/// What every cell of one tile reads: the frame, the tile, and the frame's constants, worked
/// out once per tile instead of once per cell.
struct Tile<'a> {
    f: &'a Frame<'a>,
    rect: Rect,
    /// The tile's width: pixel (x, y) is slot `(y − y0)·tw + (x − x0)` of its buffers.
    tw: usize,
    order: Order,
    per_pixel: bool,
    /// The camera's depth range.
    dmin: f64,
    dmax: f64,
    /// The nearest grid line in the tile: cells behind it need no per-pixel line test.
    nearest_line: f64,
    /// Cells may go through the span kernels: composited in the sort's order, or (per-pixel
    /// order) each pixel's result added to its runs.
    span_frame: bool,
    perspective: bool,
    /// The largest ray speed (world length per unit of depth), and for perspective rays their
    /// directions as the span kernels take them ([`span::SpanCell::rays`]).
    max_speed: f64,
    ray_dirs: Option<[f64; 4]>,
}

impl<'a> Tile<'a> {
    fn new(f: &'a Frame<'a>, order: Order, per_pixel: bool, span: bool, rect: Rect) -> Tile<'a> {
        let (dmin, dmax) = f.projector.depth();
        let mut nearest_line = f64::INFINITY;
        if f.line_depth.is_some() {
            for y in rect.y0..rect.y1 {
                for x in rect.x0..rect.x1 {
                    nearest_line = nearest_line.min(f.line_at(x, y));
                }
            }
        }
        let ray_planes = f.projector.ray_planes();
        let ray_dirs = f.projector.is_perspective().then(|| {
            let d = ray_planes.dir;
            [d[0][0], d[0][1], d[1][0], d[1][2]]
        });
        Tile {
            f,
            rect,
            tw: rect.x1 - rect.x0,
            order,
            per_pixel,
            dmin,
            dmax,
            nearest_line,
            span_frame: f.span_kernels && span,
            perspective: f.projector.is_perspective(),
            max_speed: ray_planes.max_speed,
            ray_dirs,
        }
    }

    /// The tile's number of pixels.
    fn len(&self) -> usize {
        self.tw * (self.rect.y1 - self.rect.y0)
    }

    /// Pixel (x, y)'s slot in the tile's buffers.
    #[inline(always)]
    fn slot(&self, x: usize, y: usize) -> usize {
        (y - self.rect.y0) * self.tw + (x - self.rect.x0)
    }

    /// I0, what lies behind the volume at a pixel: black where a grid line passes (the line is
    /// an opaque black background at its depth, [`super::lines`]), else the background.
    #[inline]
    fn i0(&self, x: usize, y: usize) -> [f64; 3] {
        if self.f.line_at(x, y).is_finite() {
            [0.0; 3]
        } else {
            self.f.background_at(x, y)
        }
    }

    /// The pixels before the first cell: back to front the intensity starts at I0, front to
    /// back the colour at zero (I0 is added at the end, behind everything); the transparency at
    /// one. Per-pixel order: no runs yet.
    fn start(&self) -> Pixels {
        let n = self.len();
        if self.per_pixel {
            return Pixels::Runs(Runs::new(n));
        }
        let mut acc: Vec<([f64; 3], f64)> = Vec::with_capacity(n);
        for y in self.rect.y0..self.rect.y1 {
            for x in self.rect.x0..self.rect.x1 {
                let c = if self.order == Order::BackToFront {
                    self.i0(x, y)
                } else {
                    [0.0; 3]
                };
                acc.push((c, 1.0));
            }
        }
        Pixels::Direct(acc)
    }

    /// The tile as the framebuffer keeps it, row by row: each pixel's colour with I0 behind it
    /// (front to back `C + T·I0`; per-pixel order, its runs settled by depth) and alpha `1 − T`
    /// (1 on a grid line), in `f32`. Also the most runs one pixel held, and the pixels whose
    /// runs overlapped with example pairs of cells.
    fn finish(&self, mut pixels: Pixels) -> (Vec<[f32; 4]>, usize, Overlaps) {
        let mut out = Vec::with_capacity(self.len());
        let mut k = 0;
        let most = match &pixels {
            Pixels::Runs(r) => r.most,
            Pixels::Direct(_) => 1,
        };
        for y in self.rect.y0..self.rect.y1 {
            for x in self.rect.x0..self.rect.x1 {
                let bg = self.i0(x, y);
                let (rgb, t) = match &mut pixels {
                    Pixels::Runs(runs) => runs.resolve(k, bg),
                    Pixels::Direct(acc) => {
                        let (c, t) = acc[k];
                        match self.order {
                            Order::BackToFront => (c, t),
                            Order::FrontToBack => ([0, 1, 2].map(|ch| c[ch] + t * bg[ch]), t),
                        }
                    }
                };
                k += 1;
                out.push(pixel_out(rgb, t, self.f.line_at(x, y).is_finite()));
            }
        }
        let overlaps = match pixels {
            Pixels::Runs(r) => (r.overlaps, r.overlap_cells),
            Pixels::Direct(_) => (0, Vec::new()),
        };
        (out, most, overlaps)
    }
}

/// A pixel as the framebuffer keeps it: its colour, and alpha `1 − T` (1 on a grid line), in
/// `f32`.
#[inline]
pub(super) fn pixel_out(rgb: [f64; 3], t: f64, on_line: bool) -> [f32; 4] {
    let alpha = if on_line { 1.0 } else { 1.0 - t };
    [to_f32(rgb[0]), to_f32(rgb[1]), to_f32(rgb[2]), alpha as f32]
}

/// A channel for the `f32` framebuffer: a finite value beyond the float range saturates; NaN
/// and infinities stay, to be counted and reported.
#[inline]
fn to_f32(v: f64) -> f32 {
    let m = f64::from(f32::MAX);
    if v.is_finite() {
        v.clamp(-m, m) as f32
    } else {
        v as f32
    }
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
    let tile = Tile::new(f, order, per_pixel, A::SPAN, rect);
    let canvas = draw_cells(&tile, method, list);
    let (out, most, overlaps) = tile.finish(canvas.pixels);
    (
        out,
        [canvas.fragments, canvas.lane_fragments],
        most,
        overlaps,
    )
}

/// One tile's pixels as runs, not composited: per pixel (row by row) how many, and the runs
/// themselves ([`runs::Runs::export`]) — what a rank of a distributed frame sends to the
/// pixel's owner. Also the pixel–cell pairs integrated (all, and in the span kernels).
pub(super) fn render_tile_runs<A: Approx>(
    f: &Frame,
    method: &A,
    order: Order,
    rect: Rect,
    list: &[u32],
) -> (Vec<u32>, Vec<runs::Stretch>, [u64; 2]) {
    let tile = Tile::new(f, order, true, A::SPAN, rect);
    let canvas = draw_cells(&tile, method, list);
    let mut counts = Vec::with_capacity(tile.len());
    let mut stretches = Vec::new();
    if let Pixels::Runs(runs) = &canvas.pixels {
        for slot in 0..tile.len() {
            counts.push(runs.export(slot, &mut stretches) as u32);
        }
    }
    (counts, stretches, [canvas.fragments, canvas.lane_fragments])
}

/// Draws the cells `list` (in compositing order) onto a fresh canvas of the tile.
#[inline]
fn draw_cells<A: Approx>(tile: &Tile, method: &A, list: &[u32]) -> Canvas {
    let f = tile.f;
    let mut canvas = Canvas {
        pixels: tile.start(),
        fragments: 0,
        lane_fragments: 0,
    };
    let mut reused = Reused {
        scratch: Scratch::default(),
        span_buf: span::SpanBuffer::default(),
        span_pieces: span::SpanPieces::empty(),
        fan: Fan::default(),
    };
    if A::FACES {
        reused.scratch.faces = vec![[f64::NAN; 2]; tile.len()];
    }
    // Reused from cell to cell, written in place (see `footprint_into`).
    let mut fp = Footprint::empty();
    let field: &[f64] = f.transfer.as_ref().map_or(&[], |t| &t.node_values);
    for (i, &cell) in list.iter().enumerate() {
        prefetch_ahead(f, field, list, i);
        draw_cell(
            tile,
            method,
            &mut canvas,
            &mut reused,
            &mut fp,
            cell as usize,
        );
    }
    canvas
}

/// The cells come in visibility order, scattered over the mesh: asks for the data of the cells
/// a few places after `list[i]` while that one is drawn (a hint, no value changes).
#[inline(always)]
fn prefetch_ahead(f: &Frame, field: &[f64], list: &[u32], i: usize) {
    let tets = f.vol.mesh.tets();
    if let Some(&later) = list.get(i + 8) {
        prefetch(&tets[later as usize]);
        prefetch(&f.vol.mesh.neighbors()[later as usize]);
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
}

/// One cell as each way of drawing it sees it: its corners, its depth range and what clips it.
struct CellCase<'a> {
    cell: usize,
    screen: [[f64; 2]; 4],
    depth: [f64; 4],
    /// The cell's depth range. Along every ray τ is the depth, so it bounds every interval:
    /// inside the camera's range and before every line, no pixel needs clipping.
    lo: f64,
    hi: f64,
    /// Depths closer than this are the same point for `test`'s shared faces ([`TOUCH`]).
    touch: f64,
    camera_clips: bool,
    line_clips: bool,
    unclipped: bool,
    /// The footprint's outline, for a whole projection.
    hull: Option<([[f64; 2]; 4], usize)>,
    /// The neighbours across the cell's faces, and every cell's place in the compositing
    /// order (per-pixel order only): what a fragment needs to join its pixel's runs.
    nb: &'a [u32; 4],
    rank: &'a [u32],
}

impl<'a> CellCase<'a> {
    fn new<A: Approx>(
        t: &Tile<'a>,
        method: &A,
        cell: usize,
        eye: &[[f64; 3]; 4],
        screen: [[f64; 2]; 4],
        fp: &Footprint,
    ) -> CellCase<'a> {
        let depth = eye.map(|p| -p[2]);
        let (lo, hi) = depth
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &d| {
                (lo.min(d), hi.max(d))
            });
        let camera_clips = method.clips() && (lo < t.dmin || hi > t.dmax);
        let line_clips = hi > t.nearest_line;
        CellCase {
            cell,
            screen,
            depth,
            lo,
            hi,
            touch: TOUCH * (hi - lo),
            camera_clips,
            line_clips,
            unclipped: !camera_clips && !line_clips,
            hull: fp.hull(),
            nb: &t.f.vol.mesh.neighbors()[cell],
            rank: &t.f.rank,
        }
    }

    /// A fragment of this cell for a pixel's runs, entering from neighbour `en` and leaving to
    /// `xn` between depths `near` and `far`; whether each neighbour came earlier in the
    /// compositing order tells the runs which of them may already hold it.
    #[inline]
    fn link(&self, en: u32, xn: u32, near: f64, far: f64) -> runs::Link {
        let earlier = |n: u32| n != NO_NEIGHBOR && self.rank[n as usize] < self.rank[self.cell];
        runs::Link {
            cell: self.cell as u32,
            entry_neighbor: en,
            exit_neighbor: xn,
            entry_earlier: earlier(en),
            exit_earlier: earlier(xn),
            near,
            far,
        }
    }
}

/// Draws one cell into the tile by the cheapest way that gives its exact pixels: a whole
/// unclipped cell the method can describe to them through the span kernels, a screen-space
/// method's unclipped cell with its Gouraud fan, anything else ray by ray. A flat cell, or one
/// whose footprint misses the screen, draws nothing.
fn draw_cell<A: Approx>(
    t: &Tile,
    method: &A,
    canvas: &mut Canvas,
    r: &mut Reused,
    fp: &mut Footprint,
    cell: usize,
) {
    let f = t.f;
    let tets = f.vol.mesh.tets();
    let eye = f.eye_corners(cell);
    // A flat cell has nothing to draw; its barycentric functions ([`EyeCell`]) only where
    // rays are followed through it (screen-space shading needs none).
    if !EyeCell::is_proper(&eye) {
        return;
    }
    // Built at most once: the span path and the per-ray path may both ask for it.
    let eye_once = std::cell::OnceCell::new();
    let eye_cell = || *eye_once.get_or_init(|| EyeCell::new(&eye));
    let screen = f.screen_corners(cell);
    if !footprint_into(tets[cell], &eye, &screen, &f.projector, fp) {
        return;
    }
    let fp = &*fp;
    let c = CellCase::new(t, method, cell, &eye, screen, fp);
    // A whole projection: every pixel's interval from the faces (watertight); a cell
    // reaching in front of a perspective near plane keeps the per-cell clip.
    // The fan of a screen-space method needs them only to chain runs.
    let fan_only = A::SCREEN_SPACE && c.unclipped && !t.per_pixel;
    let cell_faces = || {
        fp.projection
            .is_some()
            .then(|| CellFaces::new(tets[cell], &screen, &c.depth, f.entry_sign, t.perspective))
    };
    let faces = if fan_only { None } else { cell_faces() };
    if t.span_frame
        && c.unclipped
        && draw_span(t, method, canvas, r, &c, faces.as_ref(), eye_cell())
    {
        return;
    }
    let mut prepared: Option<A::Cell> = None;
    if A::SCREEN_SPACE && c.unclipped {
        match draw_fan(t, method, canvas, r, &c, fp, faces.as_ref()) {
            FanDrawn::Drawn => return,
            FanDrawn::NoFan(p) => prepared = Some(p),
            FanDrawn::NoOutline => {}
        }
    }
    // No fan after all (a method without one): per ray, from the faces.
    let faces = if fan_only { cell_faces() } else { faces };
    let Some(ec) = eye_cell() else {
        return;
    };
    let cell = RayCell {
        t,
        method,
        c: &c,
        fp,
        faces: faces.as_ref(),
        rays: CellRays::new(&ec, &f.projector),
    };
    cell.draw(&mut RayOut {
        canvas,
        scratch: &mut r.scratch,
        prepared,
    });
}

/// The span kernels: the whole cell's pixels at once ([`span::draw`]), composited in the sort's
/// order, or (per-pixel order) each pixel's result chained into its runs through the faces its
/// run enters and leaves by, as on the per-ray path. `false` where the cell has no outline or
/// faces, or the method cannot describe it to the kernels ([`Approx::span_cell`]): it is then
/// drawn another way.
fn draw_span<A: Approx>(
    t: &Tile,
    method: &A,
    canvas: &mut Canvas,
    r: &mut Reused,
    c: &CellCase,
    faces: Option<&CellFaces>,
    eye_cell: Option<EyeCell>,
) -> bool {
    let (Some((v, count)), Some(cf), Some(ec)) = (c.hull, faces, eye_cell) else {
        return false;
    };
    let f = t.f;
    let geometry = span::SpanGeometry {
        rays: CellRays::new(&ec, &f.projector),
        extent: c.hi - c.lo,
        length: (c.hi - c.lo) * t.max_speed,
        screen: c.screen,
    };
    if !method.span_cell(f, c.cell, &geometry, &mut r.scratch, &mut r.span_pieces) {
        return false;
    }
    let sc = &mut r.span_pieces;
    for piece in &mut sc.cells[..sc.count] {
        piece.rays = t.ray_dirs;
    }
    let acc = match &mut canvas.pixels {
        Pixels::Direct(acc) => Some(&mut acc[..]),
        Pixels::Runs(_) => None,
    };
    let drawn = span::draw(
        sc,
        &c.screen,
        &v[..count],
        cf,
        t.rect,
        &mut r.span_buf,
        acc,
        t.order,
    );
    if let Pixels::Runs(runs) = &mut canvas.pixels {
        let b = &r.span_buf;
        for &[first, len, entry, exit] in &b.runs {
            let (en, xn) = (c.nb[entry as usize], c.nb[exit as usize]);
            for i in first as usize..(first + len) as usize {
                let l = c.link(en, xn, b.near[i], b.far[i]);
                let piece = ([b.b[0][i], b.b[1][i], b.b[2][i]], b.theta[i]);
                runs.add(b.slot[i] as usize, l, piece);
            }
        }
    }
    canvas.fragments += drawn;
    canvas.lane_fragments += drawn;
    true
}

/// What became of a cell offered to the screen-space fan ([`draw_fan`]).
enum FanDrawn<C> {
    /// A near-clipped footprint has no outline to shade over; nothing was prepared.
    NoOutline,
    Drawn,
    /// The method has no fan for this cell: it is drawn per ray, with what was prepared.
    NoFan(C),
}

/// A screen-space method's unclipped cell: Gouraud shading over the outline ([`Fan`]), in
/// lanes ([`span::draw_fan`]) where the kernels are on and the pixels are composited in the
/// sort's order, else pixel by pixel (per-pixel order: each fragment chained into its runs
/// through the faces that hold it).
fn draw_fan<A: Approx>(
    t: &Tile,
    method: &A,
    canvas: &mut Canvas,
    r: &mut Reused,
    c: &CellCase,
    fp: &Footprint,
    faces: Option<&CellFaces>,
) -> FanDrawn<A::Cell> {
    let Some((v, count)) = c.hull else {
        return FanDrawn::NoOutline;
    };
    let f = t.f;
    let prepared = method.prepare(f, c.cell, fp, &mut r.scratch);
    let fan = &mut r.fan;
    if !method
        .fan_values(&prepared)
        .is_some_and(|values| fan.build(fp, &values))
    {
        return FanDrawn::NoFan(prepared);
    }
    if let (Some(brightness), true, Pixels::Direct(acc)) = (
        method.gouraud_brightness(),
        f.span_kernels,
        &mut canvas.pixels,
    ) {
        let drawn = span::draw_fan(
            fan,
            brightness,
            &c.screen,
            &v[..count],
            t.rect,
            &mut r.span_buf,
            acc,
            t.order,
        );
        canvas.fragments += drawn;
        canvas.lane_fragments += drawn;
        return FanDrawn::Drawn;
    }
    let fan = &*fan;
    let order = t.order;
    rasterize_convex(&v[..count], t.rect, |x, y| {
        let slot = t.slot(x, y);
        let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
        let piece = || method.screen_pixel(fan.at(px, py));
        match &mut canvas.pixels {
            Pixels::Direct(acc) => {
                let a = &mut acc[slot];
                if order == Order::FrontToBack && a.1 < EARLY_TERMINATION {
                    return;
                }
                canvas.fragments += 1;
                composite(order, a, piece());
            }
            Pixels::Runs(runs) => {
                let Some(h) = faces.and_then(|cf| cf.hit(px, py)) else {
                    return;
                };
                canvas.fragments += 1;
                let (en, xn) = (c.nb[h.entry_face], c.nb[h.exit_face]);
                runs.add(slot, c.link(en, xn, h.near, h.far), piece());
            }
        }
    });
    FanDrawn::Drawn
}

/// One cell drawn ray by ray: per covered pixel the ray's interval in the cell — from the
/// faces that hold the pixel centre, or for a cell reaching in front of a perspective near
/// plane from the cell's own planes — clipped, integrated by the method, and composited or
/// chained into the pixel's runs.
struct RayCell<'a, A: Approx> {
    t: &'a Tile<'a>,
    method: &'a A,
    c: &'a CellCase<'a>,
    fp: &'a Footprint,
    /// `None` for a near-clipped cell: its intervals come from `rays`.
    faces: Option<&'a CellFaces>,
    rays: CellRays,
}

/// What the per-ray pixels of one cell write to: the tile's pixels, the method's scratch space,
/// and the cell as the method prepared it (on the first pixel that needs it).
struct RayOut<'a, C> {
    canvas: &'a mut Canvas,
    scratch: &'a mut Scratch,
    prepared: Option<C>,
}

impl<A: Approx> RayCell<'_, A> {
    /// Every covered pixel: over the footprint's outline where the method needs no fan
    /// triangle (by rows, the inner edges settled once per row), else triangle by triangle
    /// with the pixel's screen-space weights in it.
    fn draw(&self, out: &mut RayOut<A::Cell>) {
        let rect = self.t.rect;
        let hull = if A::SCREEN_SPACE { None } else { self.c.hull };
        let parts = if hull.is_some() { 1 } else { self.fp.count };
        for k in 0..parts {
            let corners = self.fp.corners[k];
            let mut draw = |x: usize, y: usize, weights: [f64; 3], hit: Option<FaceHit>| {
                self.pixel(out, corners, x, y, weights, hit);
            };
            let at = |x: usize, y: usize| {
                self.faces
                    .and_then(|cf| cf.hit(x as f64 + 0.5, y as f64 + 0.5))
            };
            match (hull, self.faces) {
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
                    let tri = &self.fp.tris[k];
                    rasterize::<true>(tri, rect, |x, y, w| draw(x, y, w, at(x, y)));
                }
                (None, _) => {
                    let tri = &self.fp.tris[k];
                    rasterize::<false>(tri, rect, |x, y, w| draw(x, y, w, at(x, y)));
                }
            }
        }
    }

    /// One pixel of the cell, in footprint triangle `corners` with screen-space `weights`:
    /// its interval clipped to the camera's depth range and the nearest line; an interval
    /// clipped away integrates nothing but still passes the pixel's runs through the cell.
    #[inline]
    fn pixel(
        &self,
        out: &mut RayOut<A::Cell>,
        corners: [u8; 3],
        x: usize,
        y: usize,
        weights: [f64; 3],
        hit: Option<FaceHit>,
    ) {
        let (t, c, f) = (self.t, self.c, self.t.f);
        let slot = t.slot(x, y);
        if let Pixels::Direct(acc) = &out.canvas.pixels
            && t.order == Order::FrontToBack
            && acc[slot].1 < EARLY_TERMINATION
        {
            return;
        }
        let Some(iv) = self.interval(x, y, hit) else {
            return;
        };
        let (mut near, mut far) = (iv.near, iv.far);
        if c.camera_clips {
            near = near.max(t.dmin);
            far = far.min(t.dmax);
        }
        if c.line_clips {
            far = far.min(f.line_at(x, y));
        }
        let clipped_away = near >= far;
        if clipped_away {
            // Nothing to integrate; a run still passes through the cell.
            if let Pixels::Runs(runs) = &mut out.canvas.pixels {
                runs.add(slot, self.link(&iv), ([0.0; 3], 1.0));
            }
            return;
        }
        let scratch = &mut *out.scratch;
        let prepared = out
            .prepared
            .get_or_insert_with(|| self.method.prepare(f, c.cell, self.fp, scratch));
        let speed = match f.projector {
            Projector::Ortho { .. } => 1.0,
            Projector::Persp { .. } => f.projector.ray(x, y).speed(),
        };
        let entry_on = self.faces.is_some_and(|cf| cf.edge_on(iv.entry_face));
        let exit_on = self.faces.is_some_and(|cf| cf.edge_on(iv.exit_face));
        let px = Pixel {
            speed,
            iv,
            near,
            far,
            corners,
            weights,
            slot,
            touch: c.touch,
            edge_on: [entry_on, exit_on],
        };
        if A::FACES
            && let Pixels::Runs(runs) = &out.canvas.pixels
        {
            // The surfaces already drawn at this pixel are its runs' ends, whatever order the
            // cells came in (the cell before in compositing order need not be the one in front).
            scratch.faces[slot] = runs.ends_at(slot, [iv.near, iv.far], c.touch);
        }
        out.canvas.fragments += 1;
        let piece = self.method.pixel(f, c.cell, prepared, &px, scratch);
        match &mut out.canvas.pixels {
            Pixels::Direct(acc) => composite(t.order, &mut acc[slot], piece),
            Pixels::Runs(runs) => runs.add(slot, self.link(&iv), piece),
        }
    }

    /// The ray's interval in the cell at pixel (x, y): from the faces holding the pixel centre
    /// (`hit`; none: the centre is not in the footprint), or for a near-clipped cell from the
    /// cell's planes, where it is longer than a touch.
    #[inline]
    fn interval(&self, x: usize, y: usize, hit: Option<FaceHit>) -> Option<Interval> {
        let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
        match (self.faces, hit) {
            (Some(_), None) => None,
            (Some(_), Some(h)) => {
                let (a, b) = self.rays.line(px, py);
                Some(Interval {
                    near: h.near,
                    // Rounding can put a face crossing ~1e-16 past the other one.
                    far: h.far.max(h.near),
                    entry_face: h.entry_face,
                    exit_face: h.exit_face,
                    a,
                    b,
                })
            }
            (None, _) => self
                .rays
                .interval(px, py)
                .filter(|iv| iv.far - iv.near > self.c.touch),
        }
    }

    /// The pixel's fragment for its runs: a near-clipped cell's ray that starts at the near
    /// plane enters from no neighbour.
    #[inline]
    fn link(&self, iv: &Interval) -> runs::Link {
        let c = self.c;
        let entry = if self.faces.is_none() && iv.near <= self.t.dmin {
            NO_NEIGHBOR
        } else {
            c.nb[iv.entry_face]
        };
        c.link(entry, c.nb[iv.exit_face], iv.near, iv.far)
    }
}
