//! The error type of `natura-volume`.

use natura_core::CoreError;

/// Everything that can go wrong in `natura-volume`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VolumeError {
    /// A parameter is NaN, infinite or outside its valid range.
    #[error("invalid parameter `{name}` = {value}: {expected}")]
    InvalidParameter {
        /// The parameter's name as it appears in the API.
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// What a valid value is.
        expected: &'static str,
    },
    /// A bounding box is empty, inverted or not finite.
    #[error(
        "invalid bounds `{name}`: min {min:?}, max {max:?} (each min must be finite and below its max)"
    )]
    InvalidBounds {
        /// Which box.
        name: &'static str,
        /// Its minimum corner.
        min: [f32; 3],
        /// Its maximum corner.
        max: [f32; 3],
    },
    /// Two grids, or a grid and what it should match, disagree in size.
    #[error("size mismatch for `{name}`: expected {expected}, got {actual}")]
    SizeMismatch {
        /// What was being matched.
        name: &'static str,
        /// The size that was required.
        expected: String,
        /// The size that was given.
        actual: String,
    },
    /// A grid holds a NaN, infinite or negative density.
    #[error(
        "grid `{name}` holds {value} at voxel ({x}, {y}, {z}): densities must be finite and ≥ 0"
    )]
    BadVoxel {
        /// Which grid.
        name: &'static str,
        /// Voxel x.
        x: usize,
        /// Voxel y.
        y: usize,
        /// Voxel z.
        z: usize,
        /// The value found.
        value: f32,
    },
    /// A VDB file is corrupt, truncated or uses a feature this reader does not support.
    #[error("VDB: {0}")]
    Vdb(String),
    /// An error from `natura-core` (grid sizes, I/O, images).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// An error from `natura-noise` (noise parameters).
    #[error(transparent)]
    Noise(#[from] natura_noise::NoiseError),
    /// An error from `natura-atmos` (sky and sun).
    #[error(transparent)]
    Atmos(#[from] natura_atmos::AtmosError),
}

natura_core::from_param_error!(VolumeError::InvalidParameter, expected: expected);

/// Shorthand for `Result<T, VolumeError>`.
pub type Result<T, E = VolumeError> = std::result::Result<T, E>;

/// Checks an `f32` parameter is finite and `> 0`.
pub(crate) fn positive(name: &'static str, v: f32) -> Result<f32> {
    natura_core::check::positive(name, f64::from(v))?;
    Ok(v)
}

/// Checks an `f32` parameter is finite and `≥ 0`.
pub(crate) fn non_negative(name: &'static str, v: f32) -> Result<f32> {
    natura_core::check::non_negative(name, f64::from(v))?;
    Ok(v)
}

/// Checks an `f32` parameter is finite and in `[lo, hi]`.
pub(crate) fn in_range(
    name: &'static str,
    v: f32,
    lo: f32,
    hi: f32,
    expected: &'static str,
) -> Result<f32> {
    natura_core::check::in_range(name, f64::from(v), f64::from(lo), f64::from(hi), expected)?;
    Ok(v)
}

/// Checks every component of a vector is finite.
pub(crate) fn finite3(name: &'static str, v: glam::Vec3) -> Result<glam::Vec3> {
    natura_core::check::finite3(name, v.as_dvec3())?;
    Ok(v)
}
