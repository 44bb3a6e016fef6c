//! # natura-atmos
//!
//! Aerial perspective, sky, spectral colour, rainbow and mirage.
#![forbid(unsafe_code)]

mod dir;
mod error;
pub mod medium;
pub mod mirage;
pub mod optics;
pub mod rainbow;
pub mod scatter;
pub mod sky;
pub mod special;
pub mod spectrum;

pub use dir::Dir3;
pub use error::{AtmosError, Result};
pub use medium::{Attenuation, Medium};
