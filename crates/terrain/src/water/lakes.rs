//! The water surface: the terrain with its lakes and sea on top. Lakes are
//! the depressions Priority-Flood fills to their spill points (Barnes et al.
//! 2014, §2, Algorithm 1); which of them hold water is natura's own rule.

use natura_core::{Grid2, HeightField};

use super::large_components;
use crate::analysis::fill_depressions;
use crate::error::{Result, in_range};

/// Which filled depressions hold lakes in [`water_surface`]: natura's own
/// thresholds, which leave the puddles and pits of a triangulated surface
/// dry.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct LakeParams {
    /// A sample is lake only where the fill is deeper than this, metres. Default 1.
    pub min_depth_m: f32,
    /// Lakes (4-connected, see [`large_components`]) of fewer samples than
    /// this are left dry. Default 48.
    pub min_cells: usize,
}

impl Default for LakeParams {
    fn default() -> Self {
        Self {
            min_depth_m: 1.0,
            min_cells: 48,
        }
    }
}

impl LakeParams {
    /// Checks every parameter.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
    /// naming `min_depth_m` unless it lies in `[0, 10⁶]` m (NaN included).
    pub fn validate(&self) -> Result<()> {
        in_range("min_depth_m", f64::from(self.min_depth_m), 0.0, 1e6)
    }
}

/// The terrain with its water on top: every depression filled to its spill
/// level (Priority-Flood, [`fill_depressions`]) where the fill is deeper than
/// `lakes.min_depth_m` over a 4-connected lake of at least `lakes.min_cells`
/// samples, and everything below `sea` (metres) raised to it. Equal to the
/// terrain where dry; never below it.
///
/// # Errors
///
/// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
/// naming `sea` unless it is finite (within ±10⁶ m), and the errors of
/// [`LakeParams::validate`]; [`TerrainError::Core`](crate::TerrainError::Core)
/// naming the first NaN or infinite height, or if a grid cannot be allocated.
pub fn water_surface(terrain: &HeightField, sea: f32, lakes: &LakeParams) -> Result<HeightField> {
    in_range("sea", f64::from(sea), -1e6, 1e6)?;
    lakes.validate()?;
    let (filled, depth) = fill_depressions(terrain)?;
    let (nx, ny) = (terrain.nx(), terrain.ny());
    let wet = Grid2::from_vec(
        nx,
        ny,
        depth
            .as_slice()
            .iter()
            .map(|&d| d > lakes.min_depth_m)
            .collect(),
    )?;
    let keep = large_components(&wet, lakes.min_cells)?;
    let mut s = terrain.clone();
    let levels = filled.heights().as_slice();
    for ((v, &lake), &level) in s
        .heights_mut()
        .as_mut_slice()
        .iter_mut()
        .zip(keep.as_slice())
        .zip(levels)
    {
        if lake {
            *v = level;
        }
        *v = v.max(sea);
    }
    Ok(s)
}
