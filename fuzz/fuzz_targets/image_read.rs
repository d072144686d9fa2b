//! Any byte string given to VoRANG's own image readers (`src/framebuffer/codec/`: every format in
//! the output table that `background` reads itself) must give an image whose pixel count matches
//! its size, or an error message — never a panic, a hang or an allocation out of proportion to
//! the input.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vorang::framebuffer::{FORMATS, Read};

fuzz_target!(|data: &[u8]| {
    for format in FORMATS {
        if let Read::Own(read) = format.read {
            match read(data) {
                Ok(img) => assert_eq!(img.rgb.len(), img.width * img.height),
                Err(e) => assert!(!e.is_empty()),
            }
        }
    }
});
