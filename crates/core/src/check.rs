//! Parameter checks shared by the natura crates: one function per concept.
//!
//! Each check returns the value on success, so it can be used inline, and a
//! [`ParamError`] naming the parameter, its value and what was expected on
//! failure. Every natura crate's error enum converts a [`ParamError`] into its
//! own `InvalidParameter` variant (`From`), so a model writes
//! `check::positive("cell_size", c)?` whatever its error type.
//!
//! ```
//! use natura_core::check;
//! assert_eq!(check::positive("cell_size", 2.5), Ok(2.5));
//! let e = check::in_range("gain", f64::NAN, 0.0, 1.0, "must lie in [0, 1]").unwrap_err();
//! assert_eq!(e.to_string(), "invalid parameter `gain` = NaN: must lie in [0, 1]");
//! ```

use glam::DVec3;

/// A parameter that is NaN, infinite or outside its valid range.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("invalid parameter `{name}` = {value}: {expected}")]
pub struct ParamError {
    /// The parameter's name as it appears in the API (or scene file).
    pub name: &'static str,
    /// The offending value, formatted.
    pub value: String,
    /// What a valid value is.
    pub expected: &'static str,
}

impl ParamError {
    /// Returns the error for parameter `name` with value `value`, which should
    /// have been `expected`.
    #[must_use]
    pub fn new(name: &'static str, value: impl std::fmt::Display, expected: &'static str) -> Self {
        Self {
            name,
            value: value.to_string(),
            expected,
        }
    }
}

/// Shorthand for the result of a check.
pub type Checked<T> = Result<T, ParamError>;

/// Returns `v` if it is finite.
///
/// # Errors
///
/// Returns a [`ParamError`] naming `name` if `v` is NaN or infinite.
#[inline]
pub fn finite(name: &'static str, v: f64) -> Checked<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ParamError::new(name, v, "must be finite"))
    }
}

/// Returns `v` if it is finite and `> 0`.
///
/// # Errors
///
/// Returns a [`ParamError`] naming `name` if `v` is NaN, infinite, zero or negative.
#[inline]
pub fn positive(name: &'static str, v: f64) -> Checked<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(ParamError::new(name, v, "must be finite and > 0"))
    }
}

/// Returns `v` if it is finite and `≥ 0`.
///
/// # Errors
///
/// Returns a [`ParamError`] naming `name` if `v` is NaN, infinite or negative.
#[inline]
pub fn non_negative(name: &'static str, v: f64) -> Checked<f64> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(ParamError::new(name, v, "must be finite and ≥ 0"))
    }
}

/// Returns `v` if it is finite and lies in the closed interval `[lo, hi]`;
/// `expected` says so in words (e.g. `"must lie in [0, 1]"`).
///
/// # Errors
///
/// Returns a [`ParamError`] naming `name` with `expected` if `v` is NaN,
/// infinite or outside `[lo, hi]`.
#[inline]
pub fn in_range(
    name: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Checked<f64> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(ParamError::new(name, v, expected))
    }
}

/// Returns `n` if it lies in `lo..=hi`; `expected` says so in words.
///
/// # Errors
///
/// Returns a [`ParamError`] naming `name` with `expected` if `n` is outside
/// `lo..=hi`.
#[inline]
pub fn count(
    name: &'static str,
    n: usize,
    lo: usize,
    hi: usize,
    expected: &'static str,
) -> Checked<usize> {
    if (lo..=hi).contains(&n) {
        Ok(n)
    } else {
        Err(ParamError::new(name, n, expected))
    }
}

/// Returns `v` if every component is finite.
///
/// # Errors
///
/// Returns a [`ParamError`] naming `name` if a component is NaN or infinite.
#[inline]
pub fn finite3(name: &'static str, v: DVec3) -> Checked<DVec3> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ParamError::new(name, v, "must be finite"))
    }
}

/// Returns `v` if every component is finite and `≥ 0`.
///
/// # Errors
///
/// Returns a [`ParamError`] naming `name` if a component is NaN, infinite or negative.
#[inline]
pub fn non_negative3(name: &'static str, v: DVec3) -> Checked<DVec3> {
    if v.is_finite() && v.min_element() >= 0.0 {
        Ok(v)
    } else {
        Err(ParamError::new(
            name,
            v,
            "every component must be finite and ≥ 0",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_check_accepts_its_domain_and_names_the_parameter() {
        assert_eq!(finite("a", -3.0), Ok(-3.0));
        assert!(finite("a", f64::INFINITY).is_err());
        assert_eq!(positive("b", 1e-300), Ok(1e-300));
        for v in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(positive("b", v).unwrap_err().name, "b");
        }
        assert_eq!(non_negative("c", 0.0), Ok(0.0));
        assert!(non_negative("c", -0.1).is_err());
        assert!(non_negative("c", f64::NAN).is_err());
        assert_eq!(in_range("d", 1.0, 0.0, 1.0, "in [0, 1]"), Ok(1.0));
        assert!(in_range("d", 1.0 + 1e-12, 0.0, 1.0, "in [0, 1]").is_err());
        assert!(in_range("d", f64::NAN, f64::NEG_INFINITY, f64::INFINITY, "x").is_err());
        assert_eq!(count("n", 3, 1, 3, "1..=3"), Ok(3));
        assert!(count("n", 0, 1, 3, "1..=3").is_err());
        assert!(finite3("v", DVec3::new(0.0, f64::NAN, 0.0)).is_err());
        assert!(non_negative3("w", DVec3::new(0.0, -1.0, 0.0)).is_err());
        let e = non_negative3("w", DVec3::new(1.0, 2.0, f64::INFINITY)).unwrap_err();
        assert!(e.to_string().starts_with("invalid parameter `w`"), "{e}");
    }
}
