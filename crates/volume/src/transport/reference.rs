//! The unbiased reference: a null-scattering path tracer with multiple
//! scattering (Pharr et al. 2023, §14.1, the null-scattering equation of
//! transfer and the sampling of the majorant transmittance, and §14.2.1, the
//! simple volumetric integrator). Free flights are sampled by delta tracking
//! against a constant majorant `σ̄ = σ·max ρ` (a real collision with
//! probability `σ_t/σ̄`, otherwise a null collision that changes nothing);
//! the sun is sampled at every real collision with its transmittance
//! estimated by ratio tracking (`T = Π(1 − σ_t/σ̄)` over the majorant's
//! events; Novák et al. 2014); the environment is reached by phase-sampled
//! paths that leave the volume; absorption weights the path by the albedo;
//! Russian roulette ends long paths without bias. GroundPlane and solids are lit
//! surfaces that end a path (they do not reflect light back into the volume),
//! exactly as in the fast renderer.
//!
//! A cloud's phase function sends about half its scattering into a
//! diffraction peak a fraction of a degree wide. Evaluated toward a
//! directional sun at every collision, that peak turns paths whose direction
//! happens to lie within it into rare, very bright samples, and they dominate
//! the noise toward a low sun. So at the first few collisions of a path
//! (up to [`SUN_PEAK_DEPTH`]) the new direction is drawn from a mixture: with
//! probability [`SUN_PEAK_SHARE`] from the peak's lobe centred on the sun,
//! otherwise from the phase function, and the path is weighted by the phase
//! function over the mixture's density (the one-sample model of multiple
//! importance sampling with the balance heuristic, Veach 1997, §9.2.4; a
//! defensive mixture, Hesterberg 1995). The estimate stays unbiased because
//! the mixture's density is positive wherever the phase function is; paths
//! now reach the sun's peak often and with small weights instead of rarely
//! with large ones. Deeper collisions sample the phase function alone, since
//! a product of many mixture weights, each of mean 1 but spread, would
//! itself grow noisy; and Russian roulette judges a path by its weight
//! without the mixture's share, so the small-weight paths sent toward the
//! sun are not ended before they count.
//!
//! It is kept short and plainly correct, like pbrt-v4's simple integrator
//! beside its fast one: its job is to be the truth the fast modes are
//! measured against.

use glam::Vec3;
use natura_core::{Image, NoProgress, Progress, Seed};
use rand_core::Rng;

use super::model::emitted;
use super::{LookAtCamera, Scene};
use crate::animate::unit;
use crate::density::ray_box;
use crate::error::{Result, VolumeError};
use crate::phase::{henyey_greenstein, sample_hg};

/// The share of directions drawn from the forward peak's lobe about the sun
/// at the first collisions of a path (see the module docs).
pub const SUN_PEAK_SHARE: f32 = 0.2;

/// The collisions, counted from the eye, at which a path draws some
/// directions toward the sun's peak.
pub const SUN_PEAK_DEPTH: u32 = 2;

/// Settings of the reference renderer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct ReferenceSettings {
    /// Paths per pixel (1 to 10⁶).
    pub samples_per_pixel: u32,
    /// Longest path in scattering events (1 to 10⁵); Russian roulette ends most paths long before.
    pub max_depth: u32,
    /// Random seed.
    pub seed: u64,
    /// At the first collisions, draw some directions from the phase
    /// function's forward peak about the sun (see the module docs); `false`
    /// samples the phase function alone: the same mean, far noisier toward a
    /// low sun.
    pub sun_peak_sampling: bool,
}

impl Default for ReferenceSettings {
    /// 256 paths per pixel, up to 1000 bounces, the sun's peak sampled by two strategies.
    fn default() -> Self {
        Self {
            samples_per_pixel: 256,
            max_depth: 1000,
            seed: 1,
            sun_peak_sampling: true,
        }
    }
}

/// The reference path tracer for one scene.
#[derive(Clone, Debug)]
pub struct ReferenceRenderer<'s> {
    scene: &'s Scene<'s>,
    settings: ReferenceSettings,
    majorant: f32,
}

impl<'s> ReferenceRenderer<'s> {
    /// Prepares `scene`.
    ///
    /// # Errors
    ///
    /// As [`Scene::validate`] and [`Scene::majorant`];
    /// [`VolumeError::InvalidParameter`] for a sample count or depth of 0
    /// or absurdly large, and naming `extinction` if the expected
    /// collisions with the majorant along the density box's diagonal
    /// exceed [`MAX_COLLISIONS_PER_RAY`] (a medium too thick for delta
    /// tracking to cross).
    pub fn new(scene: &'s Scene<'s>, settings: ReferenceSettings) -> Result<Self> {
        scene.validate()?;
        super::march::check_count("samples_per_pixel", settings.samples_per_pixel, 1_000_000)?;
        super::march::check_count("max_depth", settings.max_depth, 100_000)?;
        let majorant = scene.majorant()?;
        let b = scene.density.bounds();
        check_collisions(
            scene,
            majorant,
            (b.max - b.min).length(),
            "the box's diagonal",
        )?;
        Ok(Self {
            scene,
            settings,
            majorant,
        })
    }

    /// Ratio-tracking transmittance from `p` along unit `l` out of the volume.
    fn transmittance(&self, p: Vec3, l: Vec3, rng: &mut impl Rng) -> f32 {
        let sc = self.scene;
        let Some((t0, t1)) = ray_box(p, l.recip(), &sc.density.bounds()) else {
            return 1.0;
        };
        if self.majorant <= 0.0 {
            return 1.0;
        }
        // Tracked from the box's entry point, so that the free-flight steps
        // (about 1/majorant) still move the distance in f32 when the ray
        // starts far from the box (a ground point under a low sun).
        let entry = p + l * t0;
        let length = t1 - t0;
        let mut t = 0.0f32;
        let mut tr = 1.0f32;
        loop {
            t -= (1.0 - unit(rng)).ln() / self.majorant;
            if t >= length {
                return tr;
            }
            let sigma_t = sc.medium.extinction * sc.density.density(entry + l * t);
            tr *= 1.0 - (sigma_t / self.majorant).min(1.0);
            if tr <= 0.0 {
                return 0.0;
            }
        }
    }

    /// Delta tracking from `o` along unit `d` to the next real collision
    /// before `t_max`: its distance and point.
    fn collide(&self, o: Vec3, d: Vec3, t_max: f32, rng: &mut impl Rng) -> Option<(f32, Vec3)> {
        let sc = self.scene;
        let (t0, t1) = ray_box(o, d.recip(), &sc.density.bounds())?;
        if self.majorant <= 0.0 {
            return None;
        }
        // Tracked from the box's entry point (see `transmittance`).
        let entry = o + d * t0;
        let length = t1.min(t_max) - t0;
        let mut t = 0.0f32;
        loop {
            t -= (1.0 - unit(rng)).ln() / self.majorant;
            if t >= length {
                return None;
            }
            let p = entry + d * t;
            let sigma_t = sc.medium.extinction * sc.density.density(p);
            if unit(rng) * self.majorant < sigma_t {
                return Some((t0 + t, p));
            }
        }
    }

    /// The sun's transmittance to `p` (0 behind a solid).
    fn sun_transmittance(&self, p: Vec3, l: Vec3, rng: &mut impl Rng) -> f32 {
        if self.scene.blocked(p, l) {
            0.0
        } else {
            self.transmittance(p, l, rng)
        }
    }

    /// One path's estimate of the radiance arriving at `o` along `-d`.
    pub fn radiance(&self, o: Vec3, d: Vec3, rng: &mut impl Rng) -> Vec3 {
        let sc = self.scene;
        let m = &sc.medium;
        let sun = sc.sun_unit();
        // The forward peak's asymmetry, when directions are drawn toward the sun's peak.
        let peak = if self.settings.sun_peak_sampling {
            m.phase.peak_lobe().map(|(_, g)| g)
        } else {
            None
        };
        let (mut o, mut d) = (o, d);
        let d_eye = d;
        let mut beta = Vec3::ONE;
        let mut l = Vec3::ZERO;
        let mut first_depth = f32::INFINITY;
        let mut depth = 0u32;
        // The product of the sun-peak mixture's weights over the phase
        // function's own: Russian roulette judges the path by `beta / guide`,
        // so that the small weights of directions sent toward the sun do not
        // end those paths early.
        let mut guide = 1.0f32;
        loop {
            let surface = sc.surface_hit(o, d);
            let t_ground = surface.map_or(f32::INFINITY, |(t, _)| t);
            let Some((t, p)) = self.collide(o, d, t_ground, rng) else {
                // Left the volume: the ground or the environment.
                if depth == 0 {
                    first_depth = t_ground;
                }
                let back = if let Some((t, kind)) = surface {
                    let g = o + d * t;
                    let q = sc.lift(kind, g);
                    let ts = sun.map_or(1.0, |s| self.sun_transmittance(q, s.direction, rng));
                    sc.surface_radiance(kind, g, ts)
                } else {
                    sc.environment.radiance(d)
                };
                l += beta * back;
                break;
            };
            if depth == 0 {
                first_depth = t;
            }
            if let Some(e) = sc.emission {
                l += beta * emitted(e.colour, e.field.density(p), e.offset) * (1.0 - m.albedo);
            }
            beta *= m.albedo;
            if let Some(s) = sun {
                let mu = d.dot(s.direction);
                let f = m.phase.eval(mu);
                if f > 0.0 {
                    l += beta * s.irradiance * (f * self.sun_transmittance(p, s.direction, rng));
                }
            }
            depth += 1;
            if depth >= self.settings.max_depth {
                break;
            }
            if depth >= 8 {
                let q = (beta.max_element() / guide).min(0.95);
                if unit(rng) >= q {
                    break;
                }
                beta /= q;
            }
            let (nd, w) = match (peak, sun) {
                (Some(g), Some(s)) if depth <= SUN_PEAK_DEPTH => {
                    let c = SUN_PEAK_SHARE;
                    let nd = if unit(rng) < c {
                        sample_hg(g, s.direction, [unit(rng), unit(rng)])
                    } else {
                        m.phase.sample(d, [unit(rng), unit(rng), unit(rng)]).0
                    };
                    let mu = d.dot(nd);
                    let pdf = m.phase.sample_pdf(mu);
                    let q = (1.0 - c) * pdf + c * henyey_greenstein(g, nd.dot(s.direction));
                    if !(q > 0.0 && pdf > 0.0) {
                        break;
                    }
                    guide *= pdf / q;
                    (nd, m.phase.eval(mu) / q)
                }
                _ => m.phase.sample(d, [unit(rng), unit(rng), unit(rng)]),
            };
            beta *= w;
            o = p;
            d = nd;
        }
        sc.through_air(d_eye, first_depth, l)
    }

    /// The mean of `samples_per_pixel` paths for the ray from `o` along unit `d`,
    /// with the random stream of pixel `(x, y)`.
    #[must_use]
    pub fn pixel(&self, o: Vec3, d: Vec3, x: usize, y: usize) -> Vec3 {
        let mut rng = Seed(self.settings.seed)
            .derive_index(Seed(0).hash2(x as i64, y as i64))
            .rng();
        let n = self.settings.samples_per_pixel;
        let mut s = Vec3::ZERO;
        for _ in 0..n {
            s += self.radiance(o, d, &mut rng);
        }
        s / n as f32
    }

    /// Renders `camera`'s image (bit-identical on any number of threads: each
    /// pixel has its own random stream).
    ///
    /// # Errors
    ///
    /// [`VolumeError::Core`] for a too-large image;
    /// [`VolumeError::InvalidParameter`] naming `extinction` if the
    /// majorant times the distance from the camera to the density box's
    /// farthest corner exceeds [`MAX_COLLISIONS_PER_RAY`]: the distances an
    /// eye ray tracks are then too long for `f32` to resolve the mean free
    /// path, and its free flights would stall.
    pub fn render(&self, camera: &LookAtCamera) -> Result<Image> {
        self.render_with_progress(camera, &NoProgress)
    }

    /// [`ReferenceRenderer::render`], reporting to `progress` as the stage
    /// `"reference"` with one unit per finished image row (rows finish in
    /// any order when rendering in parallel; the image is the same).
    ///
    /// # Errors
    ///
    /// As [`ReferenceRenderer::render`]; nothing is reported when the
    /// scene is refused.
    pub fn render_with_progress(
        &self,
        camera: &LookAtCamera,
        progress: &dyn Progress,
    ) -> Result<Image> {
        let b = self.scene.density.bounds();
        let eye = camera.eye();
        let far = (b.min - eye).abs().max((b.max - eye).abs()).length();
        check_collisions(
            self.scene,
            self.majorant,
            far,
            "the distance from the camera to the box's farthest corner",
        )?;
        super::render_image(
            camera,
            |o, d, x, y| self.pixel(o, d, x, y),
            "reference",
            progress,
        )
    }
}

/// Most expected collisions with the majorant along one tracked distance
/// (2¹⁷): the bound on the reference's work per free flight, and, since a
/// mean free path of the distance over 2¹⁷ is still 64 `f32` steps of it,
/// what keeps each flight's distance resolvable.
pub const MAX_COLLISIONS_PER_RAY: f32 = 131_072.0;

/// Refuses a majorant whose expected collisions over `length` metres
/// (`what`) exceed [`MAX_COLLISIONS_PER_RAY`].
fn check_collisions(scene: &Scene<'_>, majorant: f32, length: f32, what: &str) -> Result<()> {
    let n = majorant * length;
    if n.is_finite() && n <= MAX_COLLISIONS_PER_RAY {
        return Ok(());
    }
    Err(VolumeError::InvalidParameter {
        name: "extinction",
        value: format!(
            "{} (majorant {majorant} 1/m over {what}, {length} m: {n:e} expected collisions)",
            scene.medium.extinction
        ),
        expected: "extinction × maximum density × the longest distance a ray tracks \
                   must be at most 131072 expected collisions",
    })
}
