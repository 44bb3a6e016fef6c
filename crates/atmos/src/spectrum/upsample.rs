//! RGB → spectrum upsampling for reflectances: Jakob & Hanika, "A Low-Dimensional
//! Function Space for Efficient Spectral Upsampling", Computer Graphics Forum
//! 38(2), 2019.
//!
//! A smooth, bounded reflectance `S(λ) = σ(c₀λ'² + c₁λ' + c₂)` with the
//! sigmoid `σ(x) = ½ + x/(2√(1 + x²))` and `λ' ∈ [0, 1]` over 360–830 nm.
//! The paper precomputes the three coefficients on an RGB grid by Gauss–Newton
//! optimisation in CIELAB; this module runs that same optimisation per colour
//! (with the paper's continuation from grey), so no table needs shipping.

use std::sync::OnceLock;

use glam::{DMat3, DVec3};

use super::cie::{XYZ_TO_SRGB, cmf_1931};
use super::cie_data::{TABLE_MAX_NM, TABLE_MIN_NM};
use crate::error::{AtmosError, Result, invalid};

const STEP_NM: f64 = 5.0;
const SAMPLES: usize = 95; // 360..=830 by 5 nm

/// Per-sample XYZ weights `x̄·D65·Δλ / Σȳ·D65·Δλ` on the 5 nm grid.
fn weights() -> &'static [DVec3; SAMPLES] {
    static W: OnceLock<[DVec3; SAMPLES]> = OnceLock::new();
    W.get_or_init(|| {
        let mut w = [DVec3::ZERO; SAMPLES];
        let mut ysum = 0.0;
        for (i, wi) in w.iter_mut().enumerate() {
            let l = TABLE_MIN_NM + i as f64 * STEP_NM;
            let s = super::Illuminant::D65.spd(l).unwrap_or(0.0);
            *wi = cmf_1931(l).unwrap_or(DVec3::ZERO) * s;
            ysum += wi.y;
        }
        for wi in &mut w {
            *wi /= ysum;
        }
        w
    })
}

/// A Jakob–Hanika sigmoid-polynomial reflectance spectrum.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SigmoidSpectrum {
    /// Coefficients `(c₀, c₁, c₂)` of the polynomial in normalised wavelength.
    pub coeffs: [f64; 3],
}

#[inline]
fn sigmoid(x: f64) -> f64 {
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

fn lab(xyz: DVec3, white: DVec3) -> DVec3 {
    let f = |t: f64| {
        const D: f64 = 6.0 / 29.0;
        if t > D * D * D {
            t.cbrt()
        } else {
            t / (3.0 * D * D) + 4.0 / 29.0
        }
    };
    let (fx, fy, fz) = (f(xyz.x / white.x), f(xyz.y / white.y), f(xyz.z / white.z));
    DVec3::new(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz))
}

impl SigmoidSpectrum {
    /// Reflectance at `lambda_nm` (any wavelength; the polynomial extrapolates), in `[0, 1]`.
    #[inline]
    #[must_use]
    pub fn eval(&self, lambda_nm: f64) -> f64 {
        let t = (lambda_nm - TABLE_MIN_NM) / (TABLE_MAX_NM - TABLE_MIN_NM);
        let [c0, c1, c2] = self.coeffs;
        sigmoid((c0 * t + c1) * t + c2)
    }

    /// XYZ of this reflectance under D65 (white has `Y = 1`).
    #[must_use]
    pub fn xyz_d65(&self) -> DVec3 {
        let w = weights();
        let mut xyz = DVec3::ZERO;
        for (i, wi) in w.iter().enumerate() {
            xyz += *wi * self.eval(TABLE_MIN_NM + i as f64 * STEP_NM);
        }
        xyz
    }

    /// The linear sRGB of this reflectance under D65.
    #[must_use]
    pub fn to_linear_srgb(&self) -> DVec3 {
        XYZ_TO_SRGB * self.xyz_d65()
    }

    /// Fits a reflectance whose colour under D65 is the linear sRGB `rgb`,
    /// every component in `[0, 1]`, to CIE76 ΔE < 0.01.
    ///
    /// Fails with [`AtmosError::InvalidParameter`] for components outside
    /// `[0, 1]` or NaN, and [`AtmosError::NoConvergence`] if the colour cannot be
    /// reached (very saturated colours near the spectral locus, which no smooth
    /// reflectance has).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for components outside `[0, 1]` or NaN, and
    /// [`AtmosError::NoConvergence`](crate::AtmosError::NoConvergence) if the colour cannot be
    /// reached (very saturated colours near the spectral locus, which no smooth reflectance has).
    pub fn fit_reflectance(rgb: DVec3) -> Result<Self> {
        if !(rgb.is_finite() && rgb.min_element() >= 0.0 && rgb.max_element() <= 1.0) {
            return Err(invalid(
                "rgb",
                rgb,
                "reflectance components must be in [0, 1]",
            ));
        }
        let white = weights().iter().copied().sum::<DVec3>();
        let target_xyz = super::cie::linear_srgb_to_xyz(rgb);
        let grey_xyz = white * 0.5;
        let residual =
            |c: [f64; 3], goal: DVec3| lab(SigmoidSpectrum { coeffs: c }.xyz_d65(), white) - goal;
        let mut c = [0.0f64; 3];
        const STAGES: usize = 8;
        let mut last = f64::INFINITY;
        for stage in 1..=STAGES {
            let goal_xyz = grey_xyz.lerp(target_xyz, stage as f64 / STAGES as f64);
            let goal = lab(goal_xyz, white);
            let mut mu = 1e-3;
            let mut r = residual(c, goal);
            for _ in 0..60 {
                if r.length() < 1e-4 {
                    break;
                }
                // Forward-difference Jacobian (3 × 3).
                let mut cols = [DVec3::ZERO; 3];
                for (k, col) in cols.iter_mut().enumerate() {
                    let mut cp = c;
                    let h = 1e-6 * (1.0 + c[k].abs());
                    cp[k] += h;
                    *col = (residual(cp, goal) - r) / h;
                }
                let j = DMat3::from_cols(cols[0], cols[1], cols[2]);
                let jt = j.transpose();
                let g = jt * r;
                let mut improved = false;
                for _ in 0..12 {
                    let a = jt * j + DMat3::from_diagonal(DVec3::splat(mu));
                    if a.determinant().abs() < 1e-300 {
                        mu *= 10.0;
                        continue;
                    }
                    let step = -(a.inverse() * g);
                    let cn = [c[0] + step.x, c[1] + step.y, c[2] + step.z];
                    let rn = residual(cn, goal);
                    if rn.is_finite() && rn.length() < r.length() {
                        c = cn;
                        r = rn;
                        mu = (mu * 0.3).max(1e-12);
                        improved = true;
                        break;
                    }
                    mu *= 10.0;
                }
                if !improved {
                    break;
                }
            }
            last = r.length();
        }
        if last < 0.01 {
            Ok(SigmoidSpectrum { coeffs: c })
        } else {
            Err(AtmosError::NoConvergence {
                what: "Jakob–Hanika reflectance fit",
                detail: format!("ΔE = {last:.4} for rgb {rgb}"),
            })
        }
    }

    /// Fits an unbounded (emission-like) RGB by the pbrt-v4 convention:
    /// `rgb = scale·S`, with `scale = 2·max(rgb)` and `S` the reflectance fit of
    /// `rgb/scale`. Returns `(S, scale)`; black gives scale 0.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for negative or non-finite components, and
    /// [`AtmosError::NoConvergence`](crate::AtmosError::NoConvergence) as
    /// [`Self::fit_reflectance`].
    pub fn fit_unbounded(rgb: DVec3) -> Result<(Self, f64)> {
        if !(rgb.is_finite() && rgb.min_element() >= 0.0) {
            return Err(invalid("rgb", rgb, "components must be finite and >= 0"));
        }
        let m = rgb.max_element();
        if m == 0.0 {
            return Ok((
                SigmoidSpectrum {
                    coeffs: [0.0, 0.0, f64::NEG_INFINITY],
                },
                0.0,
            ));
        }
        let scale = 2.0 * m;
        Ok((Self::fit_reflectance(rgb / scale)?, scale))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn greys_and_primaries_round_trip() {
        for rgb in [
            DVec3::splat(0.5),
            DVec3::splat(0.18),
            DVec3::new(0.8, 0.2, 0.1),
            DVec3::new(0.1, 0.6, 0.2),
            DVec3::new(0.05, 0.1, 0.7),
            DVec3::splat(0.999),
            DVec3::splat(0.001),
        ] {
            let s = SigmoidSpectrum::fit_reflectance(rgb).unwrap();
            let back = s.to_linear_srgb();
            assert!((back - rgb).abs().max_element() < 2e-3, "{rgb} → {back}");
            for l in (360..=830).step_by(10) {
                let v = s.eval(l as f64);
                assert!((0.0..=1.0).contains(&v));
            }
        }
        assert!(SigmoidSpectrum::fit_reflectance(DVec3::new(1.2, 0.0, 0.0)).is_err());
        assert!(SigmoidSpectrum::fit_reflectance(DVec3::new(f64::NAN, 0.0, 0.0)).is_err());
        let (s, scale) = SigmoidSpectrum::fit_unbounded(DVec3::new(3.0, 2.0, 1.0)).unwrap();
        assert!(
            ((s.to_linear_srgb() * scale) - DVec3::new(3.0, 2.0, 1.0))
                .abs()
                .max_element()
                < 0.01
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 40, .. ProptestConfig::default() })]
        /// Moderately saturated reflectances round-trip through the spectrum.
        #[test]
        fn reflectances_round_trip(r in 0.05f64..0.95, g in 0.05f64..0.95, b in 0.05f64..0.95) {
            let rgb = DVec3::new(r, g, b);
            let s = SigmoidSpectrum::fit_reflectance(rgb).unwrap();
            prop_assert!((s.to_linear_srgb() - rgb).abs().max_element() < 3e-3);
        }
    }
}
