//! A colormap and an alphamap bound to a volume: field numbers and types checked, the fields to
//! evaluate per sample collected (each once, shared by both maps — the thesis's `field:global`
//! optimisation), and η, χ evaluated from those values.

use super::part::{Part, modulus_cuts};
use super::{
    AlphaMap, AlphaShading, ColorMap, ColorShading, FieldNeed, MapFile, Point, Shape, Transfer1D,
};
use crate::error::{ParseError, Warning};
use crate::field::Interpolator;
use crate::scene::Lighting;
use crate::volume::Volume;
use std::sync::Arc;

/// Where one field's value sits in the per-sample buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Slot {
    offset: usize,
    len: usize,
}

/// The buffer layout of one map: its category slot and each line's field slot (`None` for
/// methods that do not read a field).
#[derive(Debug, Clone)]
struct Layout {
    category: Option<Slot>,
    lines: Vec<Option<Slot>>,
    /// Per line, where the gradient of its field sits (`LIT_EMITTER` lines only).
    gradients: Vec<Option<Slot>>,
}

/// The method line of each map that applies at a point (`None`: no line matches its category
/// value, so that map gives zero).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lines {
    pub color: Option<usize>,
    pub alpha: Option<usize>,
}

/// A complex field read through one part: the part, and where the field's (re, im) pairs sit
/// in the buffer (after the slot that holds the part).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct PartOf {
    part: Part,
    raw: usize,
    /// How the complex field itself varies along a segment in a cell.
    under: Shape,
}

/// A colormap and an alphamap bound to a volume.
#[derive(Debug, Clone)]
pub struct Mapping {
    color: ColorMap,
    alpha: AlphaMap,
    /// Field numbers evaluated per sample, in buffer order.
    fields: Vec<usize>,
    slots: Vec<Slot>,
    /// For each evaluated field, the part of a complex field the maps read.
    parts: Vec<Option<PartOf>>,
    /// How each evaluated field varies along a straight segment inside a cell.
    field_shapes: Vec<Shape>,
    width: usize,
    color_layout: Layout,
    alpha_layout: Layout,
    /// Fields whose gradient (file coordinates) is evaluated per sample, and where it goes.
    gradient_fields: Vec<(usize, Slot)>,
    /// The lights of the frame being rendered ([`Mapping::lit`]); `None` until a renderer sets
    /// them, which then means the default light of the default view.
    lighting: Option<Arc<Lighting>>,
}

/// How a field varies along a straight segment inside one cell.
pub fn field_shape(i: Interpolator) -> Shape {
    match i {
        Interpolator::Constant => Shape::Constant,
        // Whitney edge functions are linear in position inside a cell.
        Interpolator::Linear | Interpolator::EdgeElem => Shape::Linear,
        Interpolator::HigherOrder | Interpolator::EdgeElemSar => Shape::Quadratic,
        Interpolator::GaussTest => Shape::Nonlinear,
    }
}

/// What binding needs to know of either kind of method.
trait Shading {
    fn need(&self) -> FieldNeed;
    fn bytes(&self) -> Option<[bool; 256]>;
    /// Whether the method is shaded by the lights (needs the field's gradient).
    fn lit(&self) -> bool {
        false
    }
}

impl Shading for dyn ColorShading {
    fn need(&self) -> FieldNeed {
        self.field_need()
    }
    fn bytes(&self) -> Option<[bool; 256]> {
        self.defined_bytes()
    }
    fn lit(&self) -> bool {
        self.phong().is_some()
    }
}

impl Shading for dyn AlphaShading {
    fn need(&self) -> FieldNeed {
        self.field_need()
    }
    fn bytes(&self) -> Option<[bool; 256]> {
        self.defined_bytes()
    }
}

/// Collects the fields a map reads and checks their numbers and types.
struct Binder<'a> {
    vol: &'a Volume,
    fields: Vec<usize>,
    slots: Vec<Slot>,
    parts: Vec<Option<Part>>,
    width: usize,
    gradient_fields: Vec<(usize, Slot)>,
    warnings: Vec<Warning>,
}

impl Binder<'_> {
    /// The buffer slot of field `field` read through `part`, holding `len` numbers; a part
    /// slot is followed by room for the field's (re, im) pairs.
    fn slot(&mut self, field: usize, part: Option<Part>, len: usize) -> Slot {
        let known =
            (0..self.fields.len()).find(|&i| (self.fields[i], self.parts[i]) == (field, part));
        if let Some(i) = known {
            return self.slots[i];
        }
        let s = Slot {
            offset: self.width,
            len,
        };
        self.fields.push(field);
        self.slots.push(s);
        self.parts.push(part);
        self.width += if part.is_some() { 3 * len } else { len };
        s
    }

    /// Where the gradient of `field` goes (three numbers), shared by the lines that need it.
    fn gradient_slot(&mut self, field: usize) -> Slot {
        if let Some((_, s)) = self.gradient_fields.iter().find(|(f, _)| *f == field) {
            return *s;
        }
        let s = Slot {
            offset: self.width,
            len: 3,
        };
        self.gradient_fields.push((field, s));
        self.width += 3;
        s
    }

    fn no_field(&self, file: &str, line: usize, what: &str, n: usize) -> ParseError {
        let count = self.vol.data.fields.len();
        let have = match count {
            0 => "has no fields".to_string(),
            1 => "has only field 0".to_string(),
            c => format!("has fields 0…{}", c - 1),
        };
        ParseError::new(
            file,
            line,
            format!("{what} {n}: the volume {} {have}", self.vol.source),
        )
    }

    fn bind<T: Shading + ?Sized>(&mut self, map: &MapFile<T>) -> Result<Layout, ParseError> {
        let file = map.file.as_str();
        let category = match &map.category {
            Some((r, line)) => {
                let line = *line;
                let n = r
                    .resolve(self.vol)
                    .map_err(|m| ParseError::new(file, line, format!("CategoryField {r}: {m}")))?;
                let f = self
                    .vol
                    .field(n)
                    .ok_or_else(|| self.no_field(file, line, "CategoryField", n))?;
                let len = r
                    .components(f, n)
                    .map_err(|m| ParseError::new(file, line, format!("CategoryField: {m}")))?;
                if len != 1 {
                    return Err(ParseError::new(
                        file,
                        line,
                        format!(
                            "CategoryField {n} must be scalar, but field {n} has {len} components ({})",
                            f.ty
                        ),
                    ));
                }
                Some(self.slot(n, r.part, len))
            }
            None => None,
        };
        let mut lines = Vec::with_capacity(map.lines.len());
        let mut gradients = vec![None; map.lines.len()];
        for (k, l) in map.lines.iter().enumerate() {
            let need = l.method.need();
            if need == FieldNeed::Any {
                lines.push(None);
                continue;
            }
            let r = l.field.as_ref().unwrap_or(&map.data_field);
            let n = r.resolve(self.vol).map_err(|m| match l.field {
                Some(_) => ParseError::new(file, l.line, format!("{}: field:{r}: {m}", l.name)),
                None => ParseError::new(file, map.data_field_line, format!("DataField {r}: {m}")),
            })?;
            let Some(f) = self.vol.field(n) else {
                return Err(match l.field {
                    Some(_) => self.no_field(file, l.line, &format!("{}: field:", l.name), n),
                    None => self.no_field(file, map.data_field_line, "DataField", n),
                });
            };
            let len = r
                .components(f, n)
                .map_err(|m| ParseError::new(file, l.line, format!("{}: {m}", l.name)))?;
            let ok = match need {
                FieldNeed::Any => true,
                FieldNeed::Scalar => len == 1,
                FieldNeed::Components(k) => len == k,
                FieldNeed::ByteConstant => f.is_byte_constant(&self.vol.data.raw),
            };
            if !ok {
                let name = f
                    .name
                    .as_deref()
                    .map(|s| format!(" \"{s}\""))
                    .unwrap_or_default();
                let denom = f
                    .denominator
                    .as_deref()
                    .map(|d| format!(" {d}"))
                    .unwrap_or_default();
                return Err(ParseError::new(
                    file,
                    l.line,
                    format!(
                        "{} needs {need}, but field {n}{name} is {{ {}{denom} }} = {}",
                        l.name,
                        f.ty,
                        f.interpolator.name()
                    ),
                ));
            }
            if let Some(def) = l.method.bytes() {
                self.warn_missing_bytes(file, l.line, l.name, n, &def);
            }
            lines.push(Some(self.slot(n, r.part, len)));
            if l.method.lit() {
                // The lighting gradient is the field's own (its real part for a complex field
                // of some interpolators, undefined for others): a part is not shaded.
                if let Some(p) = r.part {
                    return Err(ParseError::new(
                        file,
                        l.line,
                        format!(
                            "{}: {r}: lighting needs the gradient of a real field, which the {} of a complex field does not provide",
                            l.name,
                            p.meaning()
                        ),
                    ));
                }
                gradients[k] = Some(self.gradient_slot(n));
            }
        }
        Ok(Layout {
            category,
            lines,
            gradients,
        })
    }

    /// One warning listing the byte values the field takes that a CONST_CELL table lacks.
    fn warn_missing_bytes(
        &mut self,
        file: &str,
        line: usize,
        name: &str,
        n: usize,
        defined: &[bool; 256],
    ) {
        let f = &self.vol.data.fields[n];
        let raw = &self.vol.data.raw[f.sources[0]];
        let mut seen = [false; 256];
        for c in 0..raw.elements() {
            let v = raw.value(c, 0);
            if (0.0..256.0).contains(&v) {
                seen[v as usize] = true;
            }
        }
        let missing: Vec<String> = (0..256)
            .filter(|&b| seen[b] && !defined[b])
            .map(|b| b.to_string())
            .collect();
        if !missing.is_empty() {
            self.warnings.push(Warning {
                file: file.to_string(),
                line: Some(line),
                message: format!(
                    "{name}: field {n} takes the value{} {} that the table does not list; {} map to zero",
                    if missing.len() == 1 { "" } else { "s" },
                    missing.join(", "),
                    if missing.len() == 1 { "it" } else { "they" }
                ),
            });
        }
    }
}

/// The first line whose interval holds `cat` (all lines match when there is no category).
#[inline]
fn select<T: ?Sized>(map: &MapFile<T>, cat: Option<f64>) -> Option<usize> {
    match cat {
        None => (!map.lines.is_empty()).then_some(0),
        Some(v) => map
            .lines
            .iter()
            .position(|l| l.interval.is_none_or(|i| i.contains(v))),
    }
}

impl Mapping {
    /// Binds the maps to a volume. Errors name the map file and line; warnings (e.g. byte values
    /// a CONST_CELL table lacks) are returned.
    pub fn new(
        color: &ColorMap,
        alpha: &AlphaMap,
        vol: &Volume,
    ) -> Result<(Mapping, Vec<Warning>), ParseError> {
        let mut b = Binder {
            vol,
            fields: Vec::new(),
            slots: Vec::new(),
            parts: Vec::new(),
            width: 0,
            gradient_fields: Vec::new(),
            warnings: Vec::new(),
        };
        let alpha_layout = b.bind(alpha)?;
        let color_layout = b.bind(color)?;
        let field_shapes = b
            .fields
            .iter()
            .zip(&b.parts)
            .map(|(&f, part)| {
                let shape = field_shape(vol.data.fields[f].interpolator);
                part.map_or(shape, |p| p.shape(shape))
            })
            .collect();
        let parts = b
            .parts
            .iter()
            .zip(&b.slots)
            .zip(&b.fields)
            .map(|((p, s), &f)| {
                p.map(|part| PartOf {
                    part,
                    raw: s.offset + s.len,
                    under: field_shape(vol.data.fields[f].interpolator),
                })
            })
            .collect();
        Ok((
            Mapping {
                color: color.clone(),
                alpha: alpha.clone(),
                fields: b.fields,
                slots: b.slots,
                parts,
                field_shapes,
                width: b.width,
                color_layout,
                alpha_layout,
                gradient_fields: b.gradient_fields,
                lighting: None,
            },
            b.warnings,
        ))
    }

    /// Whether a colour line is shaded by lights (`LIT_EMITTER`).
    pub fn is_lit(&self) -> bool {
        !self.gradient_fields.is_empty()
    }

    /// The mapping with the lights of a frame (a renderer calls this once per frame, with the
    /// frame's view: the default light follows the camera).
    pub fn lit(&self, lighting: Lighting) -> Mapping {
        Mapping {
            lighting: Some(Arc::new(lighting)),
            ..self.clone()
        }
    }

    /// The fields to evaluate per sample, in buffer order.
    pub fn fields(&self) -> &[usize] {
        &self.fields
    }

    /// Length of the per-sample value buffer.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Evaluates every needed field at a point into `buf` (length [`Mapping::width`]).
    pub fn sample_fields(
        &self,
        vol: &Volume,
        cell: usize,
        lambda: &[f64; 4],
        pos: [f64; 3],
        buf: &mut [f64],
    ) {
        let on = vol.support();
        for ((&f, s), part) in self.fields.iter().zip(&self.slots).zip(&self.parts) {
            let field = &vol.data.fields[f];
            match part {
                None => field.eval(&on, cell, lambda, pos, &mut buf[s.offset..s.offset + s.len]),
                Some(p) => {
                    let (head, pairs) = buf.split_at_mut(p.raw);
                    let pairs = &mut pairs[..2 * s.len];
                    field.eval(&on, cell, lambda, pos, pairs);
                    p.part.apply(pairs, &mut head[s.offset..s.offset + s.len]);
                }
            }
        }
        for &(f, s) in &self.gradient_fields {
            let g = vol.data.fields[f].gradient_at(&on, cell, lambda, pos);
            buf[s.offset..s.offset + 3].copy_from_slice(&g);
        }
    }

    fn category(layout: &Layout, values: &[f64]) -> Option<f64> {
        layout.category.map(|s| values[s.offset])
    }

    /// The method lines active at a sample (by its category values). On a piece between cuts
    /// the lines are fixed; an exact integrator picks them inside the piece and evaluates the
    /// piece's ends with them, which gives the one-sided limits at a category switch.
    #[inline]
    pub fn lines_at(&self, values: &[f64]) -> Lines {
        Lines {
            color: select(&self.color, Self::category(&self.color_layout, values)),
            alpha: select(&self.alpha, Self::category(&self.alpha_layout, values)),
        }
    }

    /// `(η, χ)` at a sample with the given lines active.
    #[inline]
    pub fn eval_on(
        &self,
        lines: Lines,
        values: &[f64],
        cell: usize,
        pos: [f64; 3],
    ) -> ([f64; 3], f64) {
        let slice =
            |slot: Option<Slot>| slot.map_or(&[][..], |s| &values[s.offset..s.offset + s.len]);
        let chi = match lines.alpha {
            Some(i) => {
                let value = slice(self.alpha_layout.lines[i]);
                self.alpha.lines[i]
                    .method
                    .alpha(&Point { value, cell, pos })
            }
            None => 0.0,
        };
        let eta = match lines.color {
            Some(i) => {
                let value = slice(self.color_layout.lines[i]);
                let method = &self.color.lines[i].method;
                let eta = method.color(&Point { value, cell, pos }, chi);
                match (method.phong(), self.color_layout.gradients[i]) {
                    (Some(phong), Some(g)) => {
                        let gradient =
                            [values[g.offset], values[g.offset + 1], values[g.offset + 2]];
                        let f = match &self.lighting {
                            Some(l) => l.factor(phong, gradient),
                            None => default_lighting().factor(phong, gradient),
                        };
                        [0, 1, 2].map(|c| eta[c] * f[c])
                    }
                    _ => eta,
                }
            }
            None => [0.0; 3],
        };
        (eta, chi)
    }

    /// `(η, χ)` at a sample.
    #[inline]
    pub fn eval(&self, values: &[f64], cell: usize, pos: [f64; 3]) -> ([f64; 3], f64) {
        self.eval_on(self.lines_at(values), values, cell, pos)
    }

    /// Parameters `t ∈ (0, 1)` where η or χ change slope on a segment along which the field
    /// values run linearly from `v0` to `v1`: table values of every line's field, category
    /// boundaries, method-specific kinks. Appended to `out` unsorted.
    pub fn cuts(&self, v0: &[f64], v1: &[f64], out: &mut Vec<f64>) {
        for (layout, bounds) in [
            (&self.color_layout, interval_bounds(&self.color)),
            (&self.alpha_layout, interval_bounds(&self.alpha)),
        ] {
            if let Some(s) = layout.category {
                self.crossings(s, v0, v1, &bounds, out);
            }
        }
        for (i, slot) in self.color_layout.lines.iter().enumerate() {
            if let Some(s) = slot.filter(|s| s.len == 1) {
                self.crossings(s, v0, v1, self.color.lines[i].method.breakpoints(), out);
            }
        }
        for (i, slot) in self.alpha_layout.lines.iter().enumerate() {
            if let Some(s) = slot {
                let m = &self.alpha.lines[i].method;
                if s.len == 1 {
                    self.crossings(*s, v0, v1, m.breakpoints(), out);
                }
                m.cuts(
                    &v0[s.offset..s.offset + s.len],
                    &v1[s.offset..s.offset + s.len],
                    out,
                );
            }
        }
    }

    /// Where the scalar in slot `s` crosses the `levels` on a segment from values `v0` to `v1`:
    /// by linear interpolation, except for the modulus of a Linear complex field, whose
    /// crossings are the roots of a quadratic ([`modulus_cuts`]).
    fn crossings(&self, s: Slot, v0: &[f64], v1: &[f64], levels: &[f64], out: &mut Vec<f64>) {
        let k = self.slots.iter().position(|x| *x == s).unwrap_or(0);
        if let Some(PartOf {
            part: Part::Abs,
            raw,
            under: Shape::Linear,
        }) = self.parts[k]
        {
            let z = |v: &[f64]| [v[raw], v[raw + 1]];
            modulus_cuts(z(v0), z(v1), levels, out);
            return;
        }
        let (a, b) = (v0[s.offset], v1[s.offset]);
        for &x in levels {
            if (a < x && x < b) || (b < x && x < a) {
                out.push((x - a) / (b - a));
            }
        }
    }

    /// How η and χ vary along a piece of a ray segment inside one cell, between cuts, given the
    /// field values at a point inside the piece (which picks the active category lines).
    pub fn piece_shapes(&self, mid: &[f64]) -> (Shape, Shape) {
        let along = |slot: Option<Slot>, method_shape: Shape| -> Shape {
            match slot {
                None => method_shape.of(Shape::Constant),
                Some(s) => {
                    let k = self.slots.iter().position(|x| *x == s).unwrap_or(0);
                    method_shape.of(self.field_shapes[k])
                }
            }
        };
        let lines = self.lines_at(mid);
        let chi = match lines.alpha {
            Some(i) => along(
                self.alpha_layout.lines[i],
                self.alpha.lines[i].method.shape(),
            ),
            None => Shape::Constant,
        };
        let eta = match lines.color {
            Some(i) => {
                let m = &self.color.lines[i].method;
                let mut own = along(self.color_layout.lines[i], m.shape());
                // The lighting factor follows the gradient: constant inside a cell only where
                // the field is at most linear.
                if m.phong().is_some()
                    && along(self.color_layout.lines[i], Shape::Linear) > Shape::Linear
                {
                    own = Shape::Nonlinear;
                }
                if m.uses_absorption() {
                    own.times(chi)
                } else {
                    own
                }
            }
            None => Shape::Constant,
        };
        // A category field that itself varies non-linearly makes the line switch at unknown
        // points: no exact cut exists.
        let cat_shape = |layout: &Layout| {
            layout.category.map_or(Shape::Constant, |s| {
                let k = self.slots.iter().position(|x| *x == s).unwrap_or(0);
                self.field_shapes[k]
            })
        };
        if cat_shape(&self.color_layout) > Shape::Linear
            || cat_shape(&self.alpha_layout) > Shape::Linear
        {
            return (Shape::Nonlinear, Shape::Nonlinear);
        }
        (eta, chi)
    }

    /// The mapping as one merged 1D transfer function over a linearly interpolated scalar field,
    /// if it has that form (no categories, table or constant methods, at most one field, and
    /// that one Linear) — see [`Transfer1D`].
    pub fn transfer(&self, vol: &Volume) -> Option<Transfer1D> {
        if self.color_layout.category.is_some() || self.alpha_layout.category.is_some() {
            return None;
        }
        let (mut t, field) = self.pair_transfer(vol, 0, 0)?;
        if let Some(n) = field {
            t.node_values = node_values(vol, n);
        }
        Some(t)
    }

    /// Colour line `ci` with alpha line `ai` as one merged 1D transfer function (its node values
    /// left empty) and the field it reads, if the pair has that form.
    fn pair_transfer(
        &self,
        vol: &Volume,
        ci: usize,
        ai: usize,
    ) -> Option<(Transfer1D, Option<usize>)> {
        let (color, alpha) = (self.color.lines.get(ci)?, self.alpha.lines.get(ai)?);
        let (c, a) = (color.method.scalar_form()?, alpha.method.scalar_form()?);
        let slots = [self.color_layout.lines[ci], self.alpha_layout.lines[ai]];
        let mut field = None;
        for slot in slots.into_iter().flatten() {
            let k = self.slots.iter().position(|x| *x == slot)?;
            if self.parts[k].is_some() {
                return None;
            }
            let n = self.fields[k];
            if field.is_some_and(|f| f != n) {
                return None;
            }
            field = Some(n);
        }
        if let Some(n) = field {
            let f = &vol.data.fields[n];
            if f.interpolator != Interpolator::Linear || !f.is_scalar() {
                return None;
            }
        }
        let t = Transfer1D::new(c, color.method.uses_absorption(), a, Vec::new());
        Some((t, field))
    }

    /// For maps whose category fields are constant per cell (a material number, the usual
    /// case): a merged 1D transfer function for every pair of method lines that has that form,
    /// so that a cell — whose lines are fixed — takes the fast path of a map without
    /// categories. `None` without categories (see [`Mapping::transfer`]) or where a category
    /// field varies inside cells.
    pub fn category_transfers(&self, vol: &Volume) -> Option<CategoryTransfers> {
        let categories = [self.color_layout.category, self.alpha_layout.category];
        if categories.iter().all(Option::is_none) {
            return None;
        }
        for slot in categories.into_iter().flatten() {
            let k = self.slots.iter().position(|x| *x == slot)?;
            let f = &vol.data.fields[self.fields[k]];
            if f.interpolator != Interpolator::Constant || self.parts[k].is_some() {
                return None;
            }
        }
        let alpha_lines = self.alpha.lines.len();
        let mut fields: Vec<usize> = Vec::new();
        let mut pairs = Vec::with_capacity(self.color.lines.len() * alpha_lines);
        for ci in 0..self.color.lines.len() {
            for ai in 0..alpha_lines {
                pairs.push(self.pair_transfer(vol, ci, ai).map(|(t, field)| {
                    let values = field.map(|n| match fields.iter().position(|&f| f == n) {
                        Some(i) => i,
                        None => {
                            fields.push(n);
                            fields.len() - 1
                        }
                    });
                    (t, values)
                }));
            }
        }
        if pairs.iter().all(Option::is_none) {
            return None;
        }
        Some(CategoryTransfers {
            pairs,
            alpha_lines,
            node_values: fields.iter().map(|&n| node_values(vol, n)).collect(),
        })
    }

    /// The method lines of a cell whose category fields are constant per cell (as
    /// [`Mapping::category_transfers`] requires): the lines every sample in it selects.
    pub fn cell_lines(&self, vol: &Volume, cell: usize) -> Lines {
        let on = vol.support();
        let category = |layout: &Layout| {
            layout.category.map(|s| {
                let k = self.slots.iter().position(|x| *x == s).unwrap_or(0);
                let mut v = [0.0];
                vol.data.fields[self.fields[k]].eval(&on, cell, &[0.25; 4], [0.0; 3], &mut v);
                v[0]
            })
        };
        Lines {
            color: select(&self.color, category(&self.color_layout)),
            alpha: select(&self.alpha, category(&self.alpha_layout)),
        }
    }

    pub fn color_map(&self) -> &ColorMap {
        &self.color
    }

    pub fn alpha_map(&self) -> &AlphaMap {
        &self.alpha
    }
}

fn interval_bounds<T: ?Sized>(map: &MapFile<T>) -> Vec<f64> {
    map.lines
        .iter()
        .filter_map(|l| l.interval)
        .flat_map(|i| [i.from, i.to])
        .flatten()
        .collect()
}

/// The lighting of the default view (one white light at the camera, looking along −z), for a
/// mapping evaluated outside a renderer.
fn default_lighting() -> &'static Lighting {
    static DEFAULT: std::sync::OnceLock<Lighting> = std::sync::OnceLock::new();
    DEFAULT.get_or_init(|| {
        Lighting::new(&[], &crate::scene::View::default(), [0.0; 3])
            .expect("the identity transform is regular")
    })
}

/// A scalar Linear field's value at every node.
fn node_values(vol: &Volume, n: usize) -> Vec<f64> {
    let raw = &vol.data.raw[vol.data.fields[n].sources[0]];
    (0..vol.mesh.node_count())
        .map(|i| raw.value(i, 0))
        .collect()
}

/// The merged transfer functions of a map with per-cell categories
/// ([`Mapping::category_transfers`]).
#[derive(Debug, Clone)]
pub struct CategoryTransfers {
    /// Per colour line × alpha line: the merged function and which `node_values` it reads.
    pairs: Vec<Option<(Transfer1D, Option<usize>)>>,
    alpha_lines: usize,
    /// The node values of each field the pairs read.
    node_values: Vec<Vec<f64>>,
}

impl CategoryTransfers {
    /// The transfer function of a cell with these lines and its field's node values (empty
    /// where it reads none); `None` where a map has no line for the cell or the pair has no
    /// merged form.
    pub fn of(&self, lines: Lines) -> Option<(&Transfer1D, &[f64])> {
        let (c, a) = (lines.color?, lines.alpha?);
        let (t, values) = self.pairs.get(c * self.alpha_lines + a)?.as_ref()?;
        Some((t, values.map_or(&[][..], |i| &self.node_values[i][..])))
    }
}
