//! `exact <integration> <step> <brightness>` (thesis 6.3.1 „Exakte Methode“): per pixel, the
//! cell's ray interval is split into pieces of at most `step` world units; the field is
//! evaluated with its own interpolator and mapped at every piece end, and each piece is
//! integrated with the chosen rule. A step larger than the interval (or 0) integrates the
//! whole interval at once.

use super::{Approx, Method, MethodInfo, Pixel, Scratch, accumulate, non_negative, rule};
use crate::integrate::{RuleInfo, Segment};
use crate::render::cell::EyeCell;
use crate::render::footprint::Footprint;
use crate::render::frame::Frame;

pub const INFO: MethodInfo = MethodInfo {
    name: "exact",
    usage: "integration step brightness",
    summary: "true field values and mapping at sample points at most 'step' apart, integrated with the rule",
    parse,
};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exact {
    pub rule: &'static RuleInfo,
    pub step: f64,
    pub brightness: f64,
}

fn parse(args: &[&str]) -> Result<Method, String> {
    Ok(Method::Exact(Exact {
        rule: rule(args[0])?,
        step: non_negative(args[1], "a step length")?,
        brightness: non_negative(args[2], "a brightness factor")?,
    }))
}

impl Approx for Exact {
    type Cell = ();

    fn prepare(&self, _: &Frame, _: usize, _: &EyeCell, _: &Footprint, _: &mut Scratch) {}

    fn pixel(
        &self,
        f: &Frame,
        cell: usize,
        _: &(),
        px: &Pixel,
        s: &mut Scratch,
    ) -> ([f64; 3], f64) {
        let speed = px.ray.speed();
        let length = (px.far - px.near) * speed;
        let pieces = if self.step > 0.0 && length > self.step {
            (length / self.step).ceil() as usize
        } else {
            1
        };
        // Values at the piece ends, from the far end (τ = far) to the near end.
        s.ends.clear();
        for k in 0..=pieces {
            let tau = px.far - (px.far - px.near) * (k as f64 / pieces as f64);
            let lambda = px.iv.lambda(tau);
            s.ends.push(f.mapped(cell, &lambda, &mut s.values));
        }
        let ds = length / pieces as f64;
        let mut acc = ([0.0; 3], 1.0);
        for k in 0..pieces {
            let (far, near) = (s.ends[k], s.ends[k + 1]);
            let seg = Segment {
                eta: [far.0, near.0],
                chi: [far.1, near.1],
                ds,
            };
            accumulate(&mut acc, (self.rule.rule)(&seg));
        }
        (acc.0.map(|b| b * self.brightness), acc.1)
    }
}
