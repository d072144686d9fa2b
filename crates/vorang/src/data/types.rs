//! The data types of HyperMesh files (thesis B.2; docs/formats.md): scalar types, arrays of them, and
//! typed storage for the values of a block.

use std::fmt;

/// A HyperMesh base type. `int` and `long` are both 32-bit; they are kept apart only so that a
/// file is written back with the keyword it was read with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ScalarType {
    Byte,
    Short,
    Int,
    Long,
    Float,
    Double,
    Complex,
}

impl ScalarType {
    /// Every type with its keyword, in the order the thesis lists them.
    pub const ALL: [ScalarType; 7] = [
        ScalarType::Byte,
        ScalarType::Short,
        ScalarType::Int,
        ScalarType::Long,
        ScalarType::Float,
        ScalarType::Double,
        ScalarType::Complex,
    ];

    pub fn keyword(self) -> &'static str {
        match self {
            ScalarType::Byte => "byte",
            ScalarType::Short => "short",
            ScalarType::Int => "int",
            ScalarType::Long => "long",
            ScalarType::Float => "float",
            ScalarType::Double => "double",
            ScalarType::Complex => "complex",
        }
    }

    pub fn from_keyword(word: &str) -> Option<ScalarType> {
        Self::ALL.into_iter().find(|t| t.keyword() == word)
    }

    /// Bytes per number in a BINARY block (a complex value is two numbers).
    pub fn number_size(self) -> usize {
        match self {
            ScalarType::Byte => 1,
            ScalarType::Short => 2,
            ScalarType::Int | ScalarType::Long | ScalarType::Float => 4,
            ScalarType::Double | ScalarType::Complex => 8,
        }
    }

    /// Numbers per component: 2 (re, im) for complex, else 1.
    pub fn numbers_per_component(self) -> usize {
        if self == ScalarType::Complex { 2 } else { 1 }
    }

    pub fn is_integer(self) -> bool {
        matches!(
            self,
            ScalarType::Byte | ScalarType::Short | ScalarType::Int | ScalarType::Long
        )
    }
}

/// A scalar type or an array `type[n]` of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DataType {
    pub scalar: ScalarType,
    /// `None` for a plain scalar, `Some(n)` for `type[n]` (even `type[1]`, to write it back as
    /// it was read).
    pub array: Option<u32>,
}

impl DataType {
    pub const fn scalar(scalar: ScalarType) -> Self {
        DataType {
            scalar,
            array: None,
        }
    }

    pub const fn array(scalar: ScalarType, n: u32) -> Self {
        DataType {
            scalar,
            array: Some(n),
        }
    }

    /// Number of components (`n` of `type[n]`, 1 for a scalar).
    pub fn components(&self) -> usize {
        self.array.map_or(1, |n| n as usize)
    }

    /// Numbers stored per element (components, doubled for complex).
    pub fn numbers(&self) -> usize {
        self.components() * self.scalar.numbers_per_component()
    }

    /// Bytes per element in a BINARY block.
    pub fn element_size(&self) -> usize {
        self.numbers() * self.scalar.number_size()
    }
}

impl fmt::Display for DataType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.array {
            None => f.write_str(self.scalar.keyword()),
            Some(n) => write!(f, "{}[{}]", self.scalar.keyword(), n),
        }
    }
}

/// The values of one block, stored flat (element-major, then component, then re/im), in the
/// narrowest Rust type that holds the file's type exactly.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    U8(Vec<u8>),
    I16(Vec<i16>),
    I32(Vec<i32>),
    F32(Vec<f32>),
    /// `double` and `complex` (re, im interleaved).
    F64(Vec<f64>),
}

impl Values {
    /// Empty storage for numbers of the given type, with room for `capacity` numbers.
    pub fn with_capacity(scalar: ScalarType, capacity: usize) -> Values {
        match scalar {
            ScalarType::Byte => Values::U8(Vec::with_capacity(capacity)),
            ScalarType::Short => Values::I16(Vec::with_capacity(capacity)),
            ScalarType::Int | ScalarType::Long => Values::I32(Vec::with_capacity(capacity)),
            ScalarType::Float => Values::F32(Vec::with_capacity(capacity)),
            ScalarType::Double | ScalarType::Complex => Values::F64(Vec::with_capacity(capacity)),
        }
    }

    /// Number of stored numbers.
    pub fn len(&self) -> usize {
        match self {
            Values::U8(v) => v.len(),
            Values::I16(v) => v.len(),
            Values::I32(v) => v.len(),
            Values::F32(v) => v.len(),
            Values::F64(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number `i` as f64 (exact for every stored type).
    #[inline]
    pub fn get(&self, i: usize) -> f64 {
        match self {
            Values::U8(v) => f64::from(v[i]),
            Values::I16(v) => f64::from(v[i]),
            Values::I32(v) => f64::from(v[i]),
            Values::F32(v) => f64::from(v[i]),
            Values::F64(v) => v[i],
        }
    }

    /// Number `i` as an integer, for index blocks (`None` for floating-point storage).
    #[inline]
    pub fn get_int(&self, i: usize) -> Option<i64> {
        match self {
            Values::U8(v) => Some(i64::from(v[i])),
            Values::I16(v) => Some(i64::from(v[i])),
            Values::I32(v) => Some(i64::from(v[i])),
            Values::F32(_) | Values::F64(_) => None,
        }
    }

    /// A new storage holding the numbers of the selected elements, in the given order.
    pub fn select(&self, numbers_per_element: usize, elements: &[u32]) -> Values {
        fn pick<T: Copy>(v: &[T], n: usize, elements: &[u32]) -> Vec<T> {
            let mut out = Vec::with_capacity(elements.len() * n);
            for &e in elements {
                let start = e as usize * n;
                out.extend_from_slice(&v[start..start + n]);
            }
            out
        }
        let n = numbers_per_element;
        match self {
            Values::U8(v) => Values::U8(pick(v, n, elements)),
            Values::I16(v) => Values::I16(pick(v, n, elements)),
            Values::I32(v) => Values::I32(pick(v, n, elements)),
            Values::F32(v) => Values::F32(pick(v, n, elements)),
            Values::F64(v) => Values::F64(pick(v, n, elements)),
        }
    }

    /// Appends zeros (used only to pad data of triangles that a full-format write adds).
    pub fn pad_zeros(&mut self, count: usize) {
        match self {
            Values::U8(v) => v.resize(v.len() + count, 0),
            Values::I16(v) => v.resize(v.len() + count, 0),
            Values::I32(v) => v.resize(v.len() + count, 0),
            Values::F32(v) => v.resize(v.len() + count, 0.0),
            Values::F64(v) => v.resize(v.len() + count, 0.0),
        }
    }
}

/// The geometric element a data block is attached to (thesis B.2 "Deklaration der Rohdaten").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ElementKind {
    Node,
    Edge,
    Triangle,
    Tetrahedron,
    /// Data bound to no geometric element (`nExtra` rows).
    Extra,
}

impl ElementKind {
    pub const ALL: [ElementKind; 5] = [
        ElementKind::Node,
        ElementKind::Edge,
        ElementKind::Triangle,
        ElementKind::Tetrahedron,
        ElementKind::Extra,
    ];

    /// Keyword of the data declaration (`NodeData`, …).
    pub fn data_keyword(self) -> &'static str {
        match self {
            ElementKind::Node => "NodeData",
            ElementKind::Edge => "EdgeData",
            ElementKind::Triangle => "TriangleData",
            ElementKind::Tetrahedron => "TetrahedronData",
            ElementKind::Extra => "ExtraData",
        }
    }

    /// Keyword of the count line (`nNodes`, …).
    pub fn count_keyword(self) -> &'static str {
        match self {
            ElementKind::Node => "nNodes",
            ElementKind::Edge => "nEdges",
            ElementKind::Triangle => "nTriangles",
            ElementKind::Tetrahedron => "nTetrahedra",
            ElementKind::Extra => "nExtra",
        }
    }

    /// Singular noun for messages.
    pub fn noun(self) -> &'static str {
        match self {
            ElementKind::Node => "node",
            ElementKind::Edge => "edge",
            ElementKind::Triangle => "triangle",
            ElementKind::Tetrahedron => "tetrahedron",
            ElementKind::Extra => "extra element",
        }
    }

    pub fn index(self) -> usize {
        self as usize
    }
}

/// One raw data block (`NodeData { float } = @5` and its values).
#[derive(Debug, Clone, PartialEq)]
pub struct RawData {
    pub kind: ElementKind,
    pub ty: DataType,
    /// The optional classifying word after the type (e.g. `Materials`).
    pub denominator: Option<String>,
    pub values: Values,
}

impl RawData {
    /// Number of elements the block holds.
    pub fn elements(&self) -> usize {
        let n = self.ty.numbers();
        self.values.len().checked_div(n).unwrap_or(0)
    }

    /// Component `c` of element `e` (the real part for complex data).
    #[inline]
    pub fn value(&self, e: usize, c: usize) -> f64 {
        let per = self.ty.scalar.numbers_per_component();
        self.values.get((e * self.ty.components() + c) * per)
    }

    /// Imaginary part of component `c` of element `e` (0 for real data).
    #[inline]
    pub fn imag(&self, e: usize, c: usize) -> f64 {
        if self.ty.scalar == ScalarType::Complex {
            self.values.get((e * self.ty.components() + c) * 2 + 1)
        } else {
            0.0
        }
    }

    /// True for scalar `byte` data (materials, cell classes).
    pub fn is_byte_scalar(&self) -> bool {
        self.ty.scalar == ScalarType::Byte && self.ty.components() == 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_sizes_follow_the_thesis_table() {
        assert_eq!(DataType::scalar(ScalarType::Byte).element_size(), 1);
        assert_eq!(DataType::array(ScalarType::Short, 5).element_size(), 10);
        assert_eq!(DataType::array(ScalarType::Long, 2).element_size(), 8);
        assert_eq!(DataType::array(ScalarType::Float, 3).element_size(), 12);
        assert_eq!(DataType::scalar(ScalarType::Double).element_size(), 8);
        assert_eq!(DataType::array(ScalarType::Complex, 3).element_size(), 48);
        assert_eq!(DataType::array(ScalarType::Complex, 3).numbers(), 6);
    }

    #[test]
    fn keywords_round_trip() {
        for t in ScalarType::ALL {
            assert_eq!(ScalarType::from_keyword(t.keyword()), Some(t));
        }
        assert_eq!(ScalarType::from_keyword("Float"), None);
        assert_eq!(
            DataType::array(ScalarType::Float, 3).to_string(),
            "float[3]"
        );
        assert_eq!(DataType::scalar(ScalarType::Complex).to_string(), "complex");
    }

    #[test]
    fn complex_values_split_into_real_and_imaginary_parts() {
        let raw = RawData {
            kind: ElementKind::Edge,
            ty: DataType::array(ScalarType::Complex, 2),
            denominator: None,
            values: Values::F64(vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]),
        };
        assert_eq!(raw.elements(), 2);
        assert_eq!(raw.value(1, 0), 5.0);
        assert_eq!(raw.imag(1, 1), 8.0);
    }
}
