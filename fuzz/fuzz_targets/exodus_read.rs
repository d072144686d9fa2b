//! Any byte string given to the Exodus II reader (netCDF classic or netCDF-4/HDF5) must give a
//! description or an error naming the file — never a panic, a hang or an allocation out of
//! proportion to the input. A description that builds is a volume whose fields have ranges.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vorang::formats::{build, exodus};

fuzz_target!(|data: &[u8]| {
    let desc = match exodus::read(data, "fuzz.exo") {
        Ok(d) => d,
        Err(e) => {
            assert_eq!(e.file, "fuzz.exo");
            return;
        }
    };
    let Ok((vol, _)) = build::volume(desc) else { return };
    for n in 0..vol.data.fields.len() {
        let _ = vol.field_range(n);
    }
});
