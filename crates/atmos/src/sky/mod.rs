//! The physical sky: Rayleigh and Mie scattering with an ozone layer in a
//! spherical atmosphere, single scattering by ray marching (Nishita, Sirai,
//! Tadamura & Nakamae, SIGGRAPH 1993) and the precomputed model of Hillaire
//! ("A Scalable and Production Ready Sky and Atmosphere Rendering
//! Technique", EGSR 2020): transmittance LUT, multiple-scattering LUT,
//! sky-view LUT and aerial-perspective volume. Sun disc with limb darkening;
//! sunset and twilight colours follow from the transmittance.
//!
//! This is the physical successor of Musgrave's per-ray aerial perspective
//! (Musgrave 1993, §4.1): the density profiles are independent of the scattering model
//! (Musgrave 1993, §4.1.2), the phase functions are those the dissertation asks for
//! (Musgrave 1993, §4.1.7), and multiple scattering answers its complaint that single
//! scattering "simply isn't blue enough when the sun is low" (Musgrave 1993, §6.4.1.1).
//!
//! # Frames and units
//! World positions are metres, z up, with the ground (sea level) at `z = 0`
//! directly below the world origin; the planet's centre is at
//! `(0, 0, −bottom_radius_m)`. Radiance is spectral radiance in
//! W·m⁻²·sr⁻¹·nm⁻¹ (in [`Evaluation::Spectral`] mode converted to linear sRGB
//! through the CIE 1931 CMFs normalised so a flat spectrum has `Y` = its
//! value), so a white Lambertian ground lit by [`Atmosphere::sun_irradiance`]
//! has radiance `E·cosθ/π` on the same scale as the sky.
//!
//! ```
//! use natura_atmos::{Dir3, sky::{Atmosphere, AtmosphereParams}};
//! use glam::DVec3;
//! let atm = Atmosphere::new(AtmosphereParams::default())?;
//! let sun = Dir3::from_angles(10f64.to_radians(), 0.0)?;
//! let view = atm.sky_view(DVec3::new(0.0, 0.0, 300.0), sun)?;
//! let zenith = view.radiance(Dir3::UP);
//! assert!(zenith.z > zenith.x, "the zenith is blue");
//! let haze = view.aerial_perspective(Dir3::from_angles(-0.01, 1.0)?, 20_000.0)?;
//! assert!(haze.transmittance.max_element() < 1.0);
//! # Ok::<(), natura_atmos::AtmosError>(())
//! ```

mod batch;
mod channels;
mod data;
mod model;
mod params;
mod picture;
mod view;

use std::sync::Arc;

use glam::DVec3;
use natura_core::{NoProgress, Progress};

pub use model::{RGB_WAVELENGTHS_NM, SPECTRAL_BANDS};
pub use params::{
    AtmosphereParams, Evaluation, LutSettings, MieParams, MiePhase, OzoneParams, RayleighParams,
};
pub use picture::{Ground, SkyCamera, SkyProjection, auto_exposure};
pub use view::{ApSample, SkyView};

use crate::Dir3;
use crate::error::{Result, finite3, invalid, positive};
use crate::medium::{Attenuation, Medium};
use channels::Channels;
use model::Model;

/// The model in RGB or spectral channels.
#[derive(Debug)]
pub(crate) enum Inner {
    Rgb(Box<Model<3>>),
    Spectral(Box<Model<SPECTRAL_BANDS>>),
}

macro_rules! with_model {
    ($inner:expr, $m:ident => $body:expr) => {
        match $inner {
            Inner::Rgb(b) => {
                let $m = &**b;
                $body
            }
            Inner::Spectral(b) => {
                let $m = &**b;
                $body
            }
        }
    };
}
pub(crate) use with_model;

/// Settings of the ray-marched (Nishita 1993) reference evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct MarchSettings {
    /// Steps along the view ray (64).
    pub view_steps: usize,
    /// Steps along each light ray for the sun's transmittance (32); 0 uses the
    /// transmittance LUT instead.
    pub light_steps: usize,
}

impl Default for MarchSettings {
    fn default() -> Self {
        Self {
            view_steps: 64,
            light_steps: 32,
        }
    }
}

impl MarchSettings {
    fn validate(&self) -> Result<()> {
        if self.view_steps == 0 || self.view_steps > 1 << 20 || self.light_steps > 1 << 20 {
            return Err(invalid(
                "view_steps",
                self.view_steps,
                "view_steps must be in 1..=2^20 and light_steps in 0..=2^20",
            ));
        }
        Ok(())
    }
}

/// A physical atmosphere with its precomputed transmittance and
/// multiple-scattering LUTs; `Send + Sync`, built once from
/// [`AtmosphereParams`], cheap to clone (shared).
#[derive(Clone, Debug)]
pub struct Atmosphere {
    inner: Arc<Inner>,
    params: AtmosphereParams,
}

/// Planet-centred geometry of a point and direction.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Local {
    pub r: f64,
    pub mu: f64,
}

impl Atmosphere {
    /// Validates `params` and precomputes the transmittance and (if enabled)
    /// multiple-scattering LUTs.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `params` fail [`AtmosphereParams::validate`].
    pub fn new(params: AtmosphereParams) -> Result<Self> {
        Self::with_progress(params, &NoProgress)
    }

    /// Like [`Atmosphere::new`], reporting each LUT build to `progress`.
    ///
    /// # Errors
    ///
    /// As [`Atmosphere::new`].
    pub fn with_progress(params: AtmosphereParams, progress: &dyn Progress) -> Result<Self> {
        let inner = match params.evaluation {
            Evaluation::Rgb => Inner::Rgb(Box::new(Model::new(params, progress)?)),
            Evaluation::Spectral => Inner::Spectral(Box::new(Model::new(params, progress)?)),
        };
        Ok(Self {
            inner: Arc::new(inner),
            params,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &AtmosphereParams {
        &self.params
    }

    /// The wavelengths (nm) of the model's channels.
    #[must_use]
    pub fn wavelengths(&self) -> Vec<f64> {
        with_model!(&*self.inner, m => m.wavelengths.to_vec())
    }

    /// Planet-centred position of world point `p` (the centre is at `z = −R`).
    #[must_use]
    pub fn planet_point(&self, p: DVec3) -> DVec3 {
        p + DVec3::new(0.0, 0.0, self.params.bottom_radius_m)
    }

    /// Checks a point of the local frame: finite, above the ground, and
    /// on the frame's side of the planet (`z ≥ −bottom_radius_m`: a point
    /// below the plane through the planet's centre lies under the ground
    /// the frame stands on, whatever its distance from the centre).
    fn check_point(&self, name: &'static str, p: DVec3) -> Result<DVec3> {
        finite3(name, p)?;
        let q = self.planet_point(p);
        if q.length() < self.params.bottom_radius_m - 1e-3 {
            return Err(invalid(
                name,
                p,
                "point is below the ground (z < 0 at the planet's surface)",
            ));
        }
        if q.z < 0.0 {
            return Err(invalid(
                name,
                p,
                "point is below the ground: z must be at least −bottom_radius_m (the \
                 plane through the planet's centre)",
            ));
        }
        Ok(q)
    }

    fn local(q: DVec3, d: Dir3) -> Local {
        let r = q.length();
        Local {
            r,
            mu: (q / r).dot(d.get()).clamp(-1.0, 1.0),
        }
    }

    /// Sky radiance (linear RGB) seen from `camera` along `view` with the sun
    /// towards `sun`, by ray marching (Nishita 1993): single scattering with
    /// sunlight transmittance integrated along each light ray, plus the
    /// multiple-scattering LUT term if enabled. The sun disc is not included.
    ///
    /// This is the slow reference the LUT model is tested against.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for invalid `settings` or a `camera` that is not
    /// finite or lies below the ground.
    pub fn sky_radiance_marched(
        &self,
        camera: DVec3,
        view: Dir3,
        sun: Dir3,
        settings: MarchSettings,
    ) -> Result<DVec3> {
        settings.validate()?;
        let q = self.check_point("camera", camera)?;
        let v = Self::local(q, view);
        let s = Self::local(q, sun);
        let nu = view.dot(sun);
        Ok(with_model!(&*self.inner, m => {
            match m.view_extent(v.r, v.mu) {
                None => DVec3::ZERO,
                Some((t0, t1, _)) => {
                    let n = settings.view_steps;
                    let bound = |k: usize| t0 + (t1 - t0) * k as f64 / n as f64;
                    let (l, _) = if settings.light_steps == 0 {
                        m.march(v.r, v.mu, s.mu, nu, n, bound, |r, mu| m.sun_trans_lut(r, mu), |_, _, _| {})
                    } else {
                        let ls = settings.light_steps;
                        m.march(v.r, v.mu, s.mu, nu, n, bound, |r, mu| m.sun_trans_exact(r, mu, ls.div_ceil(8).max(1)), |_, _, _| {})
                    };
                    m.rgb(l)
                }
            }
        }))
    }

    /// Transmittance (linear RGB) of sunlight arriving at world point `point`
    /// from `sun`: the sunset reddening; 0 in the planet's shadow.
    ///
    /// In spectral mode this is `rgb(E_λ·T_λ)/rgb(E_λ)` per channel.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `point` is not finite or lies below the ground.
    pub fn sun_transmittance(&self, point: DVec3, sun: Dir3) -> Result<DVec3> {
        let q = self.check_point("point", point)?;
        let s = Self::local(q, sun);
        Ok(with_model!(&*self.inner, m => {
            let t = m.sun_trans_lut(s.r, s.mu);
            m.rgb(t * m.sun) / m.rgb(m.sun).max(DVec3::splat(1e-30))
        }))
    }

    /// Solar irradiance (linear RGB, W·m⁻²·nm⁻¹ scale) at `point` on a surface
    /// facing the sun, after atmospheric transmittance. Multiply by `cos θ`
    /// and `albedo/π` for a Lambertian surface's radiance.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `point` is not finite or lies below the ground.
    pub fn sun_irradiance(&self, point: DVec3, sun: Dir3) -> Result<DVec3> {
        let q = self.check_point("point", point)?;
        let s = Self::local(q, sun);
        Ok(with_model!(&*self.inner, m => m.rgb(m.sun_trans_lut(s.r, s.mu) * m.sun)))
    }

    /// Solar irradiance at the top of the atmosphere (linear RGB).
    #[must_use]
    pub fn sun_irradiance_top(&self) -> DVec3 {
        with_model!(&*self.inner, m => m.rgb(m.sun))
    }

    /// Radiance of the sun's disc (with limb darkening and atmospheric
    /// transmittance) seen from `camera` along `view`; zero off the disc.
    ///
    /// Limb darkening follows the power law `I(μ)/I(1) = μ^α(λ)` with
    /// `α = −0.023 + 0.292/λ[µm]` (Hestroffer & Magnan, A&A 333, 1998),
    /// normalised so the disc integrates to the solar irradiance.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `camera` is not finite or lies below the ground.
    pub fn sun_radiance(&self, camera: DVec3, view: Dir3, sun: Dir3) -> Result<DVec3> {
        let q = self.check_point("camera", camera)?;
        let v = Self::local(q, view);
        let theta = view.dot(sun).acos();
        let ts = self.params.sun_angular_radius;
        if theta >= ts {
            return Ok(DVec3::ZERO);
        }
        let mu_disc = (1.0 - (theta / ts).powi(2)).max(0.0).sqrt();
        let omega = 2.0 * std::f64::consts::PI * (1.0 - ts.cos());
        Ok(with_model!(&*self.inner, m => {
            let t = m.sun_trans_lut(v.r, v.mu);
            let l = (m.sun * t).zip(m.limb, |e, a| e * (a + 2.0) / (2.0 * omega) * mu_disc.powf(a));
            m.rgb(l)
        }))
    }

    /// Aerial perspective between `camera` and `point` by ray marching with
    /// `steps` steps (sunlight transmittance from the LUT): what the air does
    /// to light leaving `point` towards `camera`.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `steps` is outside `1..=2^20`, `camera` is not
    /// finite or below the ground, or `point` is not finite, and
    /// [`AtmosError::BadDirection`](crate::AtmosError::BadDirection) if `point` equals `camera`.
    pub fn aerial_perspective_marched(
        &self,
        camera: DVec3,
        point: DVec3,
        sun: Dir3,
        steps: usize,
    ) -> Result<Attenuation> {
        if steps == 0 || steps > 1 << 20 {
            return Err(invalid("steps", steps, "must be in 1..=2^20"));
        }
        let q = self.check_point("camera", camera)?;
        finite3("point", point)?;
        let d = (point - camera).length();
        if d == 0.0 {
            return Ok(Attenuation::NONE);
        }
        let view = Dir3::new(point - camera)?;
        Ok(self.march_segment(q, view, sun, 0.0, d, steps))
    }

    /// Marches `[t0, t1]` along `view` from planet-centred `q`: RGB attenuation.
    pub(crate) fn march_segment(
        &self,
        q: DVec3,
        view: Dir3,
        sun: Dir3,
        t0: f64,
        t1: f64,
        steps: usize,
    ) -> Attenuation {
        let v = Self::local(q, view);
        let s = Self::local(q, sun);
        let nu = view.dot(sun);
        with_model!(&*self.inner, m => {
            let bound = |k: usize| t0 + (t1 - t0) * k as f64 / steps as f64;
            let (l, t) = m.march(v.r, v.mu, s.mu, nu, steps, bound, |r, mu| m.sun_trans_lut(r, mu), |_, _, _| {});
            Attenuation {
                transmittance: m.rgb(t * m.sun) / m.rgb(m.sun).max(DVec3::splat(1e-30)),
                in_scatter: m.rgb(l),
            }
        })
    }

    /// Builds the per-frame sky-view LUT and aerial-perspective volume for a
    /// camera at world position `camera` and the sun towards `sun`.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `camera` is not finite or lies below the ground.
    pub fn sky_view(&self, camera: DVec3, sun: Dir3) -> Result<SkyView> {
        let q = self.check_point("camera", camera)?;
        Ok(view::build(self.inner.clone(), self.params, q, sun))
    }

    /// This atmosphere lit by the sun from `sun`, as a [`Medium`] (ray marched).
    #[must_use]
    pub fn sunlit(&self, sun: Dir3) -> SunlitAtmosphere<'_> {
        SunlitAtmosphere { atm: self, sun }
    }

    /// The channel model, for the other sky modules.
    pub(crate) fn inner(&self) -> &Inner {
        &self.inner
    }

    /// Convenience for tests and examples: the sun at elevation `deg` degrees and azimuth 0.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `deg` is NaN
    /// or infinite.
    pub fn sun_at_elevation_deg(deg: f64) -> Result<Dir3> {
        Dir3::from_angles(deg.to_radians(), 0.0)
    }

    /// Validates a world-space distance.
    pub(crate) fn check_distance(d: f64) -> Result<f64> {
        if d == 0.0 {
            return Ok(0.0);
        }
        Ok(positive("distance_m", d)?)
    }
}

/// An [`Atmosphere`] under a given sun, usable wherever a [`Medium`] is:
/// exact optical depth by quadrature, in-scatter by ray marching (64 steps).
#[derive(Clone, Copy, Debug)]
pub struct SunlitAtmosphere<'a> {
    atm: &'a Atmosphere,
    sun: Dir3,
}

impl SunlitAtmosphere<'_> {
    const STEPS: usize = 64;

    fn tau_rgb<const N: usize>(m: &Model<N>, tau: Channels<N>) -> DVec3 {
        let t = m.rgb(tau.exp_neg() * m.sun) / m.rgb(m.sun).max(DVec3::splat(1e-30));
        DVec3::new(
            -t.x.max(1e-300).ln(),
            -t.y.max(1e-300).ln(),
            -t.z.max(1e-300).ln(),
        )
    }

    fn extent(&self, origin: DVec3, dir: Dir3) -> (DVec3, f64) {
        let q = self.atm.planet_point(origin);
        let v = Atmosphere::local(q, dir);
        let end = with_model!(self.atm.inner(), m => m.view_extent(v.r, v.mu).map_or(0.0, |e| e.1));
        (q, end)
    }
}

impl Medium for SunlitAtmosphere<'_> {
    fn optical_depth(&self, a: DVec3, b: DVec3) -> DVec3 {
        let d = (b - a).length();
        let Ok(dir) = Dir3::new(b - a) else {
            return DVec3::ZERO;
        };
        let q = self.atm.planet_point(a);
        let v = Atmosphere::local(q, dir);
        with_model!(self.atm.inner(), m => Self::tau_rgb(m, m.optical_depth(v.r, v.mu, d, 16)))
    }

    fn optical_depth_to_infinity(&self, origin: DVec3, dir: Dir3) -> DVec3 {
        let (q, end) = self.extent(origin, dir);
        let v = Atmosphere::local(q, dir);
        with_model!(self.atm.inner(), m => Self::tau_rgb(m, m.optical_depth(v.r, v.mu, end, 32)))
    }

    fn attenuation(&self, a: DVec3, b: DVec3) -> Attenuation {
        let d = (b - a).length();
        match Dir3::new(b - a) {
            Ok(dir) => {
                self.atm
                    .march_segment(self.atm.planet_point(a), dir, self.sun, 0.0, d, Self::STEPS)
            }
            Err(_) => Attenuation::NONE,
        }
    }

    fn attenuation_to_infinity(&self, origin: DVec3, dir: Dir3) -> Attenuation {
        let (q, end) = self.extent(origin, dir);
        self.atm
            .march_segment(q, dir, self.sun, 0.0, end, Self::STEPS)
    }
}

#[cfg(test)]
mod tests;
