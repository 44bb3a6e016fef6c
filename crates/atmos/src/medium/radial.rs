//! Radial fog: a planetary atmosphere whose density depends on the distance
//! from the planet's centre (Musgrave 1993, §4.1.6–4.1.6.4), integrated exactly.

use glam::DVec3;

use super::BeerParams;
use crate::Dir3;
use crate::error::{Result, finite3, positive};
use crate::special::{erfcx, gauss_legendre8};

/// `√π / 2`.
const HALF_SQRT_PI: f64 = 0.886_226_925_452_758;

/// Musgrave's radial ("Gaussian gas planet") atmosphere, parameterised as a
/// planetary exponential atmosphere of surface radius `R` and scale height `H`.
///
/// Density is `ρ(r) = e^{−k²(r² − R²)}` with `k = 1/√(2RH)` (eq. 4.1.8, Musgrave 1993, §4.1.6.2,
/// normalised to 1 at the surface). Near the surface `r² − R² ≈ 2R(r − R)`, so
/// this *is* an exponential atmosphere of scale height `H`, and its grazing
/// column matches Chapman's `e^{−h/H}·√(2πRH)`.
///
/// **Errata corrected**: eq. 4.1.13 (Musgrave 1993, §4.1.6.4) integrates between
/// the wrong distances (from the centre, not signed along the line from the
/// closest-approach point) and drops the factor `√π/(2k)`; eq. 4.1.11 is exact,
/// not an approximation. The source's `erf`/`erfc` difference saturates for
/// Earth-thin atmospheres and shows an "ozone hole" (Musgrave 1993, §4.1.6.4); here segments
/// that straddle the closest point use `erf(ks₂) − erf(ks₁)` (no cancellation),
/// one-sided segments use `ρ(r₁)·erfcx(ks₁) − ρ(r₂)·erfcx(ks₂)` with the
/// exponents combined, and short segments (density varying by less than a
/// factor e) use 8-point Gauss–Legendre on the exact integrand.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RadialAtmosphere {
    beer: BeerParams,
    centre: DVec3,
    surface_radius: f64,
    scale_height: f64,
    k: f64,
}

impl RadialAtmosphere {
    /// An atmosphere around `centre` with surface radius `surface_radius` (m),
    /// scale height `scale_height` (m), surface extinction `extinction` (per m)
    /// and fog colour `fog_colour`.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for negative or non-finite extinction or colour, a
    /// non-finite centre, non-positive radii or scale heights, or a scale height so small
    /// that the density exponent overflows.
    pub fn new(
        extinction: DVec3,
        fog_colour: DVec3,
        centre: DVec3,
        surface_radius: f64,
        scale_height: f64,
    ) -> Result<Self> {
        let beer = BeerParams {
            extinction,
            fog_colour,
        };
        beer.validate()?;
        finite3("centre", centre)?;
        positive("surface_radius", surface_radius)?;
        positive("scale_height", scale_height)?;
        let k = 1.0 / (2.0 * surface_radius * scale_height).sqrt();
        if !(k.is_finite() && k > 0.0) {
            return Err(crate::error::invalid(
                "scale_height",
                scale_height,
                "surface_radius × scale_height must be representable",
            ));
        }
        Ok(Self {
            beer,
            centre,
            surface_radius,
            scale_height,
            k,
        })
    }

    /// The extinction and colour.
    #[must_use]
    pub fn params(&self) -> BeerParams {
        self.beer
    }

    /// The thickness constant `k = 1/√(2RH)` of `ρ = e^{−k²(r² − R²)}`.
    #[must_use]
    pub fn k(&self) -> f64 {
        self.k
    }

    /// The planet's centre.
    #[must_use]
    pub fn centre(&self) -> DVec3 {
        self.centre
    }

    /// The surface radius `R`, m.
    #[must_use]
    pub fn surface_radius(&self) -> f64 {
        self.surface_radius
    }

    /// The scale height `H`, m.
    #[must_use]
    pub fn scale_height(&self) -> f64 {
        self.scale_height
    }

    /// Relative density at `p` (1 on the surface).
    #[must_use]
    pub fn density(&self, p: DVec3) -> f64 {
        self.density_r2((p - self.centre).length_squared())
    }

    #[inline]
    fn density_r2(&self, r2: f64) -> f64 {
        let r = self.surface_radius;
        (-(self.k * self.k) * (r2 - r * r)).exp()
    }

    /// Distance along `dir` from `origin` to the planet's surface, if the ray meets it
    /// (0 if `origin` is below the surface).
    #[must_use]
    pub fn ground_hit(&self, origin: DVec3, dir: Dir3) -> Option<f64> {
        let q = origin - self.centre;
        let r = self.surface_radius;
        let c = q.length_squared() - r * r;
        // Below the surface (beyond rounding of |q|² at planetary radii).
        if c < -1e-12 * r * r {
            return Some(0.0);
        }
        let c = c.max(0.0);
        let b = q.dot(dir.get());
        if b >= 0.0 {
            return None;
        }
        let disc = b * b - c;
        if disc < 0.0 {
            return None;
        }
        // Stable root: c / (−b + √disc) is the near intersection.
        Some(c / (-b + disc.sqrt()))
    }

    /// `∫ρ ds` along the segment `a → b` (metres at surface density), exact.
    #[must_use]
    pub fn column(&self, a: DVec3, b: DVec3) -> f64 {
        let v = b - a;
        let d = v.length();
        if d == 0.0 {
            return 0.0;
        }
        let u = v / d;
        let qa = a - self.centre;
        let s1 = qa.dot(u);
        let s2 = s1 + d;
        let rp2 = qa.cross(u).length_squared();
        self.column_line(
            rp2,
            s1,
            s2,
            qa.length_squared(),
            (b - self.centre).length_squared(),
        )
    }

    /// The line integral between signed abscissae `s1 < s2` (from the closest
    /// point), for a line whose closest approach is `√rp2`; `r1²`, `r2²` are the
    /// endpoint radii squared (`r2²` unused when `s2 = ∞`).
    fn column_line(&self, rp2: f64, s1: f64, s2: f64, r1sq: f64, r2sq: f64) -> f64 {
        let k = self.k;
        let k2 = k * k;
        let big_r2 = self.surface_radius * self.surface_radius;
        let straddle = s1 < 0.0 && s2 > 0.0;
        let smax2 = (s1 * s1).max(s2 * s2);
        let smin2 = if straddle {
            0.0
        } else {
            (s1 * s1).min(s2 * s2)
        };
        if s2.is_finite() && k2 * (smax2 - smin2) <= 1.0 {
            // Density varies by less than a factor e: the erfcx difference would
            // cancel, Gauss–Legendre on the exact integrand does not.
            return gauss_legendre8(|s| (-k2 * (rp2 + s * s - big_r2)).exp(), s1, s2);
        }
        let scale = HALF_SQRT_PI / k;
        if straddle {
            let tail = if s2.is_finite() {
                libm::erf(k * s2) - libm::erf(k * s1)
            } else {
                libm::erfc(k * s1)
            };
            scale * (-k2 * (rp2 - big_r2)).exp() * tail
        } else if s1 >= 0.0 {
            let near = self.density_r2(r1sq) * erfcx(k * s1);
            let far = if s2.is_finite() {
                self.density_r2(r2sq) * erfcx(k * s2)
            } else {
                0.0
            };
            scale * (near - far).max(0.0)
        } else {
            // Entirely before the closest point: mirror s → −s.
            let near = self.density_r2(r2sq) * erfcx(-k * s2);
            let far = self.density_r2(r1sq) * erfcx(-k * s1);
            scale * (near - far).max(0.0)
        }
    }

    /// `∫ρ ds` from `origin` along `dir` until the ray leaves the atmosphere
    /// (finite for every ray, Musgrave 1993, §4.1.6.1) or meets the ground.
    /// `+∞` if `origin` is below the surface.
    #[must_use]
    pub fn column_to_infinity(&self, origin: DVec3, dir: Dir3) -> f64 {
        match self.ground_hit(origin, dir) {
            Some(t) if t <= 0.0 => f64::INFINITY,
            Some(t) => self.column(origin, origin + dir.get() * t),
            None => {
                let u = dir.get();
                let q = origin - self.centre;
                let s1 = q.dot(u);
                let rp2 = q.cross(u).length_squared();
                self.column_line(rp2, s1, f64::INFINITY, q.length_squared(), f64::INFINITY)
            }
        }
    }
}

beer_medium!(RadialAtmosphere);
