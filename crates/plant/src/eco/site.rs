//! The terrain as the plants see it: normalised altitude, slope, wetness and
//! light on the height field's samples.
//!
//! Deussen et al. 1998, §4.2, feed the population simulation with the
//! terrain's altitude, normals and a soil-humidity map from a rain-water flow
//! simulation whose parameters they do not give. Here the humidity is
//! natura-terrain's wetness ([`analysis::wetness`]: the topographic wetness
//! index of Beven & Kirkby 1979 over multiple-flow-direction accumulation,
//! rescaled to `[0, 1]` over the field), computed from the terrain or handed
//! in by a caller who shades the same terrain with it
//! ([`Site::with_wetness`]), and the light is the hill-shade under a given
//! sun.

use glam::Vec3;
use natura_core::{Grid2, HeightField};
use natura_terrain::analysis;

use crate::error::{PlantError, Result};

/// Per-sample site maps of a terrain, all `f32` grids of the field's size.
#[derive(Clone, Debug, PartialEq)]
pub struct Site {
    /// Altitude rescaled to `[0, 1]` (0 at the lowest sample, 1 at the highest).
    pub altitude: Grid2<f32>,
    /// Slope angle, radians.
    pub slope: Grid2<f32>,
    /// Wetness in `[0, 1]`: natura-terrain's [`analysis::wetness`] of the
    /// field, or the map given to [`Site::with_wetness`].
    pub wetness: Grid2<f32>,
    /// Terrain light in `[0, 1]`: the cosine between the surface normal and the sun.
    pub light: Grid2<f32>,
    /// Sample spacing, metres.
    pub cell: f32,
    /// Absolute heights, metres (for the plants' z).
    pub heights: Grid2<f32>,
}

fn normalise(g: &Grid2<f32>) -> Grid2<f32> {
    let (lo, hi) = (g.min(), g.max());
    let span = hi - lo;
    g.map(|&v| if span > 0.0 { (v - lo) / span } else { 0.5 })
}

/// Refuses a field smaller than 3×3 samples or with a non-finite height.
fn check_field(hf: &HeightField) -> Result<()> {
    if hf.nx() < 3 || hf.ny() < 3 {
        return Err(PlantError::InvalidParameter {
            name: "HeightField",
            value: format!("{}×{}", hf.nx(), hf.ny()),
            reason: "an ecosystem needs at least 3×3 samples".into(),
        });
    }
    hf.check_finite()?;
    Ok(())
}

impl Site {
    /// Analyses `hf` under the sun direction `sun` (pointing towards the
    /// sun), with natura-terrain's [`analysis::wetness`] of `hf`.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] if the field is smaller than 3×3 samples;
    /// [`PlantError::Core`] for a non-finite height or a zero `sun`;
    /// [`PlantError::Terrain`] from the drainage analysis.
    pub fn new(hf: &HeightField, sun: Vec3) -> Result<Self> {
        check_field(hf)?;
        let wetness = analysis::wetness(hf)?;
        Self::with_wetness(hf, sun, wetness)
    }

    /// As [`Site::new`] with a given wetness map (values in `[0, 1]`, one per
    /// sample of `hf`) instead of one computed from `hf`: for a field cut
    /// from a larger terrain whose wetness ([`analysis::wetness`] of the
    /// whole) other readers share, so the plants and they see the same
    /// values.
    ///
    /// # Errors
    ///
    /// As [`Site::new`]; [`PlantError::InvalidParameter`] naming `wetness` if
    /// its size differs from the field's or a value is not in `[0, 1]`.
    pub fn with_wetness(hf: &HeightField, sun: Vec3, wetness: Grid2<f32>) -> Result<Self> {
        check_field(hf)?;
        if wetness.dims() != (hf.nx(), hf.ny()) {
            return Err(PlantError::InvalidParameter {
                name: "wetness",
                value: format!("{}×{}", wetness.width(), wetness.height()),
                reason: format!("one value per sample of the {}×{} field", hf.nx(), hf.ny()),
            });
        }
        if let Some((x, y, v)) = wetness.find(|v| !(0.0..=1.0).contains(v)) {
            return Err(PlantError::InvalidParameter {
                name: "wetness",
                value: format!("{v} at ({x}, {y})"),
                reason: "values in [0, 1]".into(),
            });
        }
        let light = hf.hillshade(sun)?;
        let slope = analysis::slope(hf)?;
        Ok(Self {
            altitude: normalise(hf.heights()),
            slope,
            wetness,
            light,
            cell: hf.cell_size(),
            heights: hf.heights().clone(),
        })
    }

    /// World extent `(x, y)` in metres covered by the samples.
    #[must_use]
    pub fn extent(&self) -> (f32, f32) {
        let (nx, ny) = self.altitude.dims();
        ((nx - 1) as f32 * self.cell, (ny - 1) as f32 * self.cell)
    }

    /// Index of the sample nearest to world `(x, y)` (which must lie inside the extent).
    #[inline]
    #[must_use]
    pub fn nearest(&self, x: f32, y: f32) -> (usize, usize) {
        let (nx, ny) = self.altitude.dims();
        let i = ((x / self.cell).round() as usize).min(nx - 1);
        let j = ((y / self.cell).round() as usize).min(ny - 1);
        (i, j)
    }

    /// Bilinear terrain height at world `(x, y)`.
    #[inline]
    #[must_use]
    pub fn height(&self, x: f32, y: f32) -> f32 {
        self.heights
            .sample_bilinear(x / self.cell, y / self.cell, natura_core::Boundary::Clamp)
    }
}
