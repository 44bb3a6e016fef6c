//! natura-core's integration tests: files (corrupt and exact bytes), the camera, the FFT plans, bad input.
//!
//! One test binary for the crate's integration tests (one build and link
//! instead of one per file); each file below is a module, and
//! `cargo test -p natura-core --test it -- <module>::` runs one of them.

mod camera;
mod corrupt_files;
mod exr_bytes;
mod fft;
mod robustness;
