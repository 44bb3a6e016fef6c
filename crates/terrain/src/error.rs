//! The error type of `natura-terrain`.

use natura_core::CoreError;

/// Everything that can go wrong in `natura-terrain`.
///
/// Every variant names what was wrong and where: the parameter and its valid
/// range, the first non-finite cell, or the size a method needs.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TerrainError {
    /// An error from `natura-core` (grid construction, file I/O, a non-finite
    /// height naming its cell, …).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// An error from `natura-noise` (invalid fractal parameters, lattice sizes, …).
    #[error(transparent)]
    Noise(#[from] natura_noise::NoiseError),
    /// A parameter is NaN, infinite or outside its physical range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as it appears in the API (`ThermalParams::talus_angle`, …).
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// The valid range, in words.
        reason: String,
    },
    /// A grid is too small (or of the wrong shape) for the method asked for.
    #[error("{method} needs {needs}; got {nx} × {ny}")]
    BadSize {
        /// The method that refused the size.
        method: &'static str,
        /// What it needs, in words (`"at least 3 × 3 samples"`).
        needs: String,
        /// Samples along x given.
        nx: usize,
        /// Samples along y given.
        ny: usize,
    },
    /// Two inputs that must agree in size do not.
    #[error("size mismatch: {what} is {actual}, expected {expected}")]
    SizeMismatch {
        /// What disagreed (`"hardness map"`).
        what: &'static str,
        /// The size required.
        expected: String,
        /// The size given.
        actual: String,
    },
    /// A grid or mesh holds a NaN or infinite value at the named cell.
    #[error("non-finite value {value} in {what} at cell ({x}, {y})")]
    NonFinite {
        /// Which grid (`"water"`, `"sediment"`, `"hardness"`).
        what: &'static str,
        /// Column of the first bad cell.
        x: usize,
        /// Row of the first bad cell.
        y: usize,
        /// The value found there.
        value: f32,
    },
}

/// Shorthand for `Result<T, TerrainError>`.
pub type Result<T, E = TerrainError> = std::result::Result<T, E>;

natura_core::from_param_error!(TerrainError::InvalidParameter, expected: reason);

/// Builds an [`TerrainError::InvalidParameter`].
pub(crate) fn invalid(
    name: &'static str,
    value: impl std::fmt::Display,
    reason: impl Into<String>,
) -> TerrainError {
    TerrainError::InvalidParameter {
        name,
        value: value.to_string(),
        reason: reason.into(),
    }
}

/// Checks that `v` is finite and `>= 0`.
pub(crate) fn non_negative(name: &'static str, v: f64) -> Result<()> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(invalid(name, v, "must be finite and >= 0"))
    }
}

/// Checks that `v` is finite and `> 0`.
pub(crate) fn positive(name: &'static str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid(name, v, "must be finite and > 0"))
    }
}

/// Checks that `v` lies in the closed interval `[lo, hi]` (and is not NaN).
pub(crate) fn in_range(name: &'static str, v: f64, lo: f64, hi: f64) -> Result<()> {
    if v >= lo && v <= hi {
        Ok(())
    } else {
        Err(invalid(name, v, format!("must lie in [{lo}, {hi}]")))
    }
}

/// Checks a grid of `f32` for NaN or infinity, naming the first bad cell.
pub(crate) fn check_grid(what: &'static str, g: &natura_core::Grid2<f32>) -> Result<()> {
    match g.find(|v| !v.is_finite()) {
        Some((x, y, &value)) => Err(TerrainError::NonFinite { what, x, y, value }),
        None => Ok(()),
    }
}

/// Refuses grids smaller than `min_x × min_y`.
pub(crate) fn min_size(
    method: &'static str,
    nx: usize,
    ny: usize,
    min_x: usize,
    min_y: usize,
) -> Result<()> {
    if nx >= min_x && ny >= min_y {
        Ok(())
    } else {
        Err(TerrainError::BadSize {
            method,
            needs: format!("at least {min_x} × {min_y} samples"),
            nx,
            ny,
        })
    }
}

/// Refuses a grid whose size differs from `(nx, ny)`.
pub(crate) fn same_size(
    what: &'static str,
    g: &natura_core::Grid2<f32>,
    nx: usize,
    ny: usize,
) -> Result<()> {
    if g.dims() == (nx, ny) {
        Ok(())
    } else {
        Err(TerrainError::SizeMismatch {
            what,
            expected: format!("{nx} × {ny}"),
            actual: format!("{} × {}", g.width(), g.height()),
        })
    }
}
