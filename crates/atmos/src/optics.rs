//! Refraction and reflection at a smooth interface: Snell's law, Fresnel
//! reflectance per polarisation, critical and Brewster angles, and
//! dispersion models `n(λ)`.
//!
//! Snell: `η₁ sin θ_i = η₂ sin θ_t` (eq. 4.2.1, Musgrave 1993, §4.2.3.1; Tessendorf 2001,
//! §4.1, eq. 40).
//! Fresnel for a dielectric with zero extinction (eqs. 4.2.5-4.2.7,
//! Musgrave 1993, §4.2.3.3): the cosine form is used, which is well defined at normal
//! incidence, unlike the sin/tan form of Tessendorf 2001, §4.2 (eq. 44), which is 0/0 there.
//! Beyond the critical angle the reflectance is exactly 1 (total internal
//! reflection); nothing here ever returns NaN from `asin(> 1)`.
//!
//! Note: the course notes call the water→air critical angle "Brewster's
//! angle" (Tessendorf 2001, §4.2); that is a misnomer, and the two are kept distinct
//! here ([`critical_angle`], [`brewster_angle`]).

use glam::DVec3;

use crate::Dir3;
use crate::error::{AtmosError, Result, positive};

/// Refractive index of air used by Musgrave's rainbow simulation (Musgrave 1993, §4.2.4.3.2).
pub const AIR_MUSGRAVE_RAINBOW: f64 = 1.0003;
/// Refractive index of air "at room temperature and pressure" (Musgrave 1993, §4.3.2).
pub const AIR_ROOM: f64 = 1.00027;

/// Fresnel power reflectances of the two linear polarisations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fresnel {
    /// `r∥²`: reflectance for light polarised in the plane of incidence.
    pub r_par: f64,
    /// `r⊥²`: reflectance for light polarised perpendicular to it.
    pub r_perp: f64,
}

impl Fresnel {
    /// Reflectance of unpolarised light, `(r∥² + r⊥²)/2` (eq. 4.2.7, Musgrave 1993, §4.2.3.3).
    #[inline]
    #[must_use]
    pub fn unpolarized(&self) -> f64 {
        0.5 * (self.r_par + self.r_perp)
    }

    /// Whether this is total internal reflection.
    #[inline]
    #[must_use]
    pub fn is_total(&self) -> bool {
        self.r_par == 1.0 && self.r_perp == 1.0
    }
}

/// Returns the Fresnel reflectances for light going from index `n1` into `n2`
/// at incidence cosine `cos_i` (clamped to `[0, 1]`; its sign is ignored).
///
/// Both indices must be positive (not checked in this inner-loop helper; the
/// models that call it validate their parameters).
#[inline]
#[must_use]
pub fn fresnel(n1: f64, n2: f64, cos_i: f64) -> Fresnel {
    let ci = cos_i.abs().min(1.0);
    let eta = n1 / n2;
    let sin_t2 = eta * eta * (1.0 - ci * ci);
    if sin_t2 >= 1.0 {
        return Fresnel {
            r_par: 1.0,
            r_perp: 1.0,
        };
    }
    let ct = (1.0 - sin_t2).sqrt();
    let rpar = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct);
    let rperp = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
    Fresnel {
        r_par: rpar * rpar,
        r_perp: rperp * rperp,
    }
}

/// Returns the mirror reflection of `d` about the unit normal `n`: `d − 2(d·n)n` (C eq. 37).
#[inline]
#[must_use]
pub fn reflect(d: Dir3, n: Dir3) -> Dir3 {
    let (d, n) = (d.get(), n.get());
    let r = d - 2.0 * d.dot(n) * n;
    Dir3::new(r).unwrap_or(Dir3::UP)
}

/// Returns the refracted direction of `d` entering through a surface with unit
/// normal `n` (either side), where `eta = n_from / n_to`, or `None` on total
/// internal reflection (never NaN).
#[must_use]
pub fn refract(d: Dir3, n: Dir3, eta: f64) -> Option<Dir3> {
    let (d, mut n) = (d.get(), n.get());
    let mut cos_i = -d.dot(n);
    if cos_i < 0.0 {
        n = -n;
        cos_i = -cos_i;
    }
    let sin_t2 = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin_t2 > 1.0 || !eta.is_finite() || eta <= 0.0 {
        return None;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let t: DVec3 = eta * d + (eta * cos_i - cos_t) * n;
    Dir3::new(t).ok()
}

/// Returns the critical angle (from the normal) for light going from `n_from`
/// into the less dense `n_to`, or `None` if `n_to ≥ n_from` (no TIR).
///
/// # Errors
///
/// Returns [`AtmosError::InvalidParameter`] if either index is not finite and positive.
pub fn critical_angle(n_from: f64, n_to: f64) -> Result<Option<f64>> {
    positive("n_from", n_from)?;
    positive("n_to", n_to)?;
    Ok((n_to < n_from).then(|| (n_to / n_from).asin()))
}

/// Returns Brewster's angle `atan(n_to/n_from)` (from the normal), where `r∥ = 0`.
///
/// # Errors
///
/// Returns [`AtmosError::InvalidParameter`] if either index is not finite and positive.
pub fn brewster_angle(n_from: f64, n_to: f64) -> Result<f64> {
    positive("n_from", n_from)?;
    positive("n_to", n_to)?;
    Ok((n_to / n_from).atan())
}

/// Fraunhofer C line (Hα), nm (Musgrave 1993, §4.2.3.2).
pub const FRAUNHOFER_C_NM: f64 = 656.3;
/// Fraunhofer D line (sodium), nm (Musgrave 1993, §4.2.3.2; the source's "hydrogen" attribution is wrong).
pub const FRAUNHOFER_D_NM: f64 = 589.3;
/// Fraunhofer F line (Hβ), nm (Musgrave 1993, §4.2.3.2).
pub const FRAUNHOFER_F_NM: f64 = 486.1;

/// A refractive index as a function of vacuum wavelength in nanometres.
pub trait RefractiveIndex: Send + Sync {
    /// The refractive index at `lambda_nm`.
    fn ior(&self, lambda_nm: f64) -> f64;

    /// The Abbe number `ν = (n_D − 1)/(n_F − n_C)` (Musgrave 1993, §4.2.3.2).
    fn abbe_number(&self) -> f64 {
        (self.ior(FRAUNHOFER_D_NM) - 1.0) / (self.ior(FRAUNHOFER_F_NM) - self.ior(FRAUNHOFER_C_NM))
    }
}

/// Cauchy's two-term dispersion `n(λ) = a + b/λ²`, λ in nm (Musgrave 1993, §4.2.3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Cauchy {
    /// Constant term.
    pub a: f64,
    /// Coefficient of `λ⁻²`, nm².
    pub b_nm2: f64,
}

impl Cauchy {
    /// Musgrave's fit to water (Kaye & Laby), `a = 1.3239`, `b = 3116.3 nm²`
    /// (Musgrave 1993, §4.2.4.3.2), stated valid over 405-670 nm to a few 1e-4 (the source's
    /// "±0.0001, or 0.8%" contradicts itself: 0.0001 is 0.008 %).
    pub const WATER_MUSGRAVE: Cauchy = Cauchy {
        a: 1.3239,
        b_nm2: 3116.3,
    };

    /// A Cauchy model; refuses non-finite or non-positive `a` and negative `b`.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`] for a non-finite or non-positive `a` or a negative or NaN `b`.
    pub fn new(a: f64, b_nm2: f64) -> Result<Self> {
        positive("a", a)?;
        crate::error::non_negative("b_nm2", b_nm2)?;
        Ok(Self { a, b_nm2 })
    }
}

impl RefractiveIndex for Cauchy {
    #[inline]
    fn ior(&self, lambda_nm: f64) -> f64 {
        self.a + self.b_nm2 / (lambda_nm * lambda_nm)
    }
}

/// Musgrave's linear dispersion over normalised frequency (Musgrave 1993, §4.2.4.1), corrected.
///
/// The source's per-surface constant `c_s = (w(η − 1) − η)/0.76` is garbled
/// (it gives `η(0) = 0`). The consistent linear model is
/// `η(f) = η_red + f·w(η_red − 1)/κ`, with `f ∈ [0, 1]` running from the red to
/// the violet end of the sampled range, `w` the dispersive power and `κ` the
/// fraction of the range between the C and F lines (0.76 "per source";
/// 0.405 in wavelength or 0.386 in frequency for 380-800 nm).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LinearAbbe {
    /// Index at the red end.
    pub n_red: f64,
    /// Dispersive power `w = (n_F − n_C)/(n_D − 1)` (eq. 4.2.2).
    pub dispersive_power: f64,
    /// C–F fraction of the normalised range (0.76 in the source).
    pub kappa: f64,
}

impl LinearAbbe {
    /// A linear model; refuses non-positive `n_red`/`kappa` or negative power.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`] for a non-positive `n_red` or `kappa` or a negative
    /// dispersive power.
    pub fn new(n_red: f64, dispersive_power: f64, kappa: f64) -> Result<Self> {
        positive("n_red", n_red)?;
        crate::error::non_negative("dispersive_power", dispersive_power)?;
        positive("kappa", kappa)?;
        Ok(Self {
            n_red,
            dispersive_power,
            kappa,
        })
    }

    /// Index at normalised frequency `f` (0 = red end, 1 = violet end).
    #[inline]
    #[must_use]
    pub fn ior_at(&self, f: f64) -> f64 {
        self.n_red + f * self.dispersive_power * (self.n_red - 1.0) / self.kappa
    }
}

/// Checks an index of refraction.
pub(crate) fn check_ior(name: &'static str, n: f64) -> Result<f64> {
    if n.is_finite() && n >= 1e-3 {
        Ok(n)
    } else {
        Err(AtmosError::InvalidParameter {
            name,
            value: format!("{n}"),
            reason: "refractive index must be finite and positive",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The sin/tan form (C eq. 44) as an independent oracle.
    fn fresnel_sin_tan(n1: f64, n2: f64, ti: f64) -> f64 {
        let tt = (n1 / n2 * ti.sin()).asin();
        let a = (tt - ti).sin().powi(2) / (tt + ti).sin().powi(2);
        let b = (tt - ti).tan().powi(2) / (tt + ti).tan().powi(2);
        0.5 * (a + b)
    }

    #[test]
    fn known_values() {
        // Normal incidence.
        assert!((fresnel(1.0, 1.333, 1.0).unpolarized() - 0.020_37).abs() < 1e-5);
        assert!((fresnel(1.0, 1.34, 1.0).unpolarized() - 0.021_11).abs() < 1e-5);
        // Brewster (r∥ = 0) and critical angle.
        let b = brewster_angle(1.0, 1.333).unwrap();
        assert!((b.to_degrees() - 53.12).abs() < 0.01);
        assert!(fresnel(1.0, 1.333, b.cos()).r_par < 1e-20);
        let c = critical_angle(1.333, 1.0).unwrap().unwrap();
        assert!((c.to_degrees() - 48.61).abs() < 0.01);
        assert!(critical_angle(1.0, 1.333).unwrap().is_none());
        assert!(fresnel(1.333, 1.0, (c + 1e-9).cos()).is_total());
        assert!(!fresnel(1.333, 1.0, (c - 1e-9).cos()).is_total());
        assert!(critical_angle(f64::NAN, 1.0).is_err());
        // Musgrave's water.
        let w = Cauchy::WATER_MUSGRAVE;
        assert!((w.ior(656.3) - 1.33113).abs() < 1e-5);
        assert!((w.ior(589.3) - 1.33287).abs() < 1e-5);
        assert!((w.ior(486.1) - 1.33709).abs() < 1e-5);
        assert!((w.abbe_number() - 55.9).abs() < 0.1);
        assert!(
            (w.abbe_number() - 55.7).abs() < 0.5,
            "source says water 55.7"
        );
    }

    #[test]
    fn water_fit_against_tabulated_values() {
        // Refractive index of pure water at 20 °C (Daimon & Masumura 2007,
        // Appl. Opt. 46, 3811), at wavelengths inside the fit's 405-670 nm range.
        let table = [
            (404.7, 1.34283),
            (486.1, 1.33713),
            (546.1, 1.33445),
            (589.3, 1.33299),
            (656.3, 1.33115),
        ];
        for (l, n) in table {
            let e = (Cauchy::WATER_MUSGRAVE.ior(l) - n).abs();
            assert!(e < 3e-4, "{l} nm: {e}");
        }
    }

    #[test]
    fn linear_abbe_corrected() {
        // η(0) = η_red; F − C difference = w(η_D − 1) within the linearisation.
        let m = LinearAbbe::new(1.5, 1.0 / 60.0, 0.76).unwrap();
        assert_eq!(m.ior_at(0.0), 1.5);
        let df = m.ior_at(0.76) - m.ior_at(0.0);
        assert!((df - m.dispersive_power * (1.5 - 1.0)).abs() < 1e-15);
    }

    proptest! {
        /// Energy, bounds, reciprocity, and the two Fresnel forms agree.
        #[test]
        fn fresnel_properties(n1 in 1.0f64..2.0, n2 in 1.0f64..2.0, ti in 0.01f64..1.5) {
            let f = fresnel(n1, n2, ti.cos());
            let r = f.unpolarized();
            prop_assert!((0.0..=1.0).contains(&r));
            let st = n1 / n2 * ti.sin();
            if st < 1.0 {
                let tt = st.asin();
                let back = fresnel(n2, n1, tt.cos()).unpolarized();
                prop_assert!((back - r).abs() < 1e-12);
                if (n1 - n2).abs() > 1e-3 {
                    prop_assert!((fresnel_sin_tan(n1, n2, ti) - r).abs() < 1e-12);
                }
            } else {
                prop_assert!(f.is_total());
            }
        }

        /// Refraction gives a unit vector obeying Snell; TIR gives None.
        #[test]
        fn refraction_obeys_snell(n1 in 1.0f64..2.0, n2 in 1.0f64..2.0, ti in 0.0f64..1.55, ph in 0.0f64..std::f64::consts::TAU) {
            let n = Dir3::UP;
            let d = Dir3::new(DVec3::new(ti.sin() * ph.cos(), ti.sin() * ph.sin(), -ti.cos())).unwrap();
            match refract(d, n, n1 / n2) {
                Some(t) => {
                    prop_assert!((t.get().length() - 1.0).abs() < 1e-14);
                    let sin_t = t.get().truncate().length();
                    prop_assert!((n1 * ti.sin() - n2 * sin_t).abs() < 1e-12);
                    prop_assert!(t.get().z < 0.0);
                }
                None => prop_assert!(n1 * ti.sin() > n2 * (1.0 - 1e-12)),
            }
            let r = reflect(d, n);
            prop_assert!((r.get().z + d.get().z).abs() < 1e-15);
        }
    }
}
