//! Exponential mist: density falling with altitude (Musgrave 1993, §4.1.5).

use glam::DVec3;

use super::BeerParams;
use crate::Dir3;
use crate::error::{Result, finite, positive};
use crate::special::exprel_neg;

/// Mist whose density falls exponentially with altitude z:
/// `ρ(z) = e^{−(z − z₀)/H}`, extinction `ε̄·ρ`.
///
/// Musgrave's eq. 4.1.5 (Musgrave 1993, §4.1.5) gives the *mean* extinction over the vertical
/// span (the source labels it τ; τ is that mean times the Euclidean length). The source's near-horizontal fallbacks (eqs. 4.1.6/4.1.7,
/// Musgrave 1993, §4.1.5) are only first/second-order accurate; this model instead uses
/// the exact closed form `τ = ε̄·d·e^{−(z_min − z₀)/H}·(1 − e^{−Δ/H})/(Δ/H)`
/// evaluated with `expm1`, which is exact for horizontal rays (Δ = 0) and
/// never divides by a small difference. Lynch's receding ridges
/// (Musgrave 1993, §4.1.5) come from this model.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ExponentialMist {
    beer: BeerParams,
    base_altitude: f64,
    scale_height: f64,
}

impl ExponentialMist {
    /// Mist with extinction `extinction` (per metre) at altitude `base_altitude`
    /// (m), falling by `e` every `scale_height` metres.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for NaN, negative extinction or colour, a non-finite base
    /// altitude, and non-positive scale heights.
    pub fn new(
        extinction: DVec3,
        fog_colour: DVec3,
        base_altitude: f64,
        scale_height: f64,
    ) -> Result<Self> {
        let beer = BeerParams {
            extinction,
            fog_colour,
        };
        beer.validate()?;
        finite("base_altitude", base_altitude)?;
        positive("scale_height", scale_height)?;
        Ok(Self {
            beer,
            base_altitude,
            scale_height,
        })
    }

    /// The extinction and colour.
    #[must_use]
    pub fn params(&self) -> BeerParams {
        self.beer
    }

    /// Relative density `ρ(z)` at altitude `z`.
    #[must_use]
    pub fn density(&self, z: f64) -> f64 {
        (-(z - self.base_altitude) / self.scale_height).exp()
    }

    /// `∫ρ ds` along `a → b` (metres at reference density), exact in closed form.
    #[must_use]
    pub fn column(&self, a: DVec3, b: DVec3) -> f64 {
        let d = a.distance(b);
        if d == 0.0 {
            return 0.0;
        }
        let (lo, hi) = if a.z <= b.z { (a.z, b.z) } else { (b.z, a.z) };
        // Reference the lower end so the exponent and E(x) stay bounded (E ∈ (0, 1]).
        let x = (hi - lo) / self.scale_height;
        d * self.density(lo) * exprel_neg(x)
    }

    /// `∫ρ ds` from `origin` to infinity along `dir`: `ρ(z)·H/sin α` upward, `+∞` otherwise.
    #[must_use]
    pub fn column_to_infinity(&self, origin: DVec3, dir: Dir3) -> f64 {
        let s = dir.get().z;
        if s > 0.0 {
            self.density(origin.z) * self.scale_height / s
        } else {
            f64::INFINITY
        }
    }
}

beer_medium!(ExponentialMist);
