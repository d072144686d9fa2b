//! What the legend draws: the colormap as a function of one data value over a range.

use crate::mapping::{ColorMap, Part, ScalarColor, Table};
use crate::volume::Volume;

/// A field's data range per component (`None`: the field has none).
pub type FieldRange = Option<Vec<(f64, f64)>>;

/// The colour transfer function over `[lo, hi]`, as the legend shows it.
#[derive(Debug, Clone)]
pub struct ColorScale {
    pub lo: f64,
    pub hi: f64,
    source: Source,
    /// Emission coefficients may exceed 1 (the brightness factor and the path length decide
    /// what the image shows), so the bar shows the hues: the colours divided by the largest
    /// component where that is above 1, as they are otherwise.
    gain: f64,
}

#[derive(Debug, Clone)]
enum Source {
    Table(Table<3>),
    Constant([f64; 3]),
}

impl ColorScale {
    /// The bar's colour at data value `v`.
    pub fn color(&self, v: f64) -> [f64; 3] {
        let c = match &self.source {
            Source::Table(t) => t.eval(v),
            Source::Constant(c) => *c,
        };
        c.map(|x| x * self.gain)
    }

    /// The scale of a colormap bound to `vol`: a SIMPLE_EMITTER (or ABSORPTION_WEIGHTED: its
    /// table, before the χ factor; LIT_EMITTER: before the lights) over its table's values, or CONSTANT over the field's data
    /// range. Maps with several method lines, or whose colour is not a function of one scalar
    /// (IDENTITY, CONST_CELL), have none: the message says why.
    pub fn of_map(map: &ColorMap, vol: &Volume) -> Result<ColorScale, String> {
        Self::of_map_over(map, vol, None)
    }

    /// [`ColorScale::of_map`] with the fields' data ranges given (`ranges`, by field, where
    /// the volume is not all there is: a distributed session's whole grid), else `vol`'s.
    pub fn of_map_over(
        map: &ColorMap,
        vol: &Volume,
        ranges: Option<&[FieldRange]>,
    ) -> Result<ColorScale, String> {
        let [line] = map.lines.as_slice() else {
            return Err(format!(
                "the colormap {} has {} method lines (one per category): there is no single colour scale to draw",
                map.file,
                map.lines.len()
            ));
        };
        let data_range = || -> Result<(f64, f64), String> {
            let named = line.field.as_ref().unwrap_or(&map.data_field);
            let field = named.resolve(vol)?;
            // A complex field's part (`abs(0)`): the range of that part.
            let range = match named.part {
                Some(p) => crate::mapping::part_ranges(vol, field)
                    .map(|r| r[Part::ALL.iter().position(|&q| q == p).unwrap_or(0)].clone()),
                None => match ranges {
                    Some(r) => r.get(field).cloned().flatten(),
                    None => vol.field_range(field),
                },
            };
            match range.as_deref() {
                Some([(lo, hi)]) if lo.is_finite() && hi.is_finite() => Ok((*lo, *hi)),
                Some(_) => Err(format!("field {field} is not a scalar field")),
                None => Err(format!("the volume has no field {field}")),
            }
        };
        let (source, (lo, hi)) = match line.method.legend_form() {
            Some(ScalarColor::Table(t)) => {
                let v = t.values();
                let range = if v.len() > 1 {
                    (v[0], v[v.len() - 1])
                } else {
                    data_range()?
                };
                (Source::Table(t.clone()), range)
            }
            Some(ScalarColor::Constant(c)) => (Source::Constant(c), data_range()?),
            None => {
                return Err(format!(
                    "the colormap's {} method is not a function of one data value",
                    line.name
                ));
            }
        };
        // A constant field still gets a bar of some width around its value.
        let (lo, hi) = if lo < hi {
            (lo, hi)
        } else {
            (lo - 0.5, hi + 0.5)
        };
        let peak = match &source {
            // Piecewise linear: the largest component is at a knot.
            Source::Table(t) => t
                .values()
                .iter()
                .flat_map(|&v| t.eval(v))
                .fold(0.0, f64::max),
            Source::Constant(c) => c.iter().copied().fold(0.0, f64::max),
        };
        let gain = if peak > 1.0 { 1.0 / peak } else { 1.0 };
        Ok(ColorScale {
            lo,
            hi,
            source,
            gain,
        })
    }
}
