//! The crate's error type.

use thiserror::Error;

/// Everything that can go wrong in natura-noise: a parameter out of its domain,
/// or a batch buffer whose length does not match the lattice it is to hold.
///
/// Every variant names the offending parameter and value, so a message such as
/// ``lacunarity = 1 is invalid: must be finite and > 1`` tells the caller what
/// to fix. Evaluation itself never fails: NaN coordinates give NaN values.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum NoiseError {
    /// A scalar parameter is NaN, infinite or outside its domain.
    #[error("{name} = {value} is invalid: {expected}")]
    InvalidParam {
        /// The parameter's name as it appears in the params struct.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// What the parameter must satisfy.
        expected: &'static str,
    },
    /// The octave count asks for frequencies beyond what `f64` coordinates resolve.
    #[error(
        "octaves = {octaves} with lacunarity {lacunarity} reaches frequency {top_frequency:e} \
         × the base frequency, beyond the precision limit 2^32 (at most {max_octaves} octaves)"
    )]
    OctavesBeyondPrecision {
        /// The requested octave count.
        octaves: f64,
        /// The lacunarity it was combined with.
        lacunarity: f64,
        /// The highest octave's frequency relative to the first.
        top_frequency: f64,
        /// The largest octave count this lacunarity allows.
        max_octaves: f64,
    },
    /// A batch output buffer does not have the length its lattice needs.
    #[error("output buffer holds {got} values but the lattice has {expected} points")]
    BufferLength {
        /// Points in the lattice.
        expected: usize,
        /// Length of the buffer given.
        got: usize,
    },
    /// The parameters would let the field's values overflow: its bound on
    /// `|f|` is infinite or beyond [`MAX_BOUND`](crate::MAX_BOUND), where `f32`
    /// results stop being safe.
    #[error(
        "{field}: the parameters give values up to {bound:e}, beyond the limit {limit:e}; \
         reduce the offset, gain or the octave amplitudes"
    )]
    Unbounded {
        /// The field type.
        field: &'static str,
        /// Its bound on `|f|` with these parameters.
        bound: f64,
        /// The largest bound accepted ([`MAX_BOUND`](crate::MAX_BOUND)).
        limit: f64,
    },
    /// A lattice has a zero or overflowing point count, or a non-finite origin or step.
    #[error("invalid lattice: {what}")]
    InvalidLattice {
        /// What is wrong with it.
        what: &'static str,
    },
}

/// Shorthand for `Result<T, NoiseError>`.
pub type Result<T, E = NoiseError> = core::result::Result<T, E>;

/// Checks a shape parameter of moderate size (an offset, a gain): finite with
/// magnitude at most 1000.
pub(crate) fn moderate(name: &'static str, value: f64) -> Result<()> {
    magnitude(name, value, 1e3, "must be finite with magnitude ≤ 1000")
}

/// Checks that `value` is finite and at most `max` in magnitude.
pub(crate) fn magnitude(
    name: &'static str,
    value: f64,
    max: f64,
    expected: &'static str,
) -> Result<()> {
    if value.is_finite() && value.abs() <= max {
        Ok(())
    } else {
        Err(NoiseError::InvalidParam {
            name,
            value,
            expected,
        })
    }
}

/// Checks that a field's bound on `|f|` is finite and at most [`MAX_BOUND`](crate::MAX_BOUND).
pub(crate) fn bounded(field: &'static str, bound: f64) -> Result<()> {
    if bound.is_finite() && bound <= crate::MAX_BOUND {
        Ok(())
    } else {
        Err(NoiseError::Unbounded {
            field,
            bound,
            limit: crate::MAX_BOUND,
        })
    }
}

/// Checks that `value` is finite, naming it `name` in the error.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(NoiseError::InvalidParam {
            name,
            value,
            expected: "must be finite",
        })
    }
}

/// Checks `lo <= value <= hi` (which also rejects NaN).
pub(crate) fn in_range(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<()> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err(NoiseError::InvalidParam {
            name,
            value,
            expected,
        })
    }
}
