//! Which compiled copy of the kernels runs: the baseline (SSE2) one, or on x86-64 the copies
//! compiled with AVX2 or AVX-512 and fused multiply-adds, the widest the processor has, chosen
//! once ([`kernel`]). [`draw`] and [`draw_fan`], what the tile loop calls, go through here.

use super::body::{Draw, FanDraw, FanShade, draw_body, draw_body_with, draw_fan_body};
use super::buffer::{LANES, SpanBuffer};
use super::integrand::{SpanCell, SpanPieces};
use super::shade::integrate_piece;
use crate::render::composite::Order;
use crate::render::faces::CellFaces;
use crate::render::gouraud::Fan;
use crate::render::raster::Rect;

/// Which compiled kernel this processor runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    Baseline,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Kernel {
    /// The instruction set, for the timing line.
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Baseline => "baseline",
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2 => "AVX2",
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 => "AVX-512",
        }
    }
}

/// The widest kernel the processor supports (decided once). `VORANG_KERNEL=baseline` or
/// `avx2` caps it, to measure or compare the narrower kernels on a wider processor (an
/// unknown name or a kernel the processor lacks changes nothing).
pub fn kernel() -> Kernel {
    static CHOICE: std::sync::OnceLock<Kernel> = std::sync::OnceLock::new();
    *CHOICE.get_or_init(|| {
        let cap = std::env::var("VORANG_KERNEL").unwrap_or_default();
        #[cfg(target_arch = "x86_64")]
        {
            let allowed = match cap.as_str() {
                "baseline" => &[][..],
                "avx2" => &[Kernel::Avx2][..],
                _ => &[Kernel::Avx512, Kernel::Avx2][..],
            };
            for &k in allowed {
                if supported(k) {
                    return k;
                }
            }
        }
        let _ = cap;
        Kernel::Baseline
    })
}

/// Whether this processor can run kernel `k`.
pub fn supported(k: Kernel) -> bool {
    match k {
        Kernel::Baseline => true,
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 => {
            std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
        }
        #[cfg(target_arch = "x86_64")]
        // The AVX-512 kernels' gathering and compositing are compiled for AVX2 (every AVX-512
        // processor has it; asked all the same, as the `unsafe` calls rely on it).
        Kernel::Avx512 => {
            std::is_x86_feature_detected!("avx512f")
                && std::is_x86_feature_detected!("avx2")
                && std::is_x86_feature_detected!("fma")
        }
    }
}

/// Draws a cell through the kernel: gathers the pixels of its footprint `hull` in `rect` (the
/// tile) with their entry and exit depths from `faces`, integrates every piece, and composites
/// the results into the tile's pixels `acc` (row-major in `rect`) in `order`. Returns the number
/// of pixels composited. Gathering and compositing are compiled with the kernel, for its width.
/// Without `acc` (a per-pixel order) the results stay in `buf` — `b`, `theta`, `near`, `far`,
/// `slot` per pixel and the runs' faces in `runs` — and the count is of those pixels.
#[allow(clippy::too_many_arguments)]
pub fn draw(
    pieces: &SpanPieces,
    screen: &[[f64; 2]; 4],
    hull: &[[f64; 2]],
    faces: &CellFaces,
    rect: Rect,
    buf: &mut SpanBuffer,
    acc: Option<&mut [([f64; 3], f64)]>,
    order: Order,
) -> u64 {
    draw_with(kernel(), pieces, screen, hull, faces, rect, buf, acc, order)
}

/// [`draw`] with the kernel compiled for `k` (the baseline one where the processor lacks
/// `k`'s features).
#[allow(clippy::too_many_arguments)]
pub(super) fn draw_with(
    k: Kernel,
    pieces: &SpanPieces,
    screen: &[[f64; 2]; 4],
    hull: &[[f64; 2]],
    faces: &CellFaces,
    rect: Rect,
    buf: &mut SpanBuffer,
    acc: Option<&mut [([f64; 3], f64)]>,
    order: Order,
) -> u64 {
    let d = Draw {
        pieces,
        screen,
        hull,
        faces,
        rect,
        order,
    };
    match k {
        // SAFETY (both): the processor reported the features the function is compiled for.
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 if supported(k) => unsafe { draw_avx2(&d, buf, acc) },
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx512 if supported(k) => unsafe { draw_avx512(&d, buf, acc) },
        _ => draw_body::<LANES, false, LANES>(&d, buf, acc),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn draw_avx2(d: &Draw, buf: &mut SpanBuffer, acc: Option<&mut [([f64; 3], f64)]>) -> u64 {
    draw_body::<16, true, 4>(d, buf, acc)
}

/// The AVX-512 kernel: the integration in 32-pixel batches compiled for AVX-512 (a function of
/// its own), the gathering of pixels and the compositing around it for AVX2, which ran faster
/// there (as for the fan, [`draw_fan_avx512`]): the 150k `exact` frame's draw 1–3 % faster,
/// the bits the same (docs/performance.md).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn draw_avx512(d: &Draw, buf: &mut SpanBuffer, acc: Option<&mut [([f64; 3], f64)]>) -> u64 {
    // SAFETY: only called where the processor has AVX-512 (see `draw_with`).
    draw_body_with::<8>(d, buf, acc, |piece, buf| unsafe {
        integrate_avx512(piece, buf)
    })
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,fma")]
fn integrate_avx512(piece: &SpanCell, buf: &mut SpanBuffer) {
    integrate_piece::<32, true>(piece, buf)
}

/// Draws a cell shaded in screen space (`interpolateColor`): the Gouraud values of `fan` over
/// the footprint `hull` in `rect`, as [`crate::render::gouraud::shade`] with `brightness`,
/// composited into `acc` in `order`, in lanes. The same bits as pixel by pixel
/// ([`Fan::at_lanes`]). Returns the number of pixels composited.
#[allow(clippy::too_many_arguments)]
pub fn draw_fan(
    fan: &Fan,
    brightness: f64,
    screen: &[[f64; 2]; 4],
    hull: &[[f64; 2]],
    rect: Rect,
    buf: &mut SpanBuffer,
    acc: &mut [([f64; 3], f64)],
    order: Order,
) -> u64 {
    draw_fan_with(
        kernel(),
        fan,
        brightness,
        screen,
        hull,
        rect,
        buf,
        acc,
        order,
    )
}

/// [`draw_fan`] compiled for `k` (the baseline where the processor lacks `k`'s features).
#[allow(clippy::too_many_arguments)]
pub(super) fn draw_fan_with(
    k: Kernel,
    fan: &Fan,
    brightness: f64,
    screen: &[[f64; 2]; 4],
    hull: &[[f64; 2]],
    rect: Rect,
    buf: &mut SpanBuffer,
    acc: &mut [([f64; 3], f64)],
    order: Order,
) -> u64 {
    let d = FanDraw {
        fan,
        brightness,
        screen,
        hull,
        rect,
        order,
    };
    match k {
        // SAFETY (both): the processor reported the features the function is compiled for.
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 if supported(k) => unsafe { draw_fan_avx2(&d, buf, acc) },
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx512 if supported(k) => unsafe { draw_fan_avx512(&d, buf, acc) },
        _ => draw_fan_body::<LANES, { FanShade::Lanes as u8 }>(&d, buf, acc),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn draw_fan_avx2(d: &FanDraw, buf: &mut SpanBuffer, acc: &mut [([f64; 3], f64)]) -> u64 {
    draw_fan_body::<LANES, { FanShade::Avx2 as u8 }>(d, buf, acc)
}

/// The AVX-512 fan: its shading ([`Fan::shade_avx512`], a function of its own) in eight lanes,
/// but the gathering of pixels and the compositing around it compiled for AVX2. Compiled for
/// AVX-512 they were slower (the 150k `interpolateColor` frame's draw 95.2 ms against 86.3 ms
/// on an Intel Xeon with AVX-512, docs/performance.md); the bits are the same.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn draw_fan_avx512(d: &FanDraw, buf: &mut SpanBuffer, acc: &mut [([f64; 3], f64)]) -> u64 {
    draw_fan_body::<LANES, { FanShade::Avx512 as u8 }>(d, buf, acc)
}
