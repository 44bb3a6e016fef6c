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

/// CRC-32 (ISO-HDLC) as PNG chunks use it.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xFFFF_FFFFu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG whose header claims `w × h` pixels of `depth` bits and colour type
/// `colour`, followed by a tiny (bogus) image-data chunk and the end chunk,
/// every chunk with a correct CRC.
fn png_with_header(w: u32, h: u32, depth: u8, colour: u8) -> Vec<u8> {
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8], data: &[u8]| {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc32(&body).to_be_bytes());
    };
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[depth, colour, 0, 0, 0]);
    chunk(b"IHDR", &ihdr);
    chunk(
        b"IDAT",
        &[0x78, 0x9c, 0x63, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01],
    );
    chunk(b"IEND", &[]);
    out
}

#[test]
fn huge_png_header_is_refused_before_allocating() {
    // 2^31 − 1 squared 16-bit pixels would be 9·10^18 bytes: the header alone
    // must be refused (before, the process aborted allocating it).
    let p = write_case(
        "png-huge",
        &png_with_header(0x7FFF_FFFF, 0x7FFF_FFFF, 16, 0),
    );
    let err = HeightField::load_png16(&p, Some(1.0), Some((0.0, 1.0))).unwrap_err();
    assert!(err.to_string().contains("cap"), "{err}");
}

/// A header within the memory cap whose file cannot hold its pixels (four
/// billion 8-bit pixels in a few dozen bytes; deflate compresses at most
/// 1032 to 1) is refused as truncated before its buffer is allocated (a
/// fuzzer's find: the buffer of several gigabytes was allocated and
/// filled first). The same header over a stream that cannot seek still
/// fails, when the decoder meets the end.
#[test]
fn a_png_too_short_for_its_header_is_refused_before_allocating() {
    let bytes = png_with_header(0xF300_0000, 1, 8, 0);
    let p = write_case("png-short", &bytes);
    let err = HeightField::load_png16(&p, Some(1.0), Some((0.0, 1.0))).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("truncated")
            && msg.contains("at least 3950450 compressed bytes")
            && msg.contains(&format!("holds {}", bytes.len())),
        "{msg}"
    );
    // A file whose stream would hold the pixels at deflate's best ratio is
    // not refused by this check (it fails later, on its bogus data).
    let small = png_with_header(1032 * 4, 1, 8, 0);
    let err = HeightField::load_png16(write_case("png-fits", &small), Some(1.0), Some((0.0, 1.0)))
        .unwrap_err();
    assert!(!err.to_string().contains("need at least"), "{err}");
}

/// Every byte of a height map's EXR with its lowest bit flipped: refused, or
/// the same field (the flip of the cell size's digit in the text attributes
/// was read as another cell size before their checksum).
#[test]
fn every_flipped_bit_of_an_exr_is_refused_or_harmless() {
    let f = fixture();
    let mut read = 0;
    for at in 0..f.exr.len() {
        let p = write_case("exr-flip", &corrupt(&f.exr, at, 1));
        if let Ok(hf) = HeightField::load_exr(&p, None) {
            assert!(hf == field(), "byte {at} changed the field silently");
            read += 1;
        }
    }
    // Some flips land where nothing is read (padding, unused fields).
    assert!(read > 0 && read < f.exr.len(), "{read}");
}

#[test]
fn a_colour_png_header_is_refused_before_its_pixels_are_allocated() {
    // 60 000² RGBA pixels of 16 bits: as a grid of f32 heights (14.4 GB)
    // within the cap, but the decoder's buffer would be 28.8 GB (before, the
    // process aborted allocating it).
    let p = write_case("png-rgba", &png_with_header(60_000, 60_000, 16, 6));
    let err = HeightField::load_png16(&p, Some(1.0), Some((0.0, 1.0))).unwrap_err();
    assert!(err.to_string().contains("greyscale"), "{err}");
}

#[cfg(unix)]
#[test]
fn endless_streams_are_refused_without_reading_them_whole() {
    let err = HeightField::load_raw("/dev/zero", 64, 64, 1.0).unwrap_err();
    assert!(err.to_string().contains("found more"), "{err}");
    assert!(HeightField::load_png16("/dev/zero", Some(1.0), Some((0.0, 1.0))).is_err());
    assert!(HeightField::load_exr("/dev/zero", Some(1.0)).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, .. ProptestConfig::default() })]

    /// Any header a PNG can carry (sizes up to 2^31 − 1, any depth and colour
    /// type byte) gives a typed error or a field, never a panic or an abort.
    #[test]
    fn random_png_headers_are_refused_or_read(
        w in prop_oneof![1u32..64, 1u32..0x7FFF_FFFF],
        h in prop_oneof![1u32..64, 1u32..0x7FFF_FFFF],
        depth in prop_oneof![Just(1u8), Just(2), Just(4), Just(8), Just(16), any::<u8>()],
        colour in prop_oneof![Just(0u8), Just(2), Just(3), Just(4), Just(6), any::<u8>()],
    ) {
        let p = write_case("png-header", &png_with_header(w, h, depth, colour));
        if let Ok(hf) = HeightField::load_png16(&p, Some(1.0), Some((0.0, 1.0))) {
            prop_assert!(hf.check_finite().is_ok());
        }
    }

    /// Raw files of any requested size: a wrong length is refused, sizes over
    /// the cap are refused before reading.
    #[test]
    fn random_raw_sizes_are_refused_or_read(nx in 0usize..1 << 40, ny in 0usize..1 << 40) {
        let f = fixture();
        let p = write_case("raw-size", &f.raw);
        let r = HeightField::load_raw(&p, nx, ny, 4.0);
        prop_assert_eq!(r.is_ok(), (nx, ny) == (19, 13));
    }
}
