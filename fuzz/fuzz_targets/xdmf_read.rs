//! Any byte string given to the XDMF reader must give a description or an error naming the
//! file and a line — never a panic, a hang or an allocation out of proportion to the input.
//! (Data items in the XML are read; an HDF5 file it names is looked up beside `fuzz.xdmf`, in
//! the fuzzer's folder, and is normally missing: an error at the data item's line.)
#![no_main]

use libfuzzer_sys::fuzz_target;
use vorang::formats::{build, xdmf};

fuzz_target!(|data: &[u8]| {
    let desc = match xdmf::read(data, "fuzz.xdmf") {
        Ok(d) => d,
        Err(e) => {
            assert_eq!(e.file, "fuzz.xdmf");
            return;
        }
    };
    let Ok((vol, _)) = build::volume(desc) else { return };
    for n in 0..vol.data.fields.len() {
        let _ = vol.field_range(n);
    }
});
