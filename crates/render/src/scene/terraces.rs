//! The scene's `[terraces]` section: cliffs and benches where layered rock
//! shows on the eroded hillsides (natura-terrain's [`terrace`]), with beds
//! that follow the rock strata of the `[textures]` section, and its checks.
//!
//! [`terrace`]: natura_terrain::synth::terrace

use serde::{Deserialize, Serialize};

use super::validate::in_range;
use crate::error::{RenderError, Result};

/// Terraces on the eroded terrain: within each bed of the strata, a hard
/// layer stands as a cliff and a soft one wears back into a bench.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TerracesDesc {
    /// Whether to terrace the terrain at all.
    pub enabled: bool,
    /// Beds per cycle of the strata's colour map (`1/(zscale·txtscale)`
    /// metres of altitude in `[textures.strata]`), so each bed is that many
    /// times thinner than a cycle; the beds bend with the strata's fBm.
    pub beds_per_cycle: u32,
    /// Share of each bed's altitude range that stands as cliff, in (0, 1].
    pub cliff_fraction: f32,
    /// Flatness of the benches, 0 (no terraces) to 1 (level benches).
    pub flatness: f32,
    /// Slope below which no terraces form, degrees (full strength 10° steeper).
    pub min_slope_deg: f32,
    /// Altitude below which no terraces form, metres (full strength one bed higher).
    pub min_altitude_m: f32,
}

impl Default for TerracesDesc {
    fn default() -> Self {
        Self {
            enabled: true,
            beds_per_cycle: 8,
            cliff_fraction: 0.35,
            flatness: 0.85,
            min_slope_deg: 14.0,
            min_altitude_m: 300.0,
        }
    }
}

impl TerracesDesc {
    /// Checks every key of the section (whether or not it is enabled), and
    /// that the strata it follows repeat in altitude when it is.
    pub(crate) fn validate(&self, strata_zscale: f64, strata_txtscale: f64) -> Result<()> {
        in_range(
            "terraces.beds_per_cycle",
            f64::from(self.beds_per_cycle),
            1.0,
            1024.0,
        )?;
        if self.cliff_fraction <= 0.0 {
            return Err(RenderError::Invalid {
                name: "terraces.cliff_fraction".to_owned(),
                value: format!("{}", self.cliff_fraction),
                reason: "must lie in (0, 1]".to_owned(),
            });
        }
        in_range(
            "terraces.cliff_fraction",
            f64::from(self.cliff_fraction),
            0.0,
            1.0,
        )?;
        in_range("terraces.flatness", f64::from(self.flatness), 0.0, 1.0)?;
        in_range(
            "terraces.min_slope_deg",
            f64::from(self.min_slope_deg),
            0.0,
            80.0,
        )?;
        in_range(
            "terraces.min_altitude_m",
            f64::from(self.min_altitude_m),
            -1e6,
            1e6,
        )?;
        // The beds follow the strata: a zscale of 0 (no cycle) gives beds
        // of infinite height, as one too small for f32 does.
        let (_, bed) = self.cycle_and_bed_m(strata_zscale, strata_txtscale);
        if self.enabled && !(bed > 0.0 && bed <= MAX_BED_M) {
            return Err(RenderError::Invalid {
                name: "textures.strata.zscale".to_owned(),
                value: format!("{strata_zscale}"),
                reason: format!(
                    "gives beds of {bed} m (a cycle of 1/(zscale·txtscale) m over {} beds); \
                     while [terraces] is enabled (the beds follow the strata) they must be \
                     over 0 and at most {MAX_BED_M} m",
                    self.beds_per_cycle
                ),
            });
        }
        Ok(())
    }

    /// The strata's colour-map cycle `1/(zscale·txtscale)` and the height
    /// of one bed, metres, as the world's terraces use them.
    pub(crate) fn cycle_and_bed_m(&self, strata_zscale: f64, strata_txtscale: f64) -> (f32, f32) {
        let cycle_m = (1.0 / (strata_zscale * strata_txtscale)) as f32;
        (cycle_m, cycle_m / self.beds_per_cycle as f32)
    }
}

/// The highest bed natura-terrain's terraces take, metres.
const MAX_BED_M: f32 = 10_000.0;
