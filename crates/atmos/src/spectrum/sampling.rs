//! Wavelength sampling: stratified with Cook's jitter (Musgrave 1993, §4.2.4.1) and
//! hero wavelengths (Wilkie, Nawaz, Droske, Weidlich & Hanika, EGSR 2014).

use crate::error::{Result, invalid, positive};

/// `n` strata over `[min, max]` nm, each sample jittered within its stratum.
///
/// A sample at centre `c` representing width `Δ` is placed at `c + Δ(u − ½)`
/// (Musgrave 1993, §4.2.4.1): uniform within the stratum. With `u = ½` the centres are returned,
/// which alias spectrally (Plate 4.10); jittering turns aliasing into noise.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WavelengthSampler {
    n: usize,
    min: f64,
    max: f64,
}

impl WavelengthSampler {
    /// `n ≥ 1` strata over `[min_nm, max_nm]`, `0 < min < max`.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `n` is 0, a bound is not finite and positive, or
    /// `max_nm ≤ min_nm`.
    pub fn new(n: usize, min_nm: f64, max_nm: f64) -> Result<Self> {
        if n == 0 {
            return Err(invalid("n", n, "need at least one stratum"));
        }
        positive("min_nm", min_nm)?;
        positive("max_nm", max_nm)?;
        if max_nm <= min_nm {
            return Err(invalid("max_nm", max_nm, "must exceed min_nm"));
        }
        Ok(Self {
            n,
            min: min_nm,
            max: max_nm,
        })
    }

    /// Musgrave's 13 strata over 380–800 nm (Musgrave 1993, §4.2.4.2.1, §4.2.4.3.2).
    #[must_use]
    pub fn musgrave13() -> Self {
        Self {
            n: 13,
            min: 380.0,
            max: 800.0,
        }
    }

    /// Number of strata.
    #[must_use]
    pub fn len(&self) -> usize {
        self.n
    }

    /// Always false (at least one stratum).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Width of one stratum, nm.
    #[must_use]
    pub fn width(&self) -> f64 {
        (self.max - self.min) / self.n as f64
    }

    /// The range `(min, max)` in nm.
    #[must_use]
    pub fn range(&self) -> (f64, f64) {
        (self.min, self.max)
    }

    /// Centre of stratum `i` (clamped to the last stratum).
    #[must_use]
    pub fn centre(&self, i: usize) -> f64 {
        self.min + (i.min(self.n - 1) as f64 + 0.5) * self.width()
    }

    /// The wavelength for stratum `i` and uniform `u ∈ [0, 1)`: `centre + Δ(u − ½)`.
    #[must_use]
    pub fn sample(&self, i: usize, u: f64) -> f64 {
        self.centre(i) + self.width() * (u.clamp(0.0, 1.0) - 0.5)
    }
}

/// Hero-wavelength sampling: one uniformly chosen "hero" wavelength and
/// `N − 1` companions at equal rotations of the range, all sharing one path
/// (Wilkie et al. 2014). Each wavelength has pdf `1/(max − min)`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HeroWavelengths {
    min: f64,
    max: f64,
}

impl HeroWavelengths {
    /// Hero sampling over `[min_nm, max_nm]`.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if a bound is not finite and positive, or `max_nm ≤ min_nm`.
    pub fn new(min_nm: f64, max_nm: f64) -> Result<Self> {
        WavelengthSampler::new(1, min_nm, max_nm)?;
        Ok(Self {
            min: min_nm,
            max: max_nm,
        })
    }

    /// The `N` wavelengths for uniform `u ∈ [0, 1)`: `λ_j = min + ((u + j/N) mod 1)·(max − min)`.
    #[must_use]
    pub fn sample<const N: usize>(&self, u: f64) -> [f64; N] {
        let span = self.max - self.min;
        let u = u.clamp(0.0, 1.0);
        std::array::from_fn(|j| {
            let f = (u + j as f64 / N as f64).fract();
            self.min + f * span
        })
    }

    /// The probability density of each wavelength, `1/(max − min)` per nm.
    #[must_use]
    pub fn pdf(&self) -> f64 {
        1.0 / (self.max - self.min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::Seed;

    #[test]
    fn strata_cover_the_range() {
        let s = WavelengthSampler::musgrave13();
        assert!((s.centre(0) - 396.15).abs() < 0.01);
        assert!((s.width() - 32.31).abs() < 0.01);
        assert_eq!(s.sample(0, 0.0), 380.0);
        assert!((s.sample(12, 1.0) - 800.0).abs() < 1e-12);
        assert!(WavelengthSampler::new(0, 380.0, 800.0).is_err());
        assert!(WavelengthSampler::new(3, 800.0, 380.0).is_err());
        assert!(WavelengthSampler::new(3, f64::NAN, 380.0).is_err());
    }

    #[test]
    fn hero_wavelengths_are_uniform_and_rotated() {
        let h = HeroWavelengths::new(380.0, 780.0).unwrap();
        let seed = Seed(11);
        let mut hist = [0u32; 8];
        for i in 0..20_000 {
            let ls = h.sample::<4>(seed.uniform1(i));
            for (j, l) in ls.iter().enumerate() {
                assert!((380.0..780.0).contains(l));
                let d = (ls[j] - ls[0]).rem_euclid(400.0);
                assert!((d - 100.0 * j as f64).abs() < 1e-9);
                hist[((l - 380.0) / 50.0) as usize] += 1;
            }
        }
        // 10 000 per bin expected; 6σ ≈ 570.
        assert!(
            hist.iter().all(|&c| (9_400..=10_600).contains(&c)),
            "{hist:?}"
        );
    }
}
