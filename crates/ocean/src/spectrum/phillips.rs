//! The Phillips spectrum (Tessendorf 2001, §3.3, eqs. 23-24; fig. 8
//! for the exponent 6).

use glam::DVec2;

use super::{Spectrum, direction};
use crate::dispersion::G;
use crate::error::{Result, finite, invalid, non_negative, positive};

/// Phillips spectrum for wind-driven waves in a fully developed sea:
///
/// P(k) = A · exp(−1/(k L)²) / k⁴ · |k̂·ŵ|^p · exp(−k² ℓ²),  L = V²/g
///
/// (eq. 23 with the small-wave suppression of eq. 24; p = 2 in eq. 23,
/// p = 6 in Fig. 8, which "is clearly more aligned with the direction of the
/// wind"). L is the largest wave a wind of speed V raises; the radial factor
/// peaks at k = 1/(√2 L). P(0) = 0 (the formula is 0/0 there).
///
/// The source gives no value for A. Here P is a density (see the
/// [module docs](super)), so A is dimensionless, and the default
/// A = 0.0081/(2π) is the Phillips constant α = 0.0081 of Pierson–Moskowitz
/// spread with cos²: the height variance is then A π L²/2 (p = 2, ℓ = 0).
///
/// `against_wind` multiplies P where k̂·ŵ < 0, i.e. for waves travelling
/// against the wind under the slides' time sign. 1 keeps the source's
/// symmetric spectrum; 0 removes those waves (a common later modification,
/// not in these sources).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct Phillips {
    /// Dimensionless constant A; height variance scales linearly with it.
    pub amplitude: f64,
    /// Wind speed V, m/s (> 0). Larger V moves energy to longer waves (L = V²/g).
    pub wind_speed: f64,
    /// Wind direction ŵ, radians from +x toward +y.
    pub wind_direction: f64,
    /// Gravity g, m/s².
    pub g: f64,
    /// Small-wave suppression length ℓ, metres (eq. 24); 0 disables. Keep ℓ ≪ L.
    pub small_wave_length: f64,
    /// Directional exponent p of |k̂·ŵ|^p (2 in eq. 23, 6 in Fig. 8); larger
    /// aligns the waves more with the wind.
    pub direction_exponent: f64,
    /// Factor in [0, 1] applied to waves travelling against the wind.
    pub against_wind: f64,
}

impl Default for Phillips {
    /// The source's Figs. 6-7: V = 31 m/s along +x, ℓ = 1 m, p = 2 (§3.5).
    fn default() -> Self {
        Self {
            amplitude: 0.0081 / std::f64::consts::TAU,
            wind_speed: 31.0,
            wind_direction: 0.0,
            g: G,
            small_wave_length: 1.0,
            direction_exponent: 2.0,
            against_wind: 1.0,
        }
    }
}

impl Phillips {
    /// Returns the largest-wave length L = V²/g, metres.
    #[must_use]
    pub fn largest_wave(&self) -> f64 {
        self.wind_speed * self.wind_speed / self.g
    }

    /// Returns the wavenumber 1/(√2 L) at which the radial factor peaks, rad/m.
    #[must_use]
    pub fn peak_wavenumber(&self) -> f64 {
        1.0 / (std::f64::consts::SQRT_2 * self.largest_wave())
    }
}

impl Spectrum for Phillips {
    fn density(&self, k: DVec2) -> f64 {
        let k2 = k.length_squared();
        if k2 <= 0.0 {
            return 0.0;
        }
        let l = self.largest_wave();
        // Zero where the exponential underflows (k below 1/(27 L)), before
        // k⁻⁴ can overflow: 0 · ∞ was NaN.
        let e = (-1.0 / (k2 * l * l)).exp();
        if e == 0.0 {
            return 0.0;
        }
        let kk = k2.sqrt();
        let c = (k / kk).dot(direction(self.wind_direction));
        let mut p = self.amplitude * e / (k2 * k2)
            * c.abs().powf(self.direction_exponent)
            * (-k2 * self.small_wave_length * self.small_wave_length).exp();
        if c < 0.0 {
            p *= self.against_wind;
        }
        p
    }

    fn validate(&self) -> Result<()> {
        non_negative("amplitude", self.amplitude)?;
        positive("wind_speed", self.wind_speed)?;
        finite("wind_direction", self.wind_direction)?;
        positive("g", self.g)?;
        // L, and the k⁻⁴ factor where the exponential leaves f64 (1/(28 L)).
        let l = self.largest_wave();
        let level = self.amplitude * (28.0 * l).powi(4);
        if !(l.is_finite() && l > 0.0) {
            return Err(invalid(
                "wind_speed",
                self.wind_speed,
                "puts the largest wave V²/g outside f64's range",
            ));
        }
        if !level.is_finite() {
            return Err(invalid(
                "amplitude",
                self.amplitude,
                "with this wind speed puts the spectrum's level outside f64's range",
            ));
        }
        non_negative("small_wave_length", self.small_wave_length)?;
        non_negative("direction_exponent", self.direction_exponent)?;
        if !(0.0..=1.0).contains(&self.against_wind) {
            return Err(invalid(
                "against_wind",
                self.against_wind,
                "must be in [0, 1]",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::integrate;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    fn no_cut() -> Phillips {
        Phillips {
            wind_speed: 10.0,
            small_wave_length: 0.0,
            ..Phillips::default()
        }
    }

    #[test]
    fn zero_at_origin_and_perpendicular_to_wind() {
        for p in [2.0, 6.0] {
            let s = Phillips {
                direction_exponent: p,
                ..Phillips::default()
            };
            assert_eq!(s.density(DVec2::ZERO), 0.0);
            assert_eq!(s.density(DVec2::new(0.0, 0.05)), 0.0);
            assert!(s.density(DVec2::new(0.05, 0.0)) > 0.0);
        }
    }

    #[test]
    fn variance_matches_closed_form() {
        // ∫P d²k = A π L²/2 for p = 2, ℓ = 0 (derived by substituting u = 1/(kL)²).
        let s = no_cut();
        let l = s.largest_wave();
        let expected = s.amplitude * std::f64::consts::PI * l * l / 2.0;
        // The 1/k⁴ tail beyond k_max holds ≈ A π/(2 k_max²) of the variance.
        let k_max = 40.0 / l;
        let got =
            integrate(&s, k_max, 1600) + s.amplitude * std::f64::consts::PI / (2.0 * k_max * k_max);
        assert_relative_eq!(got, expected, max_relative = 2e-3);
    }

    #[test]
    fn radial_peak_is_at_one_over_root_two_l() {
        let s = no_cut();
        let k0 = s.peak_wavenumber();
        let f = |k: f64| s.density(DVec2::new(k, 0.0));
        assert!(f(k0) > f(k0 * 1.01) && f(k0) > f(k0 * 0.99));
    }

    #[test]
    fn higher_exponent_is_more_wind_aligned() {
        let ratio = |p: f64| {
            let s = Phillips {
                direction_exponent: p,
                ..no_cut()
            };
            let (mut aligned, mut total) = (0.0, 0.0);
            for j in -100..100 {
                for i in -100..100 {
                    let k = DVec2::new(i as f64, j as f64) * 0.002;
                    let d = s.density(k);
                    total += d;
                    if k.length() > 0.0 && (k.normalize().x).abs() > 0.9 {
                        aligned += d;
                    }
                }
            }
            aligned / total
        };
        assert!(ratio(6.0) > ratio(2.0) + 0.1);
    }

    #[test]
    fn bad_parameters_are_refused() {
        let bad = [
            Phillips {
                wind_speed: -1.0,
                ..Phillips::default()
            },
            Phillips {
                wind_speed: f64::NAN,
                ..Phillips::default()
            },
            Phillips {
                amplitude: -1.0,
                ..Phillips::default()
            },
            Phillips {
                small_wave_length: f64::INFINITY,
                ..Phillips::default()
            },
            Phillips {
                against_wind: 1.5,
                ..Phillips::default()
            },
            Phillips {
                g: 0.0,
                ..Phillips::default()
            },
        ];
        for b in bad {
            assert!(b.validate().is_err(), "{b:?}");
        }
        assert!(Phillips::default().validate().is_ok());
    }

    proptest! {
        #[test]
        fn density_properties(kx in -3.0f64..3.0, ky in -3.0f64..3.0, a in 0.0f64..0.1, l in 0.0f64..2.0) {
            let s = Phillips { amplitude: a, small_wave_length: l, ..no_cut() };
            let k = DVec2::new(kx, ky);
            let p = s.density(k);
            prop_assert!(p.is_finite() && p >= 0.0);
            // Symmetric without against-wind damping.
            prop_assert_eq!(p, s.density(-k));
            // Linear in A.
            let s2 = Phillips { amplitude: 2.0 * a, ..s };
            prop_assert!((s2.density(k) - 2.0 * p).abs() <= 1e-12 * p.abs().max(1e-300));
            // Suppression only removes energy, more as ℓ grows.
            let s3 = Phillips { small_wave_length: l + 0.5, ..s };
            prop_assert!(s3.density(k) <= p);
            // Against-wind damping.
            let s4 = Phillips { against_wind: 0.0, ..s };
            if kx < 0.0 { prop_assert_eq!(s4.density(k), 0.0); } else { prop_assert_eq!(s4.density(k), p); }
        }
    }
}
