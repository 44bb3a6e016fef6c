//! # natura-volume
//!
//! Density fields, Ebert's procedural clouds and gases, volume rendering
//! (a fast low-albedo march with shadow tables, a multiple-scattering
//! approximation, and an unbiased null-scattering path tracer as the
//! reference), and OpenVDB export.
//!
//! | module | what | source |
//! |---|---|---|
//! | [`density`] | the [`Density`] trait (density at a point, bounds for empty-space skipping), homogeneous slab and ball | |
//! | [`detail`] | any density eroded by noise octaves down to the pixel footprint, stirred by curl noise for wisps | Schneider 2015; Bridson et al. 2007, §2; Musgrave 1993, §6.3 |
//! | [`implicit`] | skeletal implicit primitives, the Wyvill blending function | Ebert 2001, "Volumetric Procedural Implicit Functions" |
//! | [`gas`] | noise and turbulence, shaping functions, basic gas, teacup steam, fog | Ebert 2001, slides "Basic gas procedure", "Steam rising from a teacup" |
//! | [`cloud`] | the cumulus procedure: cumulus, cirrus with jet stream, stratus, cirrostratus, mackerel sky | Ebert 2001, "Cloud Modeling" |
//! | [`animate`] | eased warps, "A Cloud is Born", implicit particle systems | Ebert 2001, "Animating Volumetric Procedural Clouds" |
//! | [`layer`] | layer clouds at kilometre scale for landscapes | Schneider 2015 |
//! | [`grid`] | voxel grids, baking, a fluid solver's smoke (density, temperature) | |
//! | [`transport`] | light transport: camera, medium, sun and sky from `natura-atmos`; Ebert's low-albedo march with 3-D shadow tables (direct shadow rays near the sun), multiple scattering (a photon cache of the sun's light, and of the light of the scene's ground, solids and glow, on a grid; or the octave approximation), the null-scattering reference path tracer | Ebert 2001, "Volume rendering"; Wrenninge et al. 2013; Lux & Koblinger 1991; Pharr et al. 2023, §14.1–14.2 |
//! | [`vdb`], [`export`] | OpenVDB float-grid writer and reader; raw and EXR slices | Museth 2013 |
//! | [`scene`] | presets: a layer-cloud sky over a plain at sunset, lit by `natura-atmos`; steam over a teacup; a solver's smoke round a sphere | Ebert 2001; Fedkiw et al. 2001 |
//! | [`phase`] | isotropic, Henyey–Greenstein, dual-lobe HG, HG + Draine cloud phase | Henyey & Greenstein 1941; Jendersie & d'Eon 2023 |
//!
//! Conventions: z up, metres; densities are dimensionless and scaled to
//! extinction by the medium's `extinction` (1/m per unit density), so a voxel
//! of density `ρ` and length `ℓ` transmits `exp(−σ·ρ·ℓ)`. (The smoke
//! renderer of Fedkiw et al. 2001, §5 prints the voxel transparency as
//! `exp(−C_ext·h)`, without the density; every transmittance here includes it.)
//!
//! ```
//! use natura_volume::{Density, cloud::{cloud, nine_sphere_cumulus, CloudParams}};
//! let c = cloud(nine_sphere_cumulus(), CloudParams::cumulus(), 7)?;
//! let d = c.density(natura_volume::glam::Vec3::new(0.0, 0.0, 2.0));
//! assert!((0.0..=1.0).contains(&d));
//! assert_eq!(c.density(natura_volume::glam::Vec3::splat(100.0)), 0.0);
//! # Ok::<(), natura_volume::VolumeError>(())
//! ```
// `unsafe` only where natura-simd's `multiversion!` calls the level it
// detected (the workspace denies it everywhere else).
#![deny(unsafe_code)]

pub mod animate;
pub mod cloud;
pub mod density;
pub mod detail;
mod error;
pub mod export;
pub mod gas;
pub mod grid;
pub mod implicit;
pub mod layer;
pub mod phase;
pub mod scene;
pub mod transport;
pub mod vdb;

pub use density::Density;
pub use error::{Result, VolumeError};
/// The vector types of the API, so users need no `glam` dependency of their own.
pub use glam;
