//! Any bytes as a frame cache file (header, then clouds and plants), and
//! as the payload its header's hash vouches for: the frame's preparation
//! or an error naming the file; never a panic, and no allocation beyond
//! what the file's own bytes hold. A changed payload fails the hash, so
//! the payload's parser is also given the bytes directly.
#![no_main]

#[allow(dead_code)]
#[path = "../../cli/cache.rs"]
mod cache;
#[allow(dead_code)]
#[path = "../../cli/error.rs"]
mod error;
#[allow(dead_code)]
#[path = "../../cli/limits.rs"]
mod limits;
#[allow(dead_code)]
#[path = "../../cli/manifest.rs"]
mod manifest;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // The key the header must carry: the fuzzer finds it in the input's
    // first line after a `key ` prefix, or the checks stop at the header.
    let key = std::str::from_utf8(data)
        .ok()
        .and_then(|t| t.lines().find_map(|l| l.strip_prefix("key ")))
        .unwrap_or("k")
        .to_owned();
    let _ = cache::parse_frame_cache(data.to_vec(), &key, "fuzz.bin");
    let _ = cache::frame_from_bytes(data, std::path::Path::new("fuzz.bin"));
});
