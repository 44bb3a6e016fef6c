//! Frequency spectra S(ω) of oceanography: Pierson–Moskowitz, JONSWAP and
//! TMA. **Not from the sources**: the course only names JONSWAP on a slide,
//! with no constants (Tessendorf 2001, slides "Oceanography"); the forms and
//! constants here are the standard ones (Pierson & Moskowitz 1964; Hasselmann et al. 1973, Bouws et al. 1985).

use crate::dispersion::G;
use crate::error::{Result, invalid, positive};

/// Refuses a wind (`name` = `value`, `reason` saying why) whose spectrum
/// has a scale outside f64's range: each of `scales` must be finite and
/// positive. Such winds are hundreds of orders of magnitude from any sea,
/// and their spectra were NaN (a vanishing wind puts the peak frequency at
/// infinity).
fn scales_in_range(
    name: &'static str,
    value: impl std::fmt::Display,
    reason: &'static str,
    scales: &[f64],
) -> Result<()> {
    if scales.iter().all(|s| s.is_finite() && *s > 0.0) {
        Ok(())
    } else {
        Err(invalid(name, value, reason))
    }
}

/// A one-sided frequency spectrum S(ω), m²·s: the height variance per unit of
/// angular frequency. [`super::Directional`] spreads it over directions.
pub trait FrequencySpectrum: Send + Sync + std::fmt::Debug {
    /// Returns S(ω) in m²·s for angular frequency `omega` (rad/s); 0 for ω ≤ 0.
    fn s(&self, omega: f64) -> f64;
    /// Returns the peak angular frequency ω_p, rad/s.
    fn peak_frequency(&self) -> f64;
    /// Returns the wind speed the spectrum is built from, m/s.
    fn wind_speed(&self) -> f64;
    /// Returns gravity, m/s².
    fn g(&self) -> f64;
    /// Checks the parameters.
    ///
    /// # Errors
    ///
    /// The implementation's error (for the built-in spectra,
    /// [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter)) naming the
    /// first parameter out of its range.
    fn validate(&self) -> Result<()>;
}

/// Pierson–Moskowitz (1964) spectrum of a fully developed sea:
/// S(ω) = α g² ω⁻⁵ exp(−β (ω₀/ω)⁴), α = 0.0081, β = 0.74, ω₀ = g/U₁₉.₅.
///
/// Its variance is α U⁴/(4 β g²), so the significant wave height
/// 4σ ≈ 0.21 U²/g.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct PiersonMoskowitz {
    /// Wind speed U₁₉.₅ at 19.5 m above the sea, m/s (> 0).
    pub wind_speed: f64,
    /// Gravity, m/s².
    pub g: f64,
}

impl Default for PiersonMoskowitz {
    fn default() -> Self {
        Self {
            wind_speed: 10.0,
            g: G,
        }
    }
}

/// Phillips' constant of Pierson–Moskowitz.
pub(crate) const PM_ALPHA: f64 = 0.0081;
const PM_BETA: f64 = 0.74;

impl PiersonMoskowitz {
    /// Returns the height variance α U⁴/(4 β g²) in closed form, m².
    #[must_use]
    pub fn variance(&self) -> f64 {
        PM_ALPHA * self.wind_speed.powi(4) / (4.0 * PM_BETA * self.g * self.g)
    }
}

impl FrequencySpectrum for PiersonMoskowitz {
    fn s(&self, omega: f64) -> f64 {
        if omega <= 0.0 {
            return 0.0;
        }
        let w0 = self.g / self.wind_speed;
        // Zero where the exponential underflows (below ω₀/5.6), before ω⁻⁵
        // can overflow: 0 · ∞ was NaN.
        let e = (-PM_BETA * (w0 / omega).powi(4)).exp();
        if e == 0.0 {
            return 0.0;
        }
        PM_ALPHA * self.g * self.g / omega.powi(5) * e
    }
    fn peak_frequency(&self) -> f64 {
        self.g / self.wind_speed * (0.8 * PM_BETA).powf(0.25)
    }
    fn wind_speed(&self) -> f64 {
        self.wind_speed
    }
    fn g(&self) -> f64 {
        self.g
    }
    fn validate(&self) -> Result<()> {
        positive("wind_speed", self.wind_speed)?;
        positive("g", self.g)?;
        // ω₀ and the ω⁻⁵ factor where the exponential leaves f64 (ω₀/6).
        let w0 = self.g / self.wind_speed;
        let level = PM_ALPHA * self.g * self.g / (w0 / 6.0).powi(5);
        scales_in_range(
            "wind_speed",
            self.wind_speed,
            "puts the spectrum's peak or level outside f64's range",
            &[w0, level, self.variance()],
        )
    }
}

/// JONSWAP spectrum of a fetch-limited sea (Hasselmann et al. 1973):
/// S(ω) = α g² ω⁻⁵ exp(−5/4 (ω_p/ω)⁴) γ^r, r = exp(−(ω−ω_p)²/(2σ²ω_p²)),
/// with α = 0.076 (U₁₀²/(F g))^0.22 and ω_p = 22 (g²/(U₁₀ F))^{1/3}.
///
/// γ = 1 gives back the Pierson–Moskowitz shape; the default γ = 3.3 sharpens
/// the peak. σ = 0.07 below the peak and 0.09 above.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct Jonswap {
    /// Wind speed U₁₀ at 10 m, m/s (> 0).
    pub wind_speed: f64,
    /// Fetch F (distance over which the wind has blown), metres (> 0).
    pub fetch: f64,
    /// Peak enhancement γ (≥ 1 in practice; > 0 required).
    pub gamma: f64,
    /// Peak width σ for ω ≤ ω_p.
    pub sigma_low: f64,
    /// Peak width σ for ω > ω_p.
    pub sigma_high: f64,
    /// Gravity, m/s².
    pub g: f64,
}

impl Default for Jonswap {
    fn default() -> Self {
        Self {
            wind_speed: 10.0,
            fetch: 100_000.0,
            gamma: 3.3,
            sigma_low: 0.07,
            sigma_high: 0.09,
            g: G,
        }
    }
}

impl Jonswap {
    /// Returns the fetch-dependent Phillips constant α = 0.076 (U²/(F g))^0.22.
    #[must_use]
    pub fn alpha(&self) -> f64 {
        0.076 * (self.wind_speed * self.wind_speed / (self.fetch * self.g)).powf(0.22)
    }
}

impl FrequencySpectrum for Jonswap {
    fn s(&self, omega: f64) -> f64 {
        if omega <= 0.0 {
            return 0.0;
        }
        let wp = self.peak_frequency();
        let sigma = if omega <= wp {
            self.sigma_low
        } else {
            self.sigma_high
        };
        let d = omega - wp;
        let r = (-d * d / (2.0 * sigma * sigma * wp * wp)).exp();
        // Zero where the exponential underflows (below ω_p/4.9), before ω⁻⁵
        // can overflow: 0 · ∞ was NaN.
        let e = (-1.25 * (wp / omega).powi(4)).exp();
        if e == 0.0 {
            return 0.0;
        }
        self.alpha() * self.g * self.g / omega.powi(5) * e * self.gamma.powf(r)
    }
    fn peak_frequency(&self) -> f64 {
        22.0 * (self.g * self.g / (self.wind_speed * self.fetch)).cbrt()
    }
    fn wind_speed(&self) -> f64 {
        self.wind_speed
    }
    fn g(&self) -> f64 {
        self.g
    }
    fn validate(&self) -> Result<()> {
        positive("wind_speed", self.wind_speed)?;
        positive("fetch", self.fetch)?;
        positive("gamma", self.gamma)?;
        positive("sigma_low", self.sigma_low)?;
        positive("sigma_high", self.sigma_high)?;
        positive("g", self.g)?;
        // α, ω_p, and the ω⁻⁵ factor with the peak's enhancement where the
        // exponential leaves f64 (ω_p/5). Wind and fetch set them together:
        // the error names the wind and gives both.
        let wp = self.peak_frequency();
        let level = self.alpha() * self.g * self.g / (wp / 5.0).powi(5) * self.gamma;
        scales_in_range(
            "wind_speed",
            format!("{} (fetch {})", self.wind_speed, self.fetch),
            "with this fetch puts the spectrum's peak or level outside f64's range",
            &[self.alpha(), wp, level],
        )
    }
}

/// TMA spectrum (Bouws et al. 1985): JONSWAP in water of finite depth,
/// S(ω) = S_J(ω) Φ(ω_h) with ω_h = ω √(D/g) and Kitaigorodskii's factor
/// Φ = ½ω_h² (ω_h ≤ 1), 1 − ½(2 − ω_h)² (1 < ω_h < 2), 1 otherwise.
///
/// Pair it with [`crate::Dispersion::FiniteDepth`] of the same depth (eq. 15).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Tma {
    /// The deep-water spectrum.
    pub jonswap: Jonswap,
    /// Water depth D, metres (> 0).
    pub depth: f64,
}

impl Tma {
    /// Returns Kitaigorodskii's depth factor Φ(ω_h) for dimensionless ω_h = ω√(D/g).
    #[must_use]
    pub fn depth_factor(omega_h: f64) -> f64 {
        if omega_h <= 1.0 {
            0.5 * omega_h * omega_h
        } else if omega_h < 2.0 {
            let d = 2.0 - omega_h;
            1.0 - 0.5 * d * d
        } else {
            1.0
        }
    }
}

impl FrequencySpectrum for Tma {
    fn s(&self, omega: f64) -> f64 {
        let wh = omega * (self.depth / self.jonswap.g).sqrt();
        self.jonswap.s(omega) * Self::depth_factor(wh)
    }
    fn peak_frequency(&self) -> f64 {
        self.jonswap.peak_frequency()
    }
    fn wind_speed(&self) -> f64 {
        self.jonswap.wind_speed
    }
    fn g(&self) -> f64 {
        self.jonswap.g
    }
    fn validate(&self) -> Result<()> {
        self.jonswap.validate()?;
        positive("depth", self.depth)
            .map(|_| ())
            .map_err(Into::into)
    }
}

/// Integrates `s` over (0, ω_max] with `n` midpoint cells.
#[cfg(test)]
pub(crate) fn integrate_omega(s: &dyn FrequencySpectrum, omega_max: f64, n: usize) -> f64 {
    let dw = omega_max / n as f64;
    (0..n).map(|i| s.s((i as f64 + 0.5) * dw)).sum::<f64>() * dw
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn pierson_moskowitz_variance_and_peak() {
        let pm = PiersonMoskowitz {
            wind_speed: 15.0,
            g: G,
        };
        let v = integrate_omega(&pm, 40.0, 400_000);
        // The ω⁻⁵ tail past 40 rad/s holds α g²/(4·40⁴), negligible here.
        assert_relative_eq!(v, pm.variance(), max_relative = 1e-4);
        let wp = pm.peak_frequency();
        assert!(pm.s(wp) > pm.s(wp * 1.001) && pm.s(wp) > pm.s(wp * 0.999));
        // Significant wave height ≈ 0.21 U²/g.
        assert_relative_eq!(
            4.0 * pm.variance().sqrt(),
            0.21 * 225.0 / G,
            max_relative = 0.02
        );
    }

    #[test]
    fn jonswap_with_unit_gamma_is_pierson_moskowitz_shaped() {
        let j = Jonswap {
            gamma: 1.0,
            ..Jonswap::default()
        };
        let wp = j.peak_frequency();
        for w in [0.3f64, 0.8, 1.0, 2.0, 5.0] {
            let pm_shape = j.alpha() * G * G / w.powi(5) * (-1.25 * (wp / w).powi(4)).exp();
            assert_relative_eq!(j.s(w), pm_shape, max_relative = 1e-14);
        }
        // γ multiplies the peak exactly.
        let j33 = Jonswap::default();
        assert_relative_eq!(j33.s(wp) / j.s(wp), 3.3, max_relative = 1e-14);
        // Peak is the maximum.
        assert!(j33.s(wp) > j33.s(wp * 1.01) && j33.s(wp) > j33.s(wp * 0.99));
        // Longer fetch → lower peak frequency, more energy.
        let long = Jonswap {
            fetch: 400_000.0,
            ..j33
        };
        assert!(long.peak_frequency() < j33.peak_frequency());
        assert!(integrate_omega(&long, 20.0, 20_000) > integrate_omega(&j33, 20.0, 20_000));
    }

    #[test]
    fn tma_reduces_to_jonswap_in_deep_water_and_damps_shallow() {
        let j = Jonswap::default();
        let deep = Tma {
            jonswap: j,
            depth: 1000.0,
        };
        for w in [0.5, 1.0, 3.0] {
            assert_eq!(deep.s(w), j.s(w));
        }
        let shallow = Tma {
            jonswap: j,
            depth: 3.0,
        };
        for w in [0.2, 0.5, 1.0, 1.5, 3.0] {
            assert!(shallow.s(w) <= j.s(w));
        }
        // Φ is continuous and monotone.
        let mut prev = 0.0;
        for i in 0..=300 {
            let f = Tma::depth_factor(i as f64 * 0.01);
            assert!(f >= prev && f <= 1.0);
            assert!(f - prev < 0.021);
            prev = f;
        }
        assert!(
            Tma {
                jonswap: j,
                depth: 0.0
            }
            .validate()
            .is_err()
        );
        assert!(
            Tma {
                jonswap: j,
                depth: -5.0
            }
            .validate()
            .is_err()
        );
    }

    #[test]
    fn bad_parameters_are_refused() {
        assert!(
            PiersonMoskowitz {
                wind_speed: -3.0,
                g: G
            }
            .validate()
            .is_err()
        );
        assert!(
            PiersonMoskowitz {
                wind_speed: f64::NAN,
                g: G
            }
            .validate()
            .is_err()
        );
        assert!(
            Jonswap {
                fetch: 0.0,
                ..Jonswap::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            Jonswap {
                gamma: f64::NAN,
                ..Jonswap::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            Jonswap {
                wind_speed: -1.0,
                ..Jonswap::default()
            }
            .validate()
            .is_err()
        );
    }
}
