//! Aerial perspective: participating media along straight segments.
//!
//! Every model implements one trait, [`Medium`], in `f64`: the per-channel
//! optical depth τ along a segment (or a ray to infinity), the transmittance
//! `σ = e^{−τ}` (eq. 4.1.1, Musgrave 1993, §4.1.4) and Musgrave's Beer-law blend
//! `I = σ·I_s + (1 − σ)·I_a` (eq. 4.1.2, Musgrave 1993, §4.1.4) as an [`Attenuation`].
//!
//! | model | source | optical depth |
//! |---|---|---|
//! | [`HomogeneousFog`] | Musgrave 1993, §4.1.4 | `ε·δ` |
//! | [`ExponentialMist`] | Musgrave 1993, §4.1.5 | closed form with `(1 − e^{−x})/x`, exact for horizontal rays |
//! | [`RadialAtmosphere`] | Musgrave 1993, §4.1.6–4.1.6.4 | exact Gaussian-radial line integral with `erf`/`erfcx` |
//! | [`Umbra`] | Musgrave 1993, §4.1.6.5 | day/night media switched on a shadow cylinder |
//! | [`FogSheet`] | Musgrave 1993, Plate 5.1 ("Bay Fog") | a texture at the plane's crossing times the length below it |
//!
//! Colours are linear RGB `DVec3` (or any three channels); each channel has its
//! own extinction, which is all of Musgrave's Rayleigh approximation
//! ([`RayleighRgb`], Musgrave 1993, §4.1.7).

/// Implements [`Medium`] for a Beer-law model from its column `∫ρ ds` (the
/// inherent methods `column` and `column_to_infinity`) and its `beer`
/// parameters: `τ = ε̄·column` per channel, blended towards the fog colour
/// (eqs. 4.1.1–4.1.2, Musgrave 1993, §4.1.4). Written once for every such model.
macro_rules! beer_medium {
    ($ty:ty) => {
        impl $crate::medium::Medium for $ty {
            fn optical_depth(&self, a: DVec3, b: DVec3) -> DVec3 {
                $crate::medium::scale_column(self.beer.extinction, self.column(a, b))
            }

            fn optical_depth_to_infinity(&self, origin: DVec3, dir: $crate::Dir3) -> DVec3 {
                $crate::medium::scale_column(
                    self.beer.extinction,
                    self.column_to_infinity(origin, dir),
                )
            }

            fn attenuation(&self, a: DVec3, b: DVec3) -> $crate::medium::Attenuation {
                $crate::medium::Attenuation::beer(self.optical_depth(a, b), self.beer.fog_colour)
            }

            fn attenuation_to_infinity(
                &self,
                origin: DVec3,
                dir: $crate::Dir3,
            ) -> $crate::medium::Attenuation {
                $crate::medium::Attenuation::beer(
                    self.optical_depth_to_infinity(origin, dir),
                    self.beer.fog_colour,
                )
            }
        }
    };
}

mod exponential;
mod fog_sheet;
mod homogeneous;
mod radial;
mod umbra;

pub use exponential::ExponentialMist;
pub use fog_sheet::FogSheet;
pub use homogeneous::HomogeneousFog;
pub use radial::RadialAtmosphere;
pub use umbra::Umbra;

use glam::DVec3;

use crate::Dir3;
use crate::error::{Result, non_negative3};

/// What a medium does to light along a segment: `L_eye = T·L_far + S`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attenuation {
    /// Per-channel transmittance `σ = e^{−τ}` in `[0, 1]`.
    pub transmittance: DVec3,
    /// Per-channel radiance added along the segment (`(1 − σ)·I_a` for Beer fog).
    pub in_scatter: DVec3,
}

impl Attenuation {
    /// No medium: transmittance 1, nothing added.
    pub const NONE: Attenuation = Attenuation {
        transmittance: DVec3::ONE,
        in_scatter: DVec3::ZERO,
    };

    /// Musgrave's Beer blend for optical depth `tau` and fog colour `fog` (Musgrave 1993, §4.1.4).
    #[inline]
    #[must_use]
    pub fn beer(tau: DVec3, fog: DVec3) -> Self {
        let t = exp_neg(tau);
        Attenuation {
            transmittance: t,
            in_scatter: (DVec3::ONE - t) * fog,
        }
    }

    /// Returns the radiance reaching the eye when `surface` lies behind the segment.
    #[inline]
    #[must_use]
    pub fn apply(&self, surface: DVec3) -> DVec3 {
        self.transmittance * surface + self.in_scatter
    }

    /// Returns this (nearer) segment followed by `farther`: `T = T₁T₂`, `S = S₁ + T₁S₂`.
    #[inline]
    #[must_use]
    pub fn then(self, farther: Attenuation) -> Attenuation {
        Attenuation {
            transmittance: self.transmittance * farther.transmittance,
            in_scatter: self.in_scatter + self.transmittance * farther.in_scatter,
        }
    }
}

/// `e^{−τ}` per channel, with `e^{−∞} = 0`.
#[inline]
pub(crate) fn exp_neg(tau: DVec3) -> DVec3 {
    DVec3::new((-tau.x).exp(), (-tau.y).exp(), (-tau.z).exp())
}

/// `ε·column` per channel, with `0·∞ = 0` (a channel without extinction stays clear).
#[inline]
pub(crate) fn scale_column(extinction: DVec3, column: f64) -> DVec3 {
    let f = |e: f64| if e == 0.0 { 0.0 } else { e * column };
    DVec3::new(f(extinction.x), f(extinction.y), f(extinction.z))
}

/// A participating medium seen along straight lines, in `f64` world units
/// (metres, z up).
///
/// Points are world positions; `a == b` gives zero optical depth. Implementors
/// must return finite, non-negative optical depths for finite segments and
/// may return `+∞` only for infinite rays.
pub trait Medium: Send + Sync {
    /// Per-channel optical depth τ along the segment `a → b` (symmetric in `a`, `b`).
    fn optical_depth(&self, a: DVec3, b: DVec3) -> DVec3;

    /// Per-channel optical depth from `origin` along `dir` until the ray leaves
    /// the medium or meets an opaque body the medium models (a planet); `+∞`
    /// where it never ends (a horizontal ray in flat exponential mist).
    fn optical_depth_to_infinity(&self, origin: DVec3, dir: Dir3) -> DVec3;

    /// What the segment `a → b` (a the eye) does to light from `b`.
    fn attenuation(&self, a: DVec3, b: DVec3) -> Attenuation;

    /// What the ray from `origin` along `dir` does to a background at infinity.
    fn attenuation_to_infinity(&self, origin: DVec3, dir: Dir3) -> Attenuation;

    /// Per-channel transmittance `e^{−τ}` along `a → b`, in `[0, 1]`.
    fn transmittance(&self, a: DVec3, b: DVec3) -> DVec3 {
        exp_neg(self.optical_depth(a, b))
    }

    /// Returns `surface` (radiance leaving `b` towards `a`) as seen from `a`.
    fn composite(&self, a: DVec3, b: DVec3, surface: DVec3) -> DVec3 {
        self.attenuation(a, b).apply(surface)
    }
}

/// Extinction coefficient and fog colour shared by the Beer-law models.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BeerParams {
    /// Per-channel extinction coefficient ε̄ at reference density, per metre (Musgrave 1993, §4.1.4, §4.1.7).
    pub extinction: DVec3,
    /// The fog colour `I_a` that distant objects fade to (Musgrave 1993, §4.1.4).
    pub fog_colour: DVec3,
}

impl BeerParams {
    /// Refuses negative or non-finite extinction or colour.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for negative or non-finite extinction or colour.
    pub fn validate(&self) -> Result<()> {
        non_negative3("extinction", self.extinction)?;
        non_negative3("fog_colour", self.fog_colour)?;
        Ok(())
    }
}

/// Musgrave's per-channel "Rayleigh" extinction vectors (Musgrave 1993, §4.1.7).
///
/// The source's ratio 1 : 3 : 20 is said to be the λ⁻⁴ of 800, 500 and 380 nm
/// (Musgrave 1993, §4.1.7); those wavelengths actually give 1 : 6.55 : 19.64 (an
/// erratum of the source), so both are offered.
#[derive(Clone, Copy, Debug)]
pub struct RayleighRgb;

impl RayleighRgb {
    /// The source's extinction vector `k·(1, 3, 20)` (Musgrave 1993, §4.1.7).
    #[must_use]
    pub fn musgrave_1_3_20(k: f64) -> DVec3 {
        DVec3::new(1.0, 3.0, 20.0) * k
    }

    /// `k·(λ_r/λ_r, (λ_r/λ_g)⁴, (λ_r/λ_b)⁴)`: true λ⁻⁴ ratios, red normalised to `k`.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if a wavelength is not finite and positive or `k` is
    /// negative.
    pub fn from_wavelengths(lambda_nm: [f64; 3], k: f64) -> Result<DVec3> {
        for l in lambda_nm {
            crate::error::positive("lambda_nm", l)?;
        }
        crate::error::non_negative("k", k)?;
        let r = |l: f64| (lambda_nm[0] / l).powi(4);
        Ok(DVec3::new(1.0, r(lambda_nm[1]), r(lambda_nm[2])) * k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rayleigh_ratios() {
        let v = RayleighRgb::from_wavelengths([800.0, 500.0, 380.0], 1.0).unwrap();
        assert!((v.y - 6.5536).abs() < 1e-12);
        assert!((v.z - 19.643_85).abs() < 1e-4);
        assert_eq!(
            RayleighRgb::musgrave_1_3_20(2.0),
            DVec3::new(2.0, 6.0, 40.0)
        );
        assert!(RayleighRgb::from_wavelengths([800.0, -1.0, 380.0], 1.0).is_err());
    }

    /// Blue limb against space, yellowed white against bright objects.
    #[test]
    fn rayleigh_rgb_blue_limb_and_yellow_snow() {
        let fog = DVec3::new(1.0, 0.8, 0.5);
        let eps = RayleighRgb::musgrave_1_3_20(1.0);
        for kd in [0.001, 0.01, 0.05, 0.1] {
            let a = Attenuation::beer(eps * kd, fog);
            let dark = a.apply(DVec3::ZERO);
            assert!(dark.z > dark.y && dark.y > dark.x, "kδ={kd}: {dark}");
        }
        let mid = Attenuation::beer(eps * 0.5, fog).apply(DVec3::ZERO);
        assert!(mid.y > mid.z, "{mid}");
        for kd in [0.001, 0.1, 0.5, 2.0, 10.0] {
            let lit = Attenuation::beer(eps * kd, fog).apply(DVec3::ONE);
            assert!(lit.x > lit.y && lit.y > lit.z, "kδ={kd}: {lit}");
        }
        let far = Attenuation::beer(eps * 1e3, fog).apply(DVec3::ONE);
        assert!((far - fog).abs().max_element() < 1e-12);
    }

    #[test]
    fn then_composes_like_one_segment() {
        let fog = DVec3::new(0.7, 0.8, 0.9);
        let t1 = DVec3::new(0.1, 0.2, 0.3);
        let t2 = DVec3::new(0.4, 0.05, 1.0);
        let a = Attenuation::beer(t1, fog).then(Attenuation::beer(t2, fog));
        let b = Attenuation::beer(t1 + t2, fog);
        assert!((a.transmittance - b.transmittance).abs().max_element() < 1e-15);
        assert!((a.in_scatter - b.in_scatter).abs().max_element() < 1e-15);
    }
}

#[cfg(test)]
#[path = "tests.rs"]
mod oracle_tests;
