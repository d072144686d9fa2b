//! How a method describes a cell to the span kernels: its integrand as affine functions of the
//! pixel position and the depth ([`SpanCell`]), cut into pieces where the transfer function's
//! knots cross it ([`SpanPieces`], [`Clip`]), and what it may ask of the cell's geometry to do so
//! ([`SpanGeometry`]). The methods ([`crate::render::approx`]) fill these; the kernels only read
//! them.

use crate::integrate::linear_lanes::terms_for;
use crate::render::cell::CellRays;

/// One cell's integrand: `[η_r, η_g, η_b, χ]`, each `q[k][0] + q[k][1]·x + q[k][2]·y +
/// τ·(q[k][3] + q[k][4]·x + q[k][5]·y)` at pixel position (x, y) and depth τ — or one piece of
/// it ([`Clip`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpanCell {
    pub q: [[f64; 6]; 4],
    /// Perspective rays: their direction's x and y components `[d_x0, d_xx, d_y0, d_yy]`
    /// (`d_x = d_x0 + d_xx·x`, `d_y = d_y0 + d_yy·y`, `d_z = −1`), so that a segment's length is
    /// `Δτ·|d|`; `None` for orthographic rays (`|d| = 1`).
    pub rays: Option<[f64; 4]>,
    /// Where the cell's field crosses knots of the transfer function: the part of each segment
    /// where the field is in `[lo, hi)`.
    pub clip: Option<Clip>,
    /// Series terms for the moments: bounds the truncation error for every segment of the cell
    /// ([`crate::integrate::linear_lanes::terms_for`]).
    pub terms: usize,
    /// The method's brightness factor, applied to `b`.
    pub brightness: f64,
}

/// What a method needs of a cell's geometry to describe it for the kernel.
#[derive(Debug, Clone, Copy)]
pub struct SpanGeometry {
    /// λ along the rays ([`CellRays`]).
    pub rays: CellRays,
    /// The cell's depth range (the longest Δτ of a segment) and the longest segment in world
    /// units (Δτ times the largest ray speed).
    pub extent: f64,
    pub length: f64,
    /// The nodes on screen: the footprint is their convex hull.
    pub screen: [[f64; 2]; 4],
}

impl SpanGeometry {
    /// The largest `|a[3] + a[4]·x + a[5]·y|` over the footprint (at a node: it is affine).
    pub fn max_rate(&self, a: &[f64; 6]) -> f64 {
        self.screen
            .iter()
            .map(|p| (a[3] + a[4] * p[0] + a[5] * p[1]).abs())
            .fold(0.0, f64::max)
    }

    /// Whether `a[3] + a[4]·x + a[5]·y` has the same strict sign over the whole footprint: +1,
    /// −1, or 0 if not.
    pub fn rate_sign(&self, a: &[f64; 6]) -> i8 {
        let signs = self.screen.map(|p| {
            let r = a[3] + a[4] * p[0] + a[5] * p[1];
            (r > 0.0) as i8 - (r < 0.0) as i8
        });
        if signs.iter().all(|&s| s == signs[0]) && a.iter().all(|v| v.is_finite()) {
            signs[0]
        } else {
            0
        }
    }

    /// The series terms for a piece whose absorption is at most `chi` and changes at rate
    /// `chi_rate` (the χ row of the integrand) along the rays.
    pub fn terms(&self, chi: f64, chi_rate: &[f64; 6]) -> Option<usize> {
        terms_for(
            chi * self.length,
            0.5 * self.max_rate(chi_rate) * self.extent * self.length,
        )
    }
}

/// Most pieces of the transfer function one cell may span in the kernel (more: per pixel).
pub const MAX_PIECES: usize = 4;

/// A cell's pieces for the kernel, nearest to the eye first.
#[derive(Debug, Clone, Copy)]
pub struct SpanPieces {
    pub cells: [SpanCell; MAX_PIECES],
    pub count: usize,
}

impl SpanPieces {
    /// No pieces, to be filled by [`crate::render::approx::Approx::span_cell`].
    pub fn empty() -> SpanPieces {
        let cell = SpanCell {
            q: [[0.0; 6]; 4],
            rays: None,
            clip: None,
            terms: 0,
            brightness: 0.0,
        };
        SpanPieces {
            cells: [cell; MAX_PIECES],
            count: 0,
        }
    }

    pub fn one(cell: SpanCell) -> SpanPieces {
        SpanPieces {
            cells: [cell; MAX_PIECES],
            count: 1,
        }
    }

    pub fn pieces(&self) -> &[SpanCell] {
        &self.cells[..self.count]
    }
}

/// The part of a segment where the scalar `s = s[0] + s[1]·x + s[2]·y + τ·(s[3] + s[4]·x +
/// s[5]·y)` lies between `lo` and `hi` (±∞ allowed; the τ coefficient nonzero on the cell).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clip {
    pub s: [f64; 6],
    pub lo: f64,
    pub hi: f64,
}
