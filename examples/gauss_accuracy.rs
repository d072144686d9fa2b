//! Error control on a field that is not polynomial in the cells: the gauss
//! example scene (GaussTest field, thesis 7) rendered with `exact linear 0` and with `exact` and
//! the thesis's rules at several steps, each compared with the independent reference renderer
//! (`crates/vorang/src/reference.rs`), with the render time.
//!
//! `cargo run --release --example gauss_accuracy -- [SIZE] "exact linear 0 3" "exact constEA 0.002 3" …`

use std::path::Path;
use std::time::Instant;
use vorang::Volume;
use vorang::framebuffer::Background;
use vorang::mapping::{AlphaShading, ColorShading, Mapping, parse_map};
use vorang::reference::{self, Options};
use vorang::render::{LineDraw, Method, Settings, render};
use vorang::scene::{Camera, TransformOp, View};

fn main() {
    let (vol, _) = Volume::load(Path::new("examples/gauss/gauss.hmesh")).unwrap();
    let c = parse_map::<dyn ColorShading>(
        &std::fs::read("examples/gauss/rainbow.cmap").unwrap()[..],
        "c",
    )
    .unwrap()
    .0;
    let a = parse_map::<dyn AlphaShading>(
        &std::fs::read("examples/gauss/cloud.amap").unwrap()[..],
        "a",
    )
    .unwrap()
    .0;
    let m = Mapping::new(&c, &a, &vol).unwrap().0;
    let view = View {
        transforms: vec![
            TransformOp::Rotate {
                axis: [0.0, 1.0, 0.0],
                degrees: 30.0,
            },
            TransformOp::Rotate {
                axis: [1.0, 0.0, 0.0],
                degrees: 20.0,
            },
        ],
        camera: Some(Camera::Ortho {
            left: -0.9,
            right: 0.9,
            bottom: -0.9,
            top: 0.9,
            front: -10.0,
            back: 10.0,
        }),
        ..View::default()
    };
    let n: usize = std::env::args()
        .nth(1)
        .map_or(40, |s| s.parse().expect("an image size"));
    let bg = Background::Color([0.0; 3]);
    let mut opts = Options::new(n, n);
    opts.background = bg.clone();
    opts.brightness = 3.0;
    let t = Instant::now();
    let r = reference::render(&vol, &m, &view, &opts);
    eprintln!("reference {:.1} s", t.elapsed().as_secs_f64());
    for meth in std::env::args().skip(2) {
        let words: Vec<&str> = meth.split_whitespace().collect();
        let s = Settings {
            width: n,
            height: n,
            method: Method::parse(&words).unwrap(),
            lines: LineDraw::Off,
            background: bg.clone(),
            ..Settings::default()
        };
        let t = Instant::now();
        let fb = render(&vol, &m, &view, &s, None).unwrap().0;
        let el = t.elapsed().as_secs_f64();
        let max = fb
            .pixels
            .iter()
            .zip(&r)
            .flat_map(|(p, q)| (0..4).map(move |c| (f64::from(p[c]) - q[c]).abs()))
            .fold(0.0, f64::max);
        println!("{meth}: max error {max:.2e}, {el:.3} s");
    }
}
