//! Any byte string given to the msh reader must give a volume or a located error (file and line
//! or byte offset) — never a panic, a hang or an allocation out of proportion to the input.
//! Volumes that load are written as .vtu and must read back to the same mesh.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vorang::formats::{build, vtu, msh};

fuzz_target!(|data: &[u8]| {
    let desc = match msh::read(data, "fuzz.msh") {
        Ok(d) => d,
        Err(e) => {
            assert_eq!(e.file, "fuzz.msh");
            assert!(e.line >= 1);
            return;
        }
    };
    let Ok((vol, _)) = build::volume(desc) else { return };
    for n in 0..vol.data.fields.len() {
        let _ = vol.field_range(n);
    }
    let mut out = Vec::new();
    vtu::write(&vol, &mut out).expect("writing to memory");
    let again = vtu::read(&out, "rewritten.vtu").expect("a written volume reads back");
    let (again, _) = build::volume(again).expect("a written volume builds");
    assert_eq!(again.mesh.tets(), vol.mesh.tets());
});
