//! # natura-plant
//!
//! Plants from L-systems, in the tradition of Prusinkiewicz & Lindenmayer's
//! *The Algorithmic Beauty of Plants* and the cpfg / L-Py modelling
//! languages: a text language for parametric, context-sensitive, stochastic
//! L-systems with decomposition and interpretation rules ([`lang`]); a
//! derivation engine over a struct-of-arrays module string ([`Derivation`]);
//! query modules and open L-systems that exchange data with an
//! [`Environment`] ([`open`]); and 3-D turtle interpretation into segments
//! chained as generalized cylinders, polygons and predefined surfaces
//! ([`turtle`]), with differential turtle geometry for curved limbs;
//! triangle meshes of that geometry with bark and leaf materials, exported
//! as glTF 2.0 binary (with GPU instancing of many plants) or OBJ
//! ([`mesh`]); and pictures of meshes from a small software rasterizer
//! ([`preview`]).
//!
//! The source papers' models ([`models`]): the open L-system models of Měch &
//! Prusinkiewicz 1996 with their environments (Honda's branch tiers, a clonal
//! plant foraging over patches of light, roots growing in soil water in a
//! vertical section or in 3-D soil, deciduous crowns and conifers competing
//! for light, a climber on a tree),
//! collision-based phyllotaxis with its organ placement (Fowler et al. 1992)
//! and positional-information
//! algorithms (organ spacing, compound leaves, Ridley's packing and branch
//! mapping; Prusinkiewicz et al. 2001);
//! and plant ecosystems over a natura-terrain height field after Deussen et
//! al. 1998 ([`eco`]): species with site preferences, self-thinning between
//! circles of influence over many generations (parallel and deterministic),
//! and approximate instancing into a few prototypes per species.
//!
//! ```
//! use natura_plant::{Derivation, LSystem};
//! let l = LSystem::parse("axiom: A\nA -> AB\nB -> A")?;
//! let mut d = Derivation::new(&l, 1)?;
//! d.derive(5)?;
//! assert_eq!(d.string().display(l.symbols()), "ABAABABAABAAB");
//! # Ok::<(), natura_plant::PlantError>(())
//! ```
#![forbid(unsafe_code)]

pub mod engine;
mod error;
pub mod lang;
pub mod string;
pub mod symbols;

pub use engine::{Derivation, Limits};
pub use error::{PlantError, Result, Span};
pub use lang::LSystem;
pub use string::ModuleString;
pub use symbols::SymbolTable;
pub mod turtle;
pub use turtle::{Geometry, Turtle, TurtleParams, TurtleState};
pub mod open;
pub use open::{Environment, Message, Reply};
pub mod eco;
pub mod mesh;
pub mod models;
pub use mesh::{Material, MeshParams, PlantMesh};

/// The vector types of the API, so users need no `glam` dependency of their own.
pub use glam;
/// The mesh writers: binary glTF (one plant, or many as GPU instances) and OBJ.
pub use mesh::{Instance, save_glb, save_glb_instanced, save_obj};
pub mod preview;
