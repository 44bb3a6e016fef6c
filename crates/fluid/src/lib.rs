//! # natura-fluid
//!
//! Stable fluids, smoke with vorticity confinement, and liquids.
#![forbid(unsafe_code)]

pub mod advect;
mod error;
pub mod grid;
pub mod interp;
mod par;
pub mod pressure;

pub use error::{FluidError, Result};
pub mod mac;
pub mod shape;
mod diffuse;
pub mod fft;
pub mod stable;
pub mod smoke;
pub mod export;
pub mod levelset;
pub mod liquid;

#[cfg(test)]
mod tests;
