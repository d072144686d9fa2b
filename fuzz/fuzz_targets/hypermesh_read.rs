//! Any byte string given to the HyperMesh reader must give a volume or a located error — never a
//! panic, a hang or an allocation out of proportion to the input. Successful reads are written
//! back and must read again to the same mesh.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vorang::Volume;
use vorang::hypermesh::{self, Encoding, Layout, WriteOptions};

fuzz_target!(|data: &[u8]| {
    let Ok(file) = hypermesh::read_bytes(data, "fuzz") else { return };
    if file.geometry.is_none() {
        return;
    }
    let Ok(vol) = Volume::from_file(file) else { return };
    for n in 0..vol.data.fields.len() {
        let _ = vol.field_range(n);
    }
    let mut out = Vec::new();
    let opts = WriteOptions { encoding: Encoding::Binary, layout: Layout::Small };
    hypermesh::write_volume(&vol, &mut out, opts).expect("writing to memory");
    let again = hypermesh::read_bytes(&out, "rewritten").and_then(Volume::from_file).expect("a written volume reads back");
    assert_eq!(again.mesh.tets(), vol.mesh.tets());
});
