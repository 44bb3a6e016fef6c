//! CIE 1931 2° colorimetry: colour-matching functions (tabulated and the
//! Wyman–Sloan–Shirley 2013 fit), illuminants D65 and E, XYZ ↔ linear sRGB,
//! and Bradford chromatic adaptation.

use glam::{DMat3, DVec3};

use super::cie_data::{CMF_1931, D65_SPD, TABLE_MAX_NM, TABLE_MIN_NM};
use crate::error::{AtmosError, Result, positive};

/// Returns the tabulated CIE 1931 2° colour-matching functions `(x̄, ȳ, z̄)` at
/// `lambda_nm`, linearly interpolated in the 1 nm table (CIE 015:2018), or an
/// error outside 360–830 nm or for NaN.
///
/// # Errors
///
/// Returns [`AtmosError::WavelengthOutOfRange`]
/// outside 360–830 nm or for NaN.
pub fn cmf_1931(lambda_nm: f64) -> Result<DVec3> {
    table_lerp(lambda_nm).map(|(i, f)| {
        let a = DVec3::from(CMF_1931[i]);
        let b = DVec3::from(CMF_1931[(i + 1).min(CMF_1931.len() - 1)]);
        a.lerp(b, f)
    })
}

fn table_lerp(lambda_nm: f64) -> Result<(usize, f64)> {
    if !(TABLE_MIN_NM..=TABLE_MAX_NM).contains(&lambda_nm) {
        return Err(AtmosError::WavelengthOutOfRange {
            nm: lambda_nm,
            min: TABLE_MIN_NM,
            max: TABLE_MAX_NM,
        });
    }
    let x = lambda_nm - TABLE_MIN_NM;
    let i = (x.floor() as usize).min(CMF_1931.len() - 1);
    Ok((i, x - i as f64))
}

/// Returns the Wyman, Sloan & Shirley (JCGT 2(2), 2013) multi-lobe Gaussian fit
/// to the CIE 1931 2° colour-matching functions at any wavelength (nm).
///
/// A fast path and fallback outside the table; its error against the table is
/// at most about 0.02 (measured in this crate's tests).
#[inline]
#[must_use]
pub fn cmf_wyman_2013(lambda_nm: f64) -> DVec3 {
    #[inline]
    fn g(l: f64, mu: f64, s1: f64, s2: f64) -> f64 {
        let t = (l - mu) / if l < mu { s1 } else { s2 };
        (-0.5 * t * t).exp()
    }
    let l = lambda_nm;
    DVec3::new(
        1.056 * g(l, 599.8, 37.9, 31.0) + 0.362 * g(l, 442.0, 16.0, 26.7)
            - 0.065 * g(l, 501.1, 20.4, 26.2),
        0.821 * g(l, 568.8, 46.9, 40.5) + 0.286 * g(l, 530.9, 16.3, 31.1),
        1.217 * g(l, 437.0, 11.8, 36.0) + 0.681 * g(l, 459.0, 26.0, 13.8),
    )
}

/// A standard illuminant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Illuminant {
    /// CIE standard illuminant D65 (average daylight; the sRGB white).
    D65,
    /// The equal-energy illuminant E (flat spectrum).
    E,
}

impl Illuminant {
    /// Relative spectral power at `lambda_nm` (D65: 100 at 560 nm, table 360–830 nm;
    /// E: 100 everywhere).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`] for a non-positive or NaN wavelength and
    /// [`AtmosError::WavelengthOutOfRange`] outside
    /// the D65 table.
    pub fn spd(self, lambda_nm: f64) -> Result<f64> {
        match self {
            Illuminant::E => {
                positive("lambda_nm", lambda_nm)?;
                Ok(100.0)
            }
            Illuminant::D65 => table_lerp(lambda_nm).map(|(i, f)| {
                let a = D65_SPD[i];
                let b = D65_SPD[(i + 1).min(D65_SPD.len() - 1)];
                a + (b - a) * f
            }),
        }
    }

    /// The white point XYZ with `Y = 1`, integrated from the tables at 1 nm.
    #[must_use]
    pub fn white_xyz(self) -> DVec3 {
        let mut xyz = DVec3::ZERO;
        for (i, c) in CMF_1931.iter().enumerate() {
            let s = match self {
                Illuminant::E => 1.0,
                Illuminant::D65 => D65_SPD[i],
            };
            xyz += DVec3::from(*c) * s;
        }
        xyz / xyz.y
    }
}

/// Returns `∫ s(λ)·(x̄, ȳ, z̄)(λ) dλ / ∫ ȳ dλ` over 360–830 nm with the table
/// CMFs and step `step_nm` (midpoint rule), so that a flat spectrum of value 1
/// has `Y = 1`.
///
/// # Errors
///
/// Returns [`AtmosError::InvalidParameter`] for a non-positive or NaN `step_nm`.
pub fn spectrum_to_xyz(s: impl Fn(f64) -> f64, step_nm: f64) -> Result<DVec3> {
    positive("step_nm", step_nm)?;
    let n = ((TABLE_MAX_NM - TABLE_MIN_NM) / step_nm).round().max(1.0) as usize;
    let h = (TABLE_MAX_NM - TABLE_MIN_NM) / n as f64;
    let mut xyz = DVec3::ZERO;
    let mut ysum = 0.0;
    for i in 0..=n {
        let l = TABLE_MIN_NM + i as f64 * h;
        // Trapezoid weights: exact sums of the 1 nm table when h = 1.
        let w = if i == 0 || i == n { 0.5 } else { 1.0 };
        let c = cmf_1931(l)?;
        xyz += c * (w * s(l));
        ysum += w * c.y;
    }
    Ok(xyz / ysum)
}

/// Chromaticity `(x, y)` of `xyz` (`(0, 0)` for black).
#[must_use]
pub fn xyz_to_xy(xyz: DVec3) -> (f64, f64) {
    let s = xyz.x + xyz.y + xyz.z;
    if s == 0.0 {
        (0.0, 0.0)
    } else {
        (xyz.x / s, xyz.y / s)
    }
}

/// XYZ → linear sRGB (IEC 61966-2-1, D65 white).
pub const XYZ_TO_SRGB: DMat3 = DMat3::from_cols_array(&[
    3.240_454_2,
    -0.969_266,
    0.055_643_4,
    -1.537_138_5,
    1.876_010_8,
    -0.204_025_9,
    -0.498_531_4,
    0.041_556,
    1.057_225_2,
]);

/// Linear sRGB → XYZ (the inverse of [`XYZ_TO_SRGB`]).
pub const SRGB_TO_XYZ: DMat3 = DMat3::from_cols_array(&[
    0.412_456_4,
    0.212_672_9,
    0.019_333_9,
    0.357_576_1,
    0.715_152_2,
    0.119_192,
    0.180_437_5,
    0.072_175,
    0.950_304_1,
]);

/// Converts XYZ (D65-referred) to linear sRGB. Negative components mean out of gamut
/// and are kept (clip or desaturate explicitly if needed).
#[inline]
#[must_use]
pub fn xyz_to_linear_srgb(xyz: DVec3) -> DVec3 {
    XYZ_TO_SRGB * xyz
}

/// Converts linear sRGB to XYZ (D65-referred).
#[inline]
#[must_use]
pub fn linear_srgb_to_xyz(rgb: DVec3) -> DVec3 {
    SRGB_TO_XYZ * rgb
}

/// The Bradford cone-response matrix (Lam 1985).
const BRADFORD: DMat3 = DMat3::from_cols_array(&[
    0.8951, -0.7502, 0.0389, 0.2664, 1.7135, -0.0685, -0.1614, 0.0367, 1.0296,
]);

/// Returns the Bradford chromatic-adaptation matrix taking XYZ colours seen
/// under white `from_white` to the corresponding colours under `to_white`.
///
/// # Errors
///
/// Returns [`AtmosError::InvalidParameter`] if either white has a non-positive or non-finite component.
pub fn bradford(from_white: DVec3, to_white: DVec3) -> Result<DMat3> {
    for (name, w) in [("from_white", from_white), ("to_white", to_white)] {
        if !(w.is_finite() && w.min_element() > 0.0) {
            return Err(crate::error::invalid(
                name,
                w,
                "white point components must be finite and > 0",
            ));
        }
    }
    let s = BRADFORD * from_white;
    let d = BRADFORD * to_white;
    let scale = DMat3::from_diagonal(d / s);
    Ok(BRADFORD.inverse() * scale * BRADFORD)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cmfs_integrate_as_tabulated() {
        // Y of E at 1 nm equals the table's normalisation Σȳ = 106.857 (CIE 015).
        let ysum: f64 = CMF_1931.iter().map(|c| c[1]).sum();
        assert!((ysum - 106.857).abs() < 1e-3);
        let e = spectrum_to_xyz(|_| 1.0, 1.0).unwrap();
        assert!((e.y - 1.0).abs() < 1e-12);
        // Flat spectrum has x = y = 1/3.
        let (x, y) = xyz_to_xy(e);
        assert!(
            (x - 1.0 / 3.0).abs() < 1e-3 && (y - 1.0 / 3.0).abs() < 1e-3,
            "{x} {y}"
        );
        assert!(
            cmf_1931(359.0).is_err() && cmf_1931(f64::NAN).is_err() && cmf_1931(831.0).is_err()
        );
        assert!((cmf_1931(555.0).unwrap().y - 1.0).abs() < 1e-3);
    }

    #[test]
    fn wyman_fit_matches_table() {
        let mut max_err: f64 = 0.0;
        let mut sums = DVec3::ZERO;
        for l in 360..=830 {
            let t = cmf_1931(l as f64).unwrap();
            let f = cmf_wyman_2013(l as f64);
            max_err = max_err.max((t - f).abs().max_element());
            sums += f;
        }
        assert!(max_err < 0.025, "max abs error {max_err}");
        // Spec §6.6: 1 nm sums 106.77 / 106.92 / 106.88.
        assert!(
            (sums - DVec3::new(106.77, 106.92, 106.88))
                .abs()
                .max_element()
                < 0.02,
            "{sums}"
        );
        let (x, y) = xyz_to_xy(sums);
        assert!((x - 0.3331).abs() < 2e-4 && (y - 0.3335).abs() < 2e-4);
    }

    #[test]
    fn srgb_white_points_and_adaptation() {
        // D65 white → (1, 1, 1).
        let d65 = DVec3::new(0.95047, 1.0, 1.08883);
        let rgb = xyz_to_linear_srgb(d65);
        assert!((rgb - DVec3::ONE).abs().max_element() < 1e-6, "{rgb}");
        // The D65 SPD integrated through the table CMFs: white within 1%.
        let w = Illuminant::D65.white_xyz();
        let rgbw = xyz_to_linear_srgb(w);
        assert!((rgbw - DVec3::ONE).abs().max_element() < 0.01, "{rgbw}");
        // E is pink unadapted, white after Bradford E → D65.
        let e = Illuminant::E.white_xyz();
        let pink = xyz_to_linear_srgb(e);
        assert!(
            (pink - DVec3::new(1.200, 0.950, 0.908)).abs().max_element() < 6e-3,
            "{pink}"
        );
        let m = bradford(e, w).unwrap();
        let adapted = xyz_to_linear_srgb(m * e);
        assert!(
            (adapted - DVec3::ONE).abs().max_element() < 0.01,
            "{adapted}"
        );
        assert!(bradford(DVec3::ZERO, w).is_err());
        // Round trip of the matrices.
        let v = DVec3::new(0.2, 0.5, 0.9);
        assert!(
            (linear_srgb_to_xyz(xyz_to_linear_srgb(v)) - v)
                .abs()
                .max_element()
                < 1e-6
        );
    }

    #[test]
    fn monochromatic_colours_are_out_of_gamut() {
        // Every λ in 400-700 nm has a negative linear-sRGB component.
        for l in 400..=700 {
            let rgb = xyz_to_linear_srgb(cmf_1931(l as f64).unwrap());
            assert!(rgb.min_element() < 0.0, "{l}: {rgb}");
        }
        let g = xyz_to_linear_srgb(cmf_1931(500.0).unwrap());
        let g = g / g.max_element();
        assert!(g.x < -0.9 && g.z > 0.2, "{g}");
        // λ⁻⁴ over 380-780 nm is in gamut and blue.
        let xyz = spectrum_to_xyz(
            |l| {
                if (380.0..=780.0).contains(&l) {
                    (550.0 / l).powi(4)
                } else {
                    0.0
                }
            },
            1.0,
        )
        .unwrap();
        let (x, y) = xyz_to_xy(xyz);
        assert!(
            (x - 0.240).abs() < 0.003 && (y - 0.234).abs() < 0.003,
            "{x} {y}"
        );
        let rgb = xyz_to_linear_srgb(xyz);
        assert!(rgb.min_element() > 0.0 && rgb.z > rgb.y && rgb.y > rgb.x);
    }
}
