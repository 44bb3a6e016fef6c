//! natura-ocean's integration tests: fields, frames, bad input.
//!
//! One test binary for the crate's integration tests (one build and link
//! instead of one per file); each file below is a module, and
//! `cargo test -p natura-ocean --test it -- <module>::` runs one of them.

mod fields;
mod frames;
mod robustness;
