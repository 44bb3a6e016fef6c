//! Dispersion relations ω(k): how fast a wave of wavenumber k oscillates.
//!
//! Tessendorf, *Simulating Ocean Water* (Tessendorf 2001, §3.2):
//! deep water ω² = g k (eq. 14), finite depth ω² = g k tanh(k D)
//! (eq. 15), surface tension ω² = g k (1 + k² ℓ_c²) (eq. 16),
//! and the quantised relation ω̄ = ⌊ω/ω₀⌋ ω₀ with ω₀ = 2π/T that makes an
//! animation repeat exactly after T seconds (eqs. 17-18).
//!
//! The notes call the capillary length `L`, which collides with the Phillips
//! `L = V²/g`; here it is `capillary_length`. The notes give no value for it;
//! physically ℓ_c² = σ/(ρ g), about 2.7 mm for clean water
//! ([`CAPILLARY_LENGTH_WATER`], not from the sources).

use crate::error::{Result, positive};

/// Standard gravity used by the source, m/s² ("nominally 9.8", Tessendorf 2001, §3.2).
pub const G: f64 = 9.8;

/// Capillary length √(σ/(ρ g)) of clean water at 20 °C, metres
/// (σ = 0.0728 N/m, ρ = 998 kg/m³, g = 9.8). Not from the sources.
pub const CAPILLARY_LENGTH_WATER: f64 = 2.728e-3;

/// Anything that maps a wavenumber k (rad/m) to an angular frequency ω (rad/s).
///
/// Implemented by [`Dispersion`] and [`Quantized`], so Gerstner waves and
/// tests can use either.
pub trait DispersionRelation: Send + Sync + std::fmt::Debug {
    /// Returns ω(k) in rad/s for wavenumber `k ≥ 0` in rad/m.
    fn omega(&self, k: f64) -> f64;

    /// Returns the phase speed ω/k in m/s (0 at k = 0).
    fn phase_speed(&self, k: f64) -> f64 {
        if k > 0.0 { self.omega(k) / k } else { 0.0 }
    }
}

/// The physical dispersion relations of the notes (eqs. 14-16).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Dispersion {
    /// Deep water, ω² = g k (eq. 14).
    Deep {
        /// Gravity, m/s².
        g: f64,
    },
    /// Water of finite depth, ω² = g k tanh(k D) (eq. 15); the deep
    /// relation is recovered as D → ∞.
    FiniteDepth {
        /// Gravity, m/s².
        g: f64,
        /// Depth D of the bottom below mean level, metres.
        depth: f64,
    },
    /// Deep water with surface tension, ω² = g k (1 + k² ℓ_c²) (eq. 16);
    /// matters for wavelengths of about a centimetre and less.
    Capillary {
        /// Gravity, m/s².
        g: f64,
        /// Capillary length ℓ_c (the notes' `L` of eq. 16), metres.
        capillary_length: f64,
    },
}

impl Default for Dispersion {
    fn default() -> Self {
        Dispersion::Deep { g: G }
    }
}

impl Dispersion {
    /// Checks that every parameter is finite and positive.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter) naming the first parameter that is not finite and positive.
    pub fn validate(&self) -> Result<()> {
        match *self {
            Dispersion::Deep { g } => positive("g", g).map(|_| ()).map_err(Into::into),
            Dispersion::FiniteDepth { g, depth } => {
                positive("g", g)?;
                positive("depth", depth).map(|_| ()).map_err(Into::into)
            }
            Dispersion::Capillary {
                g,
                capillary_length,
            } => {
                positive("g", g)?;
                positive("capillary_length", capillary_length)
                    .map(|_| ())
                    .map_err(Into::into)
            }
        }
    }

    /// Returns gravity g, m/s².
    #[must_use]
    pub fn g(&self) -> f64 {
        match *self {
            Dispersion::Deep { g }
            | Dispersion::FiniteDepth { g, .. }
            | Dispersion::Capillary { g, .. } => g,
        }
    }

    /// Returns ω(k) in rad/s; `k` in rad/m, `k ≥ 0`.
    #[inline]
    #[must_use]
    pub fn omega(&self, k: f64) -> f64 {
        match *self {
            Dispersion::Deep { g } => (g * k).sqrt(),
            Dispersion::FiniteDepth { g, depth } => (g * k * (k * depth).tanh()).sqrt(),
            Dispersion::Capillary {
                g,
                capillary_length: l,
            } => (g * k * (1.0 + k * k * l * l)).sqrt(),
        }
    }

    /// Returns dω/dk (the group speed), m/s, in closed form; `k > 0`.
    #[must_use]
    pub fn d_omega_dk(&self, k: f64) -> f64 {
        let w = self.omega(k);
        if w <= 0.0 {
            return 0.0;
        }
        // d(ω²)/dk = 2 ω dω/dk.
        let dw2 = match *self {
            Dispersion::Deep { g } => g,
            Dispersion::FiniteDepth { g, depth } => {
                let t = (k * depth).tanh();
                // k D sech²(k D) → 0 where tanh is 1 in f64 (k D may be ∞
                // there, and ∞ · 0 was NaN).
                let sech2 = 1.0 - t * t;
                g * t
                    + if sech2 == 0.0 {
                        0.0
                    } else {
                        g * k * depth * sech2
                    }
            }
            Dispersion::Capillary {
                g,
                capillary_length: l,
            } => g * (1.0 + 3.0 * k * k * l * l),
        };
        dw2 / (2.0 * w)
    }

    /// Returns the group speed dω/dk, m/s.
    #[must_use]
    pub fn group_speed(&self, k: f64) -> f64 {
        self.d_omega_dk(k)
    }

    /// Returns the wavenumber k (rad/m) whose frequency is `omega` (rad/s),
    /// by Newton iteration on ω(k) (exact for deep water).
    #[must_use]
    pub fn wavenumber(&self, omega: f64) -> f64 {
        let g = self.g();
        if omega <= 0.0 {
            return 0.0;
        }
        let mut k = omega * omega / g;
        if let Dispersion::Deep { .. } = self {
            return k;
        }
        if let Dispersion::FiniteDepth { depth, .. } = *self {
            // Start from the larger of the deep and shallow guesses: ω(k) is
            // concave in between, so Newton then converges monotonically.
            k = k.max(omega / (g * depth).sqrt());
        }
        for _ in 0..60 {
            let f = self.omega(k) - omega;
            let d = self.d_omega_dk(k);
            if d <= 0.0 {
                break;
            }
            let next = (k - f / d).max(k * 0.1);
            if (next - k).abs() <= 1e-15 * k {
                k = next;
                break;
            }
            k = next;
        }
        k
    }
}

impl DispersionRelation for Dispersion {
    fn omega(&self, k: f64) -> f64 {
        Dispersion::omega(self, k)
    }
}

/// A dispersion relation quantised to multiples of ω₀ = 2π/T so that every
/// wave, and therefore the whole surface, repeats exactly after `period` T
/// seconds (Tessendorf 2001, eqs. 17-18; slides "Looping in Time").
///
/// ω̄(k) = ⌊ω(k)/ω₀⌋ ω₀: the integer part, so ω̄ ≤ ω and ω − ω̄ < ω₀.
/// Waves slower than ω₀ get ω̄ = 0 and stand still (derived from eq. 18); a
/// longer T tracks the true relation more closely (Tessendorf 2001, fig. 5).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Quantized {
    /// The relation being quantised.
    pub base: Dispersion,
    /// The repeat time T, seconds.
    pub period: f64,
}

impl Quantized {
    /// Returns the quantised relation of `base` with repeat time `period` seconds.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter) if `base` fails [`Dispersion::validate`] or `period` is not finite
    /// and positive.
    pub fn new(base: Dispersion, period: f64) -> Result<Self> {
        base.validate()?;
        positive("period", period)?;
        Ok(Self { base, period })
    }

    /// Returns the base frequency ω₀ = 2π/T, rad/s.
    #[must_use]
    pub fn omega0(&self) -> f64 {
        std::f64::consts::TAU / self.period
    }

    /// Returns the integer multiple ⌊ω(k)/ω₀⌋ of ω₀ that wave k oscillates at.
    #[must_use]
    pub fn harmonic(&self, k: f64) -> u64 {
        (self.base.omega(k) / self.omega0()).floor() as u64
    }
}

impl DispersionRelation for Quantized {
    fn omega(&self, k: f64) -> f64 {
        self.harmonic(k) as f64 * self.omega0()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn limits_agree_with_deep_water() {
        let deep = Dispersion::Deep { g: G };
        let k = 0.37;
        // tanh form → √(gk) when kD ≫ 1.
        let fd = Dispersion::FiniteDepth {
            g: G,
            depth: 20.0 / k,
        };
        assert!((fd.omega(k) / deep.omega(k) - 1.0).abs() < 1e-12);
        // Shallow: ω ≈ k √(g D) for kD ≪ 1.
        let shallow = Dispersion::FiniteDepth {
            g: G,
            depth: 1e-3 / k,
        };
        assert_relative_eq!(
            shallow.omega(k),
            k * (G * 1e-3 / k).sqrt(),
            max_relative = 1e-6
        );
        // Capillary → deep when k ℓ_c → 0.
        let cap = Dispersion::Capillary {
            g: G,
            capillary_length: 1e-9,
        };
        assert_relative_eq!(cap.omega(k), deep.omega(k), max_relative = 1e-15);
    }

    #[test]
    fn group_speed_matches_finite_difference() {
        for d in [
            Dispersion::Deep { g: G },
            Dispersion::FiniteDepth { g: G, depth: 3.0 },
            Dispersion::Capillary {
                g: G,
                capillary_length: CAPILLARY_LENGTH_WATER,
            },
        ] {
            for k in [0.01, 0.3, 2.0, 150.0, 900.0] {
                let h = 1e-6 * k;
                let fd = (d.omega(k + h) - d.omega(k - h)) / (2.0 * h);
                assert_relative_eq!(d.d_omega_dk(k), fd, max_relative = 1e-6);
                let back = d.wavenumber(d.omega(k));
                assert_relative_eq!(back, k, max_relative = 1e-9);
            }
        }
        // Deep water group speed is half the phase speed.
        let d = Dispersion::Deep { g: G };
        assert_relative_eq!(
            d.group_speed(0.2),
            0.5 * d.phase_speed(0.2),
            max_relative = 1e-14
        );
    }

    #[test]
    fn quantised_frequencies_are_multiples_below_the_truth() {
        let base = Dispersion::Deep { g: G };
        for t in [20.0, 100.0, 1e6] {
            let q = Quantized::new(base, t).unwrap();
            for i in 1..200 {
                let k = i as f64 * 0.013;
                let w = base.omega(k);
                let wq = q.omega(k);
                let ratio = wq / q.omega0();
                assert!((ratio - ratio.round()).abs() < 1e-9);
                assert!(wq <= w && w - wq < q.omega0());
            }
        }
        // T → ∞ recovers ω.
        let q = Quantized::new(base, 1e9).unwrap();
        assert_relative_eq!(q.omega(0.5), base.omega(0.5), max_relative = 1e-7);
        // 20 s freezes the 1000 m patch's fundamental (its ω < ω₀).
        let q = Quantized::new(base, 20.0).unwrap();
        assert_eq!(q.omega(std::f64::consts::TAU / 1000.0), 0.0);
    }

    #[test]
    fn bad_parameters_are_refused() {
        assert!(
            Dispersion::FiniteDepth { g: G, depth: 0.0 }
                .validate()
                .is_err()
        );
        assert!(
            Dispersion::FiniteDepth { g: G, depth: -1.0 }
                .validate()
                .is_err()
        );
        assert!(Dispersion::Deep { g: f64::NAN }.validate().is_err());
        assert!(Quantized::new(Dispersion::default(), 0.0).is_err());
        assert!(Quantized::new(Dispersion::default(), f64::INFINITY).is_err());
    }
}
