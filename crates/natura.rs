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
//! ## Paths
//!
//! Each module *is* its crate, so every item has the same path below it:
//! `natura_core::HeightField` is `natura::core::HeightField`,
//! `natura_noise::Fbm` is `natura::noise::Fbm`, and
//! `natura_plant::mesh::save_glb` is `natura::plant::mesh::save_glb` (also
//! `natura::plant::save_glb`). The crates' own documentation and examples use
//! the crate names; replace `natura_xyz::` with `natura::xyz::` to use them
//! through this facade. The vector types are [`glam`](https://docs.rs/glam)'s,
//! re-exported by every crate (`natura::core::glam`, `natura::noise::glam`, …),
//! so a project needs no `glam` dependency of its own.
//!
//! ## Example
//!
//! fBm noise sampled on a grid and written as a picture:
//!
//! ```
//! use natura::core::{Grid2, Image, Ramp};
//! use natura::noise::glam::DVec2;
//! use natura::noise::{Fbm, Field, Lattice2, Perlin, Spectral};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let fbm = Fbm::new(Perlin::new(42), Spectral::default().with_frequency(1.0 / 16.0))?;
//! let lattice = Lattice2::new(DVec2::ZERO, DVec2::ONE, 64, 48)?;
//! let mut values = vec![0.0f32; lattice.len()];
//! fbm.fill_grid2(&lattice, &mut values)?;
//! assert!(values.iter().all(|v| v.is_finite()));
//!
//! let image = Image::false_colour_auto(&Grid2::from_vec(64, 48, values)?, Ramp::Terrain);
//! let path = std::env::temp_dir().join(format!("natura-facade-{}.png", std::process::id()));
//! image.save_png(&path)?;
//! assert_eq!(Image::load_png(&path)?.width(), 64);
//! std::fs::remove_file(&path)?;
//! # Ok(())
//! # }
//! ```
//!
//! ## The guide
//!
//! The user guide, `docs/guide/` in the repository
//! (<https://github.com/natura-rs/natura/tree/main/docs/guide>), has one
//! chapter per job, each a complete program using these paths; every one of
//! its programs runs as a test of this crate.
//!
//! The package also installs the `natura` command-line tool (feature `cli`,
//! default-on): scenes rendered as deterministic tiles of frames that any
//! farm can run, their checked assembly, and Slurm and Open Job Description
//! job files (see `docs/farm.md` in the repository).
#![forbid(unsafe_code)]

// The guide's chapters, whose every Rust block runs as a doc test of this
// crate (`cargo test --doc -p natura`).
#[cfg(all(doctest, feature = "core"))]
#[doc = include_str!("../docs/guide/README.md")]
mod guide_readme {}
#[cfg(all(doctest, feature = "core", feature = "noise"))]
#[doc = include_str!("../docs/guide/noise.md")]
mod guide_noise {}
#[cfg(all(doctest, feature = "terrain"))]
#[doc = include_str!("../docs/guide/terrain.md")]
mod guide_terrain {}
#[cfg(all(doctest, feature = "plant"))]
#[doc = include_str!("../docs/guide/plants.md")]
mod guide_plants {}
#[cfg(all(doctest, feature = "ocean"))]
#[doc = include_str!("../docs/guide/ocean.md")]
mod guide_ocean {}
#[cfg(all(doctest, feature = "render"))]
#[doc = include_str!("../docs/guide/render.md")]
mod guide_render {}
#[cfg(all(doctest, feature = "atmos"))]
#[doc = include_str!("../docs/guide/sky.md")]
mod guide_sky {}
#[cfg(all(doctest, feature = "fluid"))]
#[doc = include_str!("../docs/guide/fluids.md")]
mod guide_fluids {}
#[cfg(all(doctest, feature = "volume"))]
#[doc = include_str!("../docs/guide/clouds.md")]
mod guide_clouds {}
#[cfg(all(doctest, feature = "texture"))]
#[doc = include_str!("../docs/guide/textures.md")]
mod guide_textures {}

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
