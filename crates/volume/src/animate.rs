//! Ebert's cloud animation: eased warps of the cloud space, keyframed
//! primitives ("A Cloud is Born") and volumetric procedural implicit
//! particle systems.
//!
//! Ebert 2001, "Animating Volumetric Procedural Clouds": the jet-stream warp
//! amount is ramped with ease-in/ease-out over the frames while the
//! primitives stay put; in "A Cloud is Born" three primitives move together
//! and grow; in the implicit particle system a few seed primitives rise
//! under an upward turbulent force and spawn children where turbulence is
//! high; particles never die, they become dormant.

use glam::Vec3;
use natura_core::Seed;
use rand_core::Rng;

use crate::error::{Result, VolumeError, finite3, in_range, non_negative, positive};
use crate::gas::GasNoise;
use crate::implicit::{Implicit, ImplicitPrimitive, Skeleton};

/// Ease-in/ease-out `3t² − 2t³` of `t` clamped to `[0, 1]`: `ease(0) = 0`,
/// `ease(1) = 1`, monotone, zero slope at both ends. The source names the
/// easing but not the curve; this is the cubic Hermite ramp.
#[inline]
#[must_use]
pub fn ease(t: f32) -> f32 {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    t * t * (3.0 - 2.0 * t)
}

/// The eased warp amount at `frame` of an animation from `start` to `end`
/// (0 before, 1 after).
#[must_use]
pub fn eased_amount(frame: u32, start: u32, end: u32) -> f32 {
    if end <= start {
        return if frame >= end { 1.0 } else { 0.0 };
    }
    ease((frame.saturating_sub(start)) as f32 / (end - start) as f32)
}

/// A primitive keyframed between two states, interpolated with [`ease`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Keyed {
    /// The state at `t = 0`.
    pub from: ImplicitPrimitive,
    /// The state at `t = 1`.
    pub to: ImplicitPrimitive,
}

impl Keyed {
    /// The primitive at `t ∈ [0, 1]` (eased); skeletons of different kinds
    /// switch at `t = ½`.
    #[must_use]
    pub fn at(&self, t: f32) -> ImplicitPrimitive {
        let s = ease(t);
        let lerp = |a: f32, b: f32| a + (b - a) * s;
        let skeleton = match (self.from.skeleton, self.to.skeleton) {
            (Skeleton::Point(a), Skeleton::Point(b)) => Skeleton::Point(a.lerp(b, s)),
            (Skeleton::Segment { a, b }, Skeleton::Segment { a: c, b: d }) => Skeleton::Segment {
                a: a.lerp(c, s),
                b: b.lerp(d, s),
            },
            (x, y) => {
                if s < 0.5 {
                    x
                } else {
                    y
                }
            }
        };
        ImplicitPrimitive {
            skeleton,
            radius: lerp(self.from.radius, self.to.radius),
            weight: lerp(self.from.weight, self.to.weight),
        }
    }
}

/// "A Cloud is Born": three small cloud elements apart at `t = 0` that move
/// together and grow into one cumulus at `t = 1` (sizes in metres about the origin).
#[must_use]
pub fn cloud_is_born() -> Vec<Keyed> {
    let k = |a: Vec3, ra: f32, b: Vec3, rb: f32| Keyed {
        from: ImplicitPrimitive::sphere(a, ra).with_weight(0.7),
        to: ImplicitPrimitive::sphere(b, rb),
    };
    vec![
        k(
            Vec3::new(-6.0, 0.0, 2.0),
            1.2,
            Vec3::new(-1.8, 0.0, 2.2),
            3.0,
        ),
        k(Vec3::new(6.0, 1.0, 2.5), 1.0, Vec3::new(1.8, 0.3, 2.4), 2.9),
        k(
            Vec3::new(0.0, -1.0, 6.0),
            0.8,
            Vec3::new(0.0, 0.0, 4.4),
            2.6,
        ),
    ]
}

/// The primitives of `keys` at `t`.
///
/// # Errors
///
/// As [`Implicit::new`] (empty list or invalid interpolated primitive).
pub fn keyed_implicit(keys: &[Keyed], t: f32) -> Result<Implicit> {
    Implicit::new(keys.iter().map(|k| k.at(t)).collect())
}

/// Parameters of an [`ImplicitParticles`] system.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct ParticleParams {
    /// Upward (buoyant) acceleration, m/s².
    pub lift: f32,
    /// Turbulent acceleration amplitude, m/s².
    pub turbulent_force: f32,
    /// Linear drag, 1/s.
    pub drag: f32,
    /// Lifetime of an active particle, s; then it becomes dormant (never dies).
    pub lifetime: f32,
    /// Radius growth while active, m/s.
    pub growth: f32,
    /// Expected children per particle per second at turbulence 1.
    pub spawn_rate: f32,
    /// Cap on the number of particles ("a few hundred").
    pub max_particles: usize,
    /// Frequency of the turbulence driving forces and spawning (1/m).
    pub noise_frequency: f32,
}

impl Default for ParticleParams {
    /// A cumulus rising from a dozen seeds to about fifty primitives in 200
    /// frames at 24 frames/s.
    fn default() -> Self {
        Self {
            lift: 0.6,
            turbulent_force: 0.8,
            drag: 0.8,
            lifetime: 5.0,
            growth: 0.15,
            spawn_rate: 0.7,
            max_particles: 300,
            noise_frequency: 0.15,
        }
    }
}

impl ParticleParams {
    /// Checks every field.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] naming the bad field.
    pub fn validate(&self) -> Result<()> {
        crate::error::finite3("lift", Vec3::splat(self.lift))?;
        non_negative("turbulent_force", self.turbulent_force)?;
        non_negative("drag", self.drag)?;
        positive("lifetime", self.lifetime)?;
        non_negative("growth", self.growth)?;
        in_range(
            "spawn_rate",
            self.spawn_rate,
            0.0,
            100.0,
            "must lie in [0, 100]",
        )?;
        positive("noise_frequency", self.noise_frequency)?;
        if !(1..=100_000).contains(&self.max_particles) {
            return Err(VolumeError::InvalidParameter {
                name: "max_particles",
                value: self.max_particles.to_string(),
                expected: "must lie in 1..=100000",
            });
        }
        Ok(())
    }
}

/// One implicit particle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle {
    /// Its primitive (a sphere).
    pub primitive: ImplicitPrimitive,
    /// Velocity, m/s.
    pub velocity: Vec3,
    /// Age, s.
    pub age: f32,
}

impl Particle {
    /// Whether the particle has outlived its lifetime (it stays, frozen).
    #[must_use]
    pub fn dormant(&self, lifetime: f32) -> bool {
        self.age >= lifetime
    }
}

/// Ebert's volumetric procedural implicit particle system: seed primitives
/// that rise, drift with turbulence, grow, spawn children where turbulence
/// is high, and become dormant. Deterministic for a seed.
#[derive(Clone, Debug)]
pub struct ImplicitParticles {
    params: ParticleParams,
    particles: Vec<Particle>,
    noise: GasNoise,
    seed: Seed,
    steps: u64,
}

impl ImplicitParticles {
    /// A system started from `seeds` (spheres).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] for invalid params, an empty or
    /// oversized seed list or an invalid seed primitive.
    pub fn new(seeds: &[ImplicitPrimitive], params: ParticleParams, seed: u64) -> Result<Self> {
        params.validate()?;
        if seeds.is_empty() || seeds.len() > params.max_particles {
            return Err(VolumeError::InvalidParameter {
                name: "seeds",
                value: seeds.len().to_string(),
                expected: "between 1 and max_particles seed primitives",
            });
        }
        for s in seeds {
            s.validate()?;
        }
        Ok(Self {
            params,
            particles: seeds
                .iter()
                .map(|&primitive| Particle {
                    primitive,
                    velocity: Vec3::ZERO,
                    age: 0.0,
                })
                .collect(),
            noise: GasNoise::new(seed, 3)?,
            seed: Seed(seed).derive("implicit particles"),
            steps: 0,
        })
    }

    /// The particles (active and dormant).
    #[must_use]
    pub fn particles(&self) -> &[Particle] {
        &self.particles
    }

    /// Advances the system by `dt` seconds.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] for a non-positive or non-finite `dt`.
    pub fn step(&mut self, dt: f32) -> Result<()> {
        positive("dt", dt)?;
        let p = self.params;
        let mut rng = self.seed.derive_index(self.steps).rng();
        self.steps += 1;
        let mut children = Vec::new();
        for part in &mut self.particles {
            if part.dormant(p.lifetime) {
                continue;
            }
            let c = match part.primitive.skeleton {
                Skeleton::Point(c) => c,
                _ => continue,
            };
            let q = c * p.noise_frequency;
            let turb = self.noise.turbulence(q);
            let swirl = Vec3::new(
                self.noise.noise(q + Vec3::new(17.0, 0.0, 0.0)),
                self.noise.noise(q + Vec3::new(0.0, 31.0, 0.0)),
                self.noise.noise(q + Vec3::new(0.0, 0.0, 47.0)),
            );
            let acc = Vec3::Z * p.lift + swirl * p.turbulent_force - part.velocity * p.drag;
            part.velocity += acc * dt;
            let c = c + part.velocity * dt;
            part.primitive.skeleton = Skeleton::Point(c);
            part.primitive.radius += p.growth * dt;
            part.age += dt;
            // Children where turbulence is high.
            let chance = p.spawn_rate * turb * dt;
            if unit(&mut rng) < chance {
                let off = Vec3::new(
                    unit(&mut rng) - 0.5,
                    unit(&mut rng) - 0.5,
                    unit(&mut rng) * 0.5,
                ) * part.primitive.radius
                    * 1.5;
                children.push(Particle {
                    primitive: ImplicitPrimitive::sphere(c + off, part.primitive.radius * 0.7)
                        .with_weight(part.primitive.weight),
                    velocity: part.velocity,
                    age: 0.0,
                });
            }
        }
        let room = p.max_particles - self.particles.len();
        self.particles.extend(children.into_iter().take(room));
        for part in &self.particles {
            finite3("particle position", part.primitive.support().min)?;
        }
        Ok(())
    }

    /// The implicit field of all particles (dormant ones included).
    ///
    /// # Errors
    ///
    /// As [`Implicit::new`].
    pub fn implicit(&self) -> Result<Implicit> {
        Implicit::new(self.particles.iter().map(|p| p.primitive).collect())
    }
}

/// A uniform number in `[0, 1)` from 24 random bits.
#[inline]
pub(crate) fn unit(rng: &mut impl Rng) -> f32 {
    (rng.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}
