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
mod diffuse;
pub mod export;
pub mod fft;
pub mod levelset;
pub mod liquid;
pub mod mac;
pub mod shape;
pub mod smoke;
pub mod stable;

#[cfg(test)]
mod tests;
