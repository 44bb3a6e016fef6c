//! Corrupt or truncated height-map files are refused with an error, never a panic.

use natura_core::HeightField;
use proptest::prelude::*;
use std::path::PathBuf;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("natura-core-corrupt-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn field() -> HeightField {
    HeightField::from_fn(19, 13, 4.0, |i, j| {
        (i * i) as f32 * 0.7 - (j as f32 * 0.9).sin() * 30.0 + 500.0
    })
    .unwrap()
}

struct Fixture {
    png: Vec<u8>,
    exr: Vec<u8>,
    raw: Vec<u8>,
}

fn fixture() -> &'static Fixture {
    static F: std::sync::OnceLock<Fixture> = std::sync::OnceLock::new();
    F.get_or_init(|| {
        let hf = field();
        let d = dir();
        let (png, exr, raw) = (d.join("f.png"), d.join("f.exr"), d.join("f.raw"));
        hf.save_png16(&png, hf.min_max()).unwrap();
        hf.save_exr(&exr).unwrap();
        hf.save_raw(&raw).unwrap();
        Fixture {
            png: std::fs::read(png).unwrap(),
            exr: std::fs::read(exr).unwrap(),
            raw: std::fs::read(raw).unwrap(),
        }
    })
}

fn write_case(tag: &str, bytes: &[u8]) -> PathBuf {
    // One file per case and thread: proptest cases run sequentially per test,
    // but the three tests run in parallel.
    let p = dir().join(format!("case-{tag}-{:?}", std::thread::current().id()));
    std::fs::write(&p, bytes).unwrap();
    p
}

fn corrupt(bytes: &[u8], at: usize, xor: u8) -> Vec<u8> {
    let mut b = bytes.to_vec();
    let i = at % b.len();
    b[i] ^= xor;
    b
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, .. ProptestConfig::default() })]

    /// PNG chunks carry CRC-32s and the image data an Adler-32, so every single-byte
    /// corruption and every truncation is detected.
    #[test]
    fn png_corruption_is_refused(at in any::<usize>(), xor in 1u8..=255, cut in any::<usize>()) {
        let f = fixture();
        let p = write_case("png", &corrupt(&f.png, at, xor));
        prop_assert!(HeightField::load_png16(&p, None, None).is_err(), "corrupt byte {} accepted", at % f.png.len());
        let p = write_case("png-cut", &f.png[..cut % f.png.len()]);
        prop_assert!(HeightField::load_png16(&p, None, None).is_err());
    }

    /// EXR has no checksum of its own; natura's files carry one over the pixels,
    /// so a corruption is either refused or lands in bytes that do not change the
    /// data (padding, unknown attributes). Truncation is always refused.
    #[test]
    fn exr_corruption_is_refused_or_harmless(at in any::<usize>(), xor in 1u8..=255, cut in any::<usize>()) {
        let f = fixture();
        let p = write_case("exr", &corrupt(&f.exr, at, xor));
        if let Ok(hf) = HeightField::load_exr(&p, None) {
            prop_assert_eq!(hf, field(), "corrupt byte {} changed the data silently", at % f.exr.len());
        }
        let p = write_case("exr-cut", &f.exr[..cut % f.exr.len()]);
        prop_assert!(HeightField::load_exr(&p, None).is_err());
    }

    /// Raw files have no header or checksum: truncation is refused; a corrupt byte
    /// cannot be detected unless it makes a non-finite value, which is refused.
    #[test]
    fn raw_truncation_is_refused(at in any::<usize>(), xor in 1u8..=255, cut in any::<usize>()) {
        let f = fixture();
        let p = write_case("raw", &corrupt(&f.raw, at, xor));
        if let Ok(hf) = HeightField::load_raw(&p, 19, 13, 4.0) {
            prop_assert!(hf.check_finite().is_ok());
        }
        let p = write_case("raw-cut", &f.raw[..cut % f.raw.len()]);
        prop_assert!(HeightField::load_raw(&p, 19, 13, 4.0).is_err());
    }
}

#[test]
fn non_finite_raw_value_is_named() {
    let f = fixture();
    let mut b = f.raw.clone();
    b[8..12].copy_from_slice(&f32::NAN.to_le_bytes());
    let p = write_case("raw-nan", &b);
    let err = HeightField::load_raw(&p, 19, 13, 4.0)
        .unwrap_err()
        .to_string();
    // Third value of the first stored row = cell (2, 12): rows are stored north first.
    assert!(err.contains("(2, 12)"), "{err}");
}

#[test]
fn huge_exr_header_is_refused_before_allocating() {
    // A valid tiny file with its data window widened to 2^30 × 2^30 must be
    // refused from the header, not by running out of memory.
    let f = fixture();
    let key = b"dataWindow\0box2i\0";
    let pos = f
        .exr
        .windows(key.len())
        .position(|w| w == key)
        .expect("dataWindow attribute");
    let mut b = f.exr.clone();
    let val = pos + key.len() + 4; // skip the attribute size
    b[val + 8..val + 12].copy_from_slice(&(1i32 << 30).to_le_bytes()); // xMax
    b[val + 12..val + 16].copy_from_slice(&(1i32 << 30).to_le_bytes()); // yMax
    let p = write_case("exr-huge", &b);
    assert!(HeightField::load_exr(&p, None).is_err());
}
