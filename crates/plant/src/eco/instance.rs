//! Approximate instancing: a few prototypes per species stand for every plant.
//!
//! Deussen et al. 1998, §5: plants are clustered in parameter space and each
//! is drawn as its cluster's representative; for the *Lychnis* field the
//! sizes were quantized to seven values per variety and mapped to age. Here
//! each species' plant radii are quantized (weighted by the crown area, the
//! source's importance weight standing for screen area) and each
//! representative becomes one prototype: the species' L-system derived for a
//! number of steps proportional to its size, interpreted by the turtle.
//! Each prototype is derived with its own seed, so a stochastic L-system
//! gives every size class a plant of its own form as well as its own age.

use std::path::Path;

use glam::Vec3;
use natura_core::io::{WriteError, write_atomic};

use super::quantize::quantize;
use super::sim::Ecosystem;
use crate::error::{PlantError, Result};
use crate::turtle::{Geometry, Turtle, TurtleParams};
use crate::{Derivation, LSystem};

/// One representative plant.
#[derive(Clone, Debug, PartialEq)]
pub struct Prototype {
    /// Species index.
    pub species: u16,
    /// The code-book radius it represents, metres.
    pub radius: f32,
    /// Derivation steps of the species' L-system.
    pub steps: u32,
    /// Turtle geometry, base at the origin, growing along +z.
    pub geometry: Geometry,
    /// Horizontal radius of the geometry (its crown), in geometry units.
    pub geometry_radius: f32,
}

/// One placed plant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlantInstance {
    /// Species index.
    pub species: u16,
    /// Index into [`Instancing::prototypes`].
    pub prototype: u32,
    /// Base of the plant on the terrain, metres.
    pub position: Vec3,
    /// Uniform scale from prototype geometry units to metres (maps the crown to the plant's radius).
    pub scale: f32,
    /// Rotation about +z, radians.
    pub rotation: f32,
}

/// Prototypes and instances of an ecosystem.
#[derive(Clone, Debug, PartialEq)]
pub struct Instancing {
    /// Representative plants.
    pub prototypes: Vec<Prototype>,
    /// Every living plant as an instance of a prototype.
    pub instances: Vec<PlantInstance>,
}

/// Horizontal radius of what `g` draws (at least a tiny positive number).
fn crown_radius(g: &Geometry) -> f32 {
    let pts = g
        .start
        .iter()
        .chain(&g.end)
        .chain(g.polygons.iter().flat_map(|p| &p.vertices))
        .copied()
        .chain(g.surfaces.iter().map(|s| s.frame.p.as_vec3()));
    pts.map(|p| p.truncate().length())
        .fold(0.0f32, f32::max)
        .max(1e-3)
}

impl Instancing {
    /// Builds at most `per_species` prototypes per species and one instance per living plant.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] if `per_species` is 0; errors from parsing,
    /// deriving or interpreting a species' L-system.
    pub fn new(eco: &Ecosystem, per_species: usize) -> Result<Self> {
        let species = &eco.params().species;
        let plants = eco.plants();
        let seed = eco.params().seed.derive("eco.instance");
        let mut prototypes = Vec::new();
        let mut proto_of = vec![0u32; plants.len()];
        for (si, sp) in species.iter().enumerate() {
            let members: Vec<usize> = (0..plants.len())
                .filter(|&i| plants[i].species as usize == si)
                .collect();
            let radii: Vec<f32> = members.iter().map(|&i| plants[i].radius).collect();
            let weights: Vec<f32> = radii.iter().map(|r| r * r).collect();
            let q = quantize(&radii, &weights, per_species).map_err(|e| match e {
                PlantError::InvalidParameter { value, reason, .. } => {
                    PlantError::InvalidParameter {
                        name: "per_species",
                        value,
                        reason,
                    }
                }
                e => e,
            })?;
            let lsys = LSystem::parse(&sp.lsystem)?;
            let turtle = Turtle::new(&lsys, TurtleParams::for_lsystem(&lsys))?;
            let base = prototypes.len() as u32;
            for (k, &r) in q.codebook.iter().enumerate() {
                let frac = f64::from(r) / sp.max_radius;
                let steps = ((f64::from(sp.max_steps) * frac).round() as u32).max(1);
                // Each prototype its own derivation seed: a stochastic
                // L-system grows another plant of the species for each.
                let variant = seed.derive_index(si as u64).derive_index(k as u64);
                let mut d = Derivation::new(&lsys, variant.0)?;
                d.derive(steps)?;
                let geometry = turtle.interpret(d.string())?;
                let geometry_radius = crown_radius(&geometry);
                prototypes.push(Prototype {
                    species: si as u16,
                    radius: r,
                    steps,
                    geometry,
                    geometry_radius,
                });
            }
            for (m, &i) in members.iter().enumerate() {
                proto_of[i] = base + q.index[m];
            }
        }
        let instances = plants
            .iter()
            .zip(&proto_of)
            .map(|(p, &k)| PlantInstance {
                species: p.species,
                prototype: k,
                position: Vec3::new(p.x, p.y, eco.ground(p)),
                scale: p.radius / prototypes[k as usize].geometry_radius,
                rotation: (seed.uniform(&[p.id as i64]) * std::f64::consts::TAU) as f32,
            })
            .collect();
        Ok(Self {
            prototypes,
            instances,
        })
    }

    /// Instances per prototype (the source's reduction factor in objects).
    #[must_use]
    pub fn reduction(&self) -> f64 {
        self.instances.len() as f64 / self.prototypes.len().max(1) as f64
    }

    /// Writes the instances as CSV: `species,prototype,x,y,z,scale,rotation`.
    ///
    /// # Errors
    ///
    /// [`PlantError::Core`] if the file cannot be written (it is written to a temporary name and renamed).
    pub fn write_csv(&self, path: impl AsRef<Path>) -> Result<()> {
        self.write_csv_impl(path.as_ref())
    }

    /// The body of [`Self::write_csv`]: not generic, so it is compiled once, here, and not again in
    /// every crate that calls it.
    fn write_csv_impl(&self, path: &Path) -> Result<()> {
        use std::io::Write;
        Ok(write_atomic(path, |w| {
            writeln!(w, "species,prototype,x,y,z,scale,rotation").map_err(WriteError::from)?;
            for i in &self.instances {
                writeln!(
                    w,
                    "{},{},{},{},{},{},{}",
                    i.species,
                    i.prototype,
                    i.position.x,
                    i.position.y,
                    i.position.z,
                    i.scale,
                    i.rotation
                )
                .map_err(WriteError::from)?;
            }
            Ok(())
        })?)
    }
}
