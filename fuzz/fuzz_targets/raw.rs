//! Any bytes and any requested size as a raw f32 height map: a finite field
//! of exactly that size, or an error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use natura_core::HeightField;
use std::path::Path;

fuzz_target!(|input: (u32, u32, &[u8])| {
    let (nx, ny, data) = input;
    if let Ok(hf) = HeightField::from_raw_bytes(data, Path::new("fuzz.raw"), nx as usize, ny as usize, 1.0) {
        assert_eq!(hf.nx() * hf.ny() * 4, data.len());
        assert!(hf.check_finite().is_ok());
    }
});
