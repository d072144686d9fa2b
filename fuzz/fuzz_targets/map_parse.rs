//! Any bytes given to the colormap and alphamap parsers must give a map or a located error; a
//! map that parses is bound to a fixed volume and evaluated — never a panic.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use vorang::Volume;
use vorang::hypermesh;
use vorang::mapping::{AlphaMap, AlphaShading, ColorMap, ColorShading, Mapping, parse_map};

fn volume() -> &'static Volume {
    static VOL: OnceLock<Volume> = OnceLock::new();
    VOL.get_or_init(|| {
        let bytes = include_bytes!("../../tests/data/two_tets_data.hmesh");
        Volume::from_file(hypermesh::read_bytes(bytes, "two_tets_data").expect("test volume")).expect("test volume")
    })
}

fn exercise(m: &Mapping) {
    let vol = volume();
    let mut a = vec![0.0; m.width()];
    let mut b = vec![0.0; m.width()];
    m.sample_fields(vol, 0, &[0.7, 0.1, 0.1, 0.1], [0.1, 0.1, 0.1], &mut a);
    m.sample_fields(vol, 1, &[0.1, 0.2, 0.3, 0.4], [0.5, 0.6, 0.7], &mut b);
    let _ = m.eval(&a, 0, [0.1; 3]);
    let mut cuts = Vec::new();
    m.cuts(&a, &b, &mut cuts);
    let _ = m.piece_shapes(&a);
}

fuzz_target!(|data: &[u8]| {
    let vol = volume();
    if let Ok((c, _)) = parse_map::<dyn ColorShading>(data, "fuzz") {
        if let Ok((m, _)) = Mapping::new(&c, &AlphaMap::default_map(), vol) {
            exercise(&m);
        }
    }
    if let Ok((a, _)) = parse_map::<dyn AlphaShading>(data, "fuzz") {
        if let Ok((m, _)) = Mapping::new(&ColorMap::default_map(), &a, vol) {
            exercise(&m);
        }
    }
});
