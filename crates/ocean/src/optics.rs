//! Optics of the water surface (Tessendorf 2001, §4;
//! volume effects §5).
//!
//! * [`reflect`] (eq. 37) and [`refract`] (eqs. 38-42, **corrected**: the
//!   printed Γ of eq. 42 has the wrong overall sign and gives a refracted
//!   vector of length 0.5 at normal incidence);
//! * [`fresnel_reflectance`]: the exact unpolarised reflectivity of eq. 44,
//!   in a form with no 0/0 at normal incidence, = 1 beyond the critical
//!   angle; transmittance T = 1 − R (eq. 43);
//! * [`critical_angle`] (eq. 45): sin θ_c = n_t/n_i, 48.6° from the normal
//!   for water → air, i.e. 41.4° from the surface. The notes call it
//!   "Brewster's angle" and print 41.1°; both are errata. The true Brewster
//!   angle is [`brewster_angle`];
//! * [`WaterShader`]: the notes' `watercolorshader` (§4.3) with sky
//!   radiance looked up along the reflected ray (the source looks it up by
//!   the normal), plus a sun glitter term (not in the sources: the promised
//!   glitter model is missing, §4);
//! * [`WaterIop`]: the attenuation recipe of Tessendorf 2001, §5.1.
//!
//! Directions are propagation directions: `incident` points from the eye
//! toward the surface. Normals are unit vectors; z is up.

use glam::{DVec3, Vec3};

use crate::error::{Result, invalid, non_negative, positive};

/// Refractive index of water used in the text, ≈ 4/3 (Tessendorf 2001, §4.1).
pub const N_WATER: f64 = 4.0 / 3.0;
/// Refractive index of water used by the notes' shader (Tessendorf 2001, §4.3).
pub const N_WATER_SHADER: f64 = 1.34;
/// Refractive index of air.
pub const N_AIR: f64 = 1.0;
/// Bulk (Lambertian) reflectivity of the water volume, ≈ 0.04 (Tessendorf 2001, §5.1).
pub const BULK_REFLECTIVITY: f64 = 0.04;

macro_rules! vector_optics {
    ($reflect:ident, $refract:ident, $v:ty, $f:ty) => {
        /// Returns the mirror direction of `incident` about unit `normal`:
        /// n̂_r = n̂_i − 2 n̂ (n̂·n̂_i) (eq. 37), valid from either side.
        #[inline]
        #[must_use]
        pub fn $reflect(incident: $v, normal: $v) -> $v {
            incident - normal * (2.0 * normal.dot(incident))
        }

        /// Returns the refracted direction of unit `incident` through a surface
        /// with unit `normal`, from index `n_i` into `n_t`, or `None` beyond
        /// the critical angle (total internal reflection).
        ///
        /// Eqs. 41-42 corrected (the printed Γ has the wrong overall sign): n̂_t = η n̂_i + Γ n̂ with η = n_i/n_t
        /// and Γ = −η (n̂_i·n̂) ∓ √(1 − η² |n̂_i × n̂|²), "−" when n̂_i·n̂ < 0
        /// and "+" when > 0. The result is a unit vector that satisfies
        /// Snell's law and stays on the far side of the surface; the normal
        /// may face either way.
        #[inline]
        #[must_use]
        pub fn $refract(incident: $v, normal: $v, n_i: $f, n_t: $f) -> Option<$v> {
            let eta = n_i / n_t;
            let c = incident.dot(normal);
            let sin2 = (1.0 - c * c).max(0.0);
            let radicand = 1.0 - eta * eta * sin2;
            if radicand < 0.0 {
                return None;
            }
            let root = radicand.sqrt();
            let gamma = if c < 0.0 {
                -eta * c - root
            } else {
                -eta * c + root
            };
            Some(incident * eta + normal * gamma)
        }
    };
}

vector_optics!(reflect, refract, Vec3, f32);
vector_optics!(reflect_f64, refract_f64, DVec3, f64);

/// Returns the exact unpolarised Fresnel reflectance R for light meeting the
/// surface at `cos_i` = |cos θ_i| (angle from the normal), going from index
/// `n_i` into `n_t`.
///
/// Eq. 44, R = ½[sin²(θ_t−θ_i)/sin²(θ_t+θ_i) + tan²(θ_t−θ_i)/tan²(θ_t+θ_i)],
/// evaluated through the equal amplitude ratios
/// r_s = (n_i cos θ_i − n_t cos θ_t)/(n_i cos θ_i + n_t cos θ_t) and
/// r_p = (n_t cos θ_i − n_i cos θ_t)/(n_t cos θ_i + n_i cos θ_t), which are
/// continuous at normal incidence (R = ((n_i−n_t)/(n_i+n_t))², the shader's
/// special case, §4.3). Returns 1 beyond the critical angle.
/// `cos_i` is clamped to [0, 1] only to absorb round-off in callers' dot
/// products.
#[must_use]
pub fn fresnel_reflectance(cos_i: f64, n_i: f64, n_t: f64) -> f64 {
    let ci = cos_i.abs().min(1.0);
    let eta = n_i / n_t;
    let sin2_t = eta * eta * (1.0 - ci * ci);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let ct = (1.0 - sin2_t).sqrt();
    let rs = (n_i * ci - n_t * ct) / (n_i * ci + n_t * ct);
    let rp = (n_t * ci - n_i * ct) / (n_t * ci + n_i * ct);
    0.5 * (rs * rs + rp * rp)
}

/// Returns the Fresnel transmittance T = 1 − R (eq. 43: no light is lost at the interface).
#[must_use]
pub fn fresnel_transmittance(cos_i: f64, n_i: f64, n_t: f64) -> f64 {
    1.0 - fresnel_reflectance(cos_i, n_i, n_t)
}

/// Returns the critical angle θ_c = asin(n_t/n_i) from the normal (radians),
/// beyond which light from index `n_i` is totally reflected, or `None` when
/// n_t ≥ n_i (eq. 45; the notes' "Brewster's angle", §4.2).
#[must_use]
pub fn critical_angle(n_i: f64, n_t: f64) -> Option<f64> {
    (n_t < n_i).then(|| (n_t / n_i).asin())
}

/// Returns Brewster's angle atan(n_t/n_i) from the normal (radians), at which
/// p-polarised light is not reflected at all (not from the sources).
#[must_use]
pub fn brewster_angle(n_i: f64, n_t: f64) -> f64 {
    (n_t / n_i).atan()
}

/// Shades the water surface seen from the air, after the notes'
/// `watercolorshader` (Tessendorf 2001, §4.3):
///
/// C = f·(R·L_sky(r̂) + R·L_sun,glitter + (1 − R)·upwelling) + (1 − f)·air,
/// f = exp(−`aerial_fade` · distance).
///
/// R is the Fresnel reflectance at the facet (eq. 44), r̂ the reflected
/// view ray (the shader looks the sky up by the normal instead, which is wrong
/// for any facet not facing the eye), `upwelling` the light scattered up out of the
/// water. The sun adds a glitter lobe for slopes finer than the grid
/// resolves: Cox–Munk's isotropic Gaussian slope distribution with variance
/// `slope_variance`, L = R E_sun p(facet) / (4 cos θ_v cos⁴ β) (not from the
/// sources, which promise a glitter model but never give it, §4).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct WaterShader {
    /// Colour of light scattered up out of the water volume (shader: (0, 0.2, 0.3)).
    pub upwelling: Vec3,
    /// Sky radiance used when no sky function is given (shader: (0.69, 0.84, 1)).
    pub sky: Vec3,
    /// Colour of the air between eye and surface (shader: (0.1, 0.1, 0.1)).
    pub air: Vec3,
    /// Refractive index of water (shader: 1.34).
    pub n_water: f32,
    /// Exponential fade with eye distance, per metre. The shader's `Kdiffuse`
    /// is 0.91 per (unspecified) scene unit, far too strong in metres; the
    /// default 0 leaves aerial perspective to an atmosphere model.
    pub aerial_fade: f32,
    /// Unit direction toward the sun.
    pub sun_direction: Vec3,
    /// Sun irradiance on a surface facing it (same units as the sky radiance
    /// times steradians); zero disables glitter.
    pub sun_irradiance: Vec3,
    /// Variance of the unresolved facet slopes (> 0). Cox & Munk measured
    /// 0.003 + 0.00512·U₁₂.₅ for the whole surface; use less when the grid
    /// already resolves the longer waves.
    pub slope_variance: f32,
}

impl Default for WaterShader {
    fn default() -> Self {
        Self {
            upwelling: Vec3::new(0.0, 0.2, 0.3),
            sky: Vec3::new(0.69, 0.84, 1.0),
            air: Vec3::new(0.1, 0.1, 0.1),
            n_water: N_WATER_SHADER as f32,
            aerial_fade: 0.0,
            sun_direction: Vec3::new(0.0, -0.8, 0.6),
            sun_irradiance: Vec3::ZERO,
            slope_variance: 0.004,
        }
    }
}

impl WaterShader {
    /// Checks the parameters.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter) for negative or non-finite colours, a water index not above 1,
    /// a negative aerial fade or a non-positive slope variance.
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("upwelling", self.upwelling),
            ("sky", self.sky),
            ("air", self.air),
            ("sun_irradiance", self.sun_irradiance),
        ] {
            if !(v.is_finite() && v.min_element() >= 0.0) {
                return Err(invalid(name, v, "colours must be finite and ≥ 0"));
            }
        }
        if !(self.n_water.is_finite() && self.n_water > 1.0) {
            return Err(invalid("n_water", self.n_water, "must be finite and > 1"));
        }
        non_negative("aerial_fade", f64::from(self.aerial_fade))?;
        positive("slope_variance", f64::from(self.slope_variance))?;
        if !(self.sun_direction.is_finite() && (self.sun_direction.length() - 1.0).abs() < 1e-3) {
            return Err(invalid(
                "sun_direction",
                self.sun_direction,
                "must be a unit vector",
            ));
        }
        Ok(())
    }

    /// Returns the colour seen along unit `incident` (eye → surface) at a
    /// surface point with unit upward `normal`, `distance` metres from the
    /// eye. `sky` gives the sky radiance in a direction; `None` uses the
    /// constant [`WaterShader::sky`].
    #[must_use]
    pub fn shade(
        &self,
        incident: Vec3,
        normal: Vec3,
        distance: f32,
        sky: Option<&dyn Fn(Vec3) -> Vec3>,
    ) -> Vec3 {
        // The shader uses |n̂_i·n̂|: facets seen from behind (possible on a
        // choppy surface) are shaded as if seen from the front.
        let n = if incident.dot(normal) > 0.0 {
            -normal
        } else {
            normal
        };
        let cos_i = (-incident.dot(n)).clamp(0.0, 1.0);
        let r = fresnel_reflectance(f64::from(cos_i), 1.0, f64::from(self.n_water)) as f32;
        let mut dir = reflect(incident, n);
        // A reflected ray heading down would hit the water again; the single
        // interaction model (Tessendorf 2001, §2) mirrors it up into the sky instead.
        dir.z = dir.z.abs();
        let sky_l = match sky {
            Some(f) => f(dir),
            None => self.sky,
        };
        let glitter = self.glitter(incident, n);
        let fade = (-self.aerial_fade * distance.max(0.0)).exp();
        fade * (r * (sky_l + glitter) + (1.0 - r) * self.upwelling) + (1.0 - fade) * self.air
    }

    /// Returns the sun glitter radiance before the Fresnel factor.
    fn glitter(&self, incident: Vec3, n: Vec3) -> Vec3 {
        if self.sun_irradiance == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let to_eye = -incident;
        let cos_v = to_eye.dot(n);
        let cos_s = self.sun_direction.dot(n);
        if cos_v <= 0.0 || cos_s <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (to_eye + self.sun_direction).normalize_or_zero();
        let cos_b = h.dot(n);
        if cos_b <= 0.0 {
            return Vec3::ZERO;
        }
        let tan2 = (1.0 - cos_b * cos_b) / (cos_b * cos_b);
        let s2 = self.slope_variance;
        let p = (-tan2 / s2).exp() / (std::f32::consts::PI * s2);
        self.sun_irradiance * (p / (4.0 * cos_v * cos_b.powi(4)))
    }
}

/// Inherent optical properties of the water volume (Tessendorf 2001, §5.1),
/// all per metre: absorption a, scattering b, extinction c = a + b and
/// diffuse extinction K, with a < K < c.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WaterIop {
    /// Absorption coefficient a, 1/m.
    pub absorption: f64,
    /// Scattering coefficient b, 1/m.
    pub scattering: f64,
    /// Diffuse extinction K, 1/m (typically 0.03-0.1, Tessendorf 2001, §5.1).
    pub diffuse_extinction: f64,
}

impl WaterIop {
    /// Returns validated properties.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter) unless every property is finite and positive and
    /// 0 < a < K < a + b.
    pub fn new(absorption: f64, scattering: f64, diffuse_extinction: f64) -> Result<Self> {
        positive("absorption", absorption)?;
        positive("scattering", scattering)?;
        positive("diffuse_extinction", diffuse_extinction)?;
        if !(absorption < diffuse_extinction && diffuse_extinction < absorption + scattering) {
            return Err(invalid(
                "diffuse_extinction",
                diffuse_extinction,
                "must lie between absorption a and extinction c = a + b",
            ));
        }
        Ok(Self {
            absorption,
            scattering,
            diffuse_extinction,
        })
    }

    /// Returns the extinction c = a + b, 1/m.
    #[must_use]
    pub fn extinction(&self) -> f64 {
        self.absorption + self.scattering
    }

    /// Returns the intensity I₀ e^{−c s} left after path `s` metres (Tessendorf 2001, §5.1).
    #[must_use]
    pub fn direct(&self, i0: f64, s: f64) -> f64 {
        i0 * (-self.extinction() * s).exp()
    }

    /// Returns the multiply-scattered light reaching the camera,
    /// b I₀ e^{−c s} e^{−K s_c}, from a scatter point `s` metres along the
    /// sun ray and `s_cam` metres from the camera (Tessendorf 2001, §5.1).
    #[must_use]
    pub fn scattered_to_camera(&self, i0: f64, s: f64, s_cam: f64) -> f64 {
        self.scattering * self.direct(i0, s) * (-self.diffuse_extinction * s_cam).exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    /// Eq. 44 exactly as printed, in sines and tangents.
    fn eq44(theta_i: f64, n_i: f64, n_t: f64) -> f64 {
        let tt = (n_i / n_t * theta_i.sin()).asin();
        let a = (tt - theta_i).sin() / (tt + theta_i).sin();
        let b = (tt - theta_i).tan() / (tt + theta_i).tan();
        0.5 * (a * a + b * b)
    }

    #[test]
    fn fresnel_values_from_the_notes() {
        assert_relative_eq!(
            fresnel_reflectance(1.0, 1.0, N_WATER),
            0.020408,
            epsilon = 1e-6
        );
        assert_relative_eq!(
            fresnel_reflectance(1.0, 1.0, 1.34),
            0.021112,
            epsilon = 1e-6
        );
        // Continuous at θ → 0: eq. 44 at 1e-4 rad agrees with the limit.
        assert_relative_eq!(
            eq44(1e-4, 1.0, N_WATER),
            fresnel_reflectance(1.0, 1.0, N_WATER),
            epsilon = 1e-6
        );
        // Fresnel reflectance table (angle from the normal, n = 4/3).
        for (deg, r) in [
            (40.0, 0.025),
            (60.0, 0.060),
            (70.0, 0.134),
            (80.0, 0.348),
            (85.0, 0.584),
            (89.0, 0.896),
        ] {
            let th = f64::to_radians(deg);
            assert_relative_eq!(
                fresnel_reflectance(th.cos(), 1.0, N_WATER),
                r,
                epsilon = 1.5e-3
            );
            assert_relative_eq!(
                fresnel_reflectance(th.cos(), 1.0, N_WATER),
                eq44(th, 1.0, N_WATER),
                epsilon = 1e-12
            );
        }
        assert!(
            (fresnel_reflectance(89.9f64.to_radians().cos(), 1.0, N_WATER) - 0.989).abs() < 1e-3
        );
    }

    #[test]
    fn total_internal_reflection_from_inside_water() {
        let tc = critical_angle(N_WATER, 1.0).unwrap();
        assert_relative_eq!(tc.to_degrees(), 48.59, epsilon = 0.01);
        // 41.4° from the surface, not the notes' 41.1°, and not Brewster's.
        assert_relative_eq!(90.0 - tc.to_degrees(), 41.41, epsilon = 0.01);
        assert_relative_eq!(
            brewster_angle(1.0, N_WATER).to_degrees(),
            53.13,
            epsilon = 0.01
        );
        assert_relative_eq!(
            brewster_angle(N_WATER, 1.0).to_degrees(),
            36.87,
            epsilon = 0.01
        );
        assert!(critical_angle(1.0, N_WATER).is_none());
        for deg in [48.6, 50.0, 70.0, 89.0] {
            let c = f64::to_radians(deg).cos();
            assert_eq!(fresnel_reflectance(c, N_WATER, 1.0), 1.0);
            let i = DVec3::new(f64::to_radians(deg).sin(), 0.0, c);
            assert!(refract_f64(i, DVec3::Z, N_WATER, 1.0).is_none());
        }
        assert!(fresnel_reflectance(f64::to_radians(48.5).cos(), N_WATER, 1.0) < 1.0);
        // Brewster: no p-reflection, so R = r_s²/2 there.
        let tb = brewster_angle(1.0, N_WATER);
        let r = fresnel_reflectance(tb.cos(), 1.0, N_WATER);
        assert!(r < fresnel_reflectance(f64::to_radians(60.0).cos(), 1.0, N_WATER));
    }

    #[test]
    fn normal_incidence_passes_straight_through() {
        let t = refract_f64(-DVec3::Z, DVec3::Z, 1.0, N_WATER).unwrap();
        assert!((t + DVec3::Z).length() < 1e-15);
        // The printed eq. 42 would give (1 − 2η) n̂, of length 0.5 here.
        let t = refract(Vec3::new(0.0, 0.0, 1.0), Vec3::Z, N_WATER as f32, 1.0).unwrap();
        assert!((t - Vec3::Z).length() < 1e-6);
    }

    proptest! {
        #[test]
        fn fresnel_is_bounded_monotone_and_reciprocal(theta in 0.0f64..1.5, n in 1.05f64..2.0) {
            let r = fresnel_reflectance(theta.cos(), 1.0, n);
            prop_assert!((0.0..=1.0).contains(&r));
            prop_assert!((r + fresnel_transmittance(theta.cos(), 1.0, n) - 1.0).abs() < 1e-15);
            let r2 = fresnel_reflectance((theta + 1e-3).cos(), 1.0, n);
            prop_assert!(r2 >= r - 1e-12);
            // R(θ_i, n₁→n₂) = R(θ_t, n₂→n₁).
            let tt = (theta.sin() / n).asin();
            prop_assert!((fresnel_reflectance(tt.cos(), n, 1.0) - r).abs() < 1e-12);
        }

        #[test]
        fn refraction_obeys_snell(theta in 0.0f64..1.56, phi in 0.0f64..6.0, n in 1.05f64..2.0, up in proptest::bool::ANY, from_below in proptest::bool::ANY) {
            let normal = if up { DVec3::Z } else { -DVec3::Z };
            let (ni, nt) = if from_below { (n, 1.0) } else { (1.0, n) };
            let dz = if from_below { 1.0 } else { -1.0 };
            let i = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), dz * theta.cos());
            let r = reflect_f64(i, normal);
            prop_assert!((r.length() - 1.0).abs() < 1e-12);
            prop_assert!((r.dot(normal) + i.dot(normal)).abs() < 1e-12);
            match refract_f64(i, normal, ni, nt) {
                Some(t) => {
                    prop_assert!((t.length() - 1.0).abs() < 1e-12);
                    prop_assert!((ni * i.cross(normal).length() - nt * t.cross(normal).length()).abs() < 1e-12);
                    prop_assert!(t.dot(normal) * i.dot(normal) > 0.0 || theta == 0.0);
                }
                None => prop_assert!(ni > nt && ni * theta.sin() > nt),
            }
        }
    }

    #[test]
    fn shader_limits() {
        let s = WaterShader::default();
        s.validate().unwrap();
        let r = fresnel_reflectance(1.0, 1.0, 1.34) as f32;
        // Normal incidence: ≈ 0.02 sky + 0.98 upwelling.
        let c = s.shade(-Vec3::Z, Vec3::Z, 0.0, None);
        assert!(c.abs_diff_eq(r * s.sky + (1.0 - r) * s.upwelling, 1e-6));
        // With a fade: far away the air colour remains.
        let faded = WaterShader {
            aerial_fade: 0.91,
            ..s
        };
        assert!(
            faded
                .shade(-Vec3::Z, Vec3::Z, 1e4, None)
                .abs_diff_eq(s.air, 1e-6)
        );
        // Grazing views reflect more sky.
        let g = s.shade(
            Vec3::new(0.999, 0.0, -0.0447).normalize(),
            Vec3::Z,
            0.0,
            None,
        );
        assert!(g.z > c.z && g.x > c.x);
        // The sky function sees the reflected ray.
        let seen = std::cell::Cell::new(Vec3::ZERO);
        let sky = |d: Vec3| {
            seen.set(d);
            Vec3::ONE
        };
        let i = Vec3::new(0.6, 0.0, -0.8);
        let _ = s.shade(i, Vec3::Z, 0.0, Some(&sky));
        assert!(seen.get().abs_diff_eq(Vec3::new(0.6, 0.0, 0.8), 1e-6));
        // Glitter: bright where the facet mirrors the sun, nothing far from it.
        let sun = WaterShader {
            sun_direction: Vec3::new(0.6, 0.0, 0.8),
            sun_irradiance: Vec3::splat(100.0),
            ..s
        };
        let mirror = sun.shade(Vec3::new(0.6, 0.0, -0.8), Vec3::Z, 0.0, None);
        let away = sun.shade(Vec3::new(-0.6, 0.0, -0.8), Vec3::Z, 0.0, None);
        assert!(mirror.x > 10.0 * away.x.max(1e-3));
        assert!(
            WaterShader {
                slope_variance: 0.0,
                ..s
            }
            .validate()
            .is_err()
        );
        assert!(
            WaterShader {
                n_water: f32::NAN,
                ..s
            }
            .validate()
            .is_err()
        );
    }

    #[test]
    fn volume_attenuation() {
        let iop = WaterIop::new(0.03, 0.1, 0.06).unwrap();
        let mut prev = f64::MAX;
        for s in 0..20 {
            let v = iop.direct(1.0, s as f64);
            assert!(v < prev);
            prev = v;
        }
        assert_relative_eq!(
            iop.scattered_to_camera(2.0, 3.0, 4.0),
            0.1 * 2.0 * (-0.13f64 * 3.0).exp() * (-0.06f64 * 4.0).exp(),
            max_relative = 1e-14
        );
        assert!(WaterIop::new(0.03, 0.1, 0.02).is_err());
        assert!(WaterIop::new(0.03, 0.1, 0.2).is_err());
        assert!(WaterIop::new(f64::NAN, 0.1, 0.2).is_err());
    }
}
