//! The light the medium receives from the sky and from the scene's own
//! surfaces and glow, traced once per scene onto the fast mode's grid of
//! cells.
//!
//! **What it models.** Besides the sun, a medium is lit by the sky, by
//! the ground and the solids under and beside it (Lambertian surfaces lit
//! by the sun, shadowed by the medium and by each other, and by the sky:
//! [`lit_ground`]) and by its own glow (the emission `σ_a·L_e` of a hot
//! gas, scattered before it leaves). The reference path tracer gathers
//! both: a path that reaches a surface or leaves into the sky takes its
//! radiance, and every real collision adds the emission there. The fast
//! mode's march sees a surface and the glow only straight along the eye
//! ray; this cache adds the light they send into the medium, scattered
//! toward the eye at any order. The sky's light, without it, is the march's
//! ambient term (an isotropic environment occluded along the vertical) with
//! its multiple scattering by the octaves, which on a ball of optical
//! diameter 16 under a uniform sky gave 0.74 of the reference's light and
//! on one of 2 gave 1.09; traced here, 0.99–1.01 (`docs/performance.md`).
//!
//! **How.** Photons start on the sources, each chosen with probability in
//! proportion to its (unshadowed) power. The ground's light is drawn where
//! it enters the grid's box: a point on the box's floor or sides (above the
//! ground) and a cosine-distributed direction into the box, whose ray back
//! meets the ground at `q` (the space between holds no medium), with power
//! `π·L(q)·A` over the photons drawn (`A` the faces' area; a ray back that
//! meets the sky or a solid carries nothing here): every point of the
//! infinite plane is counted and no photon misses the grid. The sky's
//! light is drawn the same way on every face above the ground (the top,
//! the sides and, without a ground, the floor), with the sky's radiance
//! where the ray back leaves (a ray back that meets the ground or a solid
//! carries nothing here). A solid's
//! photons leave its surface along cosine-distributed directions with power
//! `π·L·4πr²`, and glow photons leave points in the cells, drawn in
//! proportion to their glow, along uniform directions with `4π·σ_a·L_e·V`.
//! A surface's radiance `L` takes the sun's transmittance to it through the
//! cells. Each photon is then followed through
//! free flights and scatterings sampled as the reference samples them,
//! every flight scored by its track length (Lux & Koblinger 1991, ch. 5)
//! into the cells' projections on the real spherical harmonics of bands 0
//! to 3 per colour channel; a flight ends where it meets a surface (the
//! surfaces do not reflect the medium's light back, as in the reference).
//! The march reads `Σ σ_l χ_l c_lm Y_lm(ω_o)` per channel, as it reads the
//! sun's cache ([`super::cache`]). Light from wide solid angles needs few
//! bands, but in a thick medium of low albedo the first order dominates,
//! and the sky's light there arrives from the nearest surface, a peaked
//! field that an anisotropic phase turns toward the eye: cut after band 1
//! (its σ-factor 0.64), the fast mode was 6–10 % too bright at albedo 0.8
//! under HG 0.6 and 0.8 and the 5 µm cloud phase; cut after band 3 it is
//! within 5 % (`docs/performance.md`).
//!
//! **What it costs.** Its photons run with the sun's (the scattering
//! events are [`CacheParams::local`](super::CacheParams::local)). The march reads
//! eight cells per sample, kept while an eye ray stays among the same
//! cells. With it, the environment's mean radiance no longer counts the
//! ground below the horizon nor the sky (the cache carries that light,
//! shadowed, at every order).

use glam::Vec3;
use natura_core::Seed;
use rand_core::Rng;

use super::cells::{CellGrid, Flight, written_zeros};
use super::harmonics::{MAX_COEFFS, dot, legendre_moments, sh_basis, sigma_factor};
use super::model::lit_ground;
use super::solid::uniform_direction;
use super::{MediumParams, Scene, Surface};
use crate::animate::unit;
use crate::density::{fill_densities, ray_box};

/// Photon chunks (each its own random stream and grid; summed in order).
const CHUNKS: usize = 4;
/// The highest band of the cells' radiance.
const ORDER: usize = 3;
/// Coefficients per channel: bands 0 to [`ORDER`].
const PER: usize = (ORDER + 1) * (ORDER + 1);
/// Most scattering events one photon is followed through.
const MAX_EVENTS_PER_PHOTON: u32 = 1 << 20;
/// Most photons drawn per scattering event of the budget (photons that
/// carry nothing into the grid count no event).
const MAX_DRAWS_PER_EVENT: u64 = 64;

/// The light of the scene's surfaces and glow in the medium (see the
/// module docs).
#[derive(Clone, Debug)]
pub(crate) struct LocalLight {
    grid: CellGrid,
    /// Per cell, per channel, the coefficients `∫ L Y_lm dω` of bands 0
    /// to [`ORDER`] (radiance units).
    coeffs: Vec<[f32; 3 * PER]>,
    /// Per band, the phase's Legendre moment times its σ-factor.
    band: [f32; ORDER + 1],
    /// Whether the ground is one of the sources.
    ground: bool,
    /// Whether the sky is one of the sources.
    sky: bool,
}

/// The factors of one eye direction, and the last eight cells' light
/// toward it along the eye ray.
#[derive(Clone, Debug)]
pub(crate) struct LocalEye {
    factors: [f32; PER],
    memo: std::cell::Cell<Option<(usize, [Vec3; 8])>>,
}

/// What a photon leaves.
#[derive(Clone, Copy)]
enum Source {
    Ground,
    Sky,
    Solid(usize),
    Glow,
}

/// A rectangle `origin + a·u + b·v` (`a`, `b` in `[0, 1]`) and its normal
/// into the grid's box.
struct Face {
    origin: Vec3,
    u: Vec3,
    v: Vec3,
    inward: Vec3,
    area: f32,
}

impl Face {
    fn new(origin: Vec3, u: Vec3, v: Vec3, inward: Vec3) -> Self {
        Self {
            origin,
            u,
            v,
            inward,
            area: u.cross(v).length(),
        }
    }
}

/// Faces of the grid's box by which outside light enters (the ground's:
/// the floor and sides above the ground; the sky's: every face above the
/// ground), with their cumulative areas.
struct Faces {
    faces: Vec<Face>,
    cdf: Vec<f32>,
    area: f32,
}

impl Faces {
    fn new(faces: Vec<Face>) -> Self {
        let mut sum = 0.0;
        let cdf = faces
            .iter()
            .map(|f| {
                sum += f.area;
                sum
            })
            .collect();
        Self {
            faces,
            cdf,
            area: sum,
        }
    }

    /// A point on a face, drawn in proportion to area, and a
    /// cosine-distributed direction into the box.
    fn draw(&self, rng: &mut impl Rng) -> (Vec3, Vec3) {
        let x = unit(rng) * self.area;
        let f = &self.faces[self
            .cdf
            .partition_point(|&c| c <= x)
            .min(self.faces.len() - 1)];
        let o = f.origin + f.u * unit(rng) + f.v * unit(rng);
        (o, cosine_about(f.inward, rng))
    }
}

/// The scene's sources and how each is drawn.
struct Sources {
    /// `(source, cumulative probability)`.
    choice: Vec<(Source, f32)>,
    /// The faces of the grid's box the ground's light enters by.
    ground: Option<Faces>,
    /// The faces of the grid's box the sky's light enters by.
    sky: Option<Faces>,
    /// Per cell, the glow's power `4π·σ_a·L_e·V` (RGB), and the cumulative
    /// luminance over the cells.
    glow: Vec<Vec3>,
    glow_cdf: Vec<f32>,
}

impl LocalLight {
    /// Traces the light of `scene`'s ground, solids and emission through
    /// `grid` (the transport medium's extinction per cell; `medium` that
    /// medium, `ratio` its extinction over the scene's), with `events`
    /// scattering events and random streams from `seed`. `None` when the
    /// scene has no such source or the medium does not scatter.
    pub(crate) fn new(
        scene: &Scene<'_>,
        grid: CellGrid,
        medium: &MediumParams,
        ratio: f32,
        events: u32,
        seed: u64,
    ) -> Option<Self> {
        if medium.albedo <= 0.0 || !grid.sigma.iter().any(|&s| s > 0.0) {
            return None;
        }
        let chi = legendre_moments(&medium.phase);
        let mut light = Self {
            coeffs: written_zeros(grid.count(), [0.0; 3 * PER]),
            grid,
            band: std::array::from_fn(|l| chi[l] * sigma_factor(l, ORDER)),
            ground: false,
            sky: false,
        };
        let sources = light.sources(scene)?;
        light.ground = sources.ground.is_some();
        light.sky = sources.sky.is_some();
        light.trace(scene, &sources, medium, ratio, events, seed);
        Some(light)
    }

    /// Whether the light includes the ground's (the environment's mean
    /// radiance then leaves the ground out).
    pub(crate) fn has_ground(&self) -> bool {
        self.ground
    }

    /// Whether the light includes the sky's (the environment's mean
    /// radiance then leaves the sky out, and the octaves no longer scatter it).
    pub(crate) fn has_sky(&self) -> bool {
        self.sky
    }

    /// The factors of an eye looking along unit `d`.
    pub(crate) fn eye(&self, d: Vec3) -> LocalEye {
        let mut y = [0.0f32; MAX_COEFFS];
        sh_basis(ORDER, -d, &mut y);
        LocalEye {
            // Band l holds the coefficients l² .. (l + 1)².
            factors: std::array::from_fn(|i| y[i] * self.band[i.isqrt()]),
            memo: std::cell::Cell::new(None),
        }
    }

    /// The light scattered toward the eye at `p` per unit scattering
    /// coefficient (radiance per metre over `σ_s`), per channel clamped at
    /// zero, trilinear between cell centres.
    #[inline]
    pub(crate) fn toward_eye(&self, p: Vec3, eye: &LocalEye) -> Vec3 {
        let (i, j, w) = self.grid.corners(p);
        let key = self.grid.index(i[0], i[1], i[2]);
        let v = match eye.memo.get() {
            Some((k, v)) if k == key => v,
            _ => {
                let mut v = [Vec3::ZERO; 8];
                for (out, c) in v.iter_mut().zip(self.grid.corner_cells(i, j)) {
                    let s = &self.coeffs[c];
                    let f = &eye.factors;
                    let ch = |k: usize| dot(&s[k * PER..(k + 1) * PER], f);
                    *out = Vec3::new(ch(0), ch(1), ch(2));
                }
                eye.memo.set(Some((key, v)));
                v
            }
        };
        CellGrid::blend(&v, w).max(Vec3::ZERO)
    }

    /// The radiance leaving surface `kind` at `q` (lifted off it), whose
    /// normal is `n`: the scene's own surface radiance, with the sun's
    /// transmittance taken through the cells (`ratio` turns the transport
    /// medium's optical depth into the scene's) and zero behind a solid.
    fn surface(
        scene: &Scene<'_>,
        grid: &CellGrid,
        ratio: f32,
        kind: Surface,
        q: Vec3,
        n: Vec3,
    ) -> Vec3 {
        let t = scene.sun_unit().map_or(1.0, |s| {
            if n.dot(s.direction) <= 0.0 || scene.blocked(q, s.direction) {
                0.0
            } else {
                (-grid.optical_depth(q, s.direction) / ratio).exp()
            }
        });
        scene.surface_radiance(kind, q, t)
    }

    /// The scene's sources, each with its share of the photons (`None`
    /// when it has none).
    fn sources(&self, scene: &Scene<'_>) -> Option<Sources> {
        let grid = &self.grid;
        let b = grid.bounds();
        let lum = |c: Vec3| natura_core::colour::luminance(c).max(0.0);
        let mut power: Vec<(Source, f32)> = Vec::new();
        let mut ground = None;
        // The grid's box above the ground (all of it without a ground).
        let z0 = scene.ground.map_or(b.min.z, |g| b.min.z.max(g.height));
        let above = b.max.z > z0;
        let d = Vec3::new(b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - z0);
        let lo = Vec3::new(b.min.x, b.min.y, z0);
        let (ex, ey, ez) = (Vec3::X * d.x, Vec3::Y * d.y, Vec3::Z * d.z);
        let floor = || Face::new(lo, ex, ey, Vec3::Z);
        let sides = || {
            vec![
                Face::new(lo, ey, ez, Vec3::X),
                Face::new(lo + ex, ey, ez, -Vec3::X),
                Face::new(lo, ex, ez, Vec3::Y),
                Face::new(lo + ey, ex, ez, -Vec3::Y),
            ]
        };
        if let Some(g) = scene.ground
            && above
        {
            // The floor and the four sides.
            let mut faces = vec![floor()];
            faces.extend(sides());
            let faces = Faces::new(faces);
            let floor_area = faces.faces[0].area;
            let unshadowed = match scene.sun_unit() {
                Some(s) => lit_ground(g.albedo, s.irradiance, s.direction.z, 1.0, g.sky_irradiance),
                None => lit_ground(g.albedo, Vec3::ZERO, 0.0, 1.0, g.sky_irradiance),
            };
            // The floor takes the ground's light from every inward direction,
            // a side from about half of them.
            let seen = floor_area + 0.5 * (faces.area - floor_area);
            power.push((
                Source::Ground,
                std::f32::consts::PI * lum(unshadowed) * seen,
            ));
            ground = Some(faces);
        }
        // The sky's light enters by the top, the sides and, without a
        // ground, the floor; its power is estimated from the mean radiance.
        let mut sky = None;
        let mean_sky = {
            let n = 256;
            sphere_dirs_mean(n, |d| scene.environment.radiance(d))
        };
        if above && lum(mean_sky) > 0.0 {
            let mut faces = sides();
            faces.push(Face::new(lo + ez, ex, ey, -Vec3::Z));
            if scene.ground.is_none() {
                faces.push(floor());
            }
            let faces = Faces::new(faces);
            power.push((
                Source::Sky,
                std::f32::consts::PI * lum(mean_sky) * faces.area,
            ));
            sky = Some(faces);
        }
        for (i, s) in scene.solids.iter().enumerate() {
            let e = scene.sun_unit().map_or(Vec3::ZERO, |s| s.irradiance);
            let l = s.albedo * std::f32::consts::FRAC_1_PI * (e * 0.5 + s.sky_irradiance);
            power.push((Source::Solid(i), std::f32::consts::PI * lum(l) * s.area()));
        }
        let (mut glow, mut glow_cdf) = (Vec::new(), Vec::new());
        if let Some(e) = scene.emission {
            let k = scene.medium.extinction * (1.0 - scene.medium.albedo);
            let density = scene.density;
            let mean = grid.mean_per_cell(|xs, ys, zs, out| {
                let mut t = vec![0.0f32; out.len()];
                fill_densities(density, xs, ys, zs, out);
                fill_densities(e.field, xs, ys, zs, &mut t);
                for (o, t) in out.iter_mut().zip(&t) {
                    *o *= k * (t - e.offset).max(0.0);
                }
            });
            let v = 4.0 * std::f32::consts::PI * grid.cell_volume();
            let mut sum = 0.0f32;
            for m in mean {
                let p = e.colour * (m * v);
                sum += lum(p);
                glow.push(p);
                glow_cdf.push(sum);
            }
            if sum > 0.0 {
                power.push((Source::Glow, sum));
            }
        }
        let total: f32 = power.iter().map(|p| p.1).sum();
        if !(total.is_finite() && total > 0.0) {
            return None;
        }
        let mut acc = 0.0;
        let choice = power
            .into_iter()
            .map(|(s, p)| {
                acc += p / total;
                (s, acc)
            })
            .collect();
        Some(Sources {
            choice,
            ground,
            sky,
            glow,
            glow_cdf,
        })
    }

    /// Draws one photon: its start, direction and power (RGB), or `None`
    /// when its source gives it no power.
    fn draw(
        &self,
        scene: &Scene<'_>,
        src: &Sources,
        ratio: f32,
        rng: &mut impl Rng,
    ) -> Option<(Vec3, Vec3, Vec3)> {
        use std::f32::consts::PI;
        let u = unit(rng);
        let k = src
            .choice
            .iter()
            .position(|c| u < c.1)
            .unwrap_or(src.choice.len() - 1);
        let prob = src.choice[k].1 - if k == 0 { 0.0 } else { src.choice[k - 1].1 };
        let (o, n, power) = match src.choice[k].0 {
            Source::Ground => {
                // A point on a face of the grid's box and a direction into
                // it; the ground's radiance where that ray came from.
                let gf = src.ground.as_ref()?;
                let (o, d) = gf.draw(rng);
                match scene.surface_hit(o, -d) {
                    Some((t, Surface::GroundPlane)) if d.z > 0.0 => {
                        let q = o - d * t + Vec3::Z * 1e-3;
                        let l = Self::surface(
                            scene,
                            &self.grid,
                            ratio,
                            Surface::GroundPlane,
                            q,
                            Vec3::Z,
                        );
                        return Some((o, d, l * (PI * gf.area / prob)));
                    }
                    // The sky's light (its own photons carry it), or a
                    // solid's (so do its).
                    _ => return None,
                }
            }
            Source::Sky => {
                // The same, for the rays back that meet the sky: its
                // radiance arriving along `d`.
                let sf = src.sky.as_ref()?;
                let (o, d) = sf.draw(rng);
                if scene.surface_hit(o, -d).is_some() {
                    return None;
                }
                let l = scene.environment.radiance(-d);
                return Some((o, d, l * (PI * sf.area / prob)));
            }
            Source::Solid(i) => {
                let s = &scene.solids[i];
                let (p, n) = s.sample(&mut || unit(rng));
                let q = s.lift(p);
                let l = Self::surface(scene, &self.grid, ratio, Surface::Solid(i), q, n);
                (q, n, l * (PI * s.area() / prob))
            }
            Source::Glow => {
                let total = *src.glow_cdf.last()?;
                let x = unit(rng) * total;
                let c = src
                    .glow_cdf
                    .partition_point(|&v| v <= x)
                    .min(src.glow.len() - 1);
                let before = if c == 0 { 0.0 } else { src.glow_cdf[c - 1] };
                let p_cell = (src.glow_cdf[c] - before) / total;
                if p_cell <= 0.0 {
                    return None;
                }
                let q = self.grid.cell_corner(c)
                    + Vec3::new(unit(rng), unit(rng), unit(rng)) * self.grid.h;
                return Some((
                    q,
                    uniform_direction(&mut || unit(rng)),
                    src.glow[c] / (prob * p_cell),
                ));
            }
        };
        let d = cosine_about(n, rng);
        ray_box(o, d.recip(), &self.grid.bounds())?;
        Some((o, d, power))
    }

    /// Traces the photons and sets the coefficients.
    fn trace(
        &mut self,
        scene: &Scene<'_>,
        src: &Sources,
        medium: &MediumParams,
        ratio: f32,
        events: u32,
        seed: u64,
    ) {
        let per_chunk = (u64::from(events) / CHUNKS as u64).max(1);
        let lum = |c: Vec3| natura_core::colour::luminance(c);
        let run = |k: usize| -> (Vec<[f32; 3 * PER]>, u64) {
            let mut grid = written_zeros(self.coeffs.len(), [0.0f32; 3 * PER]);
            // Streams apart from the sun cache's (which are 0..CHUNKS).
            let mut rng = Seed(seed).derive_index((CHUNKS + k) as u64).rng();
            let (mut drawn, mut used) = (0u64, 0u64);
            while used < per_chunk && drawn < MAX_DRAWS_PER_EVENT * per_chunk {
                drawn += 1;
                let Some((mut x, mut d, mut w)) = self.draw(scene, src, ratio, &mut rng) else {
                    continue;
                };
                let w0 = lum(w);
                if w0.is_nan() || w0 <= 0.0 {
                    continue;
                }
                for _ in 0..MAX_EVENTS_PER_PHOTON {
                    used += 1;
                    let mut y = [0.0f32; MAX_COEFFS];
                    sh_basis(ORDER, d, &mut y);
                    let target = -(1.0 - unit(&mut rng)).ln();
                    let t_max = scene.surface_hit(x, d).map_or(f32::INFINITY, |(t, _)| t);
                    let flight = self.grid.fly(x, d, target, t_max, |c, len| {
                        let cell = &mut grid[c];
                        for (ch, wc) in w.to_array().into_iter().enumerate() {
                            let s = wc * len;
                            for (m, b) in y[..PER].iter().enumerate() {
                                cell[ch * PER + m] += s * b;
                            }
                        }
                    });
                    match flight {
                        Flight::Left => break,
                        Flight::Collided(p) => x = p,
                    }
                    w *= medium.albedo;
                    if lum(w) < 0.1 * w0 {
                        if unit(&mut rng) < 0.5 {
                            w *= 2.0;
                        } else {
                            break;
                        }
                    }
                    d = medium.phase.sample(d, &mut || unit(&mut rng));
                }
            }
            (grid, drawn)
        };
        #[cfg(feature = "parallel")]
        let chunks: Vec<(Vec<[f32; 3 * PER]>, u64)> = {
            use rayon::prelude::*;
            (0..CHUNKS).into_par_iter().map(run).collect()
        };
        #[cfg(not(feature = "parallel"))]
        let chunks: Vec<(Vec<[f32; 3 * PER]>, u64)> = (0..CHUNKS).map(run).collect();
        let volume = self.grid.cell_volume();
        for (grid, drawn) in &chunks {
            let s = 1.0 / (*drawn as f32 * CHUNKS as f32 * volume);
            for (m, g) in self.coeffs.iter_mut().zip(grid) {
                for (a, b) in m.iter_mut().zip(g) {
                    *a += b * s;
                }
            }
        }
    }
}

/// The mean of `f` over `n` directions spread evenly over the sphere.
fn sphere_dirs_mean(n: usize, f: impl Fn(Vec3) -> Vec3) -> Vec3 {
    super::march::sphere_dirs(n).map(f).sum::<Vec3>() / n as f32
}

/// A direction about unit `n` with density `cos θ/π`.
fn cosine_about(n: Vec3, rng: &mut impl Rng) -> Vec3 {
    let (u, v) = n.any_orthonormal_pair();
    let r = unit(rng).sqrt();
    let phi = 2.0 * std::f32::consts::PI * unit(rng);
    let z = (1.0 - r * r).max(0.0).sqrt();
    (u * (r * phi.cos()) + v * (r * phi.sin()) + n * z).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::density::Homogeneous;
    use crate::phase::CloudPhase;
    use crate::transport::{Emission, GroundPlane, Sun};
    use natura_core::Aabb;

    /// `E₂(τ) = ∫₀¹ e^{−τ/μ} dμ` by the midpoint rule.
    fn e2(tau: f64) -> f64 {
        let n = 200_000;
        (0..n)
            .map(|i| (-tau / ((i as f64 + 0.5) / n as f64)).exp())
            .sum::<f64>()
            / n as f64
    }

    /// A wide slab of optical half-thickness 0.5 between `z0` and `z0 + 0.5`,
    /// nearly absorbing (single scattering negligible), isotropic.
    fn slab(z0: f32) -> (Homogeneous, MediumParams) {
        let region = Aabb {
            min: Vec3::new(-6.0, -6.0, z0),
            max: Vec3::new(6.0, 6.0, z0 + 0.5),
        };
        let medium = MediumParams {
            extinction: 2.0,
            albedo: 0.005,
            phase: CloudPhase::Isotropic,
        };
        (Homogeneous::new(region, 1.0).unwrap(), medium)
    }

    /// Every channel of `got` within the relative error `tol` of `want`.
    fn assert_rel(got: Vec3, want: Vec3, tol: f32) {
        for k in 0..3 {
            let e = (got[k] - want[k]) / want[k];
            assert!(
                e.abs() < tol,
                "channel {k}: {} vs {} ({e:+.3})",
                got[k],
                want[k]
            );
        }
    }

    /// The light at `p` toward a horizontal eye (the flux there is
    /// vertical, so this is the mean radiance over every direction).
    fn light_at(scene: &Scene<'_>, p: Vec3) -> Vec3 {
        let grid = CellGrid::new(scene.density, scene.medium.extinction, 8).unwrap();
        let l = LocalLight::new(scene, grid, &scene.medium, 1.0, 2_000_000, 7).unwrap();
        l.toward_eye(p, &l.eye(Vec3::X))
    }

    #[test]
    fn a_glowing_slab_holds_the_mean_radiance_of_its_glow() {
        // Emission σ_a·L_e throughout; at the middle of the slab the
        // radiance along μ is (1 − ω)·L_e·(1 − e^{−τ/|μ|}), τ = 0.5, whose
        // mean over the sphere is (1 − ω)·L_e·(1 − E₂(τ)).
        let (d, medium) = slab(-0.25);
        let colour = Vec3::new(1.0, 0.5, 0.25);
        let scene = Scene {
            emission: Some(Emission {
                field: &d,
                offset: 0.0,
                colour,
            }),
            ..Scene::new(&d, medium, Vec3::ZERO)
        };
        let got = light_at(&scene, Vec3::ZERO);
        let want = colour * ((1.0 - medium.albedo) * (1.0 - e2(0.5)) as f32);
        assert_rel(got, want, 0.03);
    }

    #[test]
    fn a_slab_over_a_lit_ground_holds_the_ground_light_through_its_own_shadow() {
        // A slab resting on the ground, the sun overhead: the ground below it
        // is lit through the slab's whole optical thickness 1 and by the sky,
        // L_g = a/π·(E·e^{−1} + E_sky), and seen from the centre of a cell
        // at height 0.28125 (optical depth 0.5625 above the ground) through
        // optical depth 0.5625/μ below the horizon only: the mean over the
        // sphere is L_g·E₂(0.5625)/2.
        let (d, medium) = slab(0.0);
        let (albedo, sun, sky) = (0.5f32, 1.0f32, 0.3f32);
        let scene = Scene {
            sun: Some(Sun {
                direction: Vec3::Z,
                irradiance: Vec3::splat(sun),
            }),
            ground: Some(GroundPlane {
                height: 0.0,
                albedo: Vec3::splat(albedo),
                sky_irradiance: Vec3::splat(sky),
            }),
            ..Scene::new(&d, medium, Vec3::ZERO)
        };
        let got = light_at(&scene, Vec3::new(0.0, 0.0, 0.281_25));
        let lg = f64::from(albedo) / std::f64::consts::PI
            * (f64::from(sun) * (-1f64).exp() + f64::from(sky));
        let want = (lg * e2(0.5625) / 2.0) as f32;
        let e = (got.x - want) / want;
        assert!(e.abs() < 0.03, "{} vs {want} ({e:+.3})", got.x);
        // Grey: the same in every channel.
        assert!((got.y - got.x).abs() < 1e-6 && (got.z - got.x).abs() < 1e-6);
    }

    #[test]
    fn a_slab_under_a_uniform_sky_holds_the_sky_through_its_own_depth() {
        // At the middle of the slab the sky's radiance along μ arrives through
        // optical depth 0.5/|μ|: the mean over the sphere is L·E₂(0.5).
        let (d, medium) = slab(-0.25);
        let sky = Vec3::new(1.0, 0.5, 0.25);
        let scene = Scene::new(&d, medium, sky);
        let got = light_at(&scene, Vec3::ZERO);
        let want = sky * e2(0.5) as f32;
        assert_rel(got, want, 0.03);
        // Over a ground the sky enters from above only: at the slab's
        // middle, half the sphere, L·E₂(0.5)/2 (the ground, black and unlit,
        // sends nothing).
        let (d, medium) = slab(0.0);
        let scene = Scene {
            ground: Some(GroundPlane {
                height: 0.0,
                albedo: Vec3::ZERO,
                sky_irradiance: Vec3::ZERO,
            }),
            ..Scene::new(&d, medium, sky)
        };
        let got = light_at(&scene, Vec3::new(0.0, 0.0, 0.25));
        let e = (got.x - want.x / 2.0) / (want.x / 2.0);
        assert!(e.abs() < 0.03, "{} vs {} ({e:+.3})", got.x, want.x / 2.0);
    }

    #[test]
    fn a_scene_without_surfaces_glow_or_sky_has_no_local_light() {
        let (d, medium) = slab(0.0);
        let scene = Scene::new(&d, medium, Vec3::ZERO);
        let grid = CellGrid::new(&d, medium.extinction, 8).unwrap();
        assert!(LocalLight::new(&scene, grid, &medium, 1.0, 100_000, 1).is_none());
    }
}
