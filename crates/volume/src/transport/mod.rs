//! Light transport through a volume (volume rendering): a camera, the
//! medium's optical properties, sun and sky light (from `natura-atmos` or
//! constant), an optional lit ground, and three
//! ways to render: Ebert's low-albedo ray march with 3-D shadow tables
//! ([`march`]), the same march with the octave multiple-scattering
//! approximation, and the unbiased reference ([`reference`](mod@reference)), a
//! null-scattering (delta and ratio tracking) path tracer with multiple
//! scattering after Pharr et al. 2023, §14.2 ("Volume scattering
//! integrators"), from which the fast modes' error is measured.
//!
//! Both renderers take the same [`Scene`] and call the same equations
//! ([`model`]); they differ only in how they estimate the transport.
//! Radiance is linear RGB; the sun is a directional light given by its
//! irradiance normal to the beam.

pub mod cache;
mod cells;
pub mod harmonics;
pub mod local;
pub mod march;
pub mod model;
pub mod multiple;
pub mod reference;
mod settings;
pub mod shadow;
mod solid;

use std::sync::Arc;

use glam::Vec3;
use natura_atmos::sky::{ApSample, SkyView};
use natura_core::camera::PinholeCamera;
use natura_core::{Grid2, Image, Progress};

use crate::density::Density;
use crate::error::{Result, VolumeError, finite3, in_range, non_negative, positive};
use crate::phase::CloudPhase;
pub use cache::{CacheParams, ScatterCache};
pub use march::{FastRenderer, FastSettings, MAX_SUBSTEPS, NearSunRays, Seen, Shadows};
pub use model::{MediumOctaves, ScatterOctaves};
pub use multiple::Scattering;
pub use reference::{ReferenceRenderer, ReferenceSettings};
pub use shadow::ShadowTable;
pub use solid::{Solid, SolidShape};

/// The camera the renderers take: natura-core's [`PinholeCamera`], set up
/// with [`PinholeCamera::look_at`] (radians, `u32` pixels, z up as the up
/// hint for a level horizon). Each pixel's ray goes through its centre.
pub type LookAtCamera = PinholeCamera;

/// The majorant (extinction × maximum density, 1/m) both renderers stay
/// below: [`Scene::majorant`].
pub const MAX_MAJORANT: f32 = 1e9;

/// The medium's optical properties: density `ρ` becomes extinction
/// `σ_t = extinction·ρ` (1/m), of which the fraction `albedo` scatters.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct MediumParams {
    /// Extinction per unit density (1/m).
    pub extinction: f32,
    /// Single-scattering albedo in `[0, 1]` (clouds: ≈ 1).
    pub albedo: f32,
    /// The phase function.
    pub phase: CloudPhase,
}

impl Default for MediumParams {
    /// A cloud: 1/m extinction at density 1, albedo 0.99, the cloud phase function.
    fn default() -> Self {
        Self {
            extinction: 1.0,
            albedo: 0.99,
            phase: CloudPhase::default(),
        }
    }
}

impl MediumParams {
    /// The same medium with the core of the phase function's forward
    /// diffraction peak treated as unscattered light (the δ-M similarity
    /// relations of [`model::delta_scaled`] with the core of
    /// [`CloudPhase::peak_core`] within [`PEAK_CORE_DEG`](crate::phase::PEAK_CORE_DEG)):
    /// lower extinction, lower albedo, the phase function without the
    /// core. Unchanged for phase functions without a peak.
    #[must_use]
    pub fn without_forward_peak(&self) -> Self {
        let Some(core) = self.phase.peak_core(crate::phase::PEAK_CORE_DEG) else {
            return *self;
        };
        let (extinction, albedo) = model::delta_scaled(self.extinction, self.albedo, core.weight);
        Self {
            extinction,
            albedo,
            phase: core.rest,
        }
    }

    /// Checks the fields.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] naming the bad field.
    pub fn validate(&self) -> Result<()> {
        non_negative("extinction", self.extinction)?;
        in_range(
            "extinction",
            self.extinction,
            0.0,
            1e9,
            "must be below 1e9 1/m",
        )?;
        in_range("albedo", self.albedo, 0.0, 1.0, "must lie in [0, 1]")?;
        self.phase.validate()
    }
}

/// The light arriving from far away in every direction (the sun excluded).
#[derive(Clone, Debug)]
pub enum SkyRadiance {
    /// The same radiance from every direction.
    Uniform(Vec3),
    /// The sky of `natura-atmos` (its sky-view table, without the sun disc).
    Sky(Arc<SkyView>),
}

impl SkyRadiance {
    /// Radiance arriving along `-d` (seen looking along the unit direction `d`).
    #[inline]
    #[must_use]
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        match self {
            SkyRadiance::Uniform(c) => *c,
            SkyRadiance::Sky(s) => s.radiance_f32(d),
        }
    }
}

/// A directional sun.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun {
    /// Unit direction toward the sun.
    pub direction: Vec3,
    /// Irradiance normal to the beam (linear RGB).
    pub irradiance: Vec3,
}

impl Sun {
    /// The sun of a `natura-atmos` sky view: its direction and its irradiance after the air.
    #[must_use]
    pub fn from_sky(sky: &SkyView) -> Self {
        Self {
            direction: sky.sun().as_vec3(),
            irradiance: sky.sun_irradiance(),
        }
    }
}

/// A flat Lambertian ground at height `height`, lit by the sun through the
/// volume and by the sky; it does not reflect light back into the volume
/// (in either renderer).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundPlane {
    /// Height of the plane (m).
    pub height: f32,
    /// Albedo (linear RGB, each in `[0, 1]`).
    pub albedo: Vec3,
    /// Sky irradiance on the horizontal (linear RGB).
    pub sky_irradiance: Vec3,
}

/// Optical depth standing for "blocked by a solid" (transmittance `e^{−30}`).
pub const BLOCKED_DEPTH: f32 = 30.0;

/// What a ray hits beyond the volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Surface {
    GroundPlane,
    Solid(usize),
}

/// Emission from a second field (for smoke: temperature), radiance
/// `colour·max(value − offset, 0)` per unit absorption.
#[derive(Clone, Copy)]
pub struct Emission<'a> {
    /// The field (for smoke: temperature, K).
    pub field: &'a dyn Density,
    /// Subtracted from the field (for smoke: ambient temperature).
    pub offset: f32,
    /// Radiance per unit of `value − offset`.
    pub colour: Vec3,
}

impl std::fmt::Debug for Emission<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Emission")
            .field("offset", &self.offset)
            .field("colour", &self.colour)
            .finish_non_exhaustive()
    }
}

/// Everything a renderer needs: the density, its optical properties and the lights.
#[derive(Clone)]
pub struct Scene<'a> {
    /// The density field.
    pub density: &'a dyn Density,
    /// Its optical properties.
    pub medium: MediumParams,
    /// The sun, if any.
    pub sun: Option<Sun>,
    /// Light from every direction.
    pub environment: SkyRadiance,
    /// A lit ground plane, if any.
    pub ground: Option<GroundPlane>,
    /// Emission, if any.
    pub emission: Option<Emission<'a>>,
    /// Aerial perspective between the eye and what it sees, if any.
    pub aerial: Option<Arc<SkyView>>,
    /// Opaque solids (spheres and upright cylinders).
    pub solids: Vec<Solid>,
}

impl std::fmt::Debug for Scene<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scene")
            .field("medium", &self.medium)
            .field("sun", &self.sun)
            .field("ground", &self.ground)
            .field("emission", &self.emission)
            .finish_non_exhaustive()
    }
}

impl<'a> Scene<'a> {
    /// A scene of `density` with `medium`, lit only by a uniform `environment` radiance.
    #[must_use]
    pub fn new(density: &'a dyn Density, medium: MediumParams, environment: Vec3) -> Self {
        Self {
            density,
            medium,
            sun: None,
            environment: SkyRadiance::Uniform(environment),
            ground: None,
            emission: None,
            aerial: None,
            solids: Vec::new(),
        }
    }

    /// Checks the medium, lights, ground and the density (probed with
    /// [`probe_density`](crate::density::probe_density)).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] naming the bad field (`density`
    /// for a NaN or negative density, `max_density` for a density above
    /// its bound); [`VolumeError::InvalidBounds`] for bad density bounds.
    pub fn validate(&self) -> Result<()> {
        self.medium.validate()?;
        crate::density::check_bounds("density bounds", &self.density.bounds())?;
        let m = self.density.max_density();
        if !(m.is_finite() && m >= 0.0) {
            return Err(VolumeError::InvalidParameter {
                name: "max_density",
                value: m.to_string(),
                expected: "a finite bound ≥ 0",
            });
        }
        crate::density::probe_density(self.density)?;
        if let Some(s) = self.sun {
            shadow::unit("sun.direction", s.direction)?;
            rgb("sun.irradiance", s.irradiance)?;
        }
        if let SkyRadiance::Uniform(c) = self.environment {
            rgb("environment", c)?;
        }
        if let Some(g) = self.ground {
            finite3("ground.height", Vec3::splat(g.height))?;
            rgb("ground.sky_irradiance", g.sky_irradiance)?;
            for c in g.albedo.to_array() {
                in_range(
                    "ground.albedo",
                    c,
                    0.0,
                    1.0,
                    "each channel must lie in [0, 1]",
                )?;
            }
        }
        if self.solids.len() > 10_000 {
            return Err(VolumeError::InvalidParameter {
                name: "solids",
                value: self.solids.len().to_string(),
                expected: "at most 10 000 solids",
            });
        }
        for s in &self.solids {
            finite3("solid.centre", s.centre)?;
            positive("solid.radius", s.radius)?;
            if let SolidShape::Cylinder { half_height } = s.shape {
                positive("solid.shape.half_height", half_height)?;
            }
            rgb("solid.sky_irradiance", s.sky_irradiance)?;
            for c in s.albedo.to_array() {
                in_range(
                    "solid.albedo",
                    c,
                    0.0,
                    1.0,
                    "each channel must lie in [0, 1]",
                )?;
            }
        }
        if let Some(e) = self.emission {
            finite3("emission.offset", Vec3::splat(e.offset))?;
            rgb("emission.colour", e.colour)?;
        }
        Ok(())
    }

    /// The majorant `σ̄ = extinction × the density's bound over its box`,
    /// 1/m: the rule both renderers keep, so a grid or medium one refuses
    /// the other refuses too.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] naming `majorant` (with the
    /// extinction and the density's bound) if it exceeds
    /// [`MAX_MAJORANT`] (an overflowing product included).
    pub fn majorant(&self) -> Result<f32> {
        let bound = self.density.bound_in(&self.density.bounds());
        let majorant = self.medium.extinction * bound;
        if !(majorant.is_finite() && (0.0..=MAX_MAJORANT).contains(&majorant)) {
            return Err(VolumeError::InvalidParameter {
                name: "majorant",
                value: format!(
                    "{majorant:e} (extinction {} × maximum density {bound:e})",
                    self.medium.extinction
                ),
                expected: "extinction × maximum density must be below 1e9 1/m",
            });
        }
        Ok(majorant)
    }

    /// The sun, normalised.
    pub(crate) fn sun_unit(&self) -> Option<Sun> {
        self.sun.map(|s| Sun {
            direction: s.direction.normalize(),
            irradiance: s.irradiance,
        })
    }

    /// Distance along `d` from `o` to the ground, if the ray hits it.
    #[inline]
    pub(crate) fn ground_hit(&self, o: Vec3, d: Vec3) -> Option<f32> {
        let g = self.ground?;
        if d.z >= 0.0 || o.z < g.height {
            return None;
        }
        Some((g.height - o.z) / d.z)
    }

    /// The nearest surface (ground or solid) along unit `d` from `o`.
    #[inline]
    pub(crate) fn surface_hit(&self, o: Vec3, d: Vec3) -> Option<(f32, Surface)> {
        let mut best = self.ground_hit(o, d).map(|t| (t, Surface::GroundPlane));
        for (i, s) in self.solids.iter().enumerate() {
            if let Some(t) = s.hit(o, d)
                && best.is_none_or(|(b, _)| t < b)
            {
                best = Some((t, Surface::Solid(i)));
            }
        }
        best
    }

    /// Whether a solid lies between `p` and the light along unit `l`.
    #[inline]
    pub(crate) fn blocked(&self, p: Vec3, l: Vec3) -> bool {
        self.solids.iter().any(|s| s.hit(p, l).is_some())
    }

    /// A point just off surface `s` at `p` (outside a solid), where the sun's
    /// transmittance is looked up.
    #[inline]
    pub(crate) fn lift(&self, s: Surface, p: Vec3) -> Vec3 {
        match s {
            Surface::GroundPlane => p + Vec3::Z * 1e-3,
            Surface::Solid(i) => self.solids[i].lift(p),
        }
    }

    /// Radiance of surface `s` at `p` given the sun's transmittance through the volume there.
    #[inline]
    pub(crate) fn surface_radiance(&self, s: Surface, p: Vec3, t_sun: f32) -> Vec3 {
        match s {
            Surface::GroundPlane => self.ground_radiance(t_sun),
            Surface::Solid(i) => {
                let c = &self.solids[i];
                let n = c.normal(p);
                match self.sun_unit() {
                    Some(sun) => model::lit_ground(
                        c.albedo,
                        sun.irradiance,
                        n.dot(sun.direction),
                        t_sun,
                        c.sky_irradiance,
                    ),
                    None => model::lit_ground(c.albedo, Vec3::ZERO, 0.0, 1.0, c.sky_irradiance),
                }
            }
        }
    }

    /// Radiance of the ground at `p` given the sun's transmittance there.
    #[inline]
    pub(crate) fn ground_radiance(&self, t_sun: f32) -> Vec3 {
        let Some(g) = self.ground else {
            return Vec3::ZERO;
        };
        match self.sun_unit() {
            Some(s) => model::lit_ground(
                g.albedo,
                s.irradiance,
                s.direction.z,
                t_sun,
                g.sky_irradiance,
            ),
            None => model::lit_ground(g.albedo, Vec3::ZERO, 0.0, 1.0, g.sky_irradiance),
        }
    }

    /// The eye's view of what lies at distance `depth` with radiance `l`
    /// (aerial perspective when the scene has one).
    #[inline]
    pub(crate) fn through_air(&self, d: Vec3, depth: f32, l: Vec3) -> Vec3 {
        self.air(d, depth).apply(l)
    }

    /// The air's transmittance and in-scatter over `depth` along `d` (none
    /// without aerial perspective or at infinite depth).
    #[inline]
    pub(crate) fn air(&self, d: Vec3, depth: f32) -> ApSample {
        match &self.aerial {
            Some(s) if depth.is_finite() => s.aerial_perspective_f32(d, depth),
            _ => ApSample::NONE,
        }
    }
}

fn rgb(name: &'static str, c: Vec3) -> Result<()> {
    finite3(name, c)?;
    for v in c.to_array() {
        non_negative(name, v)?;
    }
    Ok(())
}

/// Renders `camera`'s image with `radiance(origin, direction, x, y)` per
/// pixel, rows in parallel (bit-identical on any thread count), reporting
/// the stage `stage` to `progress` with one unit per finished row.
pub(crate) fn render_image(
    camera: &PinholeCamera,
    radiance: impl Fn(Vec3, Vec3, usize, usize) -> Vec3 + Sync + Send,
    stage: &str,
    progress: &dyn Progress,
) -> Result<Image> {
    Ok(Image::from_grid(trace_frame(
        camera, 1, radiance, stage, progress,
    )?))
}

/// `radiance` along `s × s` rays a pixel on a regular grid (ray `(i, j)` of
/// pixel `(x, y)` through `(x + (i + ½)/s, y + (j + ½)/s)`, stored at
/// `(x·s + i, y·s + j)`; `radiance` told the pixel), rows in parallel
/// (bit-identical on any thread count), one unit of `stage` a row of rays.
fn trace_frame(
    camera: &PinholeCamera,
    s: usize,
    radiance: impl Fn(Vec3, Vec3, usize, usize) -> Vec3 + Sync + Send,
    stage: &str,
    progress: &dyn Progress,
) -> Result<Grid2<Vec3>> {
    let eye = camera.eye();
    let res = camera.resolution();
    let (w, h) = (res.x as usize, res.y as usize);
    let mut frame = Grid2::new(w * s, h * s, Vec3::ZERO)?;
    let inv = 1.0 / s as f32;
    let row = |y: usize, row: &mut [Vec3]| {
        let py = (y as f32 + 0.5) * inv;
        for (x, v) in row.iter_mut().enumerate() {
            let d = camera.ray_at((x as f32 + 0.5) * inv, py).dir;
            *v = radiance(eye, d, x / s, y / s);
        }
        progress.advance(1);
    };
    progress.start(stage, (h * s) as u64);
    #[cfg(feature = "parallel")]
    frame.par_rows_mut(row);
    #[cfg(not(feature = "parallel"))]
    for (y, r) in frame.rows_mut().enumerate() {
        row(y, r);
    }
    progress.finish();
    Ok(frame)
}

/// The most rays per pixel side of [`FastRenderer::render_supersampled`].
pub const MAX_SUPERSAMPLE: usize = 8;

/// Renders `camera`'s image from `s × s` rays a pixel ([`trace_frame`]),
/// resolved by natura-core's camera pixel filter (`PixelFilter::camera`).
pub(crate) fn render_image_supersampled(
    camera: &PinholeCamera,
    s: usize,
    radiance: impl Fn(Vec3, Vec3, usize, usize) -> Vec3 + Sync + Send,
    stage: &str,
    progress: &dyn Progress,
) -> Result<Image> {
    if !(1..=MAX_SUPERSAMPLE).contains(&s) {
        return Err(VolumeError::InvalidParameter {
            name: "supersample",
            value: s.to_string(),
            expected: "rays per pixel side, in 1..=8",
        });
    }
    let frame = trace_frame(camera, s, radiance, stage, progress)?;
    Ok(natura_core::filter::PixelFilter::camera().resolve(&frame, s)?)
}

/// Checks a step length in metres: finite, `> 0`, and no more than `max_steps` across `extent`.
pub(crate) fn check_step(name: &'static str, step: f32, extent: f32, max_steps: f32) -> Result<()> {
    positive(name, step)?;
    if extent / step > max_steps {
        return Err(VolumeError::InvalidParameter {
            name,
            value: step.to_string(),
            expected: "too small: more than 10^7 steps across the volume",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use natura_core::CountingProgress;

    use super::*;
    use crate::density::Ball;

    fn ball_scene(ball: &Ball) -> Scene<'_> {
        Scene {
            sun: Some(Sun {
                direction: Vec3::new(0.3, -0.4, 0.8).normalize(),
                irradiance: Vec3::ONE,
            }),
            ..Scene::new(ball, MediumParams::default(), Vec3::splat(0.2))
        }
    }

    fn camera() -> LookAtCamera {
        LookAtCamera::look_at(
            Vec3::new(0.0, -4.0, 0.0),
            Vec3::ZERO,
            Vec3::Z,
            40f32.to_radians(),
            12,
            9,
        )
        .unwrap()
    }

    #[test]
    fn the_fast_renderer_reports_its_tables_and_rows_and_renders_the_same() {
        let ball = Ball::new(Vec3::ZERO, 1.0, 1.0).unwrap();
        let scene = ball_scene(&ball);
        let settings = FastSettings {
            shadows: Shadows::Table(8),
            ..FastSettings::default()
        };
        let progress = CountingProgress::new();
        let fast = FastRenderer::new_with_progress(&scene, settings, &progress).unwrap();
        let img = fast.render_with_progress(&camera(), &progress).unwrap();
        let dims = shadow::table_dims(&ball.bounds(), 8);
        let rows = (dims[1] * dims[2]) as u64;
        assert_eq!(
            progress.stages(),
            vec![
                ("shadow tables".to_owned(), 2 * rows),
                ("render".to_owned(), 9),
            ]
        );
        assert_eq!(progress.advanced(), 2 * rows + 9);
        assert_eq!(progress.finished(), 2);
        let plain = FastRenderer::new(&scene, settings).unwrap();
        assert_eq!(img, plain.render(&camera()).unwrap());
    }

    #[test]
    fn the_reference_reports_its_rows_and_renders_the_same() {
        let ball = Ball::new(Vec3::ZERO, 1.0, 1.0).unwrap();
        let scene = ball_scene(&ball);
        let settings = ReferenceSettings {
            samples_per_pixel: 1,
            ..ReferenceSettings::default()
        };
        let r = ReferenceRenderer::new(&scene, settings).unwrap();
        let progress = CountingProgress::new();
        let img = r.render_with_progress(&camera(), &progress).unwrap();
        assert_eq!(progress.stages(), vec![("reference".to_owned(), 9)]);
        assert_eq!(progress.advanced(), 9);
        assert_eq!(progress.finished(), 1);
        assert_eq!(img, r.render(&camera()).unwrap());
        // A zero-sized camera cannot be built, so no render can start with one.
        assert!(
            LookAtCamera::look_at(Vec3::new(0.0, -4.0, 0.0), Vec3::ZERO, Vec3::Z, 0.7, 0, 9)
                .is_err()
        );
    }
}
