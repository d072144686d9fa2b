//! The renderer: projected tetrahedra with exact per-pixel ray intervals (thesis chapters 2, 4,
//! 6.3).
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
//!
//! # Floor plan
//!
//! Every file imports only files after it in this list (its tests included), never one that
//! imports it back, and none imports from this one (it only declares the files and re-exports
//! what callers use):
//!
//! - [`deep`]: a rank's part of a distributed frame — the same steps, each pixel's runs kept
//!   instead of composited — and the one function that settles a pixel from every rank's runs.
//! - `schedule`: one frame — steps 1–4 above, the tiles in parallel, the statistics.
//! - `settings`: what a render is asked for (size, method, order, lines, background, tiles).
//! - `tile`: one tile's cells (step 4), each by whichever way of drawing it suits.
//! - [`approx`]: the methods, per cell and per pixel; [`span`]: whole cells in SIMD lanes.
//! - [`rows`], [`gouraud`]: a footprint's rows at once, the screen-space fan.
//! - [`faces`], [`footprint`], [`runs`]: the watertight faces, the Shirley–Tuchman footprint,
//!   the per-pixel runs.
//! - [`project`], [`raster`], [`cell`], [`lines`]: the projection classes, scan conversion,
//!   rays through one cell, grid lines.
//! - `composite`, [`frame`]: compositing a contribution, what a frame's tiles share.
//!
//! Beneath them all, shared with the visibility sort: the exact screen predicates
//! ([`crate::predicates`]).

pub mod approx;
pub mod cell;
mod composite;
pub mod deep;
pub mod faces;
pub mod footprint;
pub mod frame;
pub mod gouraud;
pub mod lines;
pub mod project;
pub mod raster;
pub mod rows;
pub mod runs;
mod schedule;
mod settings;
pub mod span;
mod tile;

pub use approx::{MAX_PIECES, METHODS, Method};
pub use composite::{EARLY_TERMINATION, Order};
pub use lines::LineDraw;
pub use raster::Rect;
pub use schedule::{
    CANCELLED, RankLoad, Stats, TileSink, Timing, Watch, auto_tile, render, render_cancellable,
    render_watched,
};
#[cfg(feature = "gpu")]
pub(crate) use schedule::{Placed, place_nodes};
pub use settings::{MAX_PIXELS, Settings, TILE, check_size};
pub use tile::TOUCH;
