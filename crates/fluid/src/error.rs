//! The error type of `natura-fluid`.

use natura_core::CoreError;

/// Everything that can go wrong in `natura-fluid`.
///
/// Every variant says what was wrong and where, so that the message alone is
/// enough to find the problem.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FluidError {
    /// A grid was asked for with a zero or oversized dimension.
    #[error("invalid grid size {dims}: {reason}")]
    InvalidSize {
        /// The dimensions asked for, e.g. `"0 × 1 × 64"`.
        dims: String,
        /// What is wrong with them.
        reason: &'static str,
    },
    /// A parameter is NaN, infinite or out of its valid range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as it appears in the API.
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// The valid range.
        reason: &'static str,
    },
    /// A source, obstacle or sample lies (partly) outside the simulation grid.
    #[error("{what} lies outside the grid: {detail}")]
    OutsideGrid {
        /// What was placed (e.g. `"density source"`).
        what: &'static str,
        /// Where it was and what the grid covers.
        detail: String,
    },
    /// A field given by the caller does not match the grid.
    #[error("size mismatch for {what}: expected {expected}, got {actual}")]
    SizeMismatch {
        /// The field concerned.
        what: &'static str,
        /// Required size.
        expected: String,
        /// Given size.
        actual: String,
    },
    /// A step produced a NaN or infinite value: the simulation stops instead
    /// of silently propagating it.
    #[error("non-finite value {value} in `{field}` at index ({}, {}, {}) after {stage}", index[0], index[1], index[2])]
    NonFinite {
        /// The field (`"u"`, `"density"`, `"phi"`, …).
        field: &'static str,
        /// Sample index `(i, j, k)` within that field's own grid.
        index: [usize; 3],
        /// The value found.
        value: f32,
        /// The stage of the step that produced it.
        stage: &'static str,
    },
    /// The requested combination of options is not supported (for example an
    /// FFT solver on a domain with walls).
    #[error("unsupported configuration: {0}")]
    Unsupported(String),
    /// An error from `natura-core` (file I/O, image encoding, grid allocation).
    #[error(transparent)]
    Core(#[from] CoreError),
}

/// Shorthand for `Result<T, FluidError>`.
pub type Result<T, E = FluidError> = std::result::Result<T, E>;

natura_core::from_param_error!(FluidError::InvalidParameter, expected: reason);

/// `Ok(())` if `value` is finite and `> 0`, else [`FluidError::InvalidParameter`].
pub(crate) fn positive(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(FluidError::InvalidParameter {
            name,
            value: format!("{value}"),
            reason: "must be finite and > 0",
        })
    }
}

/// `Ok(())` if `value` is finite and `>= 0`, else [`FluidError::InvalidParameter`].
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(FluidError::InvalidParameter {
            name,
            value: format!("{value}"),
            reason: "must be finite and >= 0",
        })
    }
}

/// `Ok(())` if `value` is finite, else [`FluidError::InvalidParameter`].
pub(crate) fn finite(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(FluidError::InvalidParameter {
            name,
            value: format!("{value}"),
            reason: "must be finite",
        })
    }
}

/// Checks a time step: finite and `> 0`.
pub(crate) fn check_dt(dt: f32) -> Result<()> {
    positive("dt", f64::from(dt))
}
