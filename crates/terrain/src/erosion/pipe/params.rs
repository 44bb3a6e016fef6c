//! The parameters of the virtual-pipe model and its mass ledger.

use crate::erosion::Edges;
use crate::error::{Result, in_range, invalid, non_negative, positive};

/// How suspended sediment moves with the water.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum SedimentTransport {
    /// Through the pipes with the water: conserves mass (default).
    Conservative,
    /// Semi-Lagrangian back-tracing along the velocity field, as Mei et al.
    /// publish it: smoother, but does not conserve sediment.
    SemiLagrangian,
}

/// Parameters of [`PipeModel`](super::PipeModel).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct PipeParams {
    /// Time step, seconds (> 0, ≤ 10).
    pub dt: f64,
    /// Gravity, m/s².
    pub gravity: f64,
    /// Virtual pipe cross-section `A`, m² (per metre of cell size it scales the flux response).
    pub pipe_area: f64,
    /// Uniform rain rate, metres of water per second.
    pub rain_m_per_s: f64,
    /// Sediment capacity constant `K_c`, metres of sediment per (m/s) of flow.
    pub k_c: f64,
    /// Dissolving (erosion) constant `K_s ∈ [0, 1]` per step.
    pub k_s: f64,
    /// Deposition constant `K_d ∈ [0, 1]` per step.
    pub k_d: f64,
    /// Evaporation rate `K_e`, per second (`K_e·Δt ≤ 1`).
    pub k_e: f64,
    /// Floor on `sin α`, so flat water still carries some sediment (Mei et al.'s remedy).
    pub min_tilt: f64,
    /// Water depth below which capacity ramps linearly to zero, metres.
    pub depth_ref: f64,
    /// Sediment transport scheme.
    pub transport: SedimentTransport,
    /// Closed, open (water and sediment leave) or periodic edges.
    pub edges: Edges,
}

impl Default for PipeParams {
    fn default() -> Self {
        Self {
            dt: 0.05,
            gravity: 9.81,
            pipe_area: 1.0,
            rain_m_per_s: 0.01,
            k_c: 0.05,
            k_s: 0.3,
            k_d: 0.3,
            k_e: 0.05,
            min_tilt: 0.05,
            depth_ref: 0.05,
            transport: SedimentTransport::Conservative,
            edges: Edges::Closed,
        }
    }
}

impl PipeParams {
    /// Refuses non-positive or huge `dt` (> 10 s), negative rates, `K_s, K_d ∉ [0, 1]`,
    /// `K_e·Δt > 1`, `min_tilt ∉ [0, 1]`.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        positive("PipeParams::dt", self.dt)?;
        if self.dt > 10.0 {
            return Err(invalid("PipeParams::dt", self.dt, "must be ≤ 10 s"));
        }
        positive("PipeParams::gravity", self.gravity)?;
        positive("PipeParams::pipe_area", self.pipe_area)?;
        non_negative("PipeParams::rain_m_per_s", self.rain_m_per_s)?;
        in_range("PipeParams::rain_m_per_s", self.rain_m_per_s, 0.0, 1.0)?;
        non_negative("PipeParams::k_c", self.k_c)?;
        in_range("PipeParams::k_c", self.k_c, 0.0, 100.0)?;
        in_range("PipeParams::k_s", self.k_s, 0.0, 1.0)?;
        in_range("PipeParams::k_d", self.k_d, 0.0, 1.0)?;
        non_negative("PipeParams::k_e", self.k_e)?;
        if self.k_e * self.dt > 1.0 {
            return Err(invalid("PipeParams::k_e", self.k_e, "k_e·dt must be ≤ 1"));
        }
        in_range("PipeParams::min_tilt", self.min_tilt, 0.0, 1.0)?;
        positive("PipeParams::depth_ref", self.depth_ref)?;
        Ok(())
    }
}

/// Running totals (sums of depths over cells, metres).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PipeLedger {
    /// Σ(terrain + sediment) when built.
    pub initial_material: f64,
    /// Rain added.
    pub rain: f64,
    /// Water evaporated.
    pub evaporated: f64,
    /// Water that left through open edges.
    pub outflow_water: f64,
    /// Sediment that left through open edges.
    pub outflow_sediment: f64,
}
