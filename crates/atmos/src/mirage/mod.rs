//! Mirages: ray paths through air whose refractive index varies with height.
//!
//! * [`StratifiedAir`]: `n(z)` from a temperature profile through the
//!   Gladstone–Dale relation `n − 1 = K·ρ` with the ideal-gas density
//!   `ρ = pM/(RT)`; hot ground gives the **inferior** mirage, a warm layer
//!   aloft (inversion) the **superior** one.
//! * [`GrinTracer`]: the ray equation `d/ds(n dx/ds) = ∇n` integrated with an
//!   adaptive Dormand–Prince 5(4) Runge–Kutta scheme. In a smooth profile the
//!   turning point is smooth: the Khular/Fabri picture (Musgrave 1993, §4.3.2)
//!   is right for smooth profiles and Musgrave's kinked "reflected hyperbola"
//!   (Musgrave 1993, §4.3.2) only for a sharp interface, which is
//! * [`PlanarMirage`]: Musgrave's semi-physical model (Musgrave 1993, §1.2.4.4,
//!   Musgrave 1993, §4.3–4.3.3): one planar index discontinuity, optionally with a perturbed
//!   (fBm-bumped) normal, and total internal reflection for glancing rays
//!   going from higher to lower index. TIR rays are reflected, never dropped
//!   (Musgrave 1993, §4.3.3).

//!
//! The files: [`air`] (the index of air from its temperature: the physics),
//! [`grin`] (the ray equation and its integrator) and [`planar`]
//! (Musgrave's planar interface).

pub mod air;
pub mod grin;
pub mod planar;

#[cfg(test)]
mod tests;

pub use air::{
    GAS_CONSTANT, GLADSTONE_DALE_AIR, GRAVITY, IndexField, MAX_TEMPERATURE_K, MOLAR_MASS_AIR,
    StratifiedAir, TemperatureProfile, UniformIndex,
};
pub use grin::{GrinTracer, MAX_GRIN_STEPS, PathEnd, RayPath, invariant_drift};
pub use planar::{Interaction, PlanarMirage};
