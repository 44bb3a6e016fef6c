//! Ebert's low-albedo ray march (Ebert 2001, "Volume rendering": single
//! scattering with atmospheric attenuation along the eye ray, shadows from
//! 3-D shadow tables), with multiple scattering ([`Scattering`](super::Scattering): a grid of
//! the sun's multiply scattered light traced once per scene, or the octave
//! approximation) and the powder term as options.
//!
//! Along the eye ray, in steps of `Δt` (midpoint samples, empty space skipped
//! with the density's bound): the source at a sample is
//! `σ_s·(E_sun·P(τ_sun) + A·Q(τ_up)) + σ_a·L_e`, where `τ` are optical depths toward the sun and
//! up (from tables or direct shadow rays), `P` the sun's single scattering
//! `p·e^{−τ}` plus the multiply scattered light (the cache's
//! [`ScatterCache::toward_eye`](super::cache::ScatterCache::toward_eye), or
//! the octave sum of [`ScatterOctaves`](super::ScatterOctaves) in the
//! medium's form, [`MediumOctaves`](super::MediumOctaves)), `Q` the
//! environment's octave sum (plain `e^{−τ}` for single scattering) and `A`
//! the environment's mean radiance; each step adds the exact integral of
//! that source over the step and multiplies the transmittance by
//! `exp(−σ_t·Δt)`. The march stops when the transmittance falls below a
//! threshold. The ambient term treats the environment as isotropic and
//! occluded along the vertical only: an approximation, measured against the
//! reference (0.74–1.14 of it on a thick ball under a uniform sky). When the
//! multiple-scattering cache traces the scene's local light
//! ([`CacheParams::local`](super::CacheParams::local) > 0), the sky's light
//! goes into the cache's grid at every order instead (see
//! [`local`](super::local)) and leaves the ambient term, as the ground's does.
//!
//! **The forward peak.** A cloud's phase function sends about half of its
//! scattering into a diffraction peak a few degrees wide or less
//! ([`CloudPhase::peak_lobe`](crate::phase::CloudPhase::peak_lobe)): light
//! that keeps its direction, as good as unscattered for the transport
//! inside the volume. With [`FastSettings::truncate_forward_peak`] the core
//! of that peak, the part of its lobe within [`PEAK_CORE_DEG`] of the
//! forward direction ([`CloudPhase::peak_core`](crate::phase::CloudPhase::peak_core)),
//! is split off as `p = f·p_core + (1 − f)·p'` (`f` the core's share) and the
//! sun's light is counted once in each part. The lobe's wings stay in `p'`:
//! for 5 µm droplets 7 % of the lobe lies beyond 20°, and at right angles
//! the lobe is a third of the whole phase function, so a peak truncated
//! whole would never turn the light it carried toward a viewer at the side
//! (a thick ball of them seen from the side was 8.5 % too dark against the
//! reference; cut at 20°, it is within the reference's noise). The part
//! outside the core travels through the δ-M medium of Wiscombe 1977
//! (`σ_t' = σ_t(1 − ω f)`, `ω' = ω(1 − f)/(1 − ω f)`, `g' = (g − f)/(1 − f)`:
//! [`MediumParams::without_forward_peak`](super::MediumParams::without_forward_peak)),
//! which carries every optical depth and the whole octave sum; its first
//! order `σ_s'·p'·e^{−τ'}` is the light scattered once out of the core. The
//! light that scatters only within the core, `e^{−τ'} − e^{−τ}` of the sun,
//! is counted at the core scattering on the eye ray that turns it toward
//! the eye, with the core scatterings before it along the sun's line and
//! after it along the eye ray (Poisson in the peak's share of the exact
//! optical depths toward the sun and the eye), each order a little wider
//! ([`PeakOrders`], where the series is derived), so the aureole round a
//! low sun shows through thin cloud, and brightens where a thicker cloud
//! lies along the sun's line.
//!
//! This is Nakajima & Tanaka's truncated multiple-scattering approximation
//! (1988, §2, "TMS": the truncated medium for the multiple scattering, the
//! exact phase function for single scattering), except for the peak: their
//! correction attenuates the whole single scattering by the δ-M optical
//! depths, which counts a path of `n` peak scatterings `n` times, and the
//! exact depths alone drop every path of two or more; the core's orders
//! count each once.
//!
//! With [`FastSettings::near_sun`] the eye rays within a few degrees of the
//! sun march their own shadow rays instead of reading the table
//! ([`NearSunRays`] says why). The multiple-scattering cache is traced in
//! the δ-M medium, as the rest of the transport. The fast mode's error
//! against the reference is in `docs/performance.md`.

use glam::Vec3;
use natura_core::{Aabb, Image, NoProgress, Progress};

use super::cache::EyeBasis;
use super::local::LocalEye;
use super::model::{PeakOrders, powder};
use super::multiple::Multiple;
pub use super::settings::{FastSettings, MAX_SUBSTEPS, NearSunRays, Shadows};
use super::shadow::{ShadowTable, optical_depth_ray, table_dims};
use super::{BLOCKED_DEPTH, LookAtCamera, MediumParams, Scene, Surface, check_step};
use crate::density::ray_box;
use crate::phase::{PEAK_CORE_DEG, PeakCore};

mod steps;
use crate::error::{Result, VolumeError, in_range, positive};

/// The fast renderer: shadow tables built once for a scene, then any number
/// of rays or images.
pub struct FastRenderer<'s> {
    scene: &'s Scene<'s>,
    settings: FastSettings,
    sun_table: Option<ShadowTable>,
    up_table: Option<ShadowTable>,
    ambient: Vec3,
    bounds: Aabb,
    /// The medium the multiple scattering travels through (δ-M when truncating).
    medium: MediumParams,
    /// Its extinction over the scene's (`1 − ω f`; 1 without truncation).
    ratio: f32,
    /// The truncated peak's core (`None` without truncation).
    peak: Option<PeakCore>,
    /// The multiple scattering, prepared for the transport medium.
    multiple: Multiple,
}

/// What [`FastRenderer::seen`] finds along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seen {
    /// The volume's light (and the air's in front of it where the volume
    /// hides what lies behind), without anything behind the volume.
    pub radiance: Vec3,
    /// Transmittance of the transport medium (the δ-M medium when the
    /// forward peak is truncated): the weight of what lies behind.
    pub transmittance: f32,
    /// Transmittance of the exact medium (the forward peak counted as
    /// scattered): the weight of a light source seen through the volume
    /// whose peak-scattered light is already in `radiance` (a sun disc).
    pub direct_transmittance: f32,
    /// Radiance of what lies behind the volume (a surface, or the environment).
    pub behind: Vec3,
}

/// What stays constant along one eye ray of [`FastRenderer::seen`].
struct EyeRay {
    o: Vec3,
    d: Vec3,
    sun: Option<super::Sun>,
    /// The forward peak's orders toward this eye ray.
    orders: Option<PeakOrders>,
    /// The share `ω f` of the exact medium's extinction that is peak scattering.
    peak_share: f32,
    /// The share of direct shadow rays in the sun's optical depths.
    near: f32,
    /// The multiple-scattering cache's factors toward this eye ray.
    eye: Option<EyeBasis>,
    /// The surfaces' and glow's light's factors toward this eye ray.
    local: Option<LocalEye>,
}

/// The running sums of one eye ray's march.
struct Along {
    /// Transmittance of the transport medium.
    tr: f32,
    /// Transmittance of the exact medium.
    tr0: f32,
    /// Radiance gathered.
    l: Vec3,
    /// Weight and weighted distance of the gathered light (its mean depth).
    depth_w: f32,
    depth_sum: f32,
    /// The exact medium's optical depth from the eye.
    tau_eye0: f32,
}

impl std::fmt::Debug for FastRenderer<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FastRenderer")
            .field("settings", &self.settings)
            .field("ambient", &self.ambient)
            .finish_non_exhaustive()
    }
}

/// Fibonacci-sphere directions for the environment's mean radiance.
pub(crate) fn sphere_dirs(n: usize) -> impl Iterator<Item = Vec3> {
    let ga = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n).map(move |i| {
        let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = ga * i as f32;
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

impl<'s> FastRenderer<'s> {
    /// Prepares `scene` (validating it and building the shadow tables).
    ///
    /// # Errors
    ///
    /// As [`Scene::validate`] and [`Scene::majorant`] (the reference's rule:
    /// an extinction times maximum density of 1e9 1/m or more, which would
    /// overflow the march's optical depths, is refused);
    /// [`VolumeError::InvalidParameter`] for a bad step, table size, powder
    /// or threshold.
    pub fn new(scene: &'s Scene<'s>, settings: FastSettings) -> Result<Self> {
        Self::new_with_progress(scene, settings, &NoProgress)
    }

    /// [`FastRenderer::new`], reporting the shadow tables' build to
    /// `progress` as the stage `"shadow tables"`, with one unit per row of
    /// table nodes (the sun's table and the sky's, one after the other).
    /// With [`Shadows::Rays`] there are no tables and nothing is reported.
    ///
    /// # Errors
    ///
    /// As [`FastRenderer::new`].
    pub fn new_with_progress(
        scene: &'s Scene<'s>,
        settings: FastSettings,
        progress: &dyn Progress,
    ) -> Result<Self> {
        scene.validate()?;
        scene.majorant()?;
        settings.scattering.validate()?;
        in_range(
            "step_growth",
            settings.step_growth,
            0.0,
            1.0,
            "must lie in [0, 1]",
        )?;
        in_range("powder", settings.powder, 0.0, 1.0, "must lie in [0, 1]")?;
        in_range(
            "min_transmittance",
            settings.min_transmittance,
            0.0,
            0.999,
            "must lie in [0, 1)",
        )?;
        let bounds = scene.density.bounds();
        let extent = (bounds.max - bounds.min).length();
        check_step("step", settings.step, extent, 1e7)?;
        if !(1..=MAX_SUBSTEPS).contains(&settings.substeps) {
            return Err(VolumeError::InvalidParameter {
                name: "substeps",
                value: settings.substeps.to_string(),
                expected: "density samples per step in 1..=16",
            });
        }
        if let Some(n) = settings.near_sun {
            in_range(
                "near_sun.within_deg",
                n.within_deg,
                1e-3,
                60.0,
                "must lie in (0, 60] degrees",
            )?;
            check_step("near_sun.step", n.step, extent, 1e7)?;
        }
        let medium = if settings.truncate_forward_peak {
            scene.medium.without_forward_peak()
        } else {
            scene.medium
        };
        let ratio = if scene.medium.extinction > 0.0 {
            medium.extinction / scene.medium.extinction
        } else {
            1.0
        };
        let peak = match scene.medium.phase.peak_core(PEAK_CORE_DEG) {
            Some(core) if settings.truncate_forward_peak && ratio > 0.0 && core.weight > 0.0 => {
                Some(core)
            }
            _ => None,
        };
        let ext = medium.extinction;
        let (sun_table, up_table) = match settings.shadows {
            Shadows::Table(n) => {
                if !(2..=1024).contains(&n) {
                    return Err(VolumeError::InvalidParameter {
                        name: "shadows",
                        value: n.to_string(),
                        expected: "a table of 2..=1024 nodes along the longest axis",
                    });
                }
                let dims = table_dims(&bounds, n);
                let sun_dir = scene.sun_unit().map(|s| s.direction);
                let tables = 1 + u64::from(sun_dir.is_some());
                progress.start("shadow tables", tables * (dims[1] * dims[2]) as u64);
                let build = |light| {
                    ShadowTable::build_reporting(
                        scene.density,
                        ext,
                        light,
                        dims,
                        &scene.solids,
                        progress,
                    )
                };
                let sun = sun_dir.map(build).transpose()?;
                let up = build(Vec3::Z)?;
                progress.finish();
                (sun, Some(up))
            }
            Shadows::Rays(h) => {
                check_step("shadows", h, extent, 1e7)?;
                (None, None)
            }
        };
        let multiple = Multiple::new(&settings.scattering, scene, &medium, ratio)?;
        // The environment's mean radiance over the sphere, the ground's unshadowed
        // radiance below the horizon (unless the cache traces the ground's light).
        let n = 512;
        let mut ambient = Vec3::ZERO;
        for d in sphere_dirs(n) {
            ambient += if scene.ground.is_some() && d.z < 0.0 {
                if multiple.traces_ground() {
                    Vec3::ZERO
                } else {
                    scene.ground_radiance(1.0)
                }
            } else if multiple.traces_sky() {
                Vec3::ZERO
            } else {
                scene.environment.radiance(d)
            };
        }
        Ok(Self {
            scene,
            settings,
            sun_table,
            up_table,
            ambient: ambient / n as f32,
            bounds,
            multiple,
            medium,
            ratio,
            peak,
        })
    }

    /// Optical depth toward the sun at `p` (solids included).
    #[inline]
    fn tau_sun(&self, p: Vec3, l: Vec3) -> f32 {
        self.tau_toward(self.sun_table.as_ref(), p, l)
    }

    /// The share of [`NearSunRays`] in the sun's optical depths for the eye
    /// ray along `d`: 1 within `within_deg` of the sun, 0 beyond 1.5 times
    /// that angle, a smoothstep of the cosine between.
    fn near_sun_share(&self, d: Vec3) -> f32 {
        match (self.settings.near_sun, self.scene.sun_unit()) {
            (Some(n), Some(s)) => {
                let mu = d.dot(s.direction);
                let inner = n.within_deg.to_radians().cos();
                let outer = (1.5 * n.within_deg).to_radians().cos();
                natura_core::smoothstep(outer, inner, mu)
            }
            _ => 0.0,
        }
    }

    /// [`Self::tau_sun`] with a share `near` of it from a direct shadow ray
    /// ([`NearSunRays`]): `(1 − near)·τ_table + near·τ_ray`.
    #[inline]
    fn tau_sun_near(&self, p: Vec3, l: Vec3, near: f32) -> f32 {
        let Some(n) = self.settings.near_sun.filter(|_| near > 0.0) else {
            return self.tau_sun(p, l);
        };
        let ray = self.tau_ray(p, l, n.step);
        if near >= 1.0 {
            ray
        } else {
            (1.0 - near) * self.tau_sun(p, l) + near * ray
        }
    }

    /// Optical depth from `p` toward `l` by a direct shadow ray in steps of
    /// `h` (solids included).
    #[inline]
    fn tau_ray(&self, p: Vec3, l: Vec3, h: f32) -> f32 {
        let sc = self.scene;
        if sc.blocked(p, l) {
            BLOCKED_DEPTH
        } else {
            optical_depth_ray(sc.density, self.medium.extinction, p, l, h)
        }
    }

    /// Optical depth of the whole line through `p` along the sun `l` within
    /// the volume's bounds: the sun's optical depth where the line leaves
    /// the bounds away from the sun.
    #[inline]
    fn sun_chord(&self, p: Vec3, l: Vec3) -> f32 {
        match ray_box(p, (-l).recip(), &self.bounds) {
            Some((_, t1)) if t1 > 0.0 => {
                let q = p - l * (t1 * (1.0 - 1e-4));
                match self.sun_table.as_ref() {
                    Some(t) => t.optical_depth(q),
                    None => self.tau_sun(q, l),
                }
            }
            _ => self.tau_sun(p, l),
        }
    }

    /// Optical depth straight up at `p` (solids included).
    #[inline]
    fn tau_up(&self, p: Vec3) -> f32 {
        self.tau_toward(self.up_table.as_ref(), p, Vec3::Z)
    }

    #[inline]
    fn tau_toward(&self, table: Option<&ShadowTable>, p: Vec3, l: Vec3) -> f32 {
        let sc = self.scene;
        match (table, self.settings.shadows) {
            // Inside the table solids are in its nodes; outside, test them here.
            (Some(t), _) => {
                if !self.bounds.contains(p) && sc.blocked(p, l) {
                    BLOCKED_DEPTH
                } else {
                    t.optical_depth(p)
                }
            }
            (None, Shadows::Rays(h)) => self.tau_ray(p, l, h),
            (None, Shadows::Table(_)) => 0.0,
        }
    }

    /// Radiance arriving at `o` along `-d` (`d` unit), as seen by the eye.
    #[must_use]
    pub fn radiance(&self, o: Vec3, d: Vec3) -> Vec3 {
        let s = self.seen(o, d);
        s.radiance + s.behind * s.transmittance
    }

    /// What the eye at `o` sees along `d` (unit), in parts: the volume's
    /// light in front of what lies behind it (with the air's), the
    /// transmittances, and the radiance behind (a surface or the
    /// environment), so that [`FastRenderer::radiance`] is
    /// `radiance + transmittance · behind`. A caller that puts its own
    /// background behind the volume (a sky with a sun disc) composes it the
    /// same way.
    #[must_use]
    pub fn seen(&self, o: Vec3, d: Vec3) -> Seen {
        let sc = self.scene;
        let sun = sc.sun_unit();
        let surface = sc.surface_hit(o, d);
        let t_ground = surface.map_or(f32::INFINITY, |(t, _)| t);
        let ray = EyeRay {
            o,
            d,
            sun,
            // The peak's orders toward this eye ray.
            orders: match (self.peak, sun) {
                (Some(core), Some(s)) => Some(PeakOrders::new(&core, d.dot(s.direction))),
                _ => None,
            },
            peak_share: self.peak.map_or(0.0, |hg| hg.weight * sc.medium.albedo),
            near: self.near_sun_share(d),
            eye: self.multiple.eye(d),
            local: self.multiple.local_eye(d),
        };
        let mut a = Along {
            tr: 1.0,
            tr0: 1.0,
            l: Vec3::ZERO,
            depth_w: 0.0,
            depth_sum: 0.0,
            tau_eye0: 0.0,
        };
        if let Some((t0, t1)) = ray_box(o, d.recip(), &self.bounds) {
            self.march(&ray, t0, t1.min(t_ground), &mut a);
        }
        let depth = if a.depth_w > 0.0 {
            a.depth_sum / a.depth_w
        } else {
            f32::INFINITY
        };
        let back = self.behind(o, d, surface);
        // The air between the eye and the volume dims its light and adds its
        // own in-scatter where the volume hides what lies behind; the sky and
        // ground behind already carry the air's light along the whole ray:
        // `T_air·L + (1 − T)·L_air + T·L_back`.
        let air = sc.air(d, depth);
        Seen {
            radiance: air.transmittance * a.l + air.in_scatter * (1.0 - a.tr),
            transmittance: a.tr,
            direct_transmittance: if a.tr > 0.0 { a.tr0 } else { 0.0 },
            behind: back,
        }
    }

    /// The sources at `p` (radiance per metre): in the transport medium
    /// (emission, the sun's light of every order, the first included, and
    /// the ambient light), and the sun's light scattered toward the eye at
    /// `p` by the forward peak's core, in the exact medium, with the core
    /// scatterings before and after it (zero without truncation).
    /// `tau_eye0` is the exact medium's optical depth from the eye.
    #[inline]
    fn sources(
        &self,
        ray: &EyeRay,
        p: Vec3,
        sigma_t: f32,
        sigma_t0: f32,
        le: Vec3,
        tau_eye0: f32,
    ) -> (Vec3, Vec3) {
        let (m0, m) = (&self.scene.medium, &self.medium);
        let mut src = le * (sigma_t * (1.0 - m.albedo));
        let mut src0 = Vec3::ZERO;
        let sigma_s = sigma_t * m.albedo;
        if sigma_s > 0.0 {
            let ms = &self.multiple;
            if let Some(s) = ray.sun {
                let tau = self.tau_sun_near(p, s.direction, ray.near);
                let mu = ray.d.dot(s.direction);
                let pw = powder(tau, self.settings.powder);
                // Every order, the first included, in the transport
                // medium: sunlight carried in by the peak counts. The
                // octaves' chord weight `1 − e^{−τ_c}` is 1 to within
                // 3.4·10⁻⁴ past τ = 8, and their lookup is skipped there.
                let chord = if ms.needs_chord(tau) {
                    self.sun_chord(p, s.direction)
                } else {
                    f32::INFINITY
                };
                src += s.irradiance
                    * (sigma_s * ms.sun(&m.phase, p, ray.eye.as_ref(), mu, tau, chord) * pw);
                // The sunlight scattered toward the eye at `p` by the
                // peak's core, with the core scatterings along the sun's
                // line before it and along the eye ray after it, in the
                // exact medium (optical depths scale with the extinction;
                // see `PeakOrders`).
                if let (Some(hg), Some(po)) = (self.peak, ray.orders) {
                    let tau0 = tau / self.ratio;
                    let lobe = po.eval(ray.peak_share * (tau0 + tau_eye0));
                    src0 = s.irradiance
                        * (sigma_t0 * m0.albedo * hg.weight * lobe * (-tau0).exp() * pw);
                }
            }
            src += self.ambient * (sigma_s * ms.ambient(self.tau_up(p)));
            if let Some(e) = &ray.local {
                src += sigma_s * ms.local(p, e);
            }
        }
        (src, src0)
    }

    /// The radiance behind the volume along the eye ray: the surface hit
    /// (lit through a direct shadow ray, seen through the air), or the
    /// environment.
    fn behind(&self, o: Vec3, d: Vec3, surface: Option<(f32, Surface)>) -> Vec3 {
        let sc = self.scene;
        let Some((t, kind)) = surface else {
            return sc.environment.radiance(d);
        };
        let p = o + d * t;
        let q = sc.lift(kind, p);
        // A surface inside the volume takes a direct shadow ray, exact at the
        // surface, where a table would interpolate across it; its steps are
        // the eye march's at the surface's distance (they grow with it as the
        // pixel's footprint does). A surface outside the volume (a plain below
        // a cloud layer) reads the table where its sunward ray enters the
        // volume: the table's nodes on that face hold exact rays, and the
        // lookup there is bilinear across the face, never across the surface.
        let ts = sc.sun_unit().map_or(1.0, |s| {
            if sc.blocked(q, s.direction) {
                return 0.0;
            }
            let tau = match (&self.sun_table, self.settings.shadows) {
                (Some(table), Shadows::Table(_)) if !sc.density.bounds().contains(q) => {
                    table.optical_depth(q)
                }
                (_, shadows) => {
                    let h = match shadows {
                        Shadows::Rays(h) => h,
                        Shadows::Table(_) => self.settings.step + self.settings.step_growth * t,
                    };
                    optical_depth_ray(sc.density, self.medium.extinction, q, s.direction, h)
                }
            };
            (-tau).exp()
        });
        sc.through_air(d, t, sc.surface_radiance(kind, p, ts))
    }

    /// Renders `camera`'s image.
    ///
    /// # Errors
    ///
    /// [`VolumeError::Core`] for a too-large image.
    pub fn render(&self, camera: &LookAtCamera) -> Result<Image> {
        self.render_with_progress(camera, &NoProgress)
    }

    /// [`FastRenderer::render`], reporting to `progress` as the stage
    /// `"render"` with one unit per finished image row (rows finish in any
    /// order when rendering in parallel; the image is the same).
    ///
    /// # Errors
    ///
    /// As [`FastRenderer::render`].
    pub fn render_with_progress(
        &self,
        camera: &LookAtCamera,
        progress: &dyn Progress,
    ) -> Result<Image> {
        super::render_image(camera, |o, d, _, _| self.radiance(o, d), "render", progress)
    }

    /// `camera`'s image from `s × s` rays a pixel on a regular grid,
    /// resolved by natura-core's camera pixel filter (a Gaussian of σ = ½
    /// pixel over each pixel's and its neighbours' rays, as a lens spreads
    /// light): the edges of solids and of thin wisps antialiased, where
    /// [`FastRenderer::render`] takes the one ray through each pixel's
    /// centre. Reports the stage `"render"` with one unit per row of rays.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] naming `supersample` unless `s` is
    /// in `1..=`[`MAX_SUPERSAMPLE`](super::MAX_SUPERSAMPLE);
    /// [`VolumeError::Core`] for a too-large image.
    pub fn render_supersampled(
        &self,
        camera: &LookAtCamera,
        s: usize,
        progress: &dyn Progress,
    ) -> Result<Image> {
        super::render_image_supersampled(
            camera,
            s,
            |o, d, _, _| self.radiance(o, d),
            "render",
            progress,
        )
    }

    /// The transmittance of the scene's medium (its phase function's peak
    /// included) the march finds along the ray from `o` in unit direction `d`
    /// over `[0, t_max]`: `exp(−σ·Σρ·Δt)` with midpoint samples.
    #[must_use]
    pub fn transmittance(&self, o: Vec3, d: Vec3, t_max: f32) -> f32 {
        let Some((t0, t1)) = ray_box(o, d.recip(), &self.bounds) else {
            return 1.0;
        };
        // The march's own steps over the whole box; each counts for its overlap
        // with [0, t_max], so the result never grows with t_max.
        let n = ((t1 - t0) / self.settings.step).ceil().max(1.0) as usize;
        let dt = (t1 - t0) / n as f32;
        let mut tau = 0.0;
        for i in 0..n {
            let a = t0 + i as f32 * dt;
            let len = (t_max.min(a + dt) - a).clamp(0.0, dt);
            if len <= 0.0 {
                break;
            }
            tau += self.scene.density.density(o + d * (a + 0.5 * dt)) * len;
        }
        (-tau * self.scene.medium.extinction).exp()
    }

    /// The sun table, when the settings use tables and the scene has a sun.
    #[must_use]
    pub fn sun_table(&self) -> Option<&ShadowTable> {
        self.sun_table.as_ref()
    }
}

/// Checks a positive number of samples is at most `max`.
pub(crate) fn check_count(name: &'static str, n: u32, max: u32) -> Result<()> {
    positive(name, n as f32)?;
    if n > max {
        return Err(VolumeError::InvalidParameter {
            name,
            value: n.to_string(),
            expected: "absurdly large",
        });
    }
    Ok(())
}
