//! # natura-fluid
//!
//! Stable fluids, smoke with vorticity confinement, and liquids — the three
//! fluid papers reprinted in the SIGGRAPH 2001 Course 47 notes: Stam's *Stable
//! Fluids* (Stam 1999), Fedkiw, Stam & Jensen's *Visual Simulation of Smoke*
//! (Fedkiw et al. 2001) and Foster & Fedkiw's *Practical Animation of Liquids*
//! (Foster & Fedkiw 2001), with their errata corrected (each
//! stated where it is fixed; bibliography in `docs/sources.md`).
//!
//! | module | what |
//! |---|---|
//! | [`stable`] | [`stable::PeriodicFluid`] (FFT, collocated) and [`stable::BoundedFluid`] (MAC, walls, obstacles), substances |
//! | [`smoke`] | [`smoke::Smoke`]: buoyancy, vorticity confinement, obstacles, sources |
//! | [`plume`] | [`plume::Plume`]: a preset, smoke rising past a sphere (the `smoke3d` example's) |
//! | [`liquid`] | [`liquid::Liquid`]: level set + marker particles, free surface, objects, gravity |
//! | [`pressure`] | MG-PCG, MIC(0)-PCG and the Gauss–Seidel baseline for `−h²∇²p = b` |
//! | [`fft`] | periodic FFT diffusion/projection and Poisson solves |
//! | [`advect`] | semi-Lagrangian, MacCormack and BFECC advection with solid clipping |
//! | [`interp`] | linear and monotone cubic (Fritsch–Carlson) interpolation |
//! | [`mac`] | MAC divergence, projection, forces, vorticity, confinement |
//! | [`levelset`] | upwind advection, reinitialisation, curvature |
//! | [`shape`], [`grid`], [`export`] | obstacles and regions, grid types, pictures and volume files |
//!
//! Conventions: z up, metres, seconds; a 2-D simulation is a grid with
//! `ny = 1` in the vertical x–z plane. Fields are `f32`; pressure solves keep
//! their iterate in `f64`. Results are bit-identical for any thread count.
//!
//! ```
//! use natura_fluid::grid::Dims;
//! use natura_fluid::shape::Shape;
//! use natura_fluid::smoke::{Smoke, SmokeParams, SmokeSource};
//! use natura_fluid::glam::Vec3;
//! let mut smoke = Smoke::new(Dims::plane(32, 64)?, 0.02, SmokeParams::default())?;
//! smoke.add_source(SmokeSource {
//!     shape: Shape::Sphere { centre: Vec3::new(0.32, 0.01, 0.2), radius: 0.08 },
//!     density: 1.0,
//!     temperature: 330.0,
//!     velocity: None,
//! })?;
//! let report = smoke.step(0.02)?;
//! assert!(report.pressure.unwrap().converged);
//! # Ok::<(), natura_fluid::FluidError>(())
//! ```
#![forbid(unsafe_code)]
// Loops over axes and cells index several parallel arrays at once, as the
// equations do; iterator chains would hide that.
#![allow(clippy::needless_range_loop)]

pub mod advect;
mod advect_linear;
mod chunks;
mod error;
pub mod grid;
pub mod interp;
pub mod pressure;

pub use error::{FluidError, Result};
/// The vector types of the API, so users need no `glam` dependency of their own.
pub use glam;
mod diffuse;
pub mod export;
pub mod fft;
pub mod levelset;
pub mod liquid;
pub mod mac;
pub mod plume;
pub mod shape;
pub mod smoke;
pub mod stable;

#[cfg(test)]
mod tests;
