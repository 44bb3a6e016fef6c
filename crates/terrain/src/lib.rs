//! # natura-terrain
//!
//! Terrain synthesis, erosion and analysis on [`natura_core::HeightField`]s.
//!
//! * [`synth`]: Fournier–Fussell–Carpenter stochastic subdivision (1-D, polylines,
//!   triangle meshes, grid triangles / quads / diamond-square) with random numbers
//!   indexed by position, Poisson faulting, successive random additions, Fourier
//!   synthesis, and noise synthesis from any scalar field.
//! * [`erosion`]: Musgrave–Kolb–Mace hydraulic erosion in a corrected,
//!   mass-conserving form, thermal weathering with a talus angle, diffusive creep,
//!   Mei–Decaudin–Hu virtual-pipe shallow-water erosion, particle (droplet)
//!   erosion, and Braun–Willett implicit stream-power erosion with uplift and
//!   depression handling.
//! * [`analysis`]: slope, curvature, D8 and multiple-flow directions, flow
//!   accumulation, depression filling, drainage networks, wetness, hypsometry,
//!   and fractal statistics (spectral slope and variogram estimates of H).
//! * [`water`]: water bodies — a sea level, lakes filled to their spill
//!   points, connected water bodies, and a coast sunk below the sea at the
//!   border.
//! * [`export`]: 16-bit PNG / EXR height maps, flow and wetness images, and
//!   triangle meshes as binary glTF or OBJ.
//!
//! Conventions follow natura: z up, metres, `f32` grids, a `Params` struct per
//! model whose `Default` is its source's values and whose `validate()` refuses
//! out-of-range input, results bit-identical for a seed on any thread count,
//! long work reporting to a [`natura_core::Progress`].
//!
//! ```
//! use natura_terrain::Seed;
//! use natura_terrain::synth::{SubdivisionParams, subdivide};
//! let hf = subdivide(65, 65, 10.0, &SubdivisionParams::default(), Seed(1))?;
//! assert_eq!(hf.nx(), 65);
//! # Ok::<(), natura_terrain::TerrainError>(())
//! ```
// `unsafe` only where natura-simd's `multiversion!` calls the
// `#[target_feature]` functions it writes.
#![deny(unsafe_code)]

mod bands;
mod error;
mod fft;

pub mod analysis;
pub mod erosion;
pub mod export;
pub mod synth;
pub mod water;

pub use error::{Result, TerrainError};
/// The vector types of the API, so users need no `glam` dependency of their own.
pub use glam;
/// The height field every model works on, and the seed of the stochastic ones.
pub use natura_core::{HeightField, Seed};
