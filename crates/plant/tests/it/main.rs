//! natura-plant's integration tests: L-systems from the book, the turtle, meshes, bad input.
//!
//! One test binary for the crate's integration tests (one build and link
//! instead of one per file); each file below is a module, and
//! `cargo test -p natura-plant --test it -- <module>::` runs one of them.

mod abop;
mod errors;
mod hostile;
mod memory;
mod mesh;
mod open;
mod phyllotaxis;
mod turtle;
