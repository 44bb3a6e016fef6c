//! The per-frame part of Hillaire 2020: the sky-view LUT (§5.3) and the
//! aerial-perspective volume (§5.4), converted to linear RGB `f32` so that
//! per-pixel lookups are cheap and the same in RGB and spectral modes.
//!
//! Both are indexed by the view direction relative to the local zenith and
//! to the sun's azimuth. The atmosphere is spherically symmetric, so the
//! relative azimuth `φ ∈ [0, π]` suffices and the volume serves every camera
//! orientation (Hillaire's froxel volume is frustum-aligned instead).

use std::f32::consts::PI;
use std::sync::Arc;

use glam::{DVec3, Vec3, Vec4};

use super::model::Model;
use super::params::AtmosphereParams;
use super::{Inner, with_model};
use crate::Dir3;
use crate::error::Result;
use crate::medium::Attenuation;

/// Aerial perspective at one pixel, in `f32` linear RGB:
/// `L_eye = transmittance · L_surface + in_scatter`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApSample {
    /// Per-channel transmittance in `[0, 1]`.
    pub transmittance: Vec3,
    /// In-scattered radiance along the segment.
    pub in_scatter: Vec3,
}

impl ApSample {
    /// No attenuation: transmittance 1, no in-scatter.
    pub const NONE: ApSample = ApSample {
        transmittance: Vec3::ONE,
        in_scatter: Vec3::ZERO,
    };

    /// Returns `surface` as seen through the air.
    #[inline]
    #[must_use]
    pub fn apply(&self, surface: Vec3) -> Vec3 {
        self.transmittance * surface + self.in_scatter
    }
}

/// The sky as seen from one camera position under one sun direction: the
/// sky-view LUT, the aerial-perspective volume, the sun disc and the sky's
/// irradiance; `Send + Sync`. Built by [`Atmosphere::sky_view`](super::Atmosphere::sky_view).
#[derive(Clone, Debug)]
pub struct SkyView {
    pub(super) model: Arc<Inner>,
    pub(super) params: AtmosphereParams,
    pub(super) q: DVec3,
    pub(super) up: Vec3,
    pub(super) sun: Dir3,
    pub(super) sun_f: Vec3,
    pub(super) mu_s: f32,
    pub(super) sin_s: f32,
    pub(super) theta_h: f32,
    pub(super) sky: Vec<Vec4>,
    pub(super) sky_w: usize,
    pub(super) sky_h: usize,
    pub(super) ap: Vec<[Vec4; 2]>,
    pub(super) ap_dims: (usize, usize, usize),
    pub(super) ap_max: f32,
    pub(super) sun_centre: Vec3,
    pub(super) limb: Vec3,
    pub(super) sun_radius: f32,
    pub(super) cos_sun_radius: f32,
    pub(super) ambient: Vec3,
    pub(super) sun_e: Vec3,
    pub(super) lanes: super::batch::LaneConsts,
}

#[inline]
fn v_to_zen(v: f64, theta_h: f64) -> f64 {
    if v < 0.5 {
        let t = 1.0 - 2.0 * v;
        theta_h * (1.0 - t * t)
    } else {
        let t = 2.0 * v - 1.0;
        theta_h + (std::f64::consts::PI - theta_h) * t * t
    }
}

#[inline]
fn u_to_az(u: f64) -> f64 {
    std::f64::consts::PI * u * u
}

fn par_fill<T: Send>(data: &mut [T], w: usize, f: impl Fn(usize, &mut [T]) + Sync + Send) {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        data.par_chunks_mut(w)
            .enumerate()
            .for_each(|(j, row)| f(j, row));
    }
    #[cfg(not(feature = "parallel"))]
    data.chunks_mut(w)
        .enumerate()
        .for_each(|(j, row)| f(j, row));
}

fn build_with<const N: usize>(
    m: &Model<N>,
    p: &AtmosphereParams,
    q: DVec3,
    sun: Dir3,
) -> (Vec<Vec3>, Vec<[Vec3; 2]>, Vec3, f64) {
    let r = q.length();
    let up = q / r;
    let mu_s = up.dot(sun.get()).clamp(-1.0, 1.0);
    let sin_s = (1.0 - mu_s * mu_s).max(0.0).sqrt();
    let b = m.bottom();
    let theta_h = std::f64::consts::PI
        - ((r * r - b * b).max(0.0).sqrt() / r)
            .clamp(-1.0, 1.0)
            .acos();
    let dir_of = |u: f64, v: f64| {
        let theta = v_to_zen(v, theta_h);
        let phi = u_to_az(u);
        let (mu, st) = (theta.cos(), theta.sin());
        (mu, mu * mu_s + st * sin_s * phi.cos())
    };
    // Sky-view LUT.
    let (w, h) = p.lut.sky_view;
    let steps = p.lut.sky_view_steps;
    let mut sky = vec![Vec3::ZERO; w * h];
    par_fill(&mut sky, w, |j, row| {
        let v = j as f64 / (h - 1) as f64;
        for (i, px) in row.iter_mut().enumerate() {
            let (mu, nu) = dir_of(i as f64 / (w - 1) as f64, v);
            if let Some((t0, t1, _)) = m.view_extent(r, mu) {
                let bound = |k: usize| {
                    let f = k as f64 / steps as f64;
                    t0 + (t1 - t0) * f * f
                };
                let (l, _) = m.march(
                    r,
                    mu,
                    mu_s,
                    nu,
                    steps,
                    bound,
                    |rr, ms| m.sun_trans_lut(rr, ms),
                    |_, _, _| {},
                );
                *px = m.rgb(l).as_vec3();
            }
        }
    });
    // Aerial-perspective volume, layout [zenith][azimuth][distance].
    let (na, nz, nd) = p.lut.aerial;
    let dmax = p.lut.aerial_max_distance_m;
    let mut ap = vec![[Vec3::ZERO, Vec3::ONE]; na * nz * nd];
    let white = m.rgb(m.sun).max(DVec3::splat(1e-30));
    let sub = 2 * (nd - 1);
    par_fill(&mut ap, na * nd, |j, row| {
        let v = j as f64 / (nz - 1) as f64;
        for a in 0..na {
            let (mu, nu) = dir_of(a as f64 / (na - 1) as f64, v);
            let cell = &mut row[a * nd..(a + 1) * nd];
            if let Some((t0, t1, _)) = m.view_extent(r, mu) {
                let bound = |k: usize| {
                    let f = k as f64 / sub as f64;
                    (dmax * f * f).clamp(t0, t1)
                };
                m.march(
                    r,
                    mu,
                    mu_s,
                    nu,
                    sub,
                    bound,
                    |rr, ms| m.sun_trans_lut(rr, ms),
                    |k, l, t| {
                        if k % 2 == 0 {
                            cell[k / 2] =
                                [m.rgb(l).as_vec3(), (m.rgb(t * m.sun) / white).as_vec3()];
                        }
                    },
                );
            }
        }
    });
    // Sun disc centre radiance (limb-darkening normalisation) after transmittance.
    let t_sun = m.sun_trans_lut(r, mu_s);
    let ts = p.sun_angular_radius;
    let omega = 2.0 * std::f64::consts::PI * (1.0 - ts.cos());
    let centre = (m.sun * t_sun).zip(m.limb, |e, a| e * (a + 2.0) / (2.0 * omega));
    let sun_centre = m.rgb(centre).as_vec3();
    (sky, ap, sun_centre, theta_h)
}

pub(crate) fn build(model: Arc<Inner>, params: AtmosphereParams, q: DVec3, sun: Dir3) -> SkyView {
    let (sky, ap, sun_centre, theta_h) = with_model!(&*model, m => build_with(m, &params, q, sun));
    let limb = with_model!(&*model, m => {
        // Per-RGB-channel limb-darkening exponents at 680/550/440 nm.
        let _ = m;
        let a = |l: f64| (-0.023 + 0.292 / (l * 1e-3)) as f32;
        Vec3::new(a(680.0), a(550.0), a(440.0))
    });
    let up = (q / q.length()).as_vec3();
    let mu_s = up.as_dvec3().dot(sun.get()).clamp(-1.0, 1.0);
    let mut view = SkyView {
        model,
        params,
        q,
        up,
        sun,
        sun_f: sun.as_vec3(),
        mu_s: mu_s as f32,
        sin_s: (1.0 - mu_s * mu_s).max(0.0).sqrt() as f32,
        theta_h: theta_h as f32,
        sky: sky.iter().map(|c| c.extend(0.0)).collect(),
        sky_w: params.lut.sky_view.0,
        sky_h: params.lut.sky_view.1,
        ap: ap
            .iter()
            .map(|[l, t]| [l.extend(0.0), t.extend(0.0)])
            .collect(),
        ap_dims: params.lut.aerial,
        ap_max: params.lut.aerial_max_distance_m as f32,
        sun_centre,
        limb,
        sun_radius: params.sun_angular_radius as f32,
        cos_sun_radius: params.sun_angular_radius.cos() as f32,
        ambient: Vec3::ZERO,
        sun_e: Vec3::ZERO,
        lanes: super::batch::LaneConsts::ZERO,
    };
    view.lanes = super::batch::LaneConsts::new(&view, q.length(), params.bottom_radius_m);
    view.ambient = view.integrate_irradiance();
    view.sun_e = view.sun_irradiance();
    view
}

impl SkyView {
    /// Sky radiance (linear RGB, without the sun disc) along `view`, from the
    /// sky-view LUT. Below the horizon it is the light scattered in front of
    /// the ground; add the ground's own radiance through [`SkyView::aerial_perspective`].
    #[must_use]
    pub fn radiance(&self, view: Dir3) -> Vec3 {
        self.radiance_f32(view.as_vec3())
    }

    /// [`SkyView::radiance`] for an `f32` direction that the caller guarantees
    /// is unit length (the hot path of image loops); a direction that is not
    /// (|d| off by more than 1e-3, or NaN) returns black instead of a wrong colour.
    #[inline]
    #[must_use]
    pub fn radiance_f32(&self, d: Vec3) -> Vec3 {
        let c = &self.lanes;
        let Some((mu, nu)) = c.cosines(d) else {
            return Vec3::ZERO;
        };
        let (u, v) = c.uv(mu, nu);
        self.sky_at(u, v).truncate()
    }

    /// Sun-disc radiance along `view` (limb-darkened, after transmittance); zero off the disc.
    #[must_use]
    pub fn sun_disc(&self, view: Dir3) -> Vec3 {
        self.sun_disc_f32(view.as_vec3())
    }

    /// [`SkyView::sun_disc`] for a unit `f32` direction (hot path).
    #[inline]
    #[must_use]
    pub fn sun_disc_f32(&self, view: Vec3) -> Vec3 {
        let c = view.dot(self.sun_f);
        if c < self.cos_sun_radius {
            return Vec3::ZERO;
        }
        let theta = c.min(1.0).acos();
        let mu = (1.0 - (theta / self.sun_radius).powi(2)).max(0.0).sqrt();
        self.sun_centre
            * Vec3::new(
                mu.powf(self.limb.x),
                mu.powf(self.limb.y),
                mu.powf(self.limb.z),
            )
    }

    /// Sky plus sun disc along `view`.
    #[must_use]
    pub fn radiance_with_sun(&self, view: Dir3) -> Vec3 {
        self.radiance(view) + self.sun_disc(view)
    }

    /// Aerial perspective along `view` over `distance_m` metres from the camera
    /// (trilinear in the volume). Beyond the volume's range
    /// ([`LutSettings::aerial_max_distance_m`](super::LutSettings)) it falls
    /// back to exact ray marching (slower).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for a negative or NaN `distance_m`.
    pub fn aerial_perspective(&self, view: Dir3, distance_m: f64) -> Result<ApSample> {
        let d = super::Atmosphere::check_distance(distance_m)?;
        if d > self.ap_max as f64 {
            let a = self.exact(view, d);
            return Ok(ApSample {
                transmittance: a.transmittance.as_vec3(),
                in_scatter: a.in_scatter.as_vec3(),
            });
        }
        Ok(self.aerial_perspective_f32(view.as_vec3(), d as f32))
    }

    fn exact(&self, view: Dir3, d: f64) -> Attenuation {
        let atm = super::Atmosphere {
            inner: self.model.clone(),
            params: self.params,
        };
        atm.march_segment(self.q, view, self.sun, 0.0, d, 48)
    }

    /// [`SkyView::aerial_perspective`] on the `f32` hot path: `d` must be a unit
    /// direction and `0 ≤ distance ≤` the volume's range (distances are clamped
    /// to it; a non-unit or NaN direction gives no attenuation).
    #[inline]
    #[must_use]
    pub fn aerial_perspective_f32(&self, d: Vec3, distance_m: f32) -> ApSample {
        let c = &self.lanes;
        let cos = c.cosines(d);
        match cos {
            Some((mu, nu)) if !distance_m.is_nan() => {
                let (u, v) = c.uv(mu, nu);
                let (l, t) = self.ap_at(u, v, c.depth(distance_m));
                ApSample {
                    transmittance: t.truncate(),
                    in_scatter: l.truncate(),
                }
            }
            _ => ApSample::NONE,
        }
    }

    /// Irradiance from the sky (not the sun) on an upward-facing horizontal
    /// surface at the camera, integrated from the sky-view LUT.
    #[must_use]
    pub fn sky_irradiance(&self) -> Vec3 {
        self.ambient
    }

    /// Solar irradiance at the camera after transmittance (linear RGB).
    #[must_use]
    pub fn sun_irradiance(&self) -> Vec3 {
        // The disc integrates to the irradiance by construction.
        let atm = super::Atmosphere {
            inner: self.model.clone(),
            params: self.params,
        };
        let p = self.q - DVec3::new(0.0, 0.0, self.params.bottom_radius_m);
        atm.sun_irradiance(p, self.sun)
            .map(|v| v.as_vec3())
            .unwrap_or(Vec3::ZERO)
    }

    /// Planet-centred camera position.
    pub(crate) fn camera_planet(&self) -> DVec3 {
        self.q
    }

    pub(crate) fn bottom_radius(&self) -> f64 {
        self.params.bottom_radius_m
    }

    pub(crate) fn aerial_range(&self) -> f64 {
        f64::from(self.ap_max)
    }

    pub(crate) fn sun_irradiance_cached(&self) -> Vec3 {
        self.sun_e
    }

    /// The sun direction this view was built for.
    #[must_use]
    pub fn sun(&self) -> Dir3 {
        self.sun
    }

    fn integrate_irradiance(&self) -> Vec3 {
        // Local tangent frame around `up`.
        let up = self.up;
        let t = if up.z.abs() < 0.9 {
            Vec3::Z.cross(up).normalize()
        } else {
            Vec3::X.cross(up).normalize()
        };
        let bt = up.cross(t);
        let (nt, np) = (32, 64);
        let mut e = Vec3::ZERO;
        let dth = std::f32::consts::FRAC_PI_2 / nt as f32;
        let dph = 2.0 * PI / np as f32;
        for i in 0..nt {
            let th = (i as f32 + 0.5) * dth;
            let (s, c) = th.sin_cos();
            for k in 0..np {
                let ph = (k as f32 + 0.5) * dph;
                let d = (t * ph.cos() + bt * ph.sin()) * s + up * c;
                e += self.radiance_f32(d.normalize()) * (c * s * dth * dph);
            }
        }
        e
    }
}
