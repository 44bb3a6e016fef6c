//! # natura
//!
//! Rust libraries that simulate and render nature, in the tradition of
//! Musgrave's fractal landscapes, Fournier–Fussell–Carpenter's stochastic
//! models, Tessendorf's ocean and Stam's stable fluids.
//!
//! This facade re-exports each natura crate as a module, each behind a
//! default-on feature of the same name; depend on the individual crates
//! (`natura-noise`, `natura-terrain`, …) to pull in less.
//!
//! | module | crate | what |
//! |---|---|---|
//! | [`core`] | `natura-core` | grids, height fields, images and colour, seeds, progress |
//! | `noise` | `natura-noise` | noise bases, fBm, multifractals, domain distortion |
//! | `terrain` | `natura-terrain` | terrain synthesis, erosion, analysis |
//! | `trace` | `natura-trace` | ray tracing of height fields, cameras |
//! | `atmos` | `natura-atmos` | aerial perspective, sky, spectral colour, rainbow, mirage |
//! | `ocean` | `natura-ocean` | FFT ocean waves, spectra, water optics |
//! | `fluid` | `natura-fluid` | stable fluids, smoke, liquids |
//! | `texture` | `natura-texture` | Musgrave's solid textures, procedural planets |
//! | `volume` | `natura-volume` | Ebert's clouds and gases, volume rendering, VDB export |
//! | `plant` | `natura-plant` | L-systems, turtle geometry, open L-systems |
//! | `render` | `natura-render` | scenes composing the crates into images |
//!
//! The package also installs the `natura` command-line tool (feature `cli`,
//! default-on): scenes rendered as deterministic tiles of frames that any
//! farm can run, their checked assembly, and Slurm and Open Job Description
//! job files (see `docs/farm.md` in the repository).
#![forbid(unsafe_code)]

#[cfg(feature = "core")]
pub use natura_core as core;

#[cfg(feature = "noise")]
pub use natura_noise as noise;

#[cfg(feature = "terrain")]
pub use natura_terrain as terrain;

#[cfg(feature = "trace")]
pub use natura_trace as trace;

#[cfg(feature = "atmos")]
pub use natura_atmos as atmos;

#[cfg(feature = "ocean")]
pub use natura_ocean as ocean;

#[cfg(feature = "fluid")]
pub use natura_fluid as fluid;

#[cfg(feature = "render")]
pub use natura_render as render;

#[cfg(feature = "texture")]
pub use natura_texture as texture;

#[cfg(feature = "plant")]
pub use natura_plant as plant;
#[cfg(feature = "volume")]
pub use natura_volume as volume;
