//! Any byte string given to the vtu reader must give a volume or a located error (file and line
//! or byte offset) — never a panic, a hang or an allocation out of proportion to the input.
//! Volumes that load are written as .vtu and must read back to the same mesh and data.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vorang::formats::{build, vtu};

static QUIET_HOOK: std::sync::Once = std::sync::Once::new();

fuzz_target!(|data: &[u8]| {
    // The reader catches a known panic inside lzma-rs (an overflow on a corrupt xz footer) and
    // reports an error. libfuzzer-sys's hook would abort on it before the catch, so print
    // panics instead: any other panic still unwinds to libfuzzer-sys, which aborts.
    QUIET_HOOK.call_once(|| std::panic::set_hook(Box::new(|info| eprintln!("{info}"))));
    let desc = match vtu::read(data, "fuzz.vtu") {
        Ok(d) => d,
        Err(e) => {
            assert_eq!(e.file, "fuzz.vtu");
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
    // VoRANG's layout gives back the identical volume (docs/formats.md, "Writing .vtu").
    assert_eq!(again.mesh.nodes(), vol.mesh.nodes());
    assert_eq!(again.mesh.tets(), vol.mesh.tets());
    assert_eq!(again.coord_type, vol.coord_type);
    assert_eq!(again.edges, vol.edges);
    assert_eq!(again.data.raw, vol.data.raw);
    assert_eq!(again.data.fields.len(), vol.data.fields.len());
    for (f, g) in again.data.fields.iter().zip(&vol.data.fields) {
        assert_eq!(
            (&f.name, f.ty, f.interpolator, &f.sources),
            (&g.name, g.ty, g.interpolator, &g.sources)
        );
    }
});
