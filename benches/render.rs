//! Rendering benchmarks (issue: performance): on generated jittered boxes of 20k, 150k and 1M
//! tetrahedra with a smooth scalar field and a five-breakpoint transfer function —
//!
//! - `load`: reading the BINARY HyperMesh file (mesh validation and adjacency included);
//! - `sort`: the visibility sort of all cells for one view;
//! - one full frame per method (`exact linear 0`, `exact constEA 0.01`, `interpolateCoeff
//!   linear`, `interpolateColor`, `test`) at 512² and 1024², orthographic and perspective;
//! - `threads`: full frames on one thread and on all threads.
//!
//! Run: `cargo bench --bench render` (all of it takes about a quarter of an hour on two cores);
//! a subset by name, e.g. `cargo bench --bench render -- interpolate_color`. Volumes are
//! generated once per run; the BINARY files go to a temporary folder.

use std::path::PathBuf;
use std::sync::OnceLock;

use vorang::Volume;
use vorang::hypermesh::{self, Encoding, Layout, WriteOptions};
use vorang::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
use vorang::render::{LineDraw, Method, Settings, render};
use vorang::scene::{Camera, LookAt, TransformOp, View};
use vorang::sort::{self, SortInput};
use vorang::volume::jittered_box;

fn main() {
    divan::main();
}

const SIZES: [usize; 3] = [20_000, 150_000, 1_000_000];

/// Five breakpoints in emission and absorption over the field's range [0.25, 0.75].
const COLORMAP: &str = "# VoRANG Colormap 1.0\nSIMPLE_EMITTER @1\n@1\n0 0 1 0.45\n0 1 0 0.55\n1 1 0 0.65\n1 0 0 0.75\n1 1 1 0.85\n";
const ALPHAMAP: &str =
    "# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n0.2 0.45\n3 0.55\n0.5 0.65\n6 0.75\n1 0.85\n";

/// The methods, as the `method` command takes them.
const METHODS: [(&str, &str); 5] = [
    ("exact_linear", "exact linear 0 1"),
    ("exact_const_ea", "exact constEA 0.01 1"),
    ("interpolate_coeff", "interpolateCoeff linear 1"),
    ("interpolate_color", "interpolateColor 1"),
    ("test", "test 0.3"),
];

/// Frames: `cells/pixels/projection`.
const FRAMES: [&str; 12] = [
    "20k/512/ortho",
    "20k/512/persp",
    "20k/1024/ortho",
    "20k/1024/persp",
    "150k/512/ortho",
    "150k/512/persp",
    "150k/1024/ortho",
    "150k/1024/persp",
    "1M/512/ortho",
    "1M/512/persp",
    "1M/1024/ortho",
    "1M/1024/persp",
];

struct Scene {
    vol: Volume,
    mapping: Mapping,
}

fn scene(cells: usize) -> &'static Scene {
    static SCENES: [OnceLock<Scene>; 3] = [OnceLock::new(), OnceLock::new(), OnceLock::new()];
    let i = SIZES
        .iter()
        .position(|&s| s == cells)
        .expect("a benchmark size");
    SCENES[i].get_or_init(|| {
        let vol = jittered_box(cells, 0.1, 1);
        let mapping = scene_maps(&vol);
        Scene { vol, mapping }
    })
}

fn scene_maps(vol: &Volume) -> Mapping {
    let c = parse_map::<dyn ColorShading>(COLORMAP.as_bytes(), "five.cmap")
        .expect("colormap")
        .0;
    let a = parse_map::<dyn AlphaShading>(ALPHAMAP.as_bytes(), "five.amap")
        .expect("alphamap")
        .0;
    Mapping::new(&c, &a, vol).expect("mapping").0
}

/// The box turned 30° about (1, 1, 0); orthographic with the default camera (the box fills
/// the picture), or perspective from 2.2 units in front of its centre.
fn view(perspective: bool) -> View {
    let mut v = View {
        transforms: vec![TransformOp::Rotate {
            axis: [1.0, 1.0, 0.0],
            degrees: 30.0,
        }],
        ..View::default()
    };
    if perspective {
        v.camera = Some(Camera::Persp {
            fovy: 40.0,
            aspect: 1.0,
            near: 0.1,
            far: 20.0,
        });
        v.look_at = LookAt {
            eye: [0.0, 0.0, 2.2],
            reference: [0.0; 3],
            up: [0.0, 1.0, 0.0],
        };
    }
    v
}

/// `"150k/512/persp"` → (cells, pixels per side, perspective).
fn frame(case: &str) -> (usize, usize, bool) {
    let parts: Vec<&str> = case.split('/').collect();
    let cells = match parts[0] {
        "20k" => 20_000,
        "150k" => 150_000,
        _ => 1_000_000,
    };
    (
        cells,
        parts[1].parse().expect("pixels"),
        parts[2] == "persp",
    )
}

fn settings(pixels: usize, method: &str) -> Settings {
    let words: Vec<&str> = method.split_whitespace().collect();
    Settings {
        width: pixels,
        height: pixels,
        method: Method::parse(&words).expect("method"),
        lines: LineDraw::Off,
        ..Settings::default()
    }
}

fn run_frame(bencher: divan::Bencher, case: &str, method: &str) {
    let (cells, pixels, perspective) = frame(case);
    let s = scene(cells);
    let (view, settings) = (view(perspective), settings(pixels, method));
    bencher.bench(|| render(&s.vol, &s.mapping, &view, &settings, None).expect("render"));
}

/// The box with 3 % of its cells removed (cavities, tunnels): non-convex, ordered per pixel.
#[divan::bench(args = ["150k/512/ortho", "150k/512/persp", "1M/512/ortho"], sample_count = 5, sample_size = 1)]
fn non_convex_exact_linear(bencher: divan::Bencher, case: &str) {
    static HOLEY: [OnceLock<Scene>; 2] = [OnceLock::new(), OnceLock::new()];
    let (cells, pixels, perspective) = frame(case);
    let s = HOLEY[usize::from(cells > 200_000)].get_or_init(|| {
        let vol = vorang::volume::jittered_box_with_holes(cells, 0.1, 1, 0.03);
        let mapping = scene_maps(&vol);
        Scene { vol, mapping }
    });
    let (view, settings) = (view(perspective), settings(pixels, METHODS[0].1));
    bencher.bench(|| render(&s.vol, &s.mapping, &view, &settings, None).expect("render"));
}

#[divan::bench(args = FRAMES, sample_count = 5, sample_size = 1)]
fn exact_linear(bencher: divan::Bencher, case: &str) {
    run_frame(bencher, case, METHODS[0].1);
}

#[divan::bench(args = FRAMES, sample_count = 5, sample_size = 1)]
fn exact_const_ea(bencher: divan::Bencher, case: &str) {
    run_frame(bencher, case, METHODS[1].1);
}

#[divan::bench(args = FRAMES, sample_count = 5, sample_size = 1)]
fn interpolate_coeff(bencher: divan::Bencher, case: &str) {
    run_frame(bencher, case, METHODS[2].1);
}

#[divan::bench(args = FRAMES, sample_count = 5, sample_size = 1)]
fn interpolate_color(bencher: divan::Bencher, case: &str) {
    run_frame(bencher, case, METHODS[3].1);
}

#[divan::bench(args = FRAMES, sample_count = 5, sample_size = 1)]
fn test(bencher: divan::Bencher, case: &str) {
    run_frame(bencher, case, METHODS[4].1);
}

/// The visibility sort alone (convexity is known after the first frame, so it is decided once
/// outside the timing, as in a session).
#[divan::bench(args = SIZES, sample_count = 10, sample_size = 1)]
fn sort(bencher: divan::Bencher, cells: usize) {
    sort_mesh(bencher, &scene(cells).vol.mesh);
}

/// The sort of a non-convex mesh (the box with 3 % of its cells removed): MPVONC's order.
#[divan::bench(args = [150_000, 1_000_000], sample_count = 10, sample_size = 1)]
fn sort_non_convex(bencher: divan::Bencher, cells: usize) {
    static HOLEY: [OnceLock<std::sync::Arc<vorang::mesh::TetMesh>>; 2] =
        [OnceLock::new(), OnceLock::new()];
    let mesh = HOLEY[usize::from(cells > 200_000)]
        .get_or_init(|| vorang::volume::jittered_box_with_holes(cells, 0.1, 1, 0.03).mesh);
    sort_mesh(bencher, mesh);
}

fn sort_mesh(bencher: divan::Bencher, mesh: &vorang::mesh::TetMesh) {
    let bbox = mesh.bbox();
    let v = view(false);
    let to_eye = v
        .view_matrix()
        .after(&v.model(bbox.center()).expect("model"));
    let eye_nodes: Vec<[f64; 3]> = mesh.nodes().iter().map(|&p| to_eye.apply(p)).collect();
    let sorter = sort::choose(mesh.is_convex());
    let screen: Vec<[f64; 2]> = eye_nodes.iter().map(|p| [p[0], -p[1]]).collect();
    let input = SortInput {
        mesh,
        eye_nodes: &eye_nodes,
        screen: &screen,
        perspective: false,
        mirrored: false,
    };
    bencher.bench(|| (sorter.sort)(&input));
}

fn binary_file(cells: usize) -> PathBuf {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    let dir = DIR.get_or_init(|| tempfile::tempdir().expect("temporary folder"));
    let path = dir.path().join(format!("box{cells}.bin"));
    if !path.exists() {
        let opts = WriteOptions {
            encoding: Encoding::Binary,
            layout: Layout::Small,
        };
        hypermesh::save_volume(&scene(cells).vol, &path, opts).expect("write benchmark file");
    }
    path
}

/// Reading a BINARY file into a volume ready to render.
#[divan::bench(args = SIZES, sample_count = 10, sample_size = 1)]
fn load(bencher: divan::Bencher, cells: usize) {
    let path = binary_file(cells);
    bencher.bench(|| Volume::load(&path).expect("read"));
}

/// 150k cells at 512², orthographic, on one thread and on all of them.
const THREADS: [&str; 6] = [
    "1/exact_linear",
    "all/exact_linear",
    "1/interpolate_color",
    "all/interpolate_color",
    "1/test",
    "all/test",
];

#[divan::bench(args = THREADS, sample_count = 5, sample_size = 1)]
fn threads(bencher: divan::Bencher, case: &str) {
    let (threads, name) = case.split_once('/').expect("threads/method");
    let method = METHODS.iter().find(|m| m.0 == name).expect("a method").1;
    let n = match threads {
        "1" => 1,
        _ => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .expect("thread pool");
    let s = scene(150_000);
    let (view, settings) = (view(false), settings(512, method));
    bencher.bench(|| {
        pool.install(|| render(&s.vol, &s.mapping, &view, &settings, None).expect("render"))
    });
}

/// The SIMD span kernels against the scalar per-pixel path they replace, same frames
/// (`Settings::span_kernels`): the speed-up of `render::span` measured in one run.
const SPAN: [&str; 6] = [
    "lanes/exact_linear/150k/512/ortho",
    "scalar/exact_linear/150k/512/ortho",
    "lanes/exact_linear/150k/512/persp",
    "scalar/exact_linear/150k/512/persp",
    "lanes/interpolate_coeff/150k/512/ortho",
    "scalar/interpolate_coeff/150k/512/ortho",
];

#[divan::bench(args = SPAN, sample_count = 5, sample_size = 1)]
fn span_kernels(bencher: divan::Bencher, case: &str) {
    let (path, rest) = case.split_once('/').expect("path/method/frame");
    let (name, frame_case) = rest.split_once('/').expect("method/frame");
    let method = METHODS.iter().find(|m| m.0 == name).expect("a method").1;
    let (cells, pixels, perspective) = frame(frame_case);
    let s = scene(cells);
    let view = view(perspective);
    let settings = Settings {
        span_kernels: path == "lanes",
        ..settings(pixels, method)
    };
    bencher.bench(|| render(&s.vol, &s.mapping, &view, &settings, None).expect("render"));
}
