//! Any byte string given to the VTKHDF reader (and so to the HDF5 layer the XDMF reader shares)
//! must give a description or an error naming the file — never a panic, a hang or an
//! allocation out of proportion to the input. A description that builds is a volume whose
//! fields have ranges.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vorang::formats::{build, read_description};

fuzz_target!(|data: &[u8]| {
    // The registry's entry: partitions read and merged, step 0.
    let mut bytes = vorang::formats::hdf::MAGIC.to_vec();
    bytes.extend_from_slice(data.get(8..).unwrap_or_default());
    let desc = match read_description(&bytes, "fuzz.vtkhdf") {
        Ok(d) => d,
        Err(e) => {
            assert_eq!(e.file, "fuzz.vtkhdf");
            return;
        }
    };
    let Ok((vol, _)) = build::volume(desc) else { return };
    for n in 0..vol.data.fields.len() {
        let _ = vol.field_range(n);
    }
});
