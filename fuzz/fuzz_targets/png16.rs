//! Any bytes as a 16-bit PNG height map: a field or an error, never a panic,
//! an abort or an allocation beyond the memory cap.
#![no_main]

use libfuzzer_sys::fuzz_target;
use natura_core::HeightField;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let reader = std::io::Cursor::new(data);
    if let Ok(hf) = HeightField::read_png16(reader, Path::new("fuzz.png"), Some(1.0), Some((0.0, 1.0))) {
        assert!(hf.check_finite().is_ok());
    }
});
