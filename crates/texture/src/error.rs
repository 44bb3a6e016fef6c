//! The error type of `natura-texture`.

use natura_atmos::AtmosError;
use natura_core::CoreError;
use natura_noise::NoiseError;

/// Everything that can go wrong in `natura-texture`.
///
/// Each variant names the offending parameter and value, so the message
/// alone is enough to find the problem. Evaluating a texture never fails:
/// parameters are checked when a texture or planet is built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TextureError {
    /// A parameter is NaN, infinite or outside its valid range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as it appears in the params struct.
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// What the parameter must satisfy.
        reason: &'static str,
    },
    /// A size (face, image, map) is zero or needs more memory than the cap.
    #[error("invalid size `{name}` = {value}: {reason}")]
    InvalidSize {
        /// Which size.
        name: &'static str,
        /// The size given.
        value: usize,
        /// Why it was refused.
        reason: String,
    },
    /// A parameter of a noise basis or fractal (from natura-noise).
    #[error(transparent)]
    Noise(#[from] NoiseError),
    /// A parameter of the atmosphere (from natura-atmos).
    #[error(transparent)]
    Atmos(#[from] AtmosError),
    /// An I/O, image or allocation error, or a camera parameter (from
    /// natura-core).
    #[error(transparent)]
    Core(#[from] CoreError),
}

/// Shorthand for `Result<T, TextureError>`.
pub type Result<T, E = TextureError> = std::result::Result<T, E>;

/// Builds a [`TextureError::InvalidParameter`].
pub(crate) fn invalid(
    name: &'static str,
    value: impl std::fmt::Display,
    reason: &'static str,
) -> TextureError {
    TextureError::InvalidParameter {
        name,
        value: value.to_string(),
        reason,
    }
}

pub(crate) use natura_core::check::{finite, in_range, non_negative, positive};

natura_core::from_param_error!(TextureError::InvalidParameter, expected: reason);

/// Returns `Ok(c)` if every channel of the colour `c` is in `[0, 1]`.
pub(crate) fn colour(name: &'static str, c: glam::DVec3) -> Result<glam::DVec3> {
    if c.cmpge(glam::DVec3::ZERO).all() && c.cmple(glam::DVec3::ONE).all() {
        Ok(c)
    } else {
        Err(invalid(name, c, "each channel must be in [0, 1]"))
    }
}

/// Returns `Ok(v)` if the vector is finite and non-zero.
pub(crate) fn direction(name: &'static str, v: glam::DVec3) -> Result<glam::DVec3> {
    if v.is_finite() && v.length_squared() > 0.0 {
        Ok(v)
    } else {
        Err(invalid(name, v, "must be finite and non-zero"))
    }
}
