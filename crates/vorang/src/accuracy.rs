//! The scenes of the accuracy report (`docs/accuracy.md`, issue: exact integration): each a
//! volume, a colormap, an alphamap and a brightness factor, rendered against the reference ray
//! caster. Shared by the report generator (`cargo run --release --example accuracy`) and the
//! tests.

use crate::Volume;
use crate::data::{DataType, ElementKind, RawData, ScalarType, Values};
use crate::field::Interpolator;
use crate::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
use crate::mesh::TetMesh;
use crate::mesh::generate::kuhn_box;
use crate::scene::{Camera, LookAt, TransformOp, View};

/// One scene of the report.
pub struct Scene {
    pub name: &'static str,
    pub what: &'static str,
    pub volume: Volume,
    pub mapping: Mapping,
}

fn maps(vol: &Volume, color: &str, alpha: &str) -> Mapping {
    let c = parse_map::<dyn ColorShading>(color.as_bytes(), "scene colormap")
        .expect("valid colormap")
        .0;
    let a = parse_map::<dyn AlphaShading>(alpha.as_bytes(), "scene alphamap")
        .expect("valid alphamap")
        .0;
    Mapping::new(&c, &a, vol).expect("maps fit the volume").0
}

fn with_fields(
    nodes: Vec<[f64; 3]>,
    tets: Vec<[u32; 4]>,
    fields: &[(&str, DataType, Vec<f64>)],
) -> Volume {
    let n = nodes.len();
    let mut vol = Volume::from_mesh("scene", TetMesh::new(nodes, tets).expect("valid mesh"));
    for (name, ty, values) in fields {
        assert_eq!(values.len(), n * ty.numbers());
        let raw = RawData {
            kind: ElementKind::Node,
            ty: *ty,
            denominator: None,
            values: Values::F64(values.clone()),
        };
        let r = vol.add_raw(raw).expect("node data");
        vol.add_field(Some(name), *ty, Interpolator::Linear, &[r])
            .expect("field");
    }
    vol
}

/// A volume with one Linear scalar node field `s` (for the degenerate-view section of the report
/// and its tests).
pub fn scalar_volume(nodes: Vec<[f64; 3]>, tets: Vec<[u32; 4]>, values: Vec<f64>) -> Volume {
    with_fields(
        nodes,
        tets,
        &[("s", DataType::scalar(ScalarType::Double), values)],
    )
}

/// A piecewise-linear emitter and absorber on `s` over [−1.5, 2].
pub fn scalar_maps(vol: &Volume) -> Mapping {
    maps(
        vol,
        "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0.9 0.1 0.1 -1.5\n0.1 0.8 0.2 -0.3\n0.2 0.3 1.0 0.6\n1 1 0.2 2\n",
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.4 -1.5\n3 -0.2\n0.8 0.7\n2.5 2\n",
    )
}

/// The scenes: the colour cuboid, a jittered mesh with a many-breakpoint map, an opaque case
/// with emission weighted by absorption, a case with absorption-free regions, and category
/// switching along the ray.
pub fn scenes() -> Vec<Scene> {
    let scalar = DataType::scalar(ScalarType::Double);
    let mut out = Vec::new();

    let (nodes, tets) = kuhn_box([2, 1, 1], [2.0, 1.0, 1.0], 0.0, 0);
    let colours: Vec<f64> = nodes
        .iter()
        .flat_map(|p| [p[0] / 2.0, p[1], p[2]])
        .collect();
    let vol = with_fields(
        nodes,
        tets,
        &[("colour", DataType::array(ScalarType::Double, 3), colours)],
    );
    let mapping = maps(
        &vol,
        "# VoRANG Colormap 1.0\nIDENTITY\n",
        "# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n1.2\n",
    );
    out.push(Scene {
        name: "farbraum",
        what: "colour cuboid: IDENTITY emission, constant χ = 1.2",
        volume: vol,
        mapping,
    });

    let (nodes, tets) = kuhn_box([4, 4, 4], [1.0; 3], 0.12, 11);
    let s: Vec<f64> = nodes
        .iter()
        .map(|p| crate::volume::smooth_scalar(*p))
        .collect();
    let vol = with_fields(nodes, tets, &[("s", scalar, s)]);
    let mapping = maps(
        &vol,
        "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 1 0.45\n0 1 0 0.55\n1 1 0 0.65\n1 0 0 0.75\n1 1 1 0.85\n",
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.2 0.45\n3 0.55\n0.5 0.65\n6 0.75\n1 0.85\n",
    );
    out.push(Scene {
        name: "jittered",
        what: "jittered box (384 cells), smooth field, 5-breakpoint maps",
        volume: vol,
        mapping,
    });

    let (nodes, tets) = kuhn_box([3, 3, 3], [1.0; 3], 0.1, 5);
    let s: Vec<f64> = nodes
        .iter()
        .map(|p| crate::volume::smooth_scalar(*p))
        .collect();
    let vol = with_fields(nodes, tets, &[("s", scalar, s)]);
    let mapping = maps(
        &vol,
        "# VoRANG Colormap 1.0\nABSORPTION_WEIGHTED @1\n@1\n0.1 0.2 0.9 0.4\n0.9 0.4 0.1 1\n",
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n5 0.4\n60 0.7\n30 1\n",
    );
    out.push(Scene {
        name: "opaque",
        what: "opaque (χ up to 60), emission ∝ absorption (η quadratic)",
        volume: vol,
        mapping,
    });

    let (nodes, tets) = kuhn_box([4, 3, 3], [1.0; 3], 0.1, 8);
    let s: Vec<f64> = nodes
        .iter()
        .map(|p| p[0] + 0.3 * (4.0 * p[1]).sin() * p[2])
        .collect();
    let vol = with_fields(nodes, tets, &[("s", scalar, s)]);
    let mapping = maps(
        &vol,
        "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n1 0.8 0.2 0\n0.2 0.4 1 1\n",
        "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0 0.35\n0 0.5\n8 0.8\n",
    );
    out.push(Scene {
        name: "clear",
        what: "absorption-free where s < 0.5 (emission only), opaque above",
        volume: vol,
        mapping,
    });

    let (nodes, tets) = kuhn_box([3, 3, 3], [1.0; 3], 0.1, 2);
    let s: Vec<f64> = nodes
        .iter()
        .map(|p| crate::volume::smooth_scalar(*p))
        .collect();
    let cat: Vec<f64> = nodes.iter().map(|p| 3.0 * p[1] + p[0]).collect();
    let vol = with_fields(nodes, tets, &[("s", scalar, s), ("category", scalar, cat)]);
    let mapping = maps(
        &vol,
        "# VoRANG Colormap 1.0\nCategoryField 1\nSIMPLE_EMITTER to:1.5 @1\nCONSTANT from:1.5 to:2.5 @2\nSIMPLE_EMITTER @3\n@1\n1 0 0 0.4\n1 1 0 0.9\n@2\n0.2 0.6 1\n@3\n0 1 0 0.4\n0 0 1 0.9\n",
        "# VoRANG Alphamap 1.0\nCategoryField 1\nSIMPLE_ABSORBER from:0.8 @1\nCONSTANT @2\n@1\n0.5 0.4\n4 0.9\n@2\n0.3\n",
    );
    out.push(Scene {
        name: "categories",
        what: "category field switching maps along the ray (discontinuous η, χ)",
        volume: vol,
        mapping,
    });

    out
}

/// The views of the report: orthographic and perspective, both rotated.
pub fn views(scene: &Scene) -> Vec<(&'static str, View)> {
    let size = scene.volume.mesh.bbox().size();
    let r = 0.6 * (size[0] * size[0] + size[1] * size[1] + size[2] * size[2]).sqrt();
    vec![
        (
            "ortho",
            View {
                transforms: vec![
                    TransformOp::Rotate {
                        axis: [0.3, 1.0, 0.1],
                        degrees: 32.0,
                    },
                    TransformOp::Rotate {
                        axis: [1.0, 0.0, 0.0],
                        degrees: -24.0,
                    },
                ],
                camera: Some(Camera::Ortho {
                    left: -r,
                    right: r,
                    bottom: -r,
                    top: r,
                    front: -10.0,
                    back: 10.0,
                }),
                ..View::default()
            },
        ),
        (
            "persp",
            View {
                transforms: vec![TransformOp::Rotate {
                    axis: [1.0, 1.0, 0.0],
                    degrees: 25.0,
                }],
                look_at: LookAt {
                    eye: [0.4 * r, 0.3 * r, 3.0 * r],
                    reference: [0.0; 3],
                    up: [0.0, 1.0, 0.0],
                },
                camera: Some(Camera::Persp {
                    fovy: 40.0,
                    aspect: 1.0,
                    near: 0.1 * r,
                    far: 20.0 * r,
                }),
            },
        ),
    ]
}
