//! # natura-noise
//!
//! Noise bases, fractional Brownian motion, multifractals and domain
//! distortion, after Musgrave's dissertation and course notes (spec
//! `noise.md`; seeds 000, 001, 003, 004). `#![no_std]` with `libm`; no images,
//! FFTs or threads.
//!
//! * **One trait**, [`Field`]: `&self` evaluation at `f64` 2-D/3-D points,
//!   analytic gradients, a value [`bound`](Field::bound) and Lipschitz
//!   constants (for ray marchers), and f32 batch fills of rows and regular
//!   lattices (SIMD with run-time dispatch: AVX-512, AVX2, SSE4.1, scalar),
//!   callable concurrently from rayon workers.
//! * **Bases** ([`basis`]): [`Perlin`] gradient noise (1-D to 4-D).
//! * **Fractals** ([`fractal`]): [`Fbm`], [`Turbulence`], [`Multifractal`]
//!   (multiplicative cascade), [`HeteroTerrain`], [`HybridMultifractal`],
//!   [`RidgedMultifractal`], [`StatsByAltitude`], parameterised by
//!   [`Spectral`] (H, lacunarity, real-valued octaves, frequency) with
//!   precomputed octave weights.
//!
//! ```
//! use natura_noise::{Field, Fbm, Perlin, Spectral, Lattice2};
//! use glam::DVec2;
//! let terrain = Fbm::new(Perlin::new(42), Spectral::default().with_h(0.8).with_frequency(0.01))?;
//! let height = terrain.eval2(DVec2::new(120.0, -40.0));
//! let (_, slope) = terrain.eval_grad2(DVec2::new(120.0, -40.0));
//! let lattice = Lattice2::new(DVec2::ZERO, DVec2::ONE, 64, 64)?;
//! let mut grid = vec![0.0f32; lattice.len()];
//! terrain.fill_grid2(&lattice, &mut grid)?;
//! assert!((grid[0] as f64 - terrain.eval2(DVec2::ZERO)).abs() < 1e-5);
//! # let _ = (height, slope);
//! # Ok::<(), natura_noise::NoiseError>(())
//! ```
//!
//! Source keys: `[D]` Musgrave 1993 dissertation (seed 000), `[E89]` Musgrave,
//! Kolb & Mace 1989 (seed 001), `[T]` *Texturing & Modeling* ch. 15 (seed
//! 003), `[M]` SIGGRAPH 2001 course notes (seed 004), with line numbers.
#![no_std]
// `unsafe` is denied crate-wide; the only exceptions are the three calls into
// `#[target_feature]` trampolines in `simd::run`, each after CPU detection.
#![deny(unsafe_code)]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

pub mod basis;
pub mod combinators;
mod error;
mod field;
pub mod fractal;
mod hash;
mod simd;

pub use basis::Fade;
pub use basis::perlin::Perlin;
pub use combinators::{Abs, Ridged, Transform};
pub use error::{NoiseError, Result};
pub use field::{Constant, Field, Lattice2, Lattice3};
pub use fractal::altitude::{StatsByAltitude, StatsByAltitudeLegacy, StatsByAltitudeParams};
pub use fractal::cascade::{CascadeForm, Multifractal, MultifractalParams};
pub use fractal::fbm::{Fbm, Turbulence};
pub use fractal::hetero::{HeteroTerrain, HeteroTerrainParams};
pub use fractal::hybrid::{HybridMultifractal, HybridParams};
pub use fractal::ridged::{RidgedMultifractal, RidgedParams};
pub use fractal::{DEFAULT_LACUNARITY, GainConvention, MAX_OCTAVES, Octaves, Spectral};
pub use simd::{Simd, SimdLevel};
