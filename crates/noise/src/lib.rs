//! # natura-noise
//!
//! Noise bases, fractional Brownian motion, multifractals and domain
//! distortion, after Musgrave's dissertation (Musgrave 1993, ch. 2 and 5), his
//! SIGGRAPH '89 paper (Musgrave et al. 1989, §3), his *Texturing & Modeling*
//! chapter (Musgrave 1998) and his SIGGRAPH 2001 course notes (Musgrave 2001).
//! `#![no_std]` with `libm`; no images, FFTs or threads.
//!
//! * **One trait**, [`Field`]: `&self` evaluation at `f64` 2-D/3-D points,
//!   analytic gradients, a value [`bound`](Field::bound) and Lipschitz
//!   constants (for ray marchers), and f32 batch fills of rows and regular
//!   lattices (SIMD with run-time dispatch: AVX-512, AVX2, SSE4.1, scalar),
//!   callable concurrently from rayon workers.
//! * **Bases** ([`basis`]): [`Perlin`] gradient noise (1-D to 4-D, quintic or
//!   the sources' cubic fade), [`Value`] noise (1-D to 4-D; "Linear"),
//!   [`Simplex`] (2-D, 3-D), [`Worley`] (F1–F4, F2−F1…, Euclidean, squared,
//!   Manhattan, Chebyshev; one feature point per cell or MojoWorld's random
//!   seed tables, [`FeaturePoints`]; exact search), [`SparseConvolution`], and
//!   Musgrave's [`Sine`], [`Steps`] and [`Checkerboard`]; all seeded by a hash
//!   of lattice position and seed (no 256-periodic table). Combinators:
//!   [`Ridged`], [`Abs`], [`Transform`].
//! * **Fractals** ([`fractal`]): [`Fbm`], [`Turbulence`], [`Multifractal`]
//!   (multiplicative cascade), [`HeteroTerrain`], [`HybridMultifractal`],
//!   [`RidgedMultifractal`], [`StatsByAltitude`] (and the legacy C `hfBm`),
//!   [`CrossoverFbm`], [`FilteredFbm`], and [`Driven`] (any parameter given by
//!   a field), parameterised by [`Spectral`] (H, lacunarity, real-valued
//!   octaves, frequency, amplitude convention) with precomputed octave weights;
//!   band-limited sums over a real-valued number of visible octaves
//!   ([`Fbm::eval3_band`], for level of detail by pixel footprint, the count
//!   given by the one footprint rule [`visible_octaves`]; [`FootprintFbm`],
//!   the world-unit fBm of a height field's detail with per-octave offsets,
//!   its gradient and the bounds a ray marcher needs), and
//!   Musgrave's vector multifractal [`VectorMultifractal`] (`MVfBm`).
//! * **Batches at arbitrary points**: [`Perlin::fill_points3`] and
//!   [`Fbm::fill_points3_band`] evaluate struct-of-arrays point lists (a
//!   sphere's hit points, a cube face) with the same SIMD dispatch as the rows.
//! * **Vector noise and distortion** ([`vector`], [`warp`]): [`DNoise`],
//!   [`VecNoise`], [`VectorFbm`], divergence-free [`CurlNoise`] ([`curl`]);
//!   [`DistNoise`], [`VlNoise`], and general [`Warped`] fields with
//!   [`Displace`] and [`Twist`] warps.
//!
//! Every type documents its source (document and section, as keyed in the
//! repository's `docs/sources.md`), the errors of the source it corrects,
//! its bound and its Lipschitz constant.
//!
//! ```
//! use natura_noise::{Field, Fbm, Perlin, Spectral, Lattice2};
//! use natura_noise::glam::DVec2;
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
#![no_std]
// `unsafe` only where natura-simd's `multiversion!` calls the
// `#[target_feature]` functions it writes.
#![deny(unsafe_code)]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

pub mod basis;
pub mod combinators;
pub mod curl;
mod error;
mod field;
pub mod fractal;
mod hash;
mod lattice_math;
pub mod vector;
pub mod warp;

pub use basis::Fade;
pub use basis::cellular::{FeaturePoints, Metric, Worley, WorleyFeature, WorleyParams};
pub use basis::checker::Checkerboard;
pub use basis::perlin::Perlin;
pub use basis::simplex::Simplex;
pub use basis::sine::Sine;
pub use basis::sparse::{SparseConvolution, SparseKernel, SparseParams};
pub use basis::steps::Steps;
pub use basis::value::{Value, ValueInterp};
pub use combinators::{Abs, Ridged, Transform};
pub use curl::CurlNoise;
pub use error::{NoiseError, Result};
pub use field::{Constant, Field, Lattice2, Lattice3};
pub use fractal::altitude::{StatsByAltitude, StatsByAltitudeLegacy, StatsByAltitudeParams};
pub use fractal::cascade::{CascadeForm, Multifractal, MultifractalParams};
pub use fractal::crossover::CrossoverFbm;
#[cfg(feature = "alloc")]
pub use fractal::driven::{Driven, DrivenKind, Param};
pub use fractal::fbm::{Fbm, Turbulence};
pub use fractal::filtered::{FilteredFbm, filter_fade};
pub use fractal::footprint::{FootprintFbm, FootprintParams};
pub use fractal::hetero::{HeteroTerrain, HeteroTerrainParams};
pub use fractal::hybrid::{HybridMultifractal, HybridParams};
pub use fractal::lod::visible_octaves;
pub use fractal::ridged::{RidgedMultifractal, RidgedParams};
pub use fractal::vector_multifractal::{VectorMultifractal, VectorMultifractalParams};
pub use fractal::{DEFAULT_LACUNARITY, GainConvention, MAX_BOUND, MAX_OCTAVES, Octaves, Spectral};
pub use natura_simd::{Simd, SimdLevel};
pub use vector::{DNoise, Smooth, VecNoise, VectorFbm, VectorField};
pub use warp::{Displace, DistNoise, Twist, TwistLaw, VlNoise, Warp, Warped};

/// The vector types of the API (`DVec2`, `DVec3`, …), so users need no
/// `glam` dependency of their own.
pub use glam;
