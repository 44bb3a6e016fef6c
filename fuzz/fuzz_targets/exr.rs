//! Any bytes as an EXR file: channels or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use natura_core::io::exr::read_exr_from;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(exr) = read_exr_from(std::io::Cursor::new(data), Path::new("fuzz.exr")) {
        for (_, values) in &exr.channels {
            assert_eq!(values.len(), exr.width * exr.height);
        }
    }
});
