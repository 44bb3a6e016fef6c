//! The error type of `natura-trace`.

use natura_core::CoreError;

/// Everything that can go wrong when building a tracer, a camera or an image.
///
/// Tracing itself never fails: a ray that cannot hit anything (a NaN or zero
/// direction, an empty `t` range) simply returns no hit.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TraceError {
    /// An error from natura-core (a grid size, a file, a non-finite height).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The height field cannot be traced: it has too few samples to form a
    /// cell, too many along an axis for exact grid arithmetic, or a NaN or
    /// infinite height.
    #[error("height field {nx} × {ny} cannot be traced: {reason}")]
    Field {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
        /// What is wrong, including the first bad cell where there is one.
        reason: String,
    },
    /// A camera or rendering parameter is NaN, infinite or out of range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as it appears in the API.
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// What the valid range is.
        reason: &'static str,
    },
}

impl TraceError {
    pub(crate) fn param(
        name: &'static str,
        value: impl std::fmt::Display,
        reason: &'static str,
    ) -> Self {
        TraceError::InvalidParameter {
            name,
            value: value.to_string(),
            reason,
        }
    }
}

/// Shorthand for `Result<T, TraceError>`.
pub type Result<T, E = TraceError> = std::result::Result<T, E>;

natura_core::from_param_error!(TraceError::InvalidParameter, expected: reason);
