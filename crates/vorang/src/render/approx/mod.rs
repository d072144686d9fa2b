//! The approximation methods (thesis 6.3.1), each one file and one entry in
//! [`METHODS`]. The tile loop is generic over [`Approx`]: the method is chosen once per frame and
//! the per-pixel code is monomorphised for it.

mod exact;
mod interpolate_coeff;
mod interpolate_color;
mod test;

pub(crate) use exact::check_step;
pub use exact::{Exact, MAX_PIECES};
pub use interpolate_coeff::InterpolateCoeff;
pub use interpolate_color::InterpolateColor;
pub use test::Test;

use super::cell::Interval;
use super::footprint::Footprint;
use super::frame::Frame;
use super::span::{SpanGeometry, SpanPieces};
use crate::integrate::{self, RuleInfo};

/// What a method sees of one covered pixel.
#[derive(Debug, Clone, Copy)]
pub struct Pixel {
    /// World length per unit of the ray parameter τ (`|d|`; 1 for orthographic rays).
    pub speed: f64,
    /// The ray's whole passage through the cell.
    pub iv: Interval,
    /// The part to integrate, after clipping to the camera's depth range and to a line in front:
    /// `near ≤ far`, both within `iv`.
    pub near: f64,
    pub far: f64,
    /// The corners of the footprint triangle holding the pixel (0…3 nodes, 4 the thick point)
    /// and the pixel's screen-space barycentric weights in it (for Gouraud interpolation).
    pub corners: [u8; 3],
    pub weights: [f64; 3],
    /// The pixel's index in the tile (for [`Scratch::faces`]).
    pub slot: usize,
    /// Depths closer than this are the same point up to rounding (the cell's [`TOUCH`]
    /// threshold).
    ///
    /// [`TOUCH`]: crate::render::TOUCH
    pub touch: f64,
    /// Whether the entry and the exit face are seen edge-on up to rounding: the ray runs in
    /// their plane, so they are no surface it crosses.
    pub edge_on: [bool; 2],
}

/// Per-tile scratch space, so the pixel loop never allocates.
#[derive(Debug, Default)]
pub struct Scratch {
    pub values: Vec<f64>,
    pub values2: Vec<f64>,
    pub ends: Vec<([f64; 3], f64)>,
    pub cuts: Vec<f64>,
    /// Per pixel of the tile, for methods with [`Approx::FACES`]: the entry and exit depth of
    /// the last cell the pixel's ray passed (NaN before the first).
    pub faces: Vec<[f64; 2]>,
}

/// An approximation method: per-cell preparation and per-pixel contribution `(b, θ)`, with the
/// brightness factor already applied to `b`.
pub trait Approx: Sync {
    type Cell;
    /// A method whose pixels, where nothing clips the cell, follow from the screen-space
    /// weights alone ([`Approx::screen_pixel`]): the ray interval is then not computed.
    const SCREEN_SPACE: bool = false;
    /// A method that keeps [`Scratch::faces`] per pixel.
    const FACES: bool = false;
    /// Whether the ray is clipped to the camera's depth range (`test` is not).
    fn clips(&self) -> bool {
        true
    }
    /// For a cell drawn in screen space: the values `[θ, η̄ (RGB)]` at the fan's vertices
    /// (nodes 0…3, the thick point 4), interpolated over the footprint; `None` to draw the cell
    /// per ray instead.
    fn fan_values(&self, _c: &Self::Cell) -> Option<[[f64; 4]; 5]> {
        None
    }
    /// The contribution of a pixel from the interpolated fan values.
    fn screen_pixel(&self, _values: [f64; 4]) -> ([f64; 3], f64) {
        unreachable!("only methods with SCREEN_SPACE are asked for screen-space pixels")
    }
    /// Where [`Approx::screen_pixel`] is [`crate::render::gouraud::shade`] with a brightness:
    /// that brightness, so whole cells can be shaded in lanes ([`crate::render::span::draw_fan`]).
    fn gouraud_brightness(&self) -> Option<f64> {
        None
    }
    /// A method that may hand whole cells to the span kernel ([`Approx::span_cell`]).
    const SPAN: bool = false;
    /// For a cell nothing clips: the cell as [`SpanPieces`] (η and χ affine along every segment
    /// within each piece, integrated by the `linear` rule, thin enough for the lanes), written
    /// into `out` (the tile's, reused: a cell's pieces are a kilobyte, not worth moving);
    /// `false` to draw the cell pixel by pixel (`out` then means nothing).
    fn span_cell(
        &self,
        _f: &Frame,
        _cell: usize,
        _geometry: &SpanGeometry,
        _s: &mut Scratch,
        _out: &mut SpanPieces,
    ) -> bool {
        false
    }
    fn prepare(&self, f: &Frame, cell: usize, fp: &Footprint, s: &mut Scratch) -> Self::Cell;
    fn pixel(
        &self,
        f: &Frame,
        cell: usize,
        c: &Self::Cell,
        px: &Pixel,
        s: &mut Scratch,
    ) -> ([f64; 3], f64);
}

/// A chosen method with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    Exact(Exact),
    InterpolateCoeff(InterpolateCoeff),
    InterpolateColor(InterpolateColor),
    Test(Test),
}

impl Default for Method {
    /// `test 0.5` (thesis A.1).
    fn default() -> Self {
        Method::Test(Test { opacity: 0.5 })
    }
}

/// One registry entry.
pub struct MethodInfo {
    pub name: &'static str,
    /// The parameters, for `wrong # args` messages and help.
    pub usage: &'static str,
    pub summary: &'static str,
    /// Builds the method from its parameters (the words after the name).
    pub parse: fn(&[&str]) -> Result<Method, String>,
}

/// Every approximation method, most exact first.
pub const METHODS: &[MethodInfo] = &[
    exact::INFO,
    interpolate_coeff::INFO,
    interpolate_color::INFO,
    test::INFO,
];

impl Method {
    /// `method <name> <params…>` as words.
    pub fn parse(words: &[&str]) -> Result<Method, String> {
        let names = || {
            METHODS
                .iter()
                .map(|m| m.name)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let Some((name, args)) = words.split_first() else {
            return Err(format!("expected a method: {}", names()));
        };
        // The thesis's own short spellings (appendix A) name the same methods.
        let name = match *name {
            "interpolCoeff" => "interpolateCoeff",
            "interpolColor" => "interpolateColor",
            other => other,
        };
        let info = METHODS
            .iter()
            .find(|m| m.name == name)
            .ok_or_else(|| format!("unknown method '{name}': expected one of {}", names()))?;
        let n = info.usage.split_whitespace().count();
        if args.len() != n {
            return Err(format!(
                "wrong # args: should be \"method {} {}\"",
                info.name, info.usage
            ));
        }
        (info.parse)(args)
    }

    pub fn name(&self) -> &'static str {
        match self {
            Method::Exact(_) => "exact",
            Method::InterpolateCoeff(_) => "interpolateCoeff",
            Method::InterpolateColor(_) => "interpolateColor",
            Method::Test(_) => "test",
        }
    }
}

/// An integration rule by name, or a message listing them.
fn rule(name: &str) -> Result<&'static RuleInfo, String> {
    integrate::find(name).ok_or_else(|| {
        format!(
            "unknown integration '{name}': expected one of {}",
            integrate::names()
        )
    })
}

/// A finite number ≥ 0 (`what` names it in the message).
fn non_negative(word: &str, what: &str) -> Result<f64, String> {
    match crate::numbers::parse_f64(word) {
        Some(v) if v >= 0.0 => Ok(v),
        _ => Err(format!("expected {what} (a number ≥ 0), found '{word}'")),
    }
}

/// Combines segment contributions given far to near into one `(b, θ)`.
#[inline]
pub(crate) fn accumulate(acc: &mut ([f64; 3], f64), piece: ([f64; 3], f64)) {
    let (b, theta) = piece;
    for c in 0..3 {
        acc.0[c] = acc.0[c] * theta + b[c];
    }
    acc.1 *= theta;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn methods_parse_with_their_parameters() {
        assert!(matches!(
            Method::parse(&["exact", "constEA", "0.1", "5"]),
            Ok(Method::Exact(_))
        ));
        assert!(matches!(
            Method::parse(&["interpolateCoeff", "trapez", "1"]),
            Ok(Method::InterpolateCoeff(_))
        ));
        assert!(matches!(
            Method::parse(&["interpolateColor", "2"]),
            Ok(Method::InterpolateColor(_))
        ));
        assert_eq!(
            Method::parse(&["test", "0.25"]),
            Ok(Method::Test(Test { opacity: 0.25 }))
        );
        assert!(Method::parse(&["test", "1.5"]).unwrap_err().contains("0…1"));
        assert!(
            Method::parse(&["exact", "simpson", "0.1", "1"])
                .unwrap_err()
                .contains("unknown integration 'simpson'")
        );
        assert!(
            Method::parse(&["exact", "constEA", "1"])
                .unwrap_err()
                .contains("wrong # args")
        );
        assert!(
            Method::parse(&["splat", "1"])
                .unwrap_err()
                .contains("unknown method 'splat'")
        );
        assert!(Method::parse(&["exact", "constEA", "-1", "1"]).is_err());
    }

    /// The thesis's short names parse to the same methods as the long ones.
    #[test]
    fn the_thesis_short_names_are_aliases() {
        assert_eq!(
            Method::parse(&["interpolCoeff", "linear", "1.5"]),
            Method::parse(&["interpolateCoeff", "linear", "1.5"])
        );
        assert_eq!(
            Method::parse(&["interpolColor", "2"]),
            Method::parse(&["interpolateColor", "2"])
        );
        assert!(
            Method::parse(&["interpolColor"])
                .unwrap_err()
                .contains("method interpolateColor brightness")
        );
    }
}
