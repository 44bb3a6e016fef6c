//! Musgrave's "Bay Fog": a stratus layer made as a texture on a plane
//! (Musgrave 1993, Plate 5.1).

use core::fmt;

use glam::{DVec2, DVec3};

use super::{Attenuation, BeerParams, Medium, scale_column};
use crate::Dir3;
use crate::error::{Result, finite};

/// A fog sheet: fog below the horizontal plane `z = top`, whose density is
/// a texture of the point where a ray crosses the plane, so that a ray's
/// optical depth is `ε̄·ρ(p)·ℓ`, with `ρ(p)` the texture at the crossing `p`
/// (clear where it is ≤ 0) and `ℓ` the length of the ray below the plane.
///
/// This is Musgrave's "Bay Fog" (Musgrave 1993, Plate 5.1): an fBm texture
/// on a plane "assigns a fog value to the ray which is refracted (at no
/// change in index of refraction) through the plane. Thus the fog is more
/// dense where the terrain behind is farther away, and it disappears near
/// the plane's intersection with the terrain. The fog also casts shadows"
/// (a shadow ray from the terrain crosses the plane too). A segment wholly
/// below the plane takes the texture straight above its midpoint. The
/// source gives no formula beyond the caption; the Beer law is its §4.1.4's.
#[derive(Clone)]
pub struct FogSheet<F> {
    beer: BeerParams,
    top: f64,
    density: F,
}

impl<F> fmt::Debug for FogSheet<F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FogSheet")
            .field("beer", &self.beer)
            .field("top", &self.top)
            .finish_non_exhaustive()
    }
}

impl<F: Fn(DVec2) -> f64 + Send + Sync> FogSheet<F> {
    /// A sheet at height `top` (m) with per-metre `extinction` at density 1,
    /// colour `fog_colour` and the density texture `density` of (x, y) (a
    /// NaN density gives a NaN optical depth).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for
    /// negative or NaN extinction or colour, or a non-finite `top`.
    pub fn new(extinction: DVec3, fog_colour: DVec3, top: f64, density: F) -> Result<Self> {
        let beer = BeerParams {
            extinction,
            fog_colour,
        };
        beer.validate()?;
        finite("top", top)?;
        Ok(Self { beer, top, density })
    }

    /// The extinction and colour.
    #[must_use]
    pub fn params(&self) -> BeerParams {
        self.beer
    }

    /// The plane's height.
    #[must_use]
    pub fn top(&self) -> f64 {
        self.top
    }

    /// The density at the crossing (x, y), 0 where the texture is ≤ 0.
    fn rho(&self, p: DVec2) -> f64 {
        let r = (self.density)(p);
        if r > 0.0 || r.is_nan() { r } else { 0.0 }
    }

    /// `ρ·ℓ` along `a → b`.
    #[must_use]
    pub fn column(&self, a: DVec3, b: DVec3) -> f64 {
        let h = self.top;
        if a.z >= h && b.z >= h {
            return 0.0;
        }
        if a.z < h && b.z < h {
            return self.rho(((a + b) * 0.5).truncate()) * a.distance(b);
        }
        let (below, above) = if a.z < h { (a, b) } else { (b, a) };
        let f = (h - below.z) / (above.z - below.z);
        let p = below.lerp(above, f);
        let rho = self.rho(p.truncate());
        if rho == 0.0 {
            return 0.0;
        }
        rho * below.distance(p)
    }

    /// `ρ·ℓ` from `origin` along `dir`: infinite for a ray that ends below
    /// the plane in fog.
    #[must_use]
    pub fn column_to_infinity(&self, origin: DVec3, dir: Dir3) -> f64 {
        let d = dir.get();
        let h = self.top;
        if origin.z < h && d.z > 0.0 {
            return self.column(origin, origin + d * ((h - origin.z) / d.z));
        }
        let at = if origin.z >= h {
            if d.z >= 0.0 {
                return 0.0;
            }
            origin + d * ((h - origin.z) / d.z)
        } else {
            origin
        };
        if self.rho(at.truncate()) == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    }
}

impl<F: Fn(DVec2) -> f64 + Send + Sync> Medium for FogSheet<F> {
    fn optical_depth(&self, a: DVec3, b: DVec3) -> DVec3 {
        scale_column(self.beer.extinction, self.column(a, b))
    }

    fn optical_depth_to_infinity(&self, origin: DVec3, dir: Dir3) -> DVec3 {
        scale_column(self.beer.extinction, self.column_to_infinity(origin, dir))
    }

    fn attenuation(&self, a: DVec3, b: DVec3) -> Attenuation {
        Attenuation::beer(self.optical_depth(a, b), self.beer.fog_colour)
    }

    fn attenuation_to_infinity(&self, origin: DVec3, dir: Dir3) -> Attenuation {
        Attenuation::beer(
            self.optical_depth_to_infinity(origin, dir),
            self.beer.fog_colour,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheet() -> FogSheet<impl Fn(DVec2) -> f64 + Send + Sync> {
        // Fog where x > 0, density x.
        FogSheet::new(
            DVec3::new(0.01, 0.02, 0.03),
            DVec3::ONE,
            10.0,
            |p: DVec2| p.x,
        )
        .unwrap()
    }

    #[test]
    fn depth_grows_with_the_length_behind_the_plane() {
        let s = sheet();
        let eye = DVec3::new(2.0, 0.0, 30.0);
        // Straight down onto ground at z = 0 and z = 5: 10 m and 5 m of fog
        // of density 2.
        assert!((s.column(eye, DVec3::new(2.0, 0.0, 0.0)) - 20.0).abs() < 1e-12);
        assert!((s.column(eye, DVec3::new(2.0, 0.0, 5.0)) - 10.0).abs() < 1e-12);
        // Ground meeting the plane: no fog; above the plane: none.
        assert_eq!(s.column(eye, DVec3::new(2.0, 0.0, 10.0)), 0.0);
        assert_eq!(s.column(eye, DVec3::new(5.0, 3.0, 12.0)), 0.0);
        // Clear where the texture is ≤ 0.
        assert_eq!(
            s.column(DVec3::new(-2.0, 0.0, 30.0), DVec3::new(-2.0, 0.0, 0.0)),
            0.0
        );
        // Symmetric, and the Beer law per channel.
        let (a, b) = (eye, DVec3::new(6.0, 1.0, 2.0));
        assert_eq!(s.column(a, b), s.column(b, a));
        let tau = s.optical_depth(a, b);
        assert!((tau - DVec3::new(0.01, 0.02, 0.03) * s.column(a, b)).length() < 1e-12);
        assert!(s.transmittance(a, b).max_element() < 1.0);
    }

    #[test]
    fn shadow_rays_and_rays_to_infinity() {
        let s = sheet();
        let up = Dir3::new(DVec3::new(0.0, 0.6, 0.8)).unwrap();
        // From the ground at z = 2 towards the sun: 8 m of height, 10 m of path.
        let g = DVec3::new(3.0, 0.0, 2.0);
        assert!((s.column_to_infinity(g, up) - 3.0 * 10.0).abs() < 1e-9);
        // Downwards into fog never ends; above the plane upwards is clear.
        let down = up.reversed();
        assert_eq!(
            s.column_to_infinity(DVec3::new(3.0, 0.0, 20.0), down),
            f64::INFINITY
        );
        assert_eq!(s.column_to_infinity(DVec3::new(3.0, 0.0, 20.0), up), 0.0);
        assert_eq!(s.column_to_infinity(DVec3::new(-3.0, 5.0, 20.0), down), 0.0);
    }

    #[test]
    fn bad_parameters_are_refused() {
        let d = |_: DVec2| 1.0;
        assert!(FogSheet::new(DVec3::splat(-1.0), DVec3::ONE, 0.0, d).is_err());
        assert!(FogSheet::new(DVec3::ONE, DVec3::ONE, f64::NAN, d).is_err());
    }
}
