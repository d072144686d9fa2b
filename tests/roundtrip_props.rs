//! Property: any valid volume written in any of the four variants (ASCII/BINARY × full/small)
//! reads back identical — nodes, cells, adjacency, raw data bit for bit, fields.

use proptest::prelude::*;
use vorang::Volume;
use vorang::field::Interpolator;
use vorang::hypermesh::{
    self, DataType, ElementKind, Encoding, Layout, RawData, ScalarType, Values, WriteOptions,
};
use vorang::mesh::TetMesh;
use vorang::mesh::generate::kuhn_box;

/// A raw data block to attach: element kind, type, array length (None = scalar), value seed.
#[derive(Debug, Clone)]
struct Spec {
    kind: ElementKind,
    scalar: ScalarType,
    array: Option<u32>,
    values: Vec<u64>,
}

fn scalar_type() -> impl Strategy<Value = ScalarType> {
    prop::sample::select(ScalarType::ALL.to_vec())
}

fn spec() -> impl Strategy<Value = Spec> {
    (
        prop::sample::select(vec![
            ElementKind::Node,
            ElementKind::Tetrahedron,
            ElementKind::Extra,
        ]),
        scalar_type(),
        prop::option::of(1u32..4),
        prop::collection::vec(any::<u64>(), 1..64),
    )
        .prop_map(|(kind, scalar, array, values)| Spec {
            kind,
            scalar,
            array,
            values,
        })
}

/// Deterministic values of any type from random bits (finite floats only, doubles within the
/// accepted ±1e150).
fn values(scalar: ScalarType, n: usize, seeds: &[u64]) -> Values {
    let bits = |i: usize| {
        seeds[i % seeds.len()].rotate_left(i as u32 * 7) ^ (i as u64).wrapping_mul(0x9E37_79B9)
    };
    let finite64 = |b: u64| {
        let v = f64::from_bits(b);
        if v.is_finite() && v.abs() <= vorang::hypermesh::MAX_MAGNITUDE {
            v
        } else {
            (b >> 12) as f64 * 1e-3
        }
    };
    match scalar {
        ScalarType::Byte => Values::U8((0..n).map(|i| bits(i) as u8).collect()),
        ScalarType::Short => Values::I16((0..n).map(|i| bits(i) as i16).collect()),
        ScalarType::Int | ScalarType::Long => Values::I32((0..n).map(|i| bits(i) as i32).collect()),
        ScalarType::Float => Values::F32(
            (0..n)
                .map(|i| {
                    let v = f32::from_bits(bits(i) as u32);
                    if v.is_finite() {
                        v
                    } else {
                        (bits(i) >> 40) as f32 * 0.5
                    }
                })
                .collect(),
        ),
        ScalarType::Double | ScalarType::Complex => {
            Values::F64((0..n).map(|i| finite64(bits(i))).collect())
        }
    }
}

fn build(cells: [usize; 3], jitter: f64, seed: u64, float_coords: bool, specs: &[Spec]) -> Volume {
    let (mut nodes, tets) = kuhn_box(cells, [1.5, 1.0, 2.0], jitter, seed);
    if float_coords {
        for p in &mut nodes {
            *p = p.map(|c| c as f32 as f64);
        }
    }
    let mesh = TetMesh::new(nodes, tets).unwrap();
    let mut vol = Volume::from_mesh("generated", mesh);
    if float_coords {
        vol.coord_type = ScalarType::Float;
    }
    let extra_rows = 3;
    for s in specs {
        let ty = DataType {
            scalar: s.scalar,
            array: s.array,
        };
        let elements = vol.count(s.kind).unwrap_or(extra_rows);
        let raw = RawData {
            kind: s.kind,
            ty,
            denominator: (s.values[0] % 3 == 0).then(|| "Tag".to_string()),
            values: values(s.scalar, elements * ty.numbers(), &s.values),
        };
        let r = vol.add_raw(raw).unwrap();
        let interp = match s.kind {
            ElementKind::Node => Some(Interpolator::Linear),
            ElementKind::Tetrahedron => Some(Interpolator::Constant),
            _ => None,
        };
        if let Some(i) = interp {
            let name = format!("f{r}");
            vol.add_field(Some(&name), ty, i, &[r]).unwrap();
        }
    }
    vol
}

/// The stored numbers as bit patterns, so that −0.0 ≠ 0.0.
fn bits(v: &Values) -> Vec<u64> {
    match v {
        Values::U8(x) => x.iter().map(|&a| a as u64).collect(),
        Values::I16(x) => x.iter().map(|&a| a as u16 as u64).collect(),
        Values::I32(x) => x.iter().map(|&a| a as u32 as u64).collect(),
        Values::F32(x) => x.iter().map(|a| a.to_bits() as u64).collect(),
        Values::F64(x) => x.iter().map(|a| a.to_bits()).collect(),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_volumes_round_trip_exactly(
        nx in 1usize..4, ny in 1usize..3, nz in 1usize..3,
        jitter in 0.0f64..0.15,
        seed in any::<u64>(),
        float_coords in any::<bool>(),
        specs in prop::collection::vec(spec(), 0..5),
    ) {
        let vol = build([nx, ny, nz], jitter, seed, float_coords, &specs);
        for encoding in [Encoding::Ascii, Encoding::Binary] {
            for layout in [Layout::Full, Layout::Small] {
                let mut bytes = Vec::new();
                hypermesh::write_volume(&vol, &mut bytes, WriteOptions { encoding, layout }).unwrap();
                let file = hypermesh::read_bytes(&bytes, "prop").map_err(|e| TestCaseError::fail(e.to_string()))?;
                let back = Volume::from_file(file).map_err(|e| TestCaseError::fail(e.to_string()))?;
                prop_assert_eq!(back.mesh.nodes(), vol.mesh.nodes());
                prop_assert_eq!(back.mesh.tets(), vol.mesh.tets());
                prop_assert_eq!(back.mesh.neighbors(), vol.mesh.neighbors());
                prop_assert_eq!(back.coord_type, vol.coord_type);
                prop_assert_eq!(back.data.raw.len(), vol.data.raw.len());
                for (a, b) in back.data.raw.iter().zip(&vol.data.raw) {
                    prop_assert_eq!((a.kind, a.ty, &a.denominator), (b.kind, b.ty, &b.denominator));
                    prop_assert_eq!(bits(&a.values), bits(&b.values));
                }
                prop_assert_eq!(back.data.fields.len(), vol.data.fields.len());
                for (a, b) in back.data.fields.iter().zip(&vol.data.fields) {
                    prop_assert_eq!((&a.name, a.ty, a.interpolator, &a.sources), (&b.name, b.ty, b.interpolator, &b.sources));
                }
            }
        }
    }
}
