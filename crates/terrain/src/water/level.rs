//! The sea level of a terrain: a quantile of the heights inside its border
//! (natura's own construction; no source).

use natura_core::HeightField;

use crate::error::{Result, in_range};

/// The `quantile` of the heights of `hf`'s interior, metres: the samples
/// more than `border_fraction` of each side from the edge (rounded up to
/// whole samples, and at most one sample short of the middle, so some
/// interior always remains). Used as a sea level: with `quantile` 0.12, an
/// eighth of the land inside a sunken coast ([`sink_coast`](super::sink_coast))
/// lies under water. The quantile is the sample of rank
/// `round((n − 1) · quantile)` of the `n` interior heights in ascending
/// order, so the level is one of the field's heights (natura's own
/// construction).
///
/// # Errors
///
/// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
/// naming `border_fraction` unless it lies in `[0, 0.5]` or `quantile`
/// unless it lies in `[0, 1]` (NaN included), and
/// [`TerrainError::Core`](crate::TerrainError::Core) naming the first NaN or
/// infinite height.
pub fn water_level(hf: &HeightField, border_fraction: f64, quantile: f64) -> Result<f32> {
    in_range("border_fraction", border_fraction, 0.0, 0.5)?;
    in_range("quantile", quantile, 0.0, 1.0)?;
    hf.check_finite()?;
    let (nx, ny) = (hf.nx(), hf.ny());
    let border =
        |n: usize| ((border_fraction * n as f64).ceil() as usize).min((n / 2).saturating_sub(1));
    let (bx, by) = (border(nx), border(ny));
    let mut hs: Vec<f32> = Vec::with_capacity((nx - 2 * bx) * (ny - 2 * by));
    for j in by..ny - by {
        hs.extend_from_slice(&hf.heights().row(j)[bx..nx - bx]);
    }
    hs.sort_by(f32::total_cmp);
    let k = ((hs.len() - 1) as f64 * quantile).round() as usize;
    Ok(hs[k])
}
