//! Wave spectra: how the variance of the surface height is spread over wave
//! vectors, behind one trait, [`Spectrum`].
//!
//! * [`Phillips`]: Tessendorf's eq. 23 with the small-wave suppression of
//!   eq. 24 and a configurable directional exponent (Tessendorf 2001, §3.3-3.5).
//! * [`Directional`]: a frequency spectrum S(ω) ([`PiersonMoskowitz`],
//!   [`Jonswap`], [`Tma`]) times a directional spreading function
//!   ([`Spreading`]: Hasselmann et al. 1980 or a fixed cos-2s), converted to
//!   wave vectors through a dispersion relation. The sources only name
//!   JONSWAP on a slide ("Oceanography") with no constants; the standard
//!   oceanographic forms used here are **not from the sources** (Pierson &
//!   Moskowitz 1964, Hasselmann et al. 1973).
//!
//! ## Normalisation and direction (errata)
//!
//! A [`Spectrum`] returns a *density* P(k) in m⁴ (variance per unit of
//! wave-vector area) of waves **travelling along +k̂**. The ocean draws
//! amplitudes with E|h̃₀(k)|² = ½ P(k) Δk_x Δk_y, so that
//! E|h̃(k,t)|² = ½ (P(k) + P(−k)) Δk_x Δk_y and the expected height variance is
//! Σ_k P(k) Δk_x Δk_y ≈ ∫ P d²k, independent of grid size. The notes instead
//! set E|h̃₀|² = P (eq. 25) while defining P as E|h̃|² (eq. 22), which is off
//! by the factor 2 that E|h̃(k,t)|² = P(k) + P(−k) shows; with
//! their bare constant A that factor only rescaled the waves, but a
//! physical spectrum needs it right.
//!
//! Direction follows the slides' time sign e^{−iωt} ("FFT solution"), under
//! which the component at k travels along +k̂ (the notes' e^{+iωt}, eq. 26,
//! would make it travel along −k̂).

mod directional;
mod frequency;
mod phillips;

pub use directional::{Directional, Spreading};
pub use frequency::{FrequencySpectrum, Jonswap, PiersonMoskowitz, Tma};
pub use phillips::Phillips;

use glam::DVec2;

use crate::error::Result;

/// A directional wave spectrum: the variance density P(k) (m⁴) of waves
/// travelling along the unit vector k̂ = k/|k|.
///
/// Implement it to "roll your own" spectrum (Tessendorf 2001, §3.3). Implementations
/// must return a finite value ≥ 0 for every k, and 0 at k = 0.
pub trait Spectrum: Send + Sync + std::fmt::Debug {
    /// Returns P(k) in m⁴ for wave vector `k` (rad/m, x east, y north).
    fn density(&self, k: DVec2) -> f64;

    /// Checks the parameters; [`crate::Ocean::new`] calls this first.
    ///
    /// # Errors
    ///
    /// The implementation's error (for the built-in spectra,
    /// [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter)) naming the
    /// first parameter out of its range.
    fn validate(&self) -> Result<()>;
}

impl<S: Spectrum + ?Sized> Spectrum for &S {
    fn density(&self, k: DVec2) -> f64 {
        (**self).density(k)
    }
    fn validate(&self) -> Result<()> {
        (**self).validate()
    }
}

impl<S: Spectrum + ?Sized> Spectrum for Box<S> {
    fn density(&self, k: DVec2) -> f64 {
        (**self).density(k)
    }
    fn validate(&self) -> Result<()> {
        (**self).validate()
    }
}

/// Returns the unit vector at angle `radians` from +x toward +y.
#[inline]
pub(crate) fn direction(radians: f64) -> DVec2 {
    DVec2::new(radians.cos(), radians.sin())
}

/// Integrates `s` over the square |k_x|, |k_y| < `k_max` with `n × n` midpoint
/// cells; used by tests and to report a spectrum's total variance.
#[must_use]
pub fn integrate(s: &dyn Spectrum, k_max: f64, n: usize) -> f64 {
    let dk = 2.0 * k_max / n as f64;
    let mut sum = 0.0;
    for j in 0..n {
        let ky = -k_max + (j as f64 + 0.5) * dk;
        for i in 0..n {
            let kx = -k_max + (i as f64 + 0.5) * dk;
            sum += s.density(DVec2::new(kx, ky));
        }
    }
    sum * dk * dk
}
