//! natura-trace's integration tests: exact hits against oracles, batches, cameras, detail.
//!
//! One test binary for the crate's integration tests (one build and link
//! instead of one per file); each file below is a module, and
//! `cargo test -p natura-trace --test it -- <module>::` runs one of them.

mod batch;
mod cameras;
mod common;
mod detail;
mod detail_octaves;
mod oracle;
mod pipeline;
mod properties;
