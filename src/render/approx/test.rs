//! `test <opacity>` (thesis 6.3.1 „Test-Methode“): geometry only. Every cell face is a
//! semi-transparent red surface of the given opacity; no depth clipping. Each face is drawn
//! once per ray: a cell draws the face the ray enters through, and the face it leaves through
//! only if that is a boundary face (an interior face is the entry face of the cell behind it).

use super::{Approx, Method, MethodInfo, Pixel, Scratch};
use crate::render::cell::EyeCell;
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

impl Approx for Test {
    type Cell = ();

    fn clips(&self) -> bool {
        false
    }

    fn prepare(&self, _: &Frame, _: usize, _: &EyeCell, _: &Footprint, _: &mut Scratch) {}

    fn pixel(
        &self,
        f: &Frame,
        cell: usize,
        _: &(),
        px: &Pixel,
        _: &mut Scratch,
    ) -> ([f64; 3], f64) {
        let a = self.opacity;
        let mut acc = ([0.0; 3], 1.0);
        let surface = |acc: &mut ([f64; 3], f64)| {
            for c in 0..3 {
                acc.0[c] = acc.0[c] * (1.0 - a) + a * RED[c];
            }
            acc.1 *= 1.0 - a;
        };
        // The exit face, if it is on the boundary and not hidden behind a line.
        let boundary_exit = f.vol.mesh.neighbor(cell, px.iv.exit_face).is_none();
        if boundary_exit && px.far >= px.iv.far {
            surface(&mut acc);
        }
        if px.near <= px.iv.near {
            surface(&mut acc);
        }
        acc
    }
}
