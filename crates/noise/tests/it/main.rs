//! natura-noise's integration tests: bases, fractals, footprints, level of detail, errata, bad input.
//!
//! One test binary for the crate's integration tests (one build and link
//! instead of one per file); each file below is a module, and
//! `cargo test -p natura-noise --test it -- <module>::` runs one of them.

mod bases;
mod common;
mod errata;
mod footprint;
mod footprint3;
mod fractal;
mod lod;
mod perlin;
mod robustness;
mod serde_round_trips;
mod simplex_bits;
mod worley_tables;
