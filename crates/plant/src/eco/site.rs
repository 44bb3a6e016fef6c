//! The terrain as the plants see it: normalised altitude, slope, wetness and
//! light on the height field's samples.
//!
//! Deussen et al. 1998, §4.2, feed the population simulation with the
//! terrain's altitude, normals and a soil-humidity map from a rain-water flow
//! simulation whose parameters they do not give. Here the humidity is the
//! topographic wetness index over multiple-flow-direction accumulation
//! (natura-terrain's drainage analysis), rescaled to `[0, 1]` over the field,
//! and the light is the hill-shade under a given sun.

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
    /// Topographic wetness rescaled to `[0, 1]`.
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

impl Site {
    /// Analyses `hf` under the sun direction `sun` (pointing towards the sun).
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] if the field is smaller than 3×3 samples;
    /// [`PlantError::Core`] for a non-finite height or a zero `sun`;
    /// [`PlantError::Terrain`] from the drainage analysis.
    pub fn new(hf: &HeightField, sun: Vec3) -> Result<Self> {
        if hf.nx() < 3 || hf.ny() < 3 {
            return Err(PlantError::InvalidParameter {
                name: "HeightField",
                value: format!("{}×{}", hf.nx(), hf.ny()),
                reason: "an ecosystem needs at least 3×3 samples".into(),
            });
        }
        hf.check_finite()?;
        let light = hf.hillshade(sun)?;
        let slope = analysis::slope(hf)?;
        let area = analysis::flow_accumulation_mfd(hf, 1.1)?;
        let wet = analysis::wetness_index(hf, &area)?;
        Ok(Self {
            altitude: normalise(hf.heights()),
            slope,
            wetness: normalise(&wet),
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
