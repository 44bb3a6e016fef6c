//! natura-texture's integration tests: textures, planets, footprints, errata, bad input.
//!
//! One test binary for the crate's integration tests (one build and link
//! instead of one per file); each file below is a module, and
//! `cargo test -p natura-texture --test it -- <module>::` runs one of them.

mod common;
mod errata;
mod footprint;
mod limits;
mod planet;
mod planet_look;
mod serde_round_trips;
mod textures;
