//! Colour and alpha mapping (thesis 6.2 and appendix C; docs/formats.md): how data values become the
//! emission η (RGB) and the absorption χ of the optical model.
//!
//! A map file names the visualised field (`DataField`), optionally a `CategoryField` that picks
//! one of several method lines per point (`from:`/`to:` intervals, first match wins), and for
//! each line a shading method with its parameter block. Each method is one file under `color/`
//! or `alpha/` and one line in [`COLOR_METHODS`] / [`ALPHA_METHODS`]; the parser, the "unknown
//! method" message, `help` and the tests all read those tables.
//!
//! [`Mapping`] binds a colormap and an alphamap to a volume: it checks field numbers and types,
//! decides which fields must be evaluated per sample (each once, shared by both maps), and
//! evaluates η and χ from those values.

mod alpha;
mod bind;
mod block;
mod color;
mod parse;
mod part;
mod preset;
mod table;
mod transfer;

use std::fmt;
use std::sync::Arc;

pub use bind::{CategoryTransfers, Lines, Mapping};
pub use block::ParamBlock;
pub use parse::{parse_map, read_map};
pub use part::{COMPLEX_HELP, MapField, Part, part_ranges};
pub use preset::{
    PRESETS, Preset, preset, preset_colormap, preset_names, preset_text, ramp_alphamap, ramp_text,
};
pub use table::{ByteTable, Table};
pub use transfer::{ScalarAlpha, ScalarColor, Transfer1D};

/// How a shading result varies with its field value between two breakpoints (for a linearly
/// interpolated field: how it varies along a ray segment).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Shape {
    Constant,
    Linear,
    Quadratic,
    /// Of higher degree or not polynomial: needs sub-stepping.
    Nonlinear,
}

impl Shape {
    /// The shape of a product of two functions of the given shapes.
    pub fn times(self, other: Shape) -> Shape {
        use Shape::*;
        match (self, other) {
            (Constant, s) | (s, Constant) => s,
            (Linear, Linear) => Quadratic,
            _ => Nonlinear,
        }
    }

    /// The shape of `g(f(s))` where `f` has shape `inner` and `g` has shape `self` in its
    /// argument.
    pub fn of(self, inner: Shape) -> Shape {
        use Shape::*;
        match (self, inner) {
            (Constant, _) | (_, Constant) => Constant,
            (s, Linear) => s,
            (Linear, s) => s,
            _ => Nonlinear,
        }
    }
}

/// What field a method can work on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldNeed {
    /// Any field (the value is not used).
    Any,
    /// A scalar field.
    Scalar,
    /// A field with exactly this many components (IDENTITY: 3, BARY_SHADING: 4).
    Components(usize),
    /// A byte field that is constant per cell (CONST_CELL).
    ByteConstant,
}

impl fmt::Display for FieldNeed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FieldNeed::Any => f.write_str("any field"),
            FieldNeed::Scalar => f.write_str("a scalar field"),
            FieldNeed::Components(n) => write!(f, "a float[{n}] field"),
            FieldNeed::ByteConstant => f.write_str("a byte Constant (per-cell) field"),
        }
    }
}

/// What a shading method sees of one sample point.
#[derive(Debug, Clone, Copy)]
pub struct Point<'a> {
    /// The method's field value at the point (its components).
    pub value: &'a [f64],
    /// The cell the point lies in.
    pub cell: usize,
    /// The point in the file's coordinates.
    pub pos: [f64; 3],
}

/// A colour shading method: data → emission η (RGB).
pub trait ColorShading: Send + Sync + fmt::Debug {
    /// η at a point; `chi` is the absorption the alphamap gives at the same point.
    fn color(&self, p: &Point, chi: f64) -> [f64; 3];
    fn field_need(&self) -> FieldNeed;
    /// Shape in the field value between breakpoints (not counting a χ factor).
    fn shape(&self) -> Shape;
    /// Field values where the shape changes (table values), ascending.
    fn breakpoints(&self) -> &[f64] {
        &[]
    }
    /// True if the result is multiplied by χ (ABSORPTION_WEIGHTED).
    fn uses_absorption(&self) -> bool {
        false
    }
    /// For per-cell byte tables: the byte values the table defines.
    fn defined_bytes(&self) -> Option<[bool; 256]> {
        None
    }
    /// The method as a piecewise-linear function of one scalar (before a χ factor), if it is
    /// one: lets the renderer use the merged [`Transfer1D`].
    fn scalar_form(&self) -> Option<ScalarColor<'_>> {
        None
    }
    /// The colour scale a legend draws for the method: its scalar form, or for a lit table
    /// (`LIT_EMITTER`) the table before the lights shade it.
    fn legend_form(&self) -> Option<ScalarColor<'_>> {
        self.scalar_form()
    }
    /// How many evaluations had to clamp a negative emission to 0 since the last call
    /// (`IDENTITY` of a field with negative components), for one warning per render.
    fn take_clamped(&self) -> u64 {
        0
    }
    /// `LIT_EMITTER`'s lighting parameters: the mapping multiplies [`ColorShading::color`] by
    /// the lights' factor at the point, from the field's gradient ([`crate::scene::Lighting`]).
    fn phong(&self) -> Option<&crate::scene::Phong> {
        None
    }
}

/// An alpha shading method: data → absorption χ.
pub trait AlphaShading: Send + Sync + fmt::Debug {
    fn alpha(&self, p: &Point) -> f64;
    fn field_need(&self) -> FieldNeed;
    fn shape(&self) -> Shape;
    fn breakpoints(&self) -> &[f64] {
        &[]
    }
    /// Extra cut parameters `t ∈ (0,1)` on a segment whose field value runs linearly from `v0`
    /// to `v1` where the shape changes for reasons other than scalar breakpoints (e.g. the
    /// `|v1 − v2|` kink of BARY_SHADING 3).
    fn cuts(&self, _v0: &[f64], _v1: &[f64], _out: &mut Vec<f64>) {}
    fn defined_bytes(&self) -> Option<[bool; 256]> {
        None
    }
    /// The method as a piecewise-linear function of one scalar, if it is one.
    fn scalar_form(&self) -> Option<ScalarAlpha<'_>> {
        None
    }
}

/// Builds a method from its parameter block (`None` for methods without one).
pub type Build<T> = fn(Option<&ParamBlock>) -> Result<Arc<T>, block::BlockError>;

/// One registry entry.
pub struct MethodInfo<T: ?Sized> {
    pub name: &'static str,
    pub summary: &'static str,
    /// The parameter block's format, for help and messages (`r g b value` rows …).
    pub params: &'static str,
    /// Whether the method needs a `@marker` block.
    pub needs_block: bool,
    pub build: Build<T>,
}

/// Every colour shading method (thesis C.2).
pub const COLOR_METHODS: &[MethodInfo<dyn ColorShading>] = &[
    color::constant::INFO,
    color::identity::INFO,
    color::simple_emitter::INFO,
    color::absorption_weighted::INFO,
    color::const_cell::INFO,
    color::lit_emitter::INFO,
];

/// Every alpha shading method (thesis C.2).
pub const ALPHA_METHODS: &[MethodInfo<dyn AlphaShading>] = &[
    alpha::constant::INFO,
    alpha::simple_absorber::INFO,
    alpha::bary_shading::INFO,
    alpha::const_cell::INFO,
];

fn names<T: ?Sized>(table: &[MethodInfo<T>]) -> String {
    table.iter().map(|m| m.name).collect::<Vec<_>>().join(", ")
}

/// Which of the two map kinds a file is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapKind {
    Color,
    Alpha,
}

impl MapKind {
    pub fn title(self) -> &'static str {
        match self {
            MapKind::Color => "Colormap",
            MapKind::Alpha => "Alphamap",
        }
    }
}

/// A method line's category interval `[from, to)`; a missing end is unbounded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    pub from: Option<f64>,
    pub to: Option<f64>,
}

impl Interval {
    pub fn contains(&self, v: f64) -> bool {
        self.from.is_none_or(|f| v >= f) && self.to.is_none_or(|t| v < t)
    }
}

/// How a map file names a field: by number (`DataField 2`, `field:2`) or by its name in
/// double quotes (`DataField "temperature"`, `field:"material"`), matched exactly against the
/// names the volume's file gave its fields (thesis appendix C, docs/formats.md). Names are resolved when the
/// map is bound to a volume, so one map file serves every file whose fields carry that name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FieldRef {
    Number(usize),
    Name(String),
}

impl FieldRef {
    /// The field number in `vol`; `Err` lists the names the volume has.
    pub fn resolve(&self, vol: &crate::volume::Volume) -> Result<usize, String> {
        match self {
            FieldRef::Number(n) => Ok(*n),
            FieldRef::Name(name) => vol
                .data
                .fields
                .iter()
                .position(|f| f.name.as_deref() == Some(name.as_str()))
                .ok_or_else(|| {
                    let names: Vec<String> = vol
                        .data
                        .fields
                        .iter()
                        .enumerate()
                        .filter_map(|(i, f)| f.name.as_ref().map(|n| format!("{i} \"{n}\"")))
                        .collect();
                    if names.is_empty() {
                        format!(
                            "the volume {} has no field named \"{name}\": its fields have no names",
                            vol.source
                        )
                    } else {
                        format!(
                            "the volume {} has no field named \"{name}\"; its named fields are {}",
                            vol.source,
                            names.join(", ")
                        )
                    }
                }),
        }
    }
}

impl std::fmt::Display for FieldRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FieldRef::Number(n) => write!(f, "{n}"),
            FieldRef::Name(s) => write!(f, "\"{s}\""),
        }
    }
}

impl From<usize> for FieldRef {
    fn from(n: usize) -> Self {
        FieldRef::Number(n)
    }
}

/// One method line of a map file.
#[derive(Debug)]
pub struct MethodLine<T: ?Sized> {
    pub name: &'static str,
    pub method: Arc<T>,
    /// `field:n` or `field:"name"`; `None` = `field:global` (the map's DataField).
    pub field: Option<MapField>,
    /// `from:`/`to:`; `None` = matches every category value.
    pub interval: Option<Interval>,
    /// 1-based line in the map file.
    pub line: usize,
}

/// A parsed colormap or alphamap.
#[derive(Debug)]
pub struct MapFile<T: ?Sized> {
    /// The file name as given (`<default>` for the built-in map).
    pub file: String,
    pub data_field: MapField,
    /// The line of `DataField` (1 if absent: the default applies to the whole file).
    pub data_field_line: usize,
    /// `CategoryField n` (or `"name"`) and its line.
    pub category: Option<(MapField, usize)>,
    pub lines: Vec<MethodLine<T>>,
}

// Written out because `derive(Clone)` would require `T: Clone`, which trait objects are not;
// only the `Arc`s are cloned.
impl<T: ?Sized> Clone for MethodLine<T> {
    fn clone(&self) -> Self {
        MethodLine {
            name: self.name,
            method: Arc::clone(&self.method),
            field: self.field.clone(),
            interval: self.interval,
            line: self.line,
        }
    }
}

impl<T: ?Sized> Clone for MapFile<T> {
    fn clone(&self) -> Self {
        MapFile {
            file: self.file.clone(),
            data_field: self.data_field.clone(),
            data_field_line: self.data_field_line,
            category: self.category.clone(),
            lines: self.lines.clone(),
        }
    }
}

pub type ColorMap = MapFile<dyn ColorShading>;
pub type AlphaMap = MapFile<dyn AlphaShading>;

impl ColorMap {
    /// No colormap given: constant red emission (1 0 0) everywhere (thesis A.1).
    pub fn default_map() -> ColorMap {
        default_map(
            Arc::new(color::constant::Constant([1.0, 0.0, 0.0])),
            "CONSTANT",
        )
    }
}

impl AlphaMap {
    /// No alphamap given: constant absorption 2 everywhere (thesis A.1).
    pub fn default_map() -> AlphaMap {
        default_map(Arc::new(alpha::constant::Constant(2.0)), "CONSTANT")
    }
}

fn default_map<T: ?Sized>(method: Arc<T>, name: &'static str) -> MapFile<T> {
    MapFile {
        file: "<default>".into(),
        data_field: MapField::from(0),
        data_field_line: 1,
        category: None,
        lines: vec![MethodLine {
            name,
            method,
            field: None,
            interval: None,
            line: 1,
        }],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_compose() {
        assert_eq!(Shape::Linear.times(Shape::Linear), Shape::Quadratic);
        assert_eq!(Shape::Linear.times(Shape::Constant), Shape::Linear);
        assert_eq!(Shape::Quadratic.times(Shape::Linear), Shape::Nonlinear);
        assert_eq!(Shape::Linear.of(Shape::Linear), Shape::Linear);
        assert_eq!(Shape::Quadratic.of(Shape::Linear), Shape::Quadratic);
        assert_eq!(Shape::Linear.of(Shape::Nonlinear), Shape::Nonlinear);
        assert_eq!(Shape::Constant.of(Shape::Nonlinear), Shape::Constant);
        assert_eq!(Shape::Nonlinear.of(Shape::Constant), Shape::Constant);
    }

    #[test]
    fn registries_have_unique_names() {
        let mut c: Vec<_> = COLOR_METHODS.iter().map(|m| m.name).collect();
        c.sort();
        c.dedup();
        assert_eq!(c.len(), COLOR_METHODS.len());
        let mut a: Vec<_> = ALPHA_METHODS.iter().map(|m| m.name).collect();
        a.sort();
        a.dedup();
        assert_eq!(a.len(), ALPHA_METHODS.len());
    }

    #[test]
    fn intervals_are_half_open() {
        let i = Interval {
            from: Some(1.0),
            to: Some(2.0),
        };
        assert!(i.contains(1.0) && i.contains(1.999) && !i.contains(2.0) && !i.contains(0.5));
        let open = Interval {
            from: None,
            to: Some(0.0),
        };
        assert!(open.contains(-1e300) && !open.contains(0.0));
    }
}
