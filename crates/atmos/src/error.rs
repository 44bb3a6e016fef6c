//! The error type of `natura-atmos`.

/// Everything that can go wrong in `natura-atmos`.
///
/// Every variant names the offending parameter or input and says what the
/// valid range is, so a message shown to a user is enough to fix the call.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AtmosError {
    /// A parameter is NaN, infinite or outside its valid range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as it appears in the API.
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// What the valid range is.
        reason: &'static str,
    },
    /// A direction vector is zero, NaN or infinite, so it cannot be normalised.
    #[error("direction `{name}` = {value} cannot be normalised (zero, NaN or infinite)")]
    BadDirection {
        /// The argument's name.
        name: &'static str,
        /// The offending vector, formatted.
        value: String,
    },
    /// A wavelength lies outside the range a table or model covers.
    #[error("wavelength {nm} nm is outside {min}–{max} nm")]
    WavelengthOutOfRange {
        /// The wavelength asked for, nm.
        nm: f64,
        /// The smallest supported wavelength, nm.
        min: f64,
        /// The largest supported wavelength, nm.
        max: f64,
    },
    /// A fit or iteration did not converge.
    #[error("{what} did not converge: {detail}")]
    NoConvergence {
        /// What was being solved.
        what: &'static str,
        /// Details (residual, iterations).
        detail: String,
    },
    /// An error from natura-core (grid allocation, image writing).
    #[error(transparent)]
    Core(#[from] natura_core::CoreError),
}

/// Shorthand for `Result<T, AtmosError>`.
pub type Result<T, E = AtmosError> = std::result::Result<T, E>;

natura_core::from_param_error!(AtmosError::InvalidParameter, expected: reason);

/// An [`AtmosError::InvalidParameter`].
pub(crate) fn invalid(
    name: &'static str,
    v: impl std::fmt::Display,
    reason: &'static str,
) -> AtmosError {
    AtmosError::InvalidParameter {
        name,
        value: format!("{v}"),
        reason,
    }
}

/// The shared parameter checks (their errors convert into [`AtmosError::InvalidParameter`]).
pub(crate) use natura_core::check::{
    finite, finite3, in_range, non_negative, non_negative3, positive,
};
