//! Homogeneous fog: constant extinction everywhere (Musgrave 1993, §4.1.4).

use glam::DVec3;

use super::BeerParams;
use crate::Dir3;
use crate::error::Result;

/// Musgrave's homogeneous fog: `σ = e^{−ε·|b − a|}` per channel (eq. 4.1.1, Musgrave 1993, §4.1.4).
///
/// Isotropic and the same everywhere; a ray that misses all geometry has
/// infinite optical depth and shows the pure fog colour (the flaw the radial
/// model fixes, Musgrave 1993, §1.2.4.1, §4.1.6.1).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HomogeneousFog {
    beer: BeerParams,
}

impl HomogeneousFog {
    /// A fog with per-metre `extinction` and colour `fog_colour`; refuses negative or NaN values.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for negative or NaN extinction or colour.
    pub fn new(extinction: DVec3, fog_colour: DVec3) -> Result<Self> {
        let beer = BeerParams {
            extinction,
            fog_colour,
        };
        beer.validate()?;
        Ok(Self { beer })
    }

    /// The extinction and colour.
    #[must_use]
    pub fn params(&self) -> BeerParams {
        self.beer
    }

    /// `∫ρ ds` along `a → b`: the path length (metres at the reference
    /// density, which fills all space).
    #[must_use]
    pub fn column(&self, a: DVec3, b: DVec3) -> f64 {
        a.distance(b)
    }

    /// `∫ρ ds` from `origin` to infinity: `+∞` in every direction.
    #[must_use]
    pub fn column_to_infinity(&self, _origin: DVec3, _dir: Dir3) -> f64 {
        f64::INFINITY
    }
}

beer_medium!(HomogeneousFog);
