//! natura-volume's integration tests: densities, the renderer against its references, VDB files, bad input.
//!
//! One test binary for the crate's integration tests (one build and link
//! instead of one per file); each file below is a module, and
//! `cargo test -p natura-volume --test it -- <module>::` runs one of them.

mod cloudscape;
mod cloudscape_fit;
mod common;
mod density;
mod detail;
mod detail_sharpness;
mod limits;
mod near_sun;
mod octave_fit;
mod render;
mod scatter_matrix;
mod shadows;
mod sky_light;
mod substeps;
mod supersample;
mod vdb;
