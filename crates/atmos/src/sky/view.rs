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

use glam::{DVec3, Vec3};

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
    model: Arc<Inner>,
    params: AtmosphereParams,
    q: DVec3,
    up: Vec3,
    sun: Dir3,
    sun_f: Vec3,
    mu_s: f32,
    sin_s: f32,
    theta_h: f32,
    sky: Vec<Vec3>,
    sky_w: usize,
    sky_h: usize,
    ap: Vec<[Vec3; 2]>,
    ap_dims: (usize, usize, usize),
    ap_max: f32,
    sun_centre: Vec3,
    limb: Vec3,
    sun_radius: f32,
    cos_sun_radius: f32,
    ambient: Vec3,
    sun_e: Vec3,
}

/// `acos(x)` in `f32` to 7e-5 rad (Abramowitz & Stegun 4.4.45), several times
/// cheaper than `f32::acos`; ample for indexing LUTs whose texels span ~0.02 rad.
#[inline]
fn fast_acos(x: f32) -> f32 {
    let a = x.abs().min(1.0);
    let p = ((-0.018_729_3 * a + 0.074_261) * a - 0.212_114_4) * a + 1.570_728_8;
    let r = p * (1.0 - a).sqrt();
    if x < 0.0 { PI - r } else { r }
}

/// Zenith angle → `[0, 1]`, concentrating texels at the horizon `θ_h` (Hillaire §5.3).
#[inline]
fn zen_to_v(theta: f32, theta_h: f32) -> f32 {
    if theta < theta_h {
        0.5 * (1.0 - (1.0 - theta / theta_h).max(0.0).sqrt())
    } else {
        0.5 + 0.5 * ((theta - theta_h) / (PI - theta_h)).clamp(0.0, 1.0).sqrt()
    }
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

/// Relative azimuth `φ ∈ [0, π]` → `[0, 1]`, concentrating texels towards the sun.
#[inline]
fn az_to_u(phi: f32) -> f32 {
    (phi / PI).clamp(0.0, 1.0).sqrt()
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
        sky,
        sky_w: params.lut.sky_view.0,
        sky_h: params.lut.sky_view.1,
        ap,
        ap_dims: params.lut.aerial,
        ap_max: params.lut.aerial_max_distance_m as f32,
        sun_centre,
        limb,
        sun_radius: params.sun_angular_radius as f32,
        cos_sun_radius: params.sun_angular_radius.cos() as f32,
        ambient: Vec3::ZERO,
        sun_e: Vec3::ZERO,
    };
    view.ambient = view.integrate_irradiance();
    view.sun_e = view.sun_irradiance();
    view
}

impl SkyView {
    /// `(u, v)` LUT coordinates of a view direction (`v` zenith, `u` azimuth from the sun).
    #[inline]
    fn uv(&self, d: Vec3) -> (f32, f32) {
        let mu = d.dot(self.up).clamp(-1.0, 1.0);
        let nu = d.dot(self.sun_f);
        let st = (1.0 - mu * mu).max(0.0).sqrt();
        let denom = st * self.sin_s;
        let cos_phi = if denom > 1e-6 {
            ((nu - mu * self.mu_s) / denom).clamp(-1.0, 1.0)
        } else {
            1.0
        };
        (
            az_to_u(fast_acos(cos_phi)),
            zen_to_v(fast_acos(mu), self.theta_h),
        )
    }

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
        if (d.length_squared() - 1.0).abs() > 2e-3 || !d.is_finite() {
            return Vec3::ZERO;
        }
        let (u, v) = self.uv(d);
        let fx = u * (self.sky_w - 1) as f32;
        let fy = v * (self.sky_h - 1) as f32;
        let i = (fx as usize).min(self.sky_w - 2);
        let j = (fy as usize).min(self.sky_h - 2);
        let (tx, ty) = (fx - i as f32, fy - j as f32);
        let w = self.sky_w;
        let a = self.sky[j * w + i].lerp(self.sky[j * w + i + 1], tx);
        let b = self.sky[(j + 1) * w + i].lerp(self.sky[(j + 1) * w + i + 1], tx);
        a.lerp(b, ty)
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
    /// back to exact ray marching (slower). Fails on a negative or NaN distance.
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
        if (d.length_squared() - 1.0).abs() > 2e-3 || !d.is_finite() || distance_m.is_nan() {
            return ApSample {
                transmittance: Vec3::ONE,
                in_scatter: Vec3::ZERO,
            };
        }
        let (na, nz, nd) = self.ap_dims;
        let (u, v) = self.uv(d);
        let w = (distance_m.max(0.0) / self.ap_max).min(1.0).sqrt();
        let fa = u * (na - 1) as f32;
        let fz = v * (nz - 1) as f32;
        let fd = w * (nd - 1) as f32;
        let (ia, iz, id) = (
            (fa as usize).min(na - 2),
            (fz as usize).min(nz - 2),
            (fd as usize).min(nd - 2),
        );
        let (ta, tz, td) = (fa - ia as f32, fz - iz as f32, fd - id as f32);
        let idx = |z: usize, a: usize| (z * na + a) * nd + id;
        let mut l = Vec3::ZERO;
        let mut t = Vec3::ZERO;
        for (z, wz) in [(iz, 1.0 - tz), (iz + 1, tz)] {
            for (a, wa) in [(ia, 1.0 - ta), (ia + 1, ta)] {
                let k = idx(z, a);
                let wgt = wz * wa;
                let (c0, c1) = (self.ap[k], self.ap[k + 1]);
                l += c0[0].lerp(c1[0], td) * wgt;
                t += c0[1].lerp(c1[1], td) * wgt;
            }
        }
        ApSample {
            transmittance: t,
            in_scatter: l,
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
