//! Musgrave's spectral rgb tables: one metameric rgb per wavelength sample,
//! columns summing to white (Musgrave 1993, §4.2.4.2–4.2.4.2.2).

use glam::DVec3;

use super::cie::{Illuminant, cmf_1931, xyz_to_linear_srgb};
use super::sampling::WavelengthSampler;
use crate::error::Result;

/// A table of `n` wavelength samples and their display rgb, with every
/// channel summing to exactly 1 over the samples (eq. "4.2.14", Musgrave 1993, §4.2.4.2),
/// so that full-intensity samples add up to white.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralRgbTable {
    sampler: WavelengthSampler,
    rgb: Vec<DVec3>,
}

impl SpectralRgbTable {
    /// Musgrave's linear model with 13 samples over 380–800 nm (Musgrave 1993, §4.2.4.2.1).
    ///
    /// Figure 4.2.4 is not in the text, so the curves are a reconstruction
    /// with the properties the text states: piecewise-linear red, green and
    /// blue ramps; violet shown as magenta (red + blue, Musgrave 1993, §4.2.4.2.1); steep roll-off
    /// at both ends; samples at the 13 stratum centres (396.2 + 32.31·k nm).
    /// Each channel is then renormalised to sum to 1.
    #[must_use]
    pub fn linear_musgrave13() -> Self {
        let s = WavelengthSampler::musgrave13();
        let ramp = |l: f64, pts: &[(f64, f64)]| -> f64 {
            if l <= pts[0].0 {
                return pts[0].1;
            }
            for w in pts.windows(2) {
                if l <= w[1].0 {
                    let f = (l - w[0].0) / (w[1].0 - w[0].0);
                    return w[0].1 + f * (w[1].1 - w[0].1);
                }
            }
            pts[pts.len() - 1].1
        };
        let rgb = (0..13)
            .map(|i| {
                let l = s.centre(i);
                DVec3::new(
                    ramp(
                        l,
                        &[
                            (380.0, 0.6),
                            (440.0, 0.0),
                            (540.0, 0.0),
                            (600.0, 1.0),
                            (700.0, 1.0),
                            (800.0, 0.2),
                        ],
                    ),
                    ramp(l, &[(440.0, 0.0), (530.0, 1.0), (580.0, 1.0), (640.0, 0.0)]),
                    ramp(l, &[(380.0, 1.0), (470.0, 1.0), (530.0, 0.0)]),
                )
            })
            .collect();
        Self::normalised(s, rgb)
    }

    /// A table built from the CIE 1931 CMFs: the XYZ of each sample (weighted by
    /// `illuminant`) mapped to linear sRGB, negatives clipped to 0, then each
    /// channel renormalised to sum to 1 (the source used
    /// illuminant B and an unpublished monitor matrix, Musgrave 1993, §4.2.4.2.2).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::WavelengthOutOfRange`](crate::AtmosError::WavelengthOutOfRange)
    /// if the sampler's range leaves the 360–830 nm table.
    pub fn from_cie(sampler: WavelengthSampler, illuminant: Illuminant) -> Result<Self> {
        let mut rgb = Vec::with_capacity(sampler.len());
        for i in 0..sampler.len() {
            let l = sampler.centre(i);
            let xyz = cmf_1931(l)? * illuminant.spd(l)?;
            rgb.push(xyz_to_linear_srgb(xyz).max(DVec3::ZERO));
        }
        Ok(Self::normalised(sampler, rgb))
    }

    fn normalised(sampler: WavelengthSampler, mut rgb: Vec<DVec3>) -> Self {
        let sum: DVec3 = rgb.iter().copied().sum();
        let inv = DVec3::ONE / sum.max(DVec3::splat(1e-300));
        for c in &mut rgb {
            *c *= inv;
        }
        Self { sampler, rgb }
    }

    /// The wavelength sampler the table was built on.
    #[must_use]
    pub fn sampler(&self) -> WavelengthSampler {
        self.sampler
    }

    /// The rgb of each sample, in order of increasing wavelength.
    #[must_use]
    pub fn samples(&self) -> &[DVec3] {
        &self.rgb
    }

    /// The rgb at any wavelength: piecewise-linear between sample centres,
    /// constant beyond the first and last, 0 outside the sampler's range.
    #[must_use]
    pub fn rgb_at(&self, lambda_nm: f64) -> DVec3 {
        let (lo, hi) = self.sampler.range();
        if !(lo..=hi).contains(&lambda_nm) {
            return DVec3::ZERO;
        }
        let x = (lambda_nm - lo) / self.sampler.width() - 0.5;
        let n = self.rgb.len();
        if x <= 0.0 {
            return self.rgb[0];
        }
        let i = x.floor() as usize;
        if i + 1 >= n {
            return self.rgb[n - 1];
        }
        self.rgb[i].lerp(self.rgb[i + 1], x - i as f64)
    }
}

/// Clamps each channel of a jittered spectral sum to at most 1 (Musgrave 1993, §4.2.4.2.1),
/// so that an over-white sum never overflows (8-bit wrap-around to black in the
/// source's era).
#[inline]
#[must_use]
pub fn clamp_sum(rgb: DVec3) -> DVec3 {
    rgb.min(DVec3::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::Seed;

    #[test]
    fn tables_sum_to_white() {
        for t in [
            SpectralRgbTable::linear_musgrave13(),
            SpectralRgbTable::from_cie(WavelengthSampler::musgrave13(), Illuminant::D65).unwrap(),
            SpectralRgbTable::from_cie(
                WavelengthSampler::new(40, 380.0, 770.0).unwrap(),
                Illuminant::E,
            )
            .unwrap(),
        ] {
            let s: DVec3 = t.samples().iter().copied().sum();
            assert!((s - DVec3::ONE).abs().max_element() < 1e-12, "{s}");
            assert!(t.samples().iter().all(|c| c.min_element() >= 0.0));
        }
        assert!(
            SpectralRgbTable::from_cie(
                WavelengthSampler::new(13, 300.0, 800.0).unwrap(),
                Illuminant::D65
            )
            .is_err()
        );
    }

    #[test]
    fn linear_model_has_magenta_violet() {
        let t = SpectralRgbTable::linear_musgrave13();
        let v = t.samples()[0];
        assert!(
            v.x > 0.0 && v.z > 0.0 && v.y == 0.0,
            "violet = magenta: {v}"
        );
        assert!(t.rgb_at(700.0).x > t.rgb_at(700.0).z);
        assert_eq!(t.rgb_at(900.0), DVec3::ZERO);
    }

    /// Jittered sums scatter around white, are clamped to ≤ 1, average ≈ 1.
    #[test]
    fn jittered_sums_average_to_white() {
        let t = SpectralRgbTable::linear_musgrave13();
        let s = t.sampler();
        let seed = Seed(5);
        let mut mean = DVec3::ZERO;
        let mut over = 0;
        let n = 4000;
        for k in 0..n {
            let mut sum = DVec3::ZERO;
            for i in 0..13 {
                sum += t.rgb_at(s.sample(i, seed.uniform2(k, i as i64)));
            }
            if sum.max_element() > 1.0 {
                over += 1;
            }
            assert!(clamp_sum(sum).max_element() <= 1.0);
            mean += sum;
        }
        mean /= n as f64;
        assert!((mean - DVec3::ONE).abs().max_element() < 0.05, "{mean}");
        assert!(
            over > n / 5,
            "about half of the jittered sums exceed 1: {over}"
        );
    }
}
