//! # natura-core
//!
//! The shared foundation of the natura crates: dense grids ([`Grid2`],
//! [`Grid3`]) with checked construction and interpolation, [`HeightField`]
//! with PNG/EXR/raw input and output, linear colour and [`Image`]s, seeds
//! and position-indexed random numbers ([`Seed`]), [`Progress`] reporting,
//! crash-safe file writing ([`io::write_atomic`]), and the cameras every
//! renderer shares ([`camera`]: pinhole, orthographic and panoramic maps from
//! pixels to rays and back), the preview rasterizer every crate's small
//! pictures are drawn with ([`preview`]), and the pixel filter both resolve
//! their samples with ([`filter`]), and the planner of every crate's fast
//! Fourier transforms ([`fft`]).
//!
//! Conventions (shared by every natura crate): right-handed, **z up**,
//! metres, seconds, radians; `f32` for grids and images, `f64` where
//! precision matters. Library code returns [`CoreError`] instead of panicking
//! on user input.
//!
//! ```
//! use natura_core::{HeightField, Seed};
//! let seed = Seed(7).derive("demo");
//! let hf = HeightField::from_fn(64, 64, 10.0, |i, j| {
//!     100.0 * seed.gaussian2(i as i64 / 8, j as i64 / 8) as f32
//! })?;
//! assert_eq!(hf.extent().x, 630.0);
//! # Ok::<(), natura_core::CoreError>(())
//! ```
#![forbid(unsafe_code)]

pub mod camera;
pub mod check;
pub mod colour;
mod error;
pub mod fft;
pub mod filter;
mod grid2;
mod grid3;
mod heightfield;
mod image;
pub mod io;
pub mod preview;
mod progress;
mod sample;
mod seed;

pub use colour::{Ramp, ToneMap};
pub use error::{CoreError, Result};
pub use grid2::{Grid2, MAX_GRID_BYTES, checked_len};
pub use grid3::Grid3;
pub use heightfield::{Aabb, HeightField};
pub use image::Image;
pub use progress::{CountingProgress, NoProgress, Progress};
pub use sample::{Boundary, Interpolate, floor_f32, smoothstep};
pub use seed::{Seed, mix64, unit_f64};

/// Run-time SIMD levels and dispatch (re-export of `natura-simd`), so the
/// crates above core share one token type and one set of trampolines.
pub use natura_simd as simd;

/// Re-export of `glam`, so users need not pin the same version themselves.
pub use glam;
