//! Parts of complex fields: a map reads a complex field through its real part
//! `re(n)`, its imaginary part `im(n)` or its modulus `abs(n)`, written wherever a map names a
//! field (`DataField abs(0)`, `CategoryField re(2)`, `field:im("E")` on a method line).
//!
//! A complex field evaluates to two numbers (re, im) per component, which no shading method
//! can use directly; naming the part is required (an unqualified complex field is an error that
//! lists the three choices), so that what is drawn is never a silent guess.
//!
//! Exactness: the real and imaginary parts of a Linear field are linear along a ray, so
//! `exact linear 0` stays exact for them. The modulus `|z0 + t·d|` is not: it is the square root
//! of a quadratic, smooth except where it touches 0. Its shape is therefore
//! [`Shape::Nonlinear`] (the exact method refines each piece until it converges), and the
//! places where it crosses a table value are found exactly from that quadratic
//! ([`modulus_cuts`]), so no kink of the table falls inside a piece.

use std::fmt;

use super::{FieldRef, Shape};
use crate::data::ScalarType;
use crate::field::Field;
use crate::volume::Volume;

/// Which part of a complex value a map uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Part {
    /// `re(n)`: the real part.
    Re,
    /// `im(n)`: the imaginary part.
    Im,
    /// `abs(n)`: the modulus √(re² + im²).
    Abs,
}

/// What `help colormap`, `help alphamap` and `docs/commands.md` say about complex fields.
pub const COMPLEX_HELP: &str = "A complex field is mapped through one part, written where the map names the field: re(n) (real part), im(n) (imaginary part) or abs(n) (modulus), e.g. 'DataField abs(0)', 'field:re(\"E\")'; a complex field without one is refused.";

impl Part {
    pub const ALL: [Part; 3] = [Part::Re, Part::Im, Part::Abs];

    /// The word written in a map file.
    pub fn keyword(self) -> &'static str {
        match self {
            Part::Re => "re",
            Part::Im => "im",
            Part::Abs => "abs",
        }
    }

    /// What it is, in words.
    pub fn meaning(self) -> &'static str {
        match self {
            Part::Re => "real part",
            Part::Im => "imaginary part",
            Part::Abs => "modulus",
        }
    }

    /// The part of each complex component: `raw` holds (re, im) pairs, `out` one number per
    /// pair.
    #[inline]
    pub fn apply(self, raw: &[f64], out: &mut [f64]) {
        for (o, z) in out.iter_mut().zip(raw.chunks_exact(2)) {
            *o = match self {
                Part::Re => z[0],
                Part::Im => z[1],
                Part::Abs => z[0].hypot(z[1]),
            };
        }
    }

    /// How the part varies along a segment on which the complex field has shape `field`.
    pub fn shape(self, field: Shape) -> Shape {
        match (self, field) {
            (Part::Re | Part::Im, s) => s,
            (Part::Abs, Shape::Constant) => Shape::Constant,
            (Part::Abs, _) => Shape::Nonlinear,
        }
    }
}

/// A field as a map names it: which field, and for a complex field which part.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MapField {
    pub field: FieldRef,
    pub part: Option<Part>,
}

impl MapField {
    /// The field number in `vol` (the part is checked when the map is bound).
    pub fn resolve(&self, vol: &Volume) -> Result<usize, String> {
        self.field.resolve(vol)
    }

    /// Parses a field word of a map file: `3`, `"name"`, or either inside `re(…)`, `im(…)`,
    /// `abs(…)`.
    pub fn parse(word: &str) -> Option<MapField> {
        for part in Part::ALL {
            let inner = word
                .strip_prefix(part.keyword())
                .and_then(|w| w.strip_prefix('('))
                .and_then(|w| w.strip_suffix(')'));
            if let Some(inner) = inner {
                return Some(MapField {
                    field: super::parse::field_ref(inner.trim())?,
                    part: Some(part),
                });
            }
        }
        super::parse::field_ref(word).map(FieldRef::into)
    }

    /// How many numbers a shading method sees of field `n` read this way: the field's own
    /// components, or one per complex component when a part is named. `Err` when a complex
    /// field has no part (naming the three choices) or a real field has one.
    pub fn components(&self, f: &Field, n: usize) -> Result<usize, String> {
        let what = describe(f, n);
        match (is_complex(f), self.part) {
            (false, None) => Ok(f.components()),
            (true, Some(_)) => Ok(f.ty.components()),
            (true, None) => {
                let r = &self.field;
                Err(format!(
                    "{what} is complex: name the part to map, its real part re({r}), imaginary part im({r}) or modulus abs({r})"
                ))
            }
            (false, Some(p)) => Err(format!(
                "{}({}): {what} is not complex, so it has no {}; write {} alone",
                p.keyword(),
                self.field,
                p.meaning(),
                self.field
            )),
        }
    }
}

impl From<FieldRef> for MapField {
    fn from(field: FieldRef) -> Self {
        MapField { field, part: None }
    }
}

impl From<usize> for MapField {
    fn from(n: usize) -> Self {
        FieldRef::Number(n).into()
    }
}

impl fmt::Display for MapField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.part {
            Some(p) => write!(f, "{}({})", p.keyword(), self.field),
            None => write!(f, "{}", self.field),
        }
    }
}

/// A field whose values are (re, im) pairs: Linear, Constant or HigherOrder over complex data.
/// (Edge-element fields of complex data are real vector fields; see thesis appendix B, docs/formats.md.)
pub fn is_complex(f: &Field) -> bool {
    f.ty.scalar == ScalarType::Complex && f.components() == 2 * f.ty.components()
}

/// `field 3 "E" { complex } = Linear` for messages.
fn describe(f: &Field, n: usize) -> String {
    let name = f
        .name
        .as_deref()
        .map(|s| format!(" \"{s}\""))
        .unwrap_or_default();
    format!("field {n}{name} {{ {} }} = {}", f.ty, f.interpolator.name())
}

/// Parameters `t ∈ (0, 1)` where `|z0 + t·(z1 − z0)|` equals `x` (at most two: the roots of
/// `|d|²t² + 2·Re(z̄0·d)·t + |z0|² − x² = 0`), and where the modulus is smallest (its only
/// kink when it touches 0, a point of strong curvature near it). Appended to `out`.
pub fn modulus_cuts(z0: [f64; 2], z1: [f64; 2], levels: &[f64], out: &mut Vec<f64>) {
    let d = [z1[0] - z0[0], z1[1] - z0[1]];
    let a = d[0] * d[0] + d[1] * d[1];
    if a == 0.0 || !a.is_finite() {
        return;
    }
    let half_b = z0[0] * d[0] + z0[1] * d[1];
    let inside = |t: f64, out: &mut Vec<f64>| {
        if t > 0.0 && t < 1.0 {
            out.push(t);
        }
    };
    inside(-half_b / a, out);
    let m0 = z0[0] * z0[0] + z0[1] * z0[1];
    for &x in levels {
        if x <= 0.0 {
            continue;
        }
        let c = m0 - x * x;
        let disc = half_b * half_b - a * c;
        if disc <= 0.0 {
            continue;
        }
        // The root of larger magnitude first, the other from the product of the roots (c/a),
        // which avoids cancellation.
        let q = -(half_b + half_b.signum() * disc.sqrt());
        let q = if q == 0.0 { -disc.sqrt() } else { q };
        inside(q / a, out);
        inside(c / q, out);
    }
}

/// The ranges of the real part, imaginary part and modulus of each component of complex field
/// `n` (`vorang info`), sampled where [`Volume::field_range`] samples: at every cell's corners
/// and centre. `None` if `n` is not a complex field.
pub fn part_ranges(vol: &Volume, n: usize) -> Option<[Vec<(f64, f64)>; 3]> {
    let f = vol.field(n).filter(|f| is_complex(f))?;
    let k = f.ty.components();
    let mut ranges: [Vec<(f64, f64)>; 3] =
        std::array::from_fn(|_| vec![(f64::INFINITY, f64::NEG_INFINITY); k]);
    let (mut pairs, mut one) = (vec![0.0; 2 * k], vec![0.0; k]);
    let on = vol.support();
    let mut samples: Vec<[f64; 4]> = (0..4)
        .map(|i| std::array::from_fn(|j| f64::from(u8::from(i == j))))
        .collect();
    samples.push([0.25; 4]);
    for cell in 0..vol.mesh.tet_count() {
        let corners = vol.mesh.corners(cell);
        for l in &samples {
            let p = [0, 1, 2].map(|d| (0..4).map(|i| l[i] * corners[i][d]).sum());
            f.eval(&on, cell, l, p, &mut pairs);
            for (part, range) in Part::ALL.into_iter().zip(&mut ranges) {
                part.apply(&pairs, &mut one);
                for (r, &v) in range.iter_mut().zip(&one) {
                    *r = (r.0.min(v), r.1.max(v));
                }
            }
        }
    }
    Some(ranges)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_parse() {
        assert_eq!(MapField::parse("3"), Some(3.into()));
        assert_eq!(
            MapField::parse("abs(2)"),
            Some(MapField {
                field: FieldRef::Number(2),
                part: Some(Part::Abs)
            })
        );
        assert_eq!(
            MapField::parse("im(\"E field\")"),
            Some(MapField {
                field: FieldRef::Name("E field".into()),
                part: Some(Part::Im)
            })
        );
        for bad in [
            "abs(", "abs()", "re(x)", "mod(1)", "abs(1", "abs 1", "re(-1)",
        ] {
            assert_eq!(MapField::parse(bad), None, "{bad}");
        }
        assert_eq!(MapField::parse("re(0)").unwrap().to_string(), "re(0)");
    }

    #[test]
    fn parts_of_pairs() {
        let raw = [3.0, -4.0, -1.0, 0.5];
        let mut out = [0.0; 2];
        Part::Re.apply(&raw, &mut out);
        assert_eq!(out, [3.0, -1.0]);
        Part::Im.apply(&raw, &mut out);
        assert_eq!(out, [-4.0, 0.5]);
        Part::Abs.apply(&raw, &mut out);
        assert_eq!(out, [5.0, 1.25f64.sqrt()]);
    }

    #[test]
    fn modulus_crossings_are_where_the_modulus_has_the_value() {
        // z(t) = (−3 + 6t) + 4i: |z| = 5 at t = 0 and 1, 4 at t = ½.
        let mut out = Vec::new();
        modulus_cuts([-3.0, 4.0], [3.0, 4.0], &[4.5, 4.0, 6.0], &mut out);
        out.sort_by(f64::total_cmp);
        let at = |t: f64| (-3.0 + 6.0 * t).hypot(4.0);
        // The minimum at ½ and the two crossings of 4.5; 4 only touches, 6 is never reached.
        assert_eq!(out.len(), 3, "{out:?}");
        assert!((out[1] - 0.5).abs() < 1e-15);
        assert!((at(out[0]) - 4.5).abs() < 1e-14 && (at(out[2]) - 4.5).abs() < 1e-14);
        // Through zero: the kink of the modulus is a cut.
        out.clear();
        modulus_cuts([-1.0, -1.0], [3.0, 3.0], &[], &mut out);
        assert_eq!(out, vec![0.25]);
    }

    #[test]
    fn shapes() {
        assert_eq!(Part::Re.shape(Shape::Linear), Shape::Linear);
        assert_eq!(Part::Im.shape(Shape::Quadratic), Shape::Quadratic);
        assert_eq!(Part::Abs.shape(Shape::Constant), Shape::Constant);
        assert_eq!(Part::Abs.shape(Shape::Linear), Shape::Nonlinear);
    }
}
