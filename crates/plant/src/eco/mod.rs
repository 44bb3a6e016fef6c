//! Plant ecosystems over a terrain (Deussen et al. 1998).
//!
//! The pipeline of Deussen et al. 1998, Fig. 1, from terrain to instances:
//!
//! 1. [`Site`]: the terrain's altitude, slope, wetness and light (§4.2, with
//!    natura-terrain's drainage analysis standing in for TerEdit's rain-water
//!    flow).
//! 2. [`Ecosystem`]: the individual-based population simulation of §4.3 —
//!    species with the source's five parameters, seeding, growth, old age and
//!    self-thinning between circles of influence, over many generations;
//!    deterministic and parallel through a spatial grid.
//! 3. [`Instancing`]: approximate instancing (§5) — per species a few
//!    prototypes, found by weighted variance-based [`quantize`]ation of the
//!    plants' sizes and grown from the species' L-system, stand for every
//!    plant; the output is an instance list (species, prototype, position,
//!    scale, rotation) plus the prototypes' turtle geometry.
//!
//! [`catalogue`] holds ready-made species at landscape scale (the conifers
//! spruce and pine, the broad-leaved beech, the shrub juniper and the ground
//! cover heather), each with its stochastic L-system and the colours of its
//! bark and leaves through the seasons.
//!
//! ```
//! use natura_core::HeightField;
//! use natura_plant::eco::{EcoParams, Ecosystem, Instancing};
//! let hf = HeightField::from_fn(33, 33, 2.0, |i, j| (i + j) as f32 * 0.2)?;
//! let mut eco = Ecosystem::new(&hf, EcoParams { steps: 3, ..EcoParams::default() })?;
//! eco.run(&natura_core::NoProgress)?;
//! let inst = Instancing::new(&eco, 3)?;
//! assert_eq!(inst.instances.len(), eco.plants().len());
//! # Ok::<(), natura_plant::PlantError>(())
//! ```

pub mod catalogue;
mod in_order;
mod instance;
mod picture;
mod quantize;
mod sim;
mod site;
mod species;

pub use instance::{Instancing, PlantInstance, Prototype};
pub use picture::{species_colour, top_view};
pub use quantize::{Quantization, quantize};
pub use sim::{EcoParams, Ecosystem, MAX_GRID_CELLS, MAX_SEEDS_PER_SPECIES, Plant, StepStats};
pub use site::Site;
pub use species::{MAX_PER_HA, MAX_RADIUS_M, MIN_RADIUS_M, Species};

#[cfg(test)]
mod tests;
