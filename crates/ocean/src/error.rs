//! The error type of `natura-ocean`.

use natura_core::CoreError;

/// Everything that can go wrong in `natura-ocean`.
///
/// Each variant names the offending parameter or value, so the message alone
/// is enough to find the problem.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OceanError {
    /// A parameter is NaN, infinite or outside its valid range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as it appears in the API.
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// The valid range.
        reason: &'static str,
    },
    /// A grid size the FFT plan cannot use (zero, not a power of two, or out of range).
    #[error("invalid grid size `{name}` = {value}: must be a power of two from 16 to 2048")]
    InvalidSize {
        /// Which size (`nx` or `ny`).
        name: &'static str,
        /// The size given.
        value: usize,
    },
    /// A spectrum returned a negative or non-finite density.
    #[error(
        "spectrum returned {value} at k = ({kx}, {ky}) rad/m; densities must be finite and ≥ 0"
    )]
    BadSpectrum {
        /// Wave-vector x component, rad/m.
        kx: f64,
        /// Wave-vector y component, rad/m.
        ky: f64,
        /// The value returned.
        value: f64,
    },
    /// A wave of a Gerstner sum is too steep (kA ≥ 1 makes its crest loop over itself).
    #[error(
        "Gerstner wave {index} has steepness kA = {steepness}; kA must be < 1 (notes eq. 9-11)"
    )]
    TooSteep {
        /// Index of the wave in the list given.
        index: usize,
        /// Its steepness k·A.
        steepness: f64,
    },
    /// Two objects that must agree in size do not (e.g. a frame from another ocean).
    #[error("size mismatch: expected {expected}, got {actual}")]
    SizeMismatch {
        /// The size that was required.
        expected: String,
        /// The size that was given.
        actual: String,
    },
    /// An error from natura-core (I/O, grid allocation, EXR encoding).
    #[error(transparent)]
    Core(#[from] CoreError),
}

/// Shorthand for `Result<T, OceanError>`.
pub type Result<T, E = OceanError> = std::result::Result<T, E>;

natura_core::from_param_error!(OceanError::InvalidParameter, expected: reason);

/// Builds an [`OceanError::InvalidParameter`].
pub(crate) fn invalid(
    name: &'static str,
    v: impl std::fmt::Display,
    reason: &'static str,
) -> OceanError {
    OceanError::InvalidParameter {
        name,
        value: v.to_string(),
        reason,
    }
}

/// The shared parameter checks (their errors convert into [`OceanError::InvalidParameter`]).
pub(crate) use natura_core::check::{finite, in_range, non_negative, positive};
