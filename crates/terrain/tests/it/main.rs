//! natura-terrain's integration tests: synthesis, erosion properties, bad input.
//!
//! One test binary for the crate's integration tests (one build and link
//! instead of one per file); each file below is a module, and
//! `cargo test -p natura-terrain --test it -- <module>::` runs one of them.

mod properties;
mod robustness;
mod serde_round_trips;
mod synthesis;
