//! # natura-atmos
//!
//! Aerial perspective, the physical sky, spectral colour, the rainbow and
//! mirages, after Musgrave's dissertation *Methods for Realistic Landscape
//! Imaging* (Musgrave 1993, ch. 4) and the SIGGRAPH 2001 course *Simulating
//! Nature* (Tessendorf 2001, Fedkiw et al. 2001), with the sources' errata
//! corrected (each stated where it is fixed) and the later physical models
//! (Nishita et al. 1993, Hillaire 2020, Jakob & Hanika 2019) added. The
//! bibliography is the repository's `docs/sources.md`.
//!
//! | module | what | source |
//! |---|---|---|
//! | [`medium`] | the [`Medium`] trait: homogeneous fog, exponential mist, exact radial (planetary) atmosphere, umbra | Musgrave 1993, §4.1.4–4.1.6.5 |
//! | [`scatter`] | Rayleigh, Henyey–Greenstein, Cornette–Shanks phase functions; physical Rayleigh coefficient | Musgrave 1993, §4.1.2; Fedkiw et al. 2001, §5, eq. 12 |
//! | [`sky`] | Rayleigh + Mie + ozone sky: Nishita ray marching, Hillaire LUTs, aerial perspective, sun disc | Nishita et al. 1993; Hillaire 2020 |
//! | [`spectrum`] | CIE 1931 CMFs, Wyman fit, XYZ → sRGB, Bradford, illuminants, sampling, upsampling, Musgrave's tables | Musgrave 1993, §4.2.4.1–4.2.4.2.2 |
//! | [`rainbow`] | Descartes paths, Fresnel, Cauchy water, the deviation/intensity table, empirical bow | Musgrave 1993, §4.2.3.3, §4.2.4.3.1–4.2.4.3.2 |
//! | [`mirage`] | Gladstone–Dale stratified air, adaptive RK ray paths, Musgrave's planar mirage with TIR | Musgrave 1993, §4.3–4.3.3 |
//! | [`optics`] | Snell, Fresnel, critical and Brewster angles, dispersion | Musgrave 1993, §4.2.3.1–4.2.3.3; Tessendorf 2001, §4.1–4.2 |
//! | [`simd`] | run-time SIMD dispatch for the batch sky lookups ([`sky::SkyView::radiance_batch`]) | |
//!
//! **Errata corrected** (each is documented where it is fixed): the radial
//! fog integral of eq. 4.1.13 uses signed along-line distances and gains
//! `√π/(2k)`, and is evaluated with `erfcx` so Earth-thin atmospheres show no
//! "ozone hole" ([`medium::RadialAtmosphere`]); eq. 4.1.5 is a mean
//! coefficient and is evaluated without cancellation
//! ([`medium::ExponentialMist`]); the 1 : 3 : 20 Rayleigh ratio is not the
//! λ⁻⁴ of its wavelengths ([`medium::RayleighRgb`]); a flat spectrum is not
//! sRGB white without adaptation ([`spectrum::bradford`]); the garbled linear
//! dispersion constant ([`optics::LinearAbbe`]); the course notes'
//! unnormalised Henyey–Greenstein and "Brewster" critical angle
//! ([`scatter`], [`optics`]).
//!
//! Conventions: world frame z up, metres, radians, wavelengths in vacuum
//! nanometres; `f64` for every integral, `f32` linear RGB on the per-pixel
//! paths ([`sky::SkyView`]). Directions are [`Dir3`]s, which can only be
//! built by normalising a finite non-zero vector. Bad input returns
//! [`AtmosError`]; nothing panics on user input.
//!
//! ```
//! use natura_atmos::glam::DVec3;
//! use natura_atmos::{Dir3, Medium, medium::ExponentialMist};
//! // Musgrave's mist with his Rayleigh-ish extinction vector: distant ridges go blue.
//! let mist = ExponentialMist::new(
//!     natura_atmos::medium::RayleighRgb::musgrave_1_3_20(2e-5),
//!     DVec3::new(0.6, 0.7, 0.9),
//!     0.0,
//!     1500.0,
//! )?;
//! let eye = DVec3::new(0.0, 0.0, 500.0);
//! let ridge = mist.composite(eye, DVec3::new(30_000.0, 0.0, 800.0), DVec3::splat(0.1));
//! assert!(ridge.z > ridge.x);
//! // A horizontal ray has the exact limit, not a division by zero.
//! let flat = mist.optical_depth(eye, DVec3::new(1000.0, 0.0, 500.0));
//! assert!(flat.is_finite());
//! # let _ = Dir3::UP;
//! # Ok::<(), natura_atmos::AtmosError>(())
//! ```
#![forbid(unsafe_code)]

mod dir;
mod error;
pub mod medium;
pub mod mirage;
pub mod optics;
pub mod rainbow;
pub mod scatter;
/// Run-time SIMD dispatch (natura-core's, re-exported): the [`simd::Simd`]
/// token the `*_batch_with` methods take.
pub use natura_core::simd;
pub mod sky;
pub mod special;
pub mod spectrum;

pub use dir::Dir3;
pub use error::{AtmosError, Result};
/// The vector types of the API, so users need no `glam` dependency of their own.
pub use glam;
pub use medium::{Attenuation, Medium};
