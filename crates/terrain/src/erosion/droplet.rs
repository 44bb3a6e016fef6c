//! Particle ("droplet") hydraulic erosion (Beyer 2015).
//!
//! Each droplet carries position, direction, speed, water and sediment. Per
//! step: `dir ← dir·inertia − ∇h·(1 − inertia)` (normalised), move one cell,
//! capacity `max(−Δh, min_slope)·speed·water·K_capacity`; over capacity (or
//! moving uphill) deposit at the old position (bilinear weights; uphill it
//! fills at most the rise), under capacity erode `min((cap − s)·K_erode, −Δh)`
//! with a radial brush of `radius` cells; `speed² ← speed² − Δh·g`;
//! `water ← water·(1 − K_evaporate)`. A droplet lives `lifetime` steps.
//!
//! **Stability.** Beyer bounds a step's total erosion by the drop `−Δh` and an
//! uphill deposit by the rise, so that a droplet neither digs a pit nor builds
//! a hill. The brush spreads the erosion over many cells, and a deposit over
//! four, so those totals alone do not bound any one cell: over millions of
//! droplets a cell can be dug or raised without limit. Here the bound holds per
//! cell: erosion never lowers a cell below the height the droplet flows down
//! to, and deposition never raises a cell above the higher end of the step.
//! Every step therefore keeps every height inside the range the terrain
//! already spans, whatever the parameters and grid size; sediment a bound
//! holds back stays in the droplet, and what it carries when it dies is laid
//! down where it stops (mass is conserved; sediment carried off the edge is
//! counted in [`DropletErosion::outflow`]).
//!
//! **Determinism and parallelism.** Droplet `k` starts at a position indexed
//! by `(seed, k)`. With `batch = 1` droplets run one after another, each on
//! the terrain the previous ones left (Beyer's algorithm). A larger `batch`
//! runs that many droplets per round in row bands: a droplet moves one cell
//! per step, so it stays within `lifetime + radius + 2` rows of its start, and
//! bands twice that high with every other band running at once never touch
//! the same cell. Each band's droplets run in index order on the live
//! terrain, so every droplet is still Beyer's droplet; only the order between
//! bands differs from the sequential run. Bands depend on the grid and the
//! parameters, never on the thread count, so results are bit-identical on any
//! number of threads. Heights are divided by the cell size inside the
//! simulation (slopes are rise per cell, so Beyer's constants mean the same at
//! any resolution); changes are converted back to metres.

use natura_core::{Grid2, HeightField, Progress, Seed};

use super::{Erodibility, check_erodibility, check_field, check_model_size};
use crate::bands;
use crate::error::{Result, in_range, invalid, non_negative, positive};

/// Parameters of [`DropletErosion`]; defaults are Beyer's (2015).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct DropletParams {
    /// Inertia `∈ [0, 1)`: 0 follows the gradient, near 1 keeps going straight. Default 0.05.
    pub inertia: f64,
    /// Sediment capacity factor. Default 4.
    pub capacity: f64,
    /// Minimum slope used in the capacity (keeps capacity on flats). Default 0.01.
    pub min_slope: f64,
    /// Fraction of free capacity eroded per step `∈ [0, 1]`. Default 0.3.
    pub erode: f64,
    /// Fraction of excess sediment deposited per step `∈ [0, 1]`. Default 0.3.
    pub deposit: f64,
    /// Fraction of water evaporating per step `∈ [0, 1)`. Default 0.01.
    pub evaporate: f64,
    /// Gravity (speed gain per metre of drop). Default 4.
    pub gravity: f64,
    /// Erosion brush radius, cells (≥ 1, ≤ 16). Default 3.
    pub radius: u32,
    /// Steps a droplet lives (1..=1000). Default 30.
    pub lifetime: u32,
    /// Initial water. Default 1.
    pub initial_water: f64,
    /// Initial speed. Default 1.
    pub initial_speed: f64,
    /// Droplets per round (1..=2²⁴): 1 runs them strictly one after another;
    /// more lets the droplets of distant row bands run at once (see the module
    /// docs). Default 1.
    pub batch: u32,
}

impl Default for DropletParams {
    fn default() -> Self {
        Self {
            inertia: 0.05,
            capacity: 4.0,
            min_slope: 0.01,
            erode: 0.3,
            deposit: 0.3,
            evaporate: 0.01,
            gravity: 4.0,
            radius: 3,
            lifetime: 30,
            initial_water: 1.0,
            initial_speed: 1.0,
            batch: 1,
        }
    }
}

impl DropletParams {
    /// Checks every field's range (see the field docs).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        if !(self.inertia >= 0.0 && self.inertia < 1.0) {
            return Err(invalid(
                "DropletParams::inertia",
                self.inertia,
                "must lie in [0, 1)",
            ));
        }
        non_negative("DropletParams::capacity", self.capacity)?;
        non_negative("DropletParams::min_slope", self.min_slope)?;
        in_range("DropletParams::erode", self.erode, 0.0, 1.0)?;
        in_range("DropletParams::deposit", self.deposit, 0.0, 1.0)?;
        if !(self.evaporate >= 0.0 && self.evaporate < 1.0) {
            return Err(invalid(
                "DropletParams::evaporate",
                self.evaporate,
                "must lie in [0, 1)",
            ));
        }
        non_negative("DropletParams::gravity", self.gravity)?;
        if !(1..=16).contains(&self.radius) {
            return Err(invalid(
                "DropletParams::radius",
                self.radius,
                "must lie in [1, 16] cells",
            ));
        }
        if !(1..=1000).contains(&self.lifetime) {
            return Err(invalid(
                "DropletParams::lifetime",
                self.lifetime,
                "must lie in [1, 1000] steps",
            ));
        }
        positive("DropletParams::initial_water", self.initial_water)?;
        non_negative("DropletParams::initial_speed", self.initial_speed)?;
        if !(1..=1 << 24).contains(&self.batch) {
            return Err(invalid(
                "DropletParams::batch",
                self.batch,
                "must lie in [1, 2^24]",
            ));
        }
        Ok(())
    }
}

/// Droplet erosion on a field of fixed size.
#[derive(Debug)]
pub struct DropletErosion {
    p: DropletParams,
    nx: usize,
    ny: usize,
    seed: Seed,
    next_droplet: u64,
    brush: Vec<(i32, i32, f32)>,
    erodibility: Option<Erodibility>,
    deposition: Vec<f32>,
    outflow: f64,
    /// Metres per cell: the simulation runs in cell units (heights / cell size),
    /// so Beyer's constants mean the same thing at any resolution.
    cell: f32,
}

impl DropletErosion {
    /// A model for fields the size of `hf`; droplet `k` starts at a position
    /// indexed by `(seed, k)`.
    ///
    /// # Errors
    ///
    /// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`](crate::TerrainError::BadSize) if
    /// `hf` is smaller than 3 × 3 samples, and [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) or
    /// [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming `height` for a NaN, infinite or
    /// out-of-range height (beyond ±[`MAX_HEIGHT`](crate::erosion::MAX_HEIGHT)).
    pub fn new(p: DropletParams, hf: &HeightField, seed: Seed) -> Result<Self> {
        p.validate()?;
        check_model_size("droplet erosion", hf)?;
        let r = p.radius as i32;
        let mut brush = Vec::new();
        for dy in -r..=r {
            for dx in -r..=r {
                let d = ((dx * dx + dy * dy) as f32).sqrt();
                if d < r as f32 {
                    brush.push((dx, dy, r as f32 - d));
                }
            }
        }
        Ok(Self {
            p,
            nx: hf.nx(),
            ny: hf.ny(),
            seed: seed.derive("droplets"),
            next_droplet: 0,
            brush,
            erodibility: None,
            deposition: vec![0.0; hf.nx() * hf.ny()],
            outflow: 0.0,
            cell: hf.cell_size(),
        })
    }

    /// Scales erosion per cell.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if the erodibility map is not the
    /// field's size.
    pub fn with_erodibility(mut self, e: Erodibility) -> Result<Self> {
        check_erodibility(Some(&e), self.nx, self.ny)?;
        self.erodibility = Some(e);
        Ok(self)
    }

    /// Net height change from droplets so far (positive: deposition), metres.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the grid cannot be allocated.
    pub fn deposition(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.deposition.clone())?)
    }

    /// Sediment carried off the edge so far (sum of heights, metres).
    #[must_use]
    pub fn outflow(&self) -> f64 {
        self.outflow
    }

    /// Simulates `droplets` more droplets.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if `hf` is not the size the model was
    /// built for, and [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) or [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
    /// naming `height` for a NaN, infinite or out-of-range height.
    pub fn run(
        &mut self,
        hf: &mut HeightField,
        droplets: u64,
        progress: &dyn Progress,
    ) -> Result<()> {
        check_field("droplet erosion", hf, self.nx, self.ny)?;
        progress.start("droplets", droplets);
        let batch = u64::from(self.p.batch);
        let mut left = droplets;
        let mut since = 0u64;
        while left > 0 {
            let k = left.min(batch);
            self.batch(hf, self.next_droplet, k);
            self.next_droplet += k;
            left -= k;
            since += k;
            if since >= 1024 || left == 0 {
                progress.advance(since);
                since = 0;
            }
        }
        progress.finish();
        Ok(())
    }

    /// Runs droplets `first..first + count`. With more than one band (see the
    /// module docs) the droplets starting in every other band run at once,
    /// each band's in index order on the live terrain; then the others.
    fn batch(&mut self, hf: &mut HeightField, first: u64, count: u64) {
        let model = DropletModel {
            p: &self.p,
            nx: self.nx,
            ny: self.ny,
            seed: self.seed,
            brush: &self.brush,
            brush_reach: reach(&self.brush),
            brush_total: self.brush.iter().map(|b| b.2).sum(),
            erodibility: self.erodibility.as_ref().map(|e| e.map().as_slice()),
            cell: self.cell,
        };
        let (nx, ny) = (self.nx, self.ny);
        let h = hf.heights_mut().as_mut_slice();
        let dep = self.deposition.as_mut_slice();
        let band = model.band_rows();
        let bands = ny.div_ceil(band);
        if count == 1 || bands < 3 {
            let mut ground = Ground {
                h,
                deposition: dep,
                offset: 0,
                cell: self.cell,
            };
            for id in first..first + count {
                self.outflow += model.simulate(&mut ground, id);
            }
            return;
        }
        // Droplets by the band their start lies in, in index order.
        let mut by_band: Vec<Vec<u64>> = vec![Vec::new(); bands];
        for id in first..first + count {
            let (_, y) = model.start(id);
            by_band[(y as usize / band).min(bands - 1)].push(id);
        }
        for parity in 0..2 {
            // Band k's droplets touch rows within half a band of it, so the
            // slices [kT − T/2, (k+1)T + T/2) of one parity are disjoint.
            let half = band / 2;
            let mut jobs = Vec::new();
            let (mut h_rest, mut d_rest) = (&mut *h, &mut *dep);
            let mut row = 0;
            for (k, ids) in by_band.iter().enumerate().skip(parity).step_by(2) {
                let lo = (k * band).saturating_sub(half).min(ny);
                let hi = ((k + 1) * band + half).min(ny);
                let (_, h_tail) = std::mem::take(&mut h_rest).split_at_mut((lo - row) * nx);
                let (_, d_tail) = std::mem::take(&mut d_rest).split_at_mut((lo - row) * nx);
                let (h_band, h_next) = h_tail.split_at_mut((hi - lo) * nx);
                let (d_band, d_next) = d_tail.split_at_mut((hi - lo) * nx);
                (h_rest, d_rest, row) = (h_next, d_next, hi);
                jobs.push((ids, h_band, d_band, lo * nx));
            }
            let outs = bands::run(jobs, |(ids, h, deposition, offset)| {
                let mut ground = Ground {
                    h,
                    deposition,
                    offset,
                    cell: model.cell,
                };
                ids.iter()
                    .map(|&id| model.simulate(&mut ground, id))
                    .sum::<f64>()
            });
            self.outflow += outs.iter().sum::<f64>();
        }
    }
}

mod model;

use model::{DropletModel, Ground, reach};

#[cfg(test)]
mod tests;
