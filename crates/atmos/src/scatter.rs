//! Scattering by molecules and aerosols: phase functions (normalised so that
//! `∫ p dω = 1` over the sphere) and the physical Rayleigh coefficient.
//!
//! Conventions differ between the sources: the dissertation's
//! `¾(1 + cos²θ)` (Musgrave 1993, §4.1.2) has mean 1 (integral 4π), and the course notes'
//! Henyey–Greenstein (Fedkiw et al. 2001, §5, eq. 12) omits `1/(4π)`. Here every phase
//! function is `1/(4π)`-normalised.

use std::f64::consts::PI;

use crate::error::{Result, in_range, positive};

/// The isotropic phase function `1/(4π)`.
pub const ISOTROPIC: f64 = 1.0 / (4.0 * PI);

/// Rayleigh phase `3(1 + cos²θ)/(16π)` (Musgrave 1993, §4.1.2 with the `1/(4π)` normalisation).
#[inline]
#[must_use]
pub fn rayleigh_phase(cos_theta: f64) -> f64 {
    3.0 / (16.0 * PI) * (1.0 + cos_theta * cos_theta)
}

/// The Henyey–Greenstein phase, written once for `f64` and `f32`.
macro_rules! henyey_greenstein_fn {
    ($(#[$doc:meta])* $name:ident, $f:ident) => {
        $(#[$doc])*
        #[inline]
        #[must_use]
        pub fn $name(g: $f, cos_theta: $f) -> $f {
            // `1 + g² − 2g cosθ ≥ (1 − |g|)² > 0` exactly; rounding can reach
            // zero as `|g| → 1`, so the denominator is kept off it.
            let d = (1.0 + g * g - 2.0 * g * cos_theta).max(1e-12);
            (1.0 - g * g) / (4.0 * core::$f::consts::PI * d * d.sqrt())
        }
    };
}

henyey_greenstein_fn!(
    /// Henyey–Greenstein phase `(1 − g²)/(4π(1 + g² − 2g cosθ)^{3/2})` (Henyey &
    /// Greenstein 1941, eq. 3; Fedkiw et al. 2001, §5, eq. 12, which omits the `1/(4π)`).
    henyey_greenstein,
    f64
);
henyey_greenstein_fn!(
    /// [`henyey_greenstein`] in `f32`, for renderers' inner loops (natura-volume's
    /// phase functions build on it).
    henyey_greenstein_f32,
    f32
);

/// Cornette–Shanks phase `3(1 − g²)(1 + cos²θ)/(8π(2 + g²)(1 + g² − 2g cosθ)^{3/2})`
/// (Cornette & Shanks, Appl. Opt. 31(16), 1992): a better Mie fit than HG that
/// tends to the Rayleigh phase as `g → 0`.
#[inline]
#[must_use]
pub fn cornette_shanks(g: f64, cos_theta: f64) -> f64 {
    let d = 1.0 + g * g - 2.0 * g * cos_theta;
    3.0 * (1.0 - g * g) * (1.0 + cos_theta * cos_theta) / (8.0 * PI * (2.0 + g * g) * d * d.sqrt())
}

/// A phase function, evaluated on the cosine of the scattering angle
/// (the angle between the propagation directions before and after).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Phase {
    /// `1/(4π)`.
    Isotropic,
    /// [`rayleigh_phase`].
    Rayleigh,
    /// [`henyey_greenstein`] with asymmetry `g ∈ (−1, 1)`.
    HenyeyGreenstein(f64),
    /// [`cornette_shanks`] with asymmetry `g ∈ (−1, 1)`.
    CornetteShanks(f64),
}

impl Phase {
    /// Refuses `|g| ≥ 1` or NaN.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `|g| ≥ 1` or `g` is NaN.
    pub fn validate(&self) -> Result<()> {
        match *self {
            Phase::HenyeyGreenstein(g) | Phase::CornetteShanks(g) => {
                in_range(
                    "g",
                    g,
                    -0.999_999,
                    0.999_999,
                    "asymmetry must lie in (−1, 1)",
                )?;
            }
            Phase::Isotropic | Phase::Rayleigh => {}
        }
        Ok(())
    }

    /// The phase function at `cos_theta`, per steradian.
    #[inline]
    #[must_use]
    pub fn eval(&self, cos_theta: f64) -> f64 {
        match *self {
            Phase::Isotropic => ISOTROPIC,
            Phase::Rayleigh => rayleigh_phase(cos_theta),
            Phase::HenyeyGreenstein(g) => henyey_greenstein(g, cos_theta),
            Phase::CornetteShanks(g) => cornette_shanks(g, cos_theta),
        }
    }
}

/// Returns the Rayleigh scattering coefficient `β = 8π³(n² − 1)²/(3Nλ⁴)·F_K` in m⁻¹
/// at `lambda_nm`, for refractive index `n = 1 + n_minus_1`, molecular number
/// density `number_density` (m⁻³) and King correction factor `king`.
///
/// This is eq. 4.0's angular coefficient integrated over the sphere (Musgrave 1993,
/// §4.1.2). With `n` held fixed the coefficient follows λ⁻⁴ exactly. With
/// `n − 1 = 0.0003`, `N = 2.545e25` and `F_K = 1` it is 1.28e-5 m⁻¹ at 550 nm.
/// The coefficient scales with the local density as `β₀ρ/ρ₀`: do not
/// divide by the local `N` while holding `n` fixed (that would count the density twice).
///
/// # Errors
///
/// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if any argument is not finite and positive.
pub fn rayleigh_coefficient(
    lambda_nm: f64,
    n_minus_1: f64,
    number_density: f64,
    king: f64,
) -> Result<f64> {
    positive("lambda_nm", lambda_nm)?;
    positive("n_minus_1", n_minus_1)?;
    positive("number_density", number_density)?;
    positive("king", king)?;
    let n2m1 = n_minus_1 * (2.0 + n_minus_1);
    let l = lambda_nm * 1e-9;
    Ok(8.0 * PI.powi(3) * n2m1 * n2m1 / (3.0 * number_density * l.powi(4)) * king)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::integrate;

    fn sphere_integral(p: impl Fn(f64) -> f64) -> f64 {
        // ∫ p dω = 2π ∫_{-1}^{1} p(μ) dμ.
        2.0 * PI * integrate(p, -1.0, 1.0, 1e-13, 40)
    }

    #[test]
    fn phase_functions_integrate_to_one() {
        assert!((sphere_integral(|_| ISOTROPIC) - 1.0).abs() < 1e-12);
        assert!((sphere_integral(rayleigh_phase) - 1.0).abs() < 1e-12);
        // D's convention ¾(1 + cos²θ) integrates to 4π.
        assert!(
            (2.0 * PI * integrate(|m| 0.75 * (1.0 + m * m), -1.0, 1.0, 1e-13, 30) - 4.0 * PI).abs()
                < 1e-11
        );
        for g in [-0.7, 0.0, 0.3, 0.76, 0.9, 0.99] {
            let hg = sphere_integral(|m| henyey_greenstein(g, m));
            let cs = sphere_integral(|m| cornette_shanks(g, m));
            assert!((hg - 1.0).abs() < 1e-9, "HG g={g}: {hg}");
            assert!((cs - 1.0).abs() < 1e-9, "CS g={g}: {cs}");
            // HG's mean cosine is g.
            let mean = 2.0 * PI * integrate(|m| m * henyey_greenstein(g, m), -1.0, 1.0, 1e-13, 40);
            assert!((mean - g).abs() < 1e-9);
        }
        assert!((cornette_shanks(0.0, 0.3) - rayleigh_phase(0.3)).abs() < 1e-15);
        assert!(Phase::HenyeyGreenstein(1.0).validate().is_err());
        assert!(Phase::CornetteShanks(f64::NAN).validate().is_err());
        assert!(Phase::CornetteShanks(0.8).validate().is_ok());
    }

    /// Eq. 4.0 (Musgrave 1993, §4.1.2) divides by the number density `N`;
    /// since `n − 1` is itself proportional to `N`, the coefficient grows
    /// with density: at a fraction `q` of the reference density it is
    /// `q·β₀` (to the size of `n − 1`, from `(n² − 1)² = (n − 1)²(n + 1)²`).
    /// Dividing by the local `N` while holding `n` fixed, the reading the
    /// equation invites, would give `β₀/q` instead.
    #[test]
    fn rayleigh_grows_with_density_not_against_it() {
        let (n1, big_n) = (2.9e-4, 2.545e25);
        let b0 = rayleigh_coefficient(550.0, n1, big_n, 1.0).unwrap();
        for q in [0.05, 0.37, 1.0, 1.8] {
            let physical = rayleigh_coefficient(550.0, q * n1, q * big_n, 1.0).unwrap();
            assert!(
                (physical / (q * b0) - 1.0).abs() < 1e-3,
                "q {q}: {physical} vs {}",
                q * b0
            );
            let misread = rayleigh_coefficient(550.0, n1, q * big_n, 1.0).unwrap();
            assert!((misread / (b0 / q) - 1.0).abs() < 1e-12);
            if q != 1.0 {
                assert!((misread / physical - 1.0).abs() > 0.5);
            }
        }
    }

    #[test]
    fn rayleigh_follows_inverse_fourth_power() {
        let b550 = rayleigh_coefficient(550.0, 3e-4, 2.545e25, 1.0).unwrap();
        assert!((b550 - 1.28e-5).abs() < 0.01e-5, "{b550}");
        for l in [380.0, 440.0, 680.0, 800.0] {
            let b = rayleigh_coefficient(l, 3e-4, 2.545e25, 1.0).unwrap();
            let ratio = b / b550;
            let expect = (550.0f64 / l).powi(4);
            assert!((ratio - expect).abs() < 1e-13 * expect, "{l}");
        }
        assert!(rayleigh_coefficient(-1.0, 3e-4, 2.545e25, 1.0).is_err());
        assert!(rayleigh_coefficient(550.0, f64::NAN, 2.545e25, 1.0).is_err());
    }
}
