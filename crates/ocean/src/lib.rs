//! # natura-ocean
//!
//! Ocean waves after Jerry Tessendorf's *Simulating Ocean Water* (Tessendorf 2001,
//! notes and slides in the SIGGRAPH 2001 course *Simulating Nature*): random
//! wave spectra evolved in closed form and summed by FFT on a periodic
//! patch, with slopes, choppy displacement, the Jacobian and its folds, foam,
//! normals, Gerstner waves and the optics of the water surface.
//!
//! ```
//! use natura_ocean::{Ocean, OceanParams, Phillips, Seed};
//! let params = OceanParams { nx: 64, ny: 64, lx: 200.0, ly: 200.0, choppiness: 1.0, ..OceanParams::default() };
//! let spectrum = Phillips { wind_speed: 12.0, small_wave_length: 0.1, ..Phillips::default() };
//! let ocean = Ocean::new(&params, &spectrum, Seed(7))?;
//! let mut frame = ocean.evaluate(0.0)?;
//! ocean.evaluate_into(1.5, &mut frame)?; // no allocation
//! let h = frame.height();
//! assert!(h.mean().abs() < 1e-4);
//! # Ok::<(), natura_ocean::OceanError>(())
//! ```
//!
//! ## Modules
//!
//! | item | what | source |
//! |---|---|---|
//! | [`spectrum`] | [`Phillips`], [`PiersonMoskowitz`], [`Jonswap`], [`Tma`], [`Spreading`] | eqs. 23-24; Pierson & Moskowitz 1964, Hasselmann et al. 1973 |
//! | [`dispersion`] | deep, finite depth, capillary, quantised (looping) | eqs. 14-18 |
//! | [`Ocean`], [`Frame`] | height, slope, choppy displacement, Jacobian, normals | eqs. 19-36 |
//! | [`foam`] | whitecaps accumulated from the Jacobian | beyond the notes |
//! | [`surface`] | periodic bilinear sampler at world (x, y) | |
//! | [`cascade`] | 2-3 patches with split spectral bands | beyond the notes |
//! | [`gerstner`] | sums of Gerstner waves with steepness checks | eqs. 9-13 |
//! | [`optics`] | Fresnel, reflect/refract, critical angle, water shading | eqs. 37-45, §4.3 |
//! | [`export`] | EXR maps and frame sequences | |
//! | [`preview`] | false-colour maps and a shaded top view (the example's pictures) | fig. 7 |
//! | [`reference`](mod@reference) | the straightforward one-FFT-per-field evaluation (oracle, baseline) | |
//!
//! ## Conventions and errata
//!
//! * **z up.** The notes are y-up with horizontal (x, z); here horizontal is
//!   (x, y) and height is z. Units are metres, seconds, radians.
//! * **Time sign** e^{−iωt} (the slides' "FFT solution"), so a spectrum's P(k) is energy
//!   travelling along +k̂; the notes' eq. 26 has the opposite sign.
//! * **Variance**: E|h̃(k,t)|² = ½(P(k) + P(−k)) Δk², not P(k) as eq. 22
//!   implies (see [`spectrum`]).
//! * **Nyquist** row and column are zeroed, so every field is real.
//! * **Choppy sign**: eq. 29 with x + λD folds troughs, not crests;
//!   [`OceanParams::choppiness`] is −λ so crests sharpen.
//! * **Eq. 42** (refraction) has the wrong overall sign; [`optics::refract`]
//!   uses the corrected form.
//! * **"Brewster's angle"** (§4.2) is the critical angle, 48.6° from the
//!   normal (41.4° from the surface, not 41.1°): [`optics::critical_angle`].
#![forbid(unsafe_code)]

pub mod cascade;
pub mod dispersion;
mod error;
pub mod export;
mod fastmath;
mod fft;
pub mod foam;
mod frame;
pub mod gerstner;
pub mod optics;
mod patch;
pub mod preview;
pub mod reference;
pub mod spectrum;
pub mod surface;

pub use cascade::{Cascade, CascadeFrame};
pub use dispersion::{Dispersion, DispersionRelation, G, Quantized};
pub use error::{OceanError, Result};
/// The vector types of the API, so users need no `glam` dependency of their own.
pub use glam;

pub use foam::{Foam, FoamParams, whitecap_coverage};
pub use frame::{Frame, FrameField, JacobianEigen, normal_from};

pub use gerstner::{GerstnerSea, GerstnerWave};
pub use patch::{
    AmplitudeScheme, DirectSample, MAX_CHOPPINESS, MAX_FIELD_BOUND, MAX_LENGTH, MAX_SIZE,
    MIN_LENGTH, MIN_SIZE, Ocean, OceanParams,
};
pub use spectrum::{
    Directional, FrequencySpectrum, Jonswap, Phillips, PiersonMoskowitz, Spectrum, Spreading, Tma,
};
pub use surface::{Surface, WaterSurface};

/// Re-export of natura-core's seed type.
pub use natura_core::Seed;
/// Re-export of the complex type used for spectra.
pub use natura_core::fft::Complex;
