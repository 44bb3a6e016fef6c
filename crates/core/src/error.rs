//! The error type of `natura-core`.

use std::path::PathBuf;

/// Everything that can go wrong in `natura-core`.
///
/// Every variant names what was asked for and where, so that a message shown
/// to a user is enough to find the problem without a debugger.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CoreError {
    /// A grid or image was asked for with a zero dimension.
    #[error("a zero dimension was asked for: {dims}")]
    ZeroDimension {
        /// The dimensions asked for, e.g. `"0 × 512"`.
        dims: String,
    },
    /// A grid or image was asked for whose byte count overflows or exceeds the cap.
    #[error("size {dims} needs {bytes} bytes, over the cap of {cap} bytes")]
    TooLarge {
        /// The dimensions asked for.
        dims: String,
        /// The byte count asked for (`u128` so that overflowing products are still exact).
        bytes: u128,
        /// The cap in force ([`crate::MAX_GRID_BYTES`]).
        cap: u64,
    },
    /// Two grids or a grid and a buffer disagree in size.
    #[error("size mismatch: expected {expected}, got {actual}")]
    SizeMismatch {
        /// The size that was required.
        expected: String,
        /// The size that was given.
        actual: String,
    },
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
    /// A height field or grid holds a NaN or infinite value.
    #[error("non-finite value {value} at cell ({x}, {y})")]
    NonFinite {
        /// Column of the first bad cell.
        x: usize,
        /// Row of the first bad cell.
        y: usize,
        /// The value found there.
        value: f32,
    },
    /// The operating system refused a read or write.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A file could be read but its contents are not what was expected
    /// (corrupt, truncated, wrong size or wrong format).
    #[error("{}: {problem}", path.display())]
    Format {
        /// The file concerned.
        path: PathBuf,
        /// What is wrong with it.
        problem: String,
    },
}

impl CoreError {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        CoreError::Io {
            path: path.into(),
            source,
        }
    }

    pub(crate) fn format(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        CoreError::Format {
            path: path.into(),
            problem: problem.into(),
        }
    }
}

/// Shorthand for `Result<T, CoreError>`.
pub type Result<T, E = CoreError> = std::result::Result<T, E>;

crate::from_param_error!(CoreError::InvalidParameter, expected: reason);

/// Writes the conversion from a failed parameter check
/// ([`ParamError`](crate::check::ParamError)) into a crate's own error enum,
/// so that `check::positive("cell_size", c)?` works whatever the error type.
///
/// `from_param_error!(MyError::Variant, expected: field)` fills the struct
/// variant's `name` and `value` from the check's, and its `field` from what
/// the check expected; each through `Into`, so the variant may hold
/// `&'static str` or `String`. An optional `value: f` passes the formatted
/// value through `f(&String) -> String` first (to shorten it, say).
///
/// ```
/// #[derive(Debug)]
/// pub enum MyError {
///     Invalid { name: String, value: String, reason: String },
/// }
/// natura_core::from_param_error!(MyError::Invalid, expected: reason);
///
/// fn gain(g: f64) -> Result<f64, MyError> {
///     Ok(natura_core::check::positive("gain", g)?)
/// }
/// let MyError::Invalid { name, reason, .. } = gain(-1.0).unwrap_err();
/// assert_eq!((name.as_str(), reason.as_str()), ("gain", "must be finite and > 0"));
/// ```
#[macro_export]
macro_rules! from_param_error {
    ($error:ident :: $variant:ident, expected: $field:ident $(, value: $map:expr)? $(,)?) => {
        impl ::core::convert::From<$crate::check::ParamError> for $error {
            fn from(e: $crate::check::ParamError) -> Self {
                let value = e.value;
                $(let value = ($map)(&value);)?
                $error::$variant {
                    name: ::core::convert::Into::into(e.name),
                    value: ::core::convert::Into::into(value),
                    $field: ::core::convert::Into::into(e.expected),
                }
            }
        }
    };
}
