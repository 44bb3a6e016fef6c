//! Raw and EXR slices of voxel grids (the OpenVDB export is in [`crate::vdb`]).

use std::path::Path;

use glam::Vec3;
use natura_core::{Grid2, Image};

use crate::error::{Result, VolumeError};
use crate::grid::GridDensity;

/// The voxels as raw little-endian `f32`, `x` fastest, then `y`, then `z`
/// (the layout of `natura_core::Grid3`), through a temporary name and a rename.
///
/// # Errors
///
/// [`VolumeError::Core`] for an I/O failure.
pub fn write_raw(path: impl AsRef<Path>, grid: &GridDensity) -> Result<()> {
    let bytes: Vec<u8> = grid
        .grid()
        .as_slice()
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    natura_core::io::write_bytes_atomic(path, &bytes)?;
    Ok(())
}

/// The horizontal slice `z = k` as a grey linear image (row 0 at the largest `y`).
///
/// # Errors
///
/// [`VolumeError::InvalidParameter`] for `k` outside the grid.
pub fn slice_z(grid: &GridDensity, k: usize) -> Result<Image> {
    let (nx, ny, nz) = grid.grid().dims();
    if k >= nz {
        return Err(VolumeError::InvalidParameter {
            name: "k",
            value: k.to_string(),
            expected: "a slice index below the grid's z size",
        });
    }
    let s = grid.grid().slice_z(k);
    Ok(Image::from_grid(Grid2::from_fn(nx, ny, |x, y| {
        Vec3::splat(s[(ny - 1 - y) * nx + x])
    })?))
}

/// Writes the slice `z = k` as a linear float EXR, through a temporary name and a rename.
///
/// # Errors
///
/// As [`slice_z`]; [`VolumeError::Core`] for an I/O failure.
pub fn write_exr_slice(path: impl AsRef<Path>, grid: &GridDensity, k: usize) -> Result<()> {
    slice_z(grid, k)?.save_exr(path)?;
    Ok(())
}
