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
//! Russian roulette ends long paths without bias (see below). GroundPlane and solids are lit
//! surfaces that end a path (they do not reflect light back into the volume),
//! exactly as in the fast renderer.
//!
//! A cloud's phase function sends about half its scattering into a
//! diffraction peak a fraction of a degree wide. Evaluated toward a
//! directional sun at a collision, that peak turns the paths whose
//! direction happens to lie within it into rare, very bright samples: at
//! 20 µm the peak is a Henyey–Greenstein lobe of `g ≈ 0.995`, worth about
//! 6000/sr toward its axis. Those samples make the estimate heavy-tailed:
//! a few hundred thousand paths then usually miss them and come out low
//! (by 15–40 % on a slab of cloud seen from above), and now and then meet
//! one and come out high. So the sun's light through the peak at each
//! collision after the first is estimated by two strategies, combined by
//! multiple importance sampling with the balance heuristic (Veach 1997,
//! §9.2): the path's own direction, drawn from the phase function (exactly) at the
//! collision before (density `p_A`), and an extra direction drawn there from
//! the peak's lobe about the sun (density `p_B`), followed to its own
//! collision and lit by its own shadow ray. Each counts the peak's light
//! with weight `p_A/(p_A + p_B)` or `p_B/(p_A + p_B)`; the rest of the phase
//! function is lit as before. Neither estimate can be large: where the
//! peak is large the second strategy's density is too. The path itself
//! samples the phase function alone, so its weight stays the phase's own.
//! The first collision's direction is the eye's, not sampled, and is lit
//! through the whole phase function.
//!
//! **Russian roulette** starts after eight collisions and only once the
//! path's weight `β` (the albedo's product so far) has fallen below 1: the
//! path goes on with probability `max β` and its weight is divided by it,
//! so a surviving path's weight is at most 1 (Pharr et al. 2023, §2.2.4).
//! In a thick, nearly conservative medium that lets a path live as long as
//! its light does. An earlier rule, survival with probability
//! `min(max β, 0.95)`, is as unbiased in expectation, but in such a medium
//! (albedo 0.99 and over) it kills 5 % of the paths at each collision and
//! multiplies the survivors' weights by 1/0.95, so the light of paths of a
//! few hundred scatterings rests on samples of weight `10⁶` and more, which
//! no affordable run draws: a ball of optical diameter 50 and albedo 0.999
//! read some 4 % too dark at 96 paths a pixel, consistently.
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

/// Settings of the reference renderer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct ReferenceSettings {
    /// Paths per pixel (1 to 10⁶).
    pub samples_per_pixel: u32,
    /// Longest path in scattering events (1 to 10⁵). Most paths leave the
    /// medium or end by Russian roulette long before; in a ball of optical
    /// diameter 50 and albedo 0.999, raising it from 1000 to 10⁵ moved the
    /// image's total by 0.1 %.
    pub max_depth: u32,
    /// Random seed.
    pub seed: u64,
    /// Light the phase function's forward peak toward the sun by two
    /// strategies (see the module docs); `false` evaluates it along the
    /// path's direction alone: the same mean, heavy-tailed and far noisier.
    pub sun_peak_sampling: bool,
}

impl Default for ReferenceSettings {
    /// 256 paths per pixel, up to 1000 bounces, the sun's peak lit by two strategies.
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

    /// The second strategy's estimate of the sun's light through the phase
    /// function's forward peak (share `share`, lobe `g`) at the collision
    /// after `p`, reached along `d`, per unit irradiance and path weight: a
    /// direction `ω` drawn from the lobe about the sun (`p_B`), followed to
    /// a real collision and lit there, weighted by the phase function at
    /// `p` over `p_A + p_B` (see the module docs).
    fn peak_toward_sun(
        &self,
        p: Vec3,
        d: Vec3,
        share: f32,
        g: f32,
        sun: Vec3,
        rng: &mut impl Rng,
    ) -> f32 {
        let sc = self.scene;
        let m = &sc.medium;
        let w = sample_hg(g, sun, [unit(rng), unit(rng)]);
        let pb = henyey_greenstein(g, w.dot(sun));
        let c = d.dot(w);
        let pa = m.phase.eval(c);
        let both = pa + pb;
        if both.is_nan() || both <= 0.0 {
            return 0.0;
        }
        let t_ground = sc.surface_hit(p, w).map_or(f32::INFINITY, |(t, _)| t);
        let Some((_, q)) = self.collide(p, w, t_ground, rng) else {
            return 0.0;
        };
        m.phase.eval(c) * m.albedo * share * pb / both * self.sun_transmittance(q, sun, rng)
    }

    /// One path's estimate of the radiance arriving at `o` along `-d`.
    pub fn radiance(&self, o: Vec3, d: Vec3, rng: &mut impl Rng) -> Vec3 {
        let sc = self.scene;
        let m = &sc.medium;
        let sun = sc.sun_unit();
        // The forward peak `(f, g)` and the rest of the phase function, when
        // the peak's light toward the sun is estimated by two strategies.
        let peak = if self.settings.sun_peak_sampling {
            m.phase
                .peak_lobe()
                .map(|lobe| (lobe, m.phase.forward_peak().1))
        } else {
            None
        };
        let (mut o, mut d) = (o, d);
        let d_eye = d;
        let mut beta = Vec3::ONE;
        let mut l = Vec3::ZERO;
        let mut first_depth = f32::INFINITY;
        let mut depth = 0u32;
        // The density with which `d` was drawn (none for the eye's ray).
        let mut pdf_d: Option<f32> = None;
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
                let f = match (peak, pdf_d) {
                    // The peak's share by the path's own direction, the
                    // rest in full.
                    (Some(((share, g), rest)), Some(pa)) => {
                        let pb = henyey_greenstein(g, mu);
                        (1.0 - share) * rest.eval(mu) + share * pb * (pa / (pa + pb))
                    }
                    _ => m.phase.eval(mu),
                };
                if f > 0.0 {
                    l += beta * s.irradiance * (f * self.sun_transmittance(p, s.direction, rng));
                }
            }
            depth += 1;
            if depth >= self.settings.max_depth {
                break;
            }
            if depth >= 8 {
                let q = beta.max_element();
                if q < 1.0 {
                    if unit(rng) >= q {
                        break;
                    }
                    beta /= q;
                }
            }
            // The peak's light at the next collision by the second strategy.
            if let (Some(((share, g), _)), Some(s)) = (peak, sun) {
                l += beta * s.irradiance * self.peak_toward_sun(p, d, share, g, s.direction, rng);
            }
            let nd = m.phase.sample(d, &mut || unit(rng));
            pdf_d = Some(m.phase.eval(d.dot(nd)));
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
