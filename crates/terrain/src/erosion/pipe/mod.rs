//! Virtual-pipe shallow-water hydraulic erosion (Mei et al. 2007, "Fast
//! Hydraulic Erosion Simulation and Visualization on GPU", §3; the pipe model
//! is O'Brien & Hodgins 1995). Not in Musgrave's texts: it is the stable
//! successor of the hydraulic scheme of Musgrave et al. 1989, §4.1, and keeps
//! its `K_c / K_s / K_d` naming.
//!
//! Per step (Mei et al. 2007, §3; `l` = cell size, `A` = pipe
//! cross-section, `g` = gravity):
//! 1. rain: `d₁ = d + Δt·r`;
//! 2. outflow flux to each of the 4 neighbours through virtual pipes,
//!    `f ← max(0, f + Δt·A·g·Δh/l)`, scaled by `K = min(1, d₁·l²/(Σf·Δt))` so a
//!    cell never sends more water than it holds;
//! 3. depth from the net flux, `d₂ = d₁ + Δt·(Σf_in − Σf_out)/l²`, and the
//!    velocity field from the average through-flux;
//! 4. capacity `C = K_c·sin(α)·|v|` (α the local tilt, floored at `min_tilt`;
//!    ramped to 0 in films thinner than `depth_ref`); under capacity, dissolve
//!    `K_s(C − s)` of the bed; over, deposit `K_d(s − C)`;
//! 5. sediment transport; 6. evaporation `d ← d(1 − K_e·Δt)`.
//!
//! **Correction.** The paper transports sediment semi-Lagrangianly
//! (`s(x) ← s(x − vΔt)`), which does not conserve sediment: material appears
//! and vanishes wherever the velocity field converges or diverges. The
//! default [`SedimentTransport::Conservative`] moves sediment with the water
//! through the same pipes (each pipe carries the fraction of the cell's
//! sediment equal to the fraction of its water it carries this step), which
//! conserves terrain + sediment exactly in exact arithmetic and keeps
//! sediment non-negative. [`SedimentTransport::SemiLagrangian`] reproduces
//! the paper. Velocities are capped at one cell per step (the CFL limit of the
//! explicit scheme) so extreme `Δt` stays finite.
//!
//! Defaults are chosen for metres and seconds; the paper's constants are for
//! its own unit grid and are not reproduced.
//!
//! The code is laid out so that the model is read in one place:
//! `pipe/model.rs` holds the per-cell equations (the only place the
//! model's arithmetic is written), the reference passes (`reference.rs`)
//! call them cell by cell, the row kernels (`row_kernels.rs`) call them in
//! vectorised loops over the interior of each row, and the fused sweep
//! (`one_pass.rs`) runs the whole step in one pass over the rows.
//! Every path computes the same operations in the same order, so they agree
//! bit for bit.

mod grid;
mod model;
mod one_pass;
mod params;
mod reference;
mod row_kernels;
#[cfg(test)]
mod tests;

use natura_core::simd::Simd;
use natura_core::{Grid2, HeightField, Progress};

use super::{Erodibility, check_field, check_model_size, check_softness};
use crate::bands;
use crate::error::{Result, invalid};
use grid::Step;
use model::Coefficients;

pub use params::{PipeLedger, PipeParams, SedimentTransport};

/// The virtual-pipe erosion model on a field of fixed size.
#[derive(Debug)]
pub struct PipeModel {
    p: PipeParams,
    nx: usize,
    ny: usize,
    cell: f32,
    water: Vec<f32>,
    water1: Vec<f32>,
    sediment: Vec<f32>,
    sediment1: Vec<f32>,
    flux: [Vec<f32>; 4], // to x−1, x+1, y−1, y+1
    /// u and v of the last step: empty unless recorded ([`Self::with_velocity`])
    /// or needed (semi-Lagrangian transport).
    vel: [Vec<f32>; 2],
    record_velocity: bool,
    /// The next step's bed (swapped with the field's heights after each step).
    bed: Grid2<f32>,
    /// The field's heights when the current `run` / `step` call began (its
    /// net change is added to `deposit` when the call ends).
    bed_start: Grid2<f32>,
    erodibility: Option<Erodibility>,
    ledger: PipeLedger,
    deposit: Vec<f32>,
}

/// Rows per chunk of the fused sweep: enough chunks to balance the cores,
/// few enough that the halos recomputed at chunk boundaries stay cheap.
const CHUNK_ROWS: usize = 64;

/// Which code computes a step. Users always get [`Path::fast`]; the tests
/// run the others (and the fast path at every supported instruction set)
/// as its oracles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Path {
    /// Every cell through the per-cell reference functions, in three passes.
    #[cfg_attr(not(test), allow(dead_code))]
    Reference,
    /// Three passes, the interior of each row through the row kernels
    /// compiled for the given instruction set.
    #[cfg_attr(not(test), allow(dead_code))]
    Rows(Simd),
    /// The fused sweep in chunks of about `chunk_rows` rows, with the row
    /// kernels at `simd` (conservative transport; the semi-Lagrangian one
    /// takes [`Path::Rows`]).
    Fused {
        /// Rows per chunk.
        chunk_rows: usize,
        /// The row kernels' instruction set.
        simd: Simd,
    },
}

impl Path {
    /// The path [`PipeModel::run`] and [`PipeModel::step`] take: the fused
    /// sweep at the CPU's widest instruction set.
    pub(crate) fn fast() -> Path {
        Path::Fused {
            chunk_rows: CHUNK_ROWS,
            simd: Simd::best(),
        }
    }
}

impl PipeModel {
    /// A dry model for fields the size of `hf`.
    ///
    /// # Errors
    ///
    /// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`](crate::TerrainError::BadSize) if
    /// `hf` is smaller than 3 × 3 samples, and [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) or
    /// [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming `height` for a NaN, infinite or
    /// out-of-range height (beyond ±[`MAX_HEIGHT`](crate::erosion::MAX_HEIGHT)).
    pub fn new(p: PipeParams, hf: &HeightField) -> Result<Self> {
        p.validate()?;
        check_model_size("pipe-model erosion", hf)?;
        let n = hf.nx() * hf.ny();
        natura_core::checked_len::<f32>(&[n, 16])?;
        let z = || vec![0.0f32; n];
        Ok(Self {
            p,
            nx: hf.nx(),
            ny: hf.ny(),
            cell: hf.cell_size(),
            water: z(),
            water1: Vec::new(),
            sediment: z(),
            sediment1: Vec::new(),
            flux: [z(), z(), z(), z()],
            vel: [Vec::new(), Vec::new()],
            record_velocity: false,
            bed: Grid2::from_vec(hf.nx(), hf.ny(), z())?,
            bed_start: Grid2::from_vec(hf.nx(), hf.ny(), z())?,
            erodibility: None,
            ledger: PipeLedger {
                initial_material: hf.heights().sum(),
                ..Default::default()
            },
            deposit: z(),
        })
    }

    /// Scales `K_s` per cell.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if the erodibility map is not the
    /// field's size.
    pub fn with_erodibility(mut self, e: Erodibility) -> Result<Self> {
        check_softness(&e, self.nx, self.ny, self.p.k_s)?;
        self.erodibility = Some(e);
        Ok(self)
    }

    /// Keeps (`true`) or drops (`false`, the default) the water velocity of
    /// each step for [`Self::velocity`]. Recording writes two more planes per
    /// step (about a fifth of the step's memory traffic), so the model only
    /// does it when asked; the semi-Lagrangian transport needs the velocity
    /// and always keeps it. Nothing else the model computes depends on this.
    #[must_use]
    pub fn with_velocity(mut self, record: bool) -> Self {
        self.record_velocity = record;
        self
    }

    /// Whether the steps keep u and v.
    fn keeps_velocity(&self) -> bool {
        self.record_velocity || self.p.transport == SedimentTransport::SemiLagrangian
    }

    /// Sets the water depth (metres ≥ 0, finite).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if `water` is not the field's size, and
    /// [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) or [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) for a
    /// negative or non-finite depth.
    pub fn set_water(&mut self, water: &Grid2<f32>) -> Result<()> {
        crate::error::same_size("water", water, self.nx, self.ny)?;
        crate::error::check_grid("water", water)?;
        if let Some((x, y, &v)) = water.find(|&v| v < 0.0) {
            return Err(invalid(
                "water",
                format!("{v} at cell ({x}, {y})"),
                "must be >= 0",
            ));
        }
        self.ledger.rain += water.sum() - bands::sum_f32(&self.water);
        self.water.copy_from_slice(water.as_slice());
        Ok(())
    }

    /// Water depth, metres.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the grid cannot be allocated.
    pub fn water(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.water.clone())?)
    }

    /// Suspended sediment, metres.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the grid cannot be allocated.
    pub fn sediment(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.sediment.clone())?)
    }

    /// Net deposition since the model was built (positive: material laid
    /// down), metres: the sum over the model's `run` / `step` calls of the
    /// bed's change during each call (so changes made to the field between
    /// calls, by other models, are not counted).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the grid cannot be allocated.
    pub fn deposition(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.deposit.clone())?)
    }

    /// Water velocity `(u, v)` of the last step, m/s. Kept only by a model
    /// built [`with_velocity(true)`](Self::with_velocity) or with the
    /// semi-Lagrangian transport; otherwise an error says so. Before the
    /// first step it is zero.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the grids cannot be allocated.
    pub fn velocity(&self) -> Result<(Grid2<f32>, Grid2<f32>)> {
        if !self.keeps_velocity() {
            return Err(invalid(
                "PipeModel::velocity",
                "not recorded",
                "build the model with `with_velocity(true)` to keep the velocity",
            ));
        }
        if self.vel[0].is_empty() {
            let z = Grid2::from_vec(self.nx, self.ny, vec![0.0f32; self.nx * self.ny])?;
            return Ok((z.clone(), z));
        }
        Ok((
            Grid2::from_vec(self.nx, self.ny, self.vel[0].clone())?,
            Grid2::from_vec(self.nx, self.ny, self.vel[1].clone())?,
        ))
    }

    /// Σ water depth, metres.
    #[must_use]
    pub fn total_water(&self) -> f64 {
        bands::sum_f32(&self.water)
    }

    /// Σ suspended sediment, metres.
    #[must_use]
    pub fn total_sediment(&self) -> f64 {
        bands::sum_f32(&self.sediment)
    }

    /// The ledger.
    #[must_use]
    pub fn ledger(&self) -> PipeLedger {
        self.ledger
    }

    /// Runs `steps` steps.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if `hf` is not the size the model was
    /// built for, and [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) or [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
    /// naming `height` for a NaN, infinite or out-of-range height.
    pub fn run(&mut self, hf: &mut HeightField, steps: u32, progress: &dyn Progress) -> Result<()> {
        self.run_on(hf, steps, progress, Path::fast())
    }

    /// [`run`](Self::run) through the given path.
    pub(crate) fn run_on(
        &mut self,
        hf: &mut HeightField,
        steps: u32,
        progress: &dyn Progress,
        path: Path,
    ) -> Result<()> {
        check_field("pipe-model erosion", hf, self.nx, self.ny)?;
        progress.start("pipe model", u64::from(steps));
        for k in 0..steps {
            self.step_unchecked(hf, path);
            if k == 0 {
                // Keep the heights the call began with; the steps alternate
                // between the field and the other buffer.
                std::mem::swap(&mut self.bed, &mut self.bed_start);
            }
            progress.advance(1);
        }
        if steps > 0 {
            self.add_deposit(hf);
        }
        progress.finish();
        Ok(())
    }

    /// One step.
    ///
    /// # Errors
    ///
    /// As [`run`](Self::run).
    pub fn step(&mut self, hf: &mut HeightField) -> Result<()> {
        self.step_on(hf, Path::fast())
    }

    /// [`step`](Self::step) through the given path.
    pub(crate) fn step_on(&mut self, hf: &mut HeightField, path: Path) -> Result<()> {
        check_field("pipe-model erosion", hf, self.nx, self.ny)?;
        self.step_unchecked(hf, path);
        std::mem::swap(&mut self.bed, &mut self.bed_start);
        self.add_deposit(hf);
        Ok(())
    }

    /// Adds the bed's change over the call that just ended (`hf` now against
    /// `bed_start`) to the deposit: the deposit mirrors the bed to one
    /// rounding, and the steps need not read and write a deposit plane.
    fn add_deposit(&mut self, hf: &HeightField) {
        let nx = self.nx;
        let (now, start) = (hf.heights().as_slice(), self.bed_start.as_slice());
        bands::map_bands(nx, self.ny, [self.deposit.as_mut_slice()], |y0, y1, [d]| {
            let (now, start) = (&now[y0 * nx..y1 * nx], &start[y0 * nx..y1 * nx]);
            for ((d, &h), &h0) in d.iter_mut().zip(now).zip(start) {
                *d += h - h0;
            }
        });
    }

    /// One step. With the default conservative transport the whole step is
    /// one fused sweep per chunk of rows (`one_pass.rs`); the semi-Lagrangian
    /// transport (which gathers from up to two rows away) runs as three
    /// passes over the grid (`reference.rs`). Both use
    /// the same row functions, which send the interior of each row through
    /// branch-free slice kernels (vectorised at the CPU's widest SIMD level)
    /// and the grid's edge cells through the general per-cell code that
    /// resolves closed, open and periodic neighbours; every path computes the
    /// same operations in the same order, so they agree bit for bit (only the
    /// evaporation ledger is summed in a different order).
    fn step_unchecked(&mut self, hf: &mut HeightField, path: Path) {
        let c = Step {
            k: Coefficients::new(&self.p, self.cell),
            nx: self.nx,
            ny: self.ny,
            edges: self.p.edges,
            simd: match path {
                Path::Reference => None,
                Path::Rows(simd) | Path::Fused { simd, .. } => Some(simd),
            },
        };
        let n = if self.keeps_velocity() {
            self.nx * self.ny
        } else {
            0
        };
        for p in &mut self.vel {
            p.resize(n, 0.0);
        }
        match path {
            Path::Fused { chunk_rows, .. }
                if self.p.transport == SedimentTransport::Conservative =>
            {
                self.step_fused(&c, hf, chunk_rows);
            }
            _ => self.step_passes(&c, hf),
        }
        self.ledger.rain += f64::from(c.k.rain) * (self.nx * self.ny) as f64;
        // The new bed becomes the field's heights; the old heights become scratch.
        std::mem::swap(hf.heights_mut(), &mut self.bed);
    }
}
/// Adds per-cell outflows (`(row, amount)`, in row order) to a ledger the way
/// the band passes sum them: per band of [`bands::BAND_ROWS`] rows from zero,
/// then band by band, so every path gives the same ledger bit for bit.
fn replay(ledger: &mut f64, contributions: &[(usize, f64)]) {
    let mut i = 0;
    while i < contributions.len() {
        let band = contributions[i].0 / bands::BAND_ROWS;
        let mut acc = 0.0f64;
        while i < contributions.len() && contributions[i].0 / bands::BAND_ROWS == band {
            acc += contributions[i].1;
            i += 1;
        }
        *ledger += acc;
    }
}
