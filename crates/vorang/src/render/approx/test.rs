//! `test <opacity>` (thesis 6.3.1 „Test-Methode“): geometry only. Every cell face is a
//! semi-transparent red surface of the given opacity; no depth clipping. Each face is drawn
//! once per ray: a cell draws the faces the ray enters and leaves it through, except a face at
//! a depth where the pixel already holds a surface — [`Scratch::faces`]: where the previous
//! cell of this pixel (in compositing order, which is the order along the ray) left or
//! entered, or in per-pixel order (non-convex meshes, `render/runs.rs`) where one of the
//! pixel's runs ends. Deciding by depth rather than by
//! which faces are shared also gets a ray right that leaves the mesh exactly through an edge or
//! node, where the cell beyond the exit face is only touched and draws nothing.

use super::{Approx, Method, MethodInfo, Pixel, Scratch};
use crate::render::footprint::Footprint;
use crate::render::frame::Frame;

pub const INFO: MethodInfo = MethodInfo {
    name: "test",
    usage: "opacity",
    summary: "every cell face drawn as a semi-transparent red surface (geometry only, no clipping)",
    parse,
};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Test {
    pub opacity: f64,
}

fn parse(args: &[&str]) -> Result<Method, String> {
    match crate::numbers::parse_f64(args[0]) {
        Some(v) if (0.0..=1.0).contains(&v) => Ok(Method::Test(Test { opacity: v })),
        _ => Err(format!("expected an opacity 0…1, found '{}'", args[0])),
    }
}

const RED: [f64; 3] = [1.0, 0.0, 0.0];

impl Test {
    /// A run's map `(b, θ)` without the surface at its near end: where the cells of two ranks
    /// meet along a ray, each rank drew the face between them (its run ends or starts there),
    /// one process draws it once (docs/distributed.md). The near surface is the last map the
    /// run applies, `I ↦ I·(1 − a) + a·red`; undone here. Opaque surfaces (a = 1) hide what
    /// lies behind them, so drawing one twice is drawing it once: nothing to undo.
    pub fn without_near_surface(&self, (b, theta): ([f64; 3], f64)) -> ([f64; 3], f64) {
        let a = self.opacity;
        if a >= 1.0 {
            return (b, theta);
        }
        let keep = 1.0 - a;
        (
            std::array::from_fn(|c| (b[c] - a * RED[c]) / keep),
            theta / keep,
        )
    }
}

impl Approx for Test {
    type Cell = ();
    const FACES: bool = true;

    fn clips(&self) -> bool {
        false
    }

    fn prepare(&self, _: &Frame, _: usize, _: &Footprint, _: &mut Scratch) {}

    fn pixel(&self, _: &Frame, _: usize, _: &(), px: &Pixel, s: &mut Scratch) -> ([f64; 3], f64) {
        let a = self.opacity;
        let previous = s.faces[px.slot];
        let seen = |depth: f64| previous.iter().any(|&d| (d - depth).abs() <= px.touch);
        let mut acc = ([0.0; 3], 1.0);
        let mut surface = |depth: f64| {
            if seen(depth) {
                return;
            }
            for c in 0..3 {
                acc.0[c] = acc.0[c] * (1.0 - a) + a * RED[c];
            }
            acc.1 *= 1.0 - a;
        };
        // Far to near: the exit face unless a line hides it, then the entry face. A face seen
        // edge-on up to rounding is no surface the ray crosses (as when it is exactly edge-on).
        let exit = px.far >= px.iv.far && !px.edge_on[1];
        if exit {
            surface(px.iv.far);
        }
        // A ray that only touches the cell (an edge or a node) crosses one surface there.
        let touches = px.iv.far - px.iv.near <= px.touch;
        if px.near <= px.iv.near && !px.edge_on[0] && !(touches && exit) {
            surface(px.iv.near);
        }
        s.faces[px.slot] = [px.iv.near, px.iv.far];
        acc
    }
}
