//! Gerstner waves: the Lagrangian model in which every surface particle
//! moves on a circle (Tessendorf 2001, §3.1; Fournier &
//! Reeves 1986).
//!
//! A particle at rest position x₀ = (x₀, y₀) is at
//!
//! x = x₀ − Σᵢ k̂ᵢ Aᵢ sin(kᵢ·x₀ − ωᵢt + φᵢ),  z = Σᵢ Aᵢ cos(kᵢ·x₀ − ωᵢt + φᵢ)
//!
//! (eqs. 12-13, z up). The steepness kA controls the shape: crests sharpen
//! as kA → 1, and for kA > 1 the crest loops over itself. Each wave
//! must have kA < 1 ([`GerstnerSea::new`] refuses steeper ones); Σ kA < 1
//! guarantees no loops at all (derived: the horizontal map's Jacobian is
//! I − Σ k̂ᵢk̂ᵢᵀ kᵢAᵢ cos θᵢ), which [`GerstnerSea::is_loop_free`]
//! reports. ωᵢ comes from a dispersion relation (§3.2); with a
//! [`crate::Quantized`] one the sea repeats exactly after its period.

use glam::{DMat2, DVec2, DVec3};

use crate::dispersion::DispersionRelation;
use crate::error::{OceanError, Result, finite, non_negative};

/// One Gerstner wave (eqs. 9-11).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GerstnerWave {
    /// Wave vector k, rad/m; points in the direction of travel (|k| = 2π/wavelength).
    pub wave_vector: DVec2,
    /// Amplitude A, metres.
    pub amplitude: f64,
    /// Angular frequency ω, rad/s.
    pub omega: f64,
    /// Phase φ, radians.
    pub phase: f64,
}

impl GerstnerWave {
    /// Returns a wave with frequency from `dispersion` (eq. 14-18).
    #[must_use]
    pub fn new(
        wave_vector: DVec2,
        amplitude: f64,
        phase: f64,
        dispersion: &dyn DispersionRelation,
    ) -> Self {
        Self {
            wave_vector,
            amplitude,
            omega: dispersion.omega(wave_vector.length()),
            phase,
        }
    }

    /// Returns the steepness k·A.
    #[must_use]
    pub fn steepness(&self) -> f64 {
        self.wave_vector.length() * self.amplitude
    }

    #[inline]
    fn theta(&self, x0: DVec2, t: f64) -> f64 {
        self.wave_vector.dot(x0) - self.omega * t + self.phase
    }

    fn validate(&self, index: usize) -> Result<()> {
        finite("wave_vector.x", self.wave_vector.x)?;
        finite("wave_vector.y", self.wave_vector.y)?;
        non_negative("amplitude", self.amplitude)?;
        finite("omega", self.omega)?;
        finite("phase", self.phase)?;
        if self.wave_vector.length() == 0.0 && self.amplitude > 0.0 {
            return Err(crate::error::invalid(
                "wave_vector",
                "0",
                "a wave needs a non-zero wave vector",
            ));
        }
        let s = self.steepness();
        if s >= 1.0 {
            return Err(OceanError::TooSteep {
                index,
                steepness: s,
            });
        }
        Ok(())
    }
}

/// A sum of Gerstner waves (eqs. 12-13), checked for steepness.
#[derive(Clone, Debug, PartialEq)]
pub struct GerstnerSea {
    waves: Vec<GerstnerWave>,
}

impl GerstnerSea {
    /// Returns the sum of `waves`.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::TooSteep`] if a wave has kA ≥ 1 and
    /// [`OceanError::InvalidParameter`] if a wave has a non-finite or non-positive parameter.
    pub fn new(waves: Vec<GerstnerWave>) -> Result<Self> {
        for (i, w) in waves.iter().enumerate() {
            w.validate(i)?;
        }
        Ok(Self { waves })
    }

    /// Returns the waves.
    #[must_use]
    pub fn waves(&self) -> &[GerstnerWave] {
        &self.waves
    }

    /// Returns Σ kᵢAᵢ.
    #[must_use]
    pub fn total_steepness(&self) -> f64 {
        self.waves.iter().map(GerstnerWave::steepness).sum()
    }

    /// Returns whether Σ kᵢAᵢ < 1, which guarantees that no crest loops.
    #[must_use]
    pub fn is_loop_free(&self) -> bool {
        self.total_steepness() < 1.0
    }

    /// Returns the position (x, y, z) at time `t` of the particle at rest position `x0`.
    #[must_use]
    pub fn position(&self, x0: DVec2, t: f64) -> DVec3 {
        let mut p = x0;
        let mut z = 0.0;
        for w in &self.waves {
            let th = w.theta(x0, t);
            let k = w.wave_vector.length();
            if k > 0.0 {
                p -= w.wave_vector / k * (w.amplitude * th.sin());
            }
            z += w.amplitude * th.cos();
        }
        p.extend(z)
    }

    /// Returns the Jacobian ∂x/∂x₀ of the horizontal map at `x0`, time `t`:
    /// I − Σ k̂k̂ᵀ kA cos θ (derived from eqs. 12-13). Its determinant is ≤ 0 where
    /// the surface loops.
    #[must_use]
    pub fn jacobian(&self, x0: DVec2, t: f64) -> DMat2 {
        let mut j = DMat2::IDENTITY;
        for w in &self.waves {
            let k = w.wave_vector.length();
            if k == 0.0 {
                continue;
            }
            let kh = w.wave_vector / k;
            let c = k * w.amplitude * w.theta(x0, t).cos();
            j -= DMat2::from_cols(kh * kh.x, kh * kh.y) * c;
        }
        j
    }

    /// Returns the unit upward normal of the surface at the particle from `x0`.
    #[must_use]
    pub fn normal(&self, x0: DVec2, t: f64) -> DVec3 {
        // Tangents ∂P/∂x₀ and ∂P/∂y₀ of P = (x, y, z).
        let j = self.jacobian(x0, t);
        let mut dz = DVec2::ZERO;
        for w in &self.waves {
            dz -= w.wave_vector * (w.amplitude * w.theta(x0, t).sin());
        }
        let tx = DVec3::new(j.x_axis.x, j.x_axis.y, dz.x);
        let ty = DVec3::new(j.y_axis.x, j.y_axis.y, dz.y);
        let n = tx.cross(ty);
        let n = if n.z < 0.0 { -n } else { n };
        n.normalize_or(DVec3::Z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispersion::{Dispersion, Quantized};

    fn one(ka: f64) -> GerstnerSea {
        let k = 0.5;
        GerstnerSea {
            waves: vec![GerstnerWave::new(
                DVec2::new(k, 0.0),
                ka / k,
                0.0,
                &Dispersion::default(),
            )],
        }
    }

    #[test]
    fn monotone_below_unit_steepness_and_looping_above() {
        let xs = |s: &GerstnerSea| -> Vec<f64> {
            (0..2000)
                .map(|i| s.position(DVec2::new(i as f64 * 0.01, 0.0), 0.3).x)
                .collect()
        };
        let x = xs(&one(0.8));
        assert!(x.windows(2).all(|w| w[1] > w[0]));
        assert!(GerstnerSea::new(one(0.8).waves).is_ok());
        let x = xs(&one(1.3));
        assert!(x.windows(2).any(|w| w[1] < w[0]));
        assert!(matches!(
            GerstnerSea::new(one(1.3).waves),
            Err(OceanError::TooSteep { index: 0, .. })
        ));
        // The Jacobian determinant matches 1 − kA cos θ.
        let s = one(0.6);
        for x in [0.0, 1.0, 2.5] {
            let d = s.jacobian(DVec2::new(x, 3.0), 0.7).determinant();
            assert!((d - (1.0 - 0.6 * (0.5 * x - s.waves[0].omega * 0.7).cos())).abs() < 1e-12);
        }
    }

    #[test]
    fn crests_are_narrower_than_troughs() {
        // Width of the region above the mean vs below, over one wavelength.
        let s = one(0.7);
        let n = 100_000;
        let l = std::f64::consts::TAU / 0.5;
        let pts: Vec<DVec3> = (0..=n)
            .map(|i| s.position(DVec2::new(i as f64 * l / n as f64, 0.0), 0.0))
            .collect();
        let (mut up, mut down) = (0.0, 0.0);
        for w in pts.windows(2) {
            let dx = w[1].x - w[0].x;
            if w[0].z > 0.0 { up += dx } else { down += dx }
        }
        assert!(up < 0.8 * down, "crest {up} vs trough {down}");
    }

    #[test]
    fn quantised_sea_loops() {
        let q = Quantized::new(Dispersion::default(), 12.0).unwrap();
        let waves = (0..3)
            .map(|i| {
                let k = DVec2::from_angle(0.4 * i as f64) * (0.2 + 0.13 * i as f64);
                GerstnerWave::new(k, 0.25 / k.length(), i as f64, &q)
            })
            .collect();
        let s = GerstnerSea::new(waves).unwrap();
        assert!(s.is_loop_free() == (s.total_steepness() < 1.0));
        for t in [0.0, 1.3, 7.7] {
            let x0 = DVec2::new(3.0, -2.0);
            let a = s.position(x0, t);
            let b = s.position(x0, t + 12.0);
            assert!((a - b).length() < 1e-9);
            let n = s.normal(x0, t);
            assert!((n.length() - 1.0).abs() < 1e-12 && n.z > 0.0);
        }
    }

    #[test]
    fn normal_is_perpendicular_to_the_surface() {
        let s = one(0.5);
        let x0 = DVec2::new(1.2, 0.4);
        let h = 1e-6;
        let p = |d: DVec2| s.position(x0 + d, 2.0);
        let tx = (p(DVec2::new(h, 0.0)) - p(DVec2::new(-h, 0.0))) / (2.0 * h);
        let n = s.normal(x0, 2.0);
        assert!(n.dot(tx).abs() < 1e-8);
        assert!(
            GerstnerSea::new(vec![GerstnerWave {
                amplitude: f64::NAN,
                ..one(0.5).waves[0]
            }])
            .is_err()
        );
    }
}
