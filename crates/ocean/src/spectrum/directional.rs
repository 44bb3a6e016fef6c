//! Directional spectra: a frequency spectrum spread over directions and
//! converted to wave vectors (not from the sources: Pierson & Moskowitz 1964, Hasselmann
//! et al. 1973 and the spreading functions of oceanography).

use glam::DVec2;

use super::{FrequencySpectrum, Spectrum, direction};
use crate::dispersion::Dispersion;
use crate::error::{Result, finite, invalid, non_negative};

/// A directional spreading function D(ω, θ), normalised so ∫D dθ = 1 over
/// (−π, π], with θ the angle between the direction of travel and the wind.
///
/// Both variants use the cos-2s form N(s) cos^{2s}(θ/2),
/// N(s) = 2^{2s−1} Γ(s+1)² / (π Γ(2s+1)) (Longuet-Higgins et al. 1963), which
/// is 0 for waves travelling straight against the wind and largest along it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Spreading {
    /// A fixed spreading exponent s (≥ 0; larger is narrower).
    Cos2s {
        /// The exponent s.
        s: f64,
    },
    /// Hasselmann et al. (1980): s = 6.97 (ω/ω_p)^4.06 for ω ≤ ω_p and
    /// 9.77 (ω/ω_p)^{−2.33 − 1.45 (U/c_p − 1.17)} above, c_p = g/ω_p.
    /// Narrowest at the peak, broader for shorter and longer waves.
    #[default]
    Hasselmann,
}

/// ln N(s) for the cos-2s normalisation.
fn ln_norm(s: f64) -> f64 {
    (2.0 * s - 1.0) * std::f64::consts::LN_2 + 2.0 * libm::lgamma(s + 1.0)
        - std::f64::consts::PI.ln()
        - libm::lgamma(2.0 * s + 1.0)
}

impl Spreading {
    /// Returns the exponent s at frequency `omega` for a sea with peak `omega_p`,
    /// wind speed `wind` and gravity `g`.
    #[must_use]
    pub fn exponent(&self, omega: f64, omega_p: f64, wind: f64, g: f64) -> f64 {
        match *self {
            Spreading::Cos2s { s } => s,
            Spreading::Hasselmann => {
                let r = omega / omega_p;
                if r <= 1.0 {
                    6.97 * r.powf(4.06)
                } else {
                    let cp = g / omega_p;
                    9.77 * r.powf(-2.33 - 1.45 * (wind / cp - 1.17))
                }
            }
        }
    }

    /// Returns D = N(s) cos^{2s}(θ/2) for spreading exponent `s` and angle `theta` (radians).
    #[must_use]
    pub fn cos_2s(s: f64, theta: f64) -> f64 {
        let c = (0.5 * theta).cos().abs();
        if c == 0.0 {
            return if s == 0.0 {
                1.0 / std::f64::consts::TAU
            } else {
                0.0
            };
        }
        (ln_norm(s) + 2.0 * s * c.ln()).exp()
    }

    /// Checks the parameters.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter) for a negative or NaN spreading exponent.
    pub fn validate(&self) -> Result<()> {
        if let Spreading::Cos2s { s } = *self {
            non_negative("s", s)?;
        }
        Ok(())
    }
}

/// A frequency spectrum S(ω) spread over directions and expressed over wave
/// vectors: P(k) = S(ω(k)) D(ω, θ) (dω/dk) / k, m⁴.
///
/// The Jacobian (dω/dk)/k makes ∫P d²k = ∫S dω, so the height variance does
/// not depend on the grid. `dispersion` converts k to ω; use the same one for
/// the ocean's time evolution (finite depth with [`super::Tma`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Directional<F> {
    /// The frequency spectrum.
    pub spectrum: F,
    /// How energy spreads about the wind direction.
    pub spreading: Spreading,
    /// Wind direction, radians from +x toward +y.
    pub wind_direction: f64,
    /// Dispersion used to map k to ω.
    pub dispersion: Dispersion,
}

impl<F: FrequencySpectrum> Directional<F> {
    /// Returns the directional spectrum of `spectrum` with Hasselmann spreading
    /// about `wind_direction` in deep water.
    pub fn new(spectrum: F, wind_direction: f64) -> Self {
        Self {
            dispersion: Dispersion::Deep { g: spectrum.g() },
            spectrum,
            spreading: Spreading::Hasselmann,
            wind_direction,
        }
    }
}

impl<F: FrequencySpectrum> Spectrum for Directional<F> {
    fn density(&self, k: DVec2) -> f64 {
        let kk = k.length();
        if kk <= 0.0 {
            return 0.0;
        }
        let w = self.dispersion.omega(kk);
        let s_w = self.spectrum.s(w);
        if s_w <= 0.0 {
            return 0.0;
        }
        let wind = direction(self.wind_direction);
        let kh = k / kk;
        let theta = kh.perp_dot(wind).atan2(kh.dot(wind));
        let s = self.spreading.exponent(
            w,
            self.spectrum.peak_frequency(),
            self.spectrum.wind_speed(),
            self.spectrum.g(),
        );
        s_w * Spreading::cos_2s(s, theta) * self.dispersion.d_omega_dk(kk) / kk
    }

    fn validate(&self) -> Result<()> {
        self.spectrum.validate()?;
        self.spreading.validate()?;
        finite("wind_direction", self.wind_direction)?;
        self.dispersion.validate()?;
        // The Jacobian (dω/dk)/k can take the density over wave vectors past
        // f64 where S(ω) is finite (a wind of 10⁵² m/s; a capillary length
        // of 10¹⁸⁶ m): along the wind at eight wavenumbers a decade over
        // f64's whole range, with room for the peak between samples (the
        // density varies by less than 10⁶ over an eighth of a decade).
        let wind = direction(self.wind_direction);
        let out = (-2400..=2400).any(|j| {
            let k = 10f64.powf(f64::from(j) / 8.0);
            !(self.density(wind * k) * 1e6).is_finite()
        });
        if out {
            return Err(invalid(
                "wind_speed",
                self.spectrum.wind_speed(),
                "puts the spectrum's density over wave vectors outside f64's range",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::frequency::integrate_omega;
    use crate::spectrum::{Jonswap, PiersonMoskowitz, integrate};
    use approx::assert_relative_eq;

    #[test]
    fn spreading_is_normalised() {
        for s in [0.0, 0.5, 1.0, 3.7, 20.0, 150.0] {
            let n = 20_000;
            let dt = std::f64::consts::TAU / n as f64;
            let total: f64 = (0..n)
                .map(|i| Spreading::cos_2s(s, -std::f64::consts::PI + (i as f64 + 0.5) * dt))
                .sum::<f64>()
                * dt;
            assert_relative_eq!(total, 1.0, max_relative = 1e-7);
        }
    }

    #[test]
    fn less_energy_against_the_wind() {
        let d = Directional::new(Jonswap::default(), 0.3);
        let wind = direction(0.3);
        let wp = Jonswap::default().peak_frequency();
        for f in [0.7, 1.0, 1.5, 3.0] {
            let k = Dispersion::Deep { g: crate::G }.wavenumber(wp * f);
            let with = d.density(wind * k);
            let against = d.density(-wind * k);
            assert!(with > 0.0);
            assert!(against < 1e-6 * with, "{f}: {with} vs {against}");
            // Side-on is in between.
            let side = d.density(wind.perp() * k);
            assert!(side < with && side >= against);
        }
    }

    #[test]
    fn wave_vector_density_integrates_to_frequency_variance() {
        let pm = PiersonMoskowitz {
            wind_speed: 8.0,
            g: crate::G,
        };
        for spreading in [Spreading::Hasselmann, Spreading::Cos2s { s: 4.0 }] {
            let d = Directional {
                spreading,
                ..Directional::new(pm, 1.0)
            };
            let wp = pm.peak_frequency();
            let k_max = 12.0 * wp * wp / crate::G;
            let expected = integrate_omega(&pm, (crate::G * k_max).sqrt(), 200_000);
            let got = integrate(&d, k_max, 1500);
            assert_relative_eq!(got, expected, max_relative = 0.02);
        }
    }
}
