//! natura-render's integration tests: scenes, forests, sky, detail, regions, stray pixels, the main job's reference picture.
//!
//! One test binary for the crate's integration tests (one build and link
//! instead of one per file); each file below is a module, and
//! `cargo test -p natura-render --test it -- <module>::` runs one of them.

mod common;
mod detail;
mod forest;
mod forest_far;
mod quickstart;
mod reference_picture;
mod region;
mod render;
mod scene_edits;
mod scene_text;
mod scene_values;
mod seed_sweep;
mod sky;
mod stray_pixels;
mod surface_snow_water;
mod terraces;
