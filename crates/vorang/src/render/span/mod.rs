//! Span kernels: a cell's covered pixels integrated together, in SIMD lanes.
//!
//! Every quantity the `linear` rule needs is, along the ray of pixel (x, y), affine in the
//! depth τ with coefficients affine in x and y (for an orthographic view, affine in all three):
//! η (RGB) and χ inside one piece of the transfer function (`exact linear`), or interpolated
//! from the nodes (`interpolateCoeff linear`). So a cell is described once by four affine
//! functions ([`SpanCell`]); the scan conversion only gathers its pixels' entry and exit depths
//! (from the watertight faces, [`super::faces`]) into a [`SpanBuffer`], and the kernel integrates
//! them all: the ends' η and χ, the moments of the rule with a series length fixed per cell
//! ([`crate::integrate::linear_lanes`]) and θ without `exp`.
//! The scalar per-pixel path stays the reference; cells whose segments may cross a table knot or
//! be optically thick take it.
//!
//! The kernel is compiled for the baseline target (SSE2) and, on x86-64, again with AVX2 and
//! AVX-512 enabled; the widest the processor has is chosen once. The AVX2 and AVX-512 kernels
//! use fused multiply-adds (every x86-64 processor with AVX2 has them): the same operations in
//! the same order, so they give the same bits, and fewer of them (about 5 % of an `exact`
//! frame). The baseline rounds each product and sum separately, so its images differ from theirs
//! in the last bits (≤ 10⁻¹⁴ in the tests); the thread count changes no bit on any of them.
//!
//! The files, each importing only those listed after it: `dispatch` picks the compiled copy
//! and holds its entry points; `body` gathers a cell's rows and composites them; `shade`
//! integrates the gathered pixels; [`SpanBuffer`] holds them; `integrand` is how a method
//! describes a cell ([`SpanCell`], [`SpanPieces`]).

mod body;
mod buffer;
mod dispatch;
mod integrand;
mod shade;
#[cfg(test)]
mod tests;

pub use buffer::SpanBuffer;
pub use dispatch::{Kernel, draw, draw_fan, kernel, supported};
pub use integrand::{Clip, MAX_PIECES, SpanCell, SpanGeometry, SpanPieces};
