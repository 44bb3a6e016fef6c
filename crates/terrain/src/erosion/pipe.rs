//! Virtual-pipe shallow-water hydraulic erosion (Mei, Decaudin & Hu 2007,
//! "Fast Hydraulic Erosion Simulation and Visualization on GPU"; the pipe model
//! is O'Brien & Hodgins 1995). Not in Musgrave's texts: it is the stable
//! successor of the hydraulic scheme of Musgrave et al. 1989, §4.1, and keeps
//! its `K_c / K_s / K_d` naming.
//!
//! Per step (`l` = cell size, `A` = pipe cross-section, `g` = gravity):
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

// The kernels index many parallel row slices with one counter (the form that vectorises).
#![allow(clippy::needless_range_loop)]

use natura_core::{Grid2, HeightField, Progress};

use super::{Edges, Erodibility, check_erodibility, check_field, check_model_size};
use crate::error::{Result, in_range, invalid, non_negative, positive};
use crate::par;

/// How suspended sediment moves with the water.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SedimentTransport {
    /// Through the pipes with the water: conserves mass (default).
    Conservative,
    /// Semi-Lagrangian back-tracing along the velocity field, as Mei et al.
    /// publish it: smoother, but does not conserve sediment.
    SemiLagrangian,
}

/// Parameters of [`PipeModel`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    /// Interior cells through the row kernels (false only in tests: every
    /// cell through the general per-cell path, the fast path's oracle).
    fast: bool,
    /// Conservative transport as one fused sweep (false only in tests: the
    /// three-pass path, the fused sweep's oracle).
    fused: bool,
    /// Rows per chunk of the fused sweep.
    chunk_rows: usize,
}

/// Rows per chunk of the fused sweep: enough chunks to balance the cores,
/// few enough that the halos recomputed at chunk boundaries stay cheap.
const CHUNK_ROWS: usize = 64;

const L: usize = 0;
const R: usize = 1;
const B: usize = 2;
const T: usize = 3;

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
            fast: true,
            fused: true,
            chunk_rows: CHUNK_ROWS,
        })
    }

    /// Scales `K_s` per cell.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if the erodibility map is not the
    /// field's size.
    pub fn with_erodibility(mut self, e: Erodibility) -> Result<Self> {
        check_erodibility(Some(&e), self.nx, self.ny)?;
        if f64::from(e.max()) * self.p.k_s > 1.0 {
            return Err(invalid("erodibility", e.max(), "max × k_s must be ≤ 1"));
        }
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
        self.ledger.rain += water.sum() - par::sum_f32(&self.water);
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
        par::sum_f32(&self.water)
    }

    /// Σ suspended sediment, metres.
    #[must_use]
    pub fn total_sediment(&self) -> f64 {
        par::sum_f32(&self.sediment)
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
        check_field("pipe-model erosion", hf, self.nx, self.ny)?;
        progress.start("pipe model", u64::from(steps));
        for k in 0..steps {
            self.step_unchecked(hf);
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
        check_field("pipe-model erosion", hf, self.nx, self.ny)?;
        self.step_unchecked(hf);
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
        par::map_bands(nx, self.ny, [self.deposit.as_mut_slice()], |y0, y1, [d]| {
            let (now, start) = (&now[y0 * nx..y1 * nx], &start[y0 * nx..y1 * nx]);
            for ((d, &h), &h0) in d.iter_mut().zip(now).zip(start) {
                *d += h - h0;
            }
        });
    }

    /// One step. With the default conservative transport the whole step is
    /// one fused sweep per chunk of rows ([`Self::step_fused`]); the
    /// semi-Lagrangian transport (which gathers from up to two rows away)
    /// runs as three passes over the grid ([`Self::step_passes`]). Both use
    /// the same row functions, which send the interior of each row through
    /// branch-free slice kernels (vectorised at the CPU's widest SIMD level)
    /// and the grid's edge cells through the general per-cell code that
    /// resolves closed, open and periodic neighbours; every path computes the
    /// same operations in the same order, so they agree bit for bit (only the
    /// evaporation ledger is summed in a different order).
    fn step_unchecked(&mut self, hf: &mut HeightField) {
        let c = Consts::new(&self.p, self.cell, self.nx, self.ny);
        let n = if self.keeps_velocity() {
            self.nx * self.ny
        } else {
            0
        };
        for p in &mut self.vel {
            p.resize(n, 0.0);
        }
        if self.fast && self.fused && self.p.transport == SedimentTransport::Conservative {
            self.step_fused(&c, hf);
        } else {
            self.step_passes(&c, hf, self.fast);
        }
        self.ledger.rain += f64::from(c.rain) * (self.nx * self.ny) as f64;
        // The new bed becomes the field's heights; the old heights become scratch.
        std::mem::swap(hf.heights_mut(), &mut self.bed);
    }

    /// Rows `[y0, y1)` of each chunk of the fused sweep: about `chunk_rows`
    /// rows each, depending only on the grid size (never on the thread count).
    fn chunks(&self) -> Vec<(usize, usize)> {
        let ny = self.ny;
        // At most eight chunks: halos cost rows, and two to eight cores share them.
        let rows = self.chunk_rows.max(ny / 8).max(1);
        let n = ny.div_ceil(rows).max(1);
        (0..n).map(|k| (k * ny / n, (k + 1) * ny / n)).collect()
    }

    /// The step as one sweep per chunk of rows. Within a chunk, iteration
    /// `t` runs pass A (rain, fluxes) on row `t`, pass B (depth, velocity,
    /// erosion, evaporation) on row `t − 1` and the conservative transport
    /// (pass C) on row `t − 2`, so each row of every plane is read from
    /// memory once per step while its neighbours are still in cache. Water,
    /// fluxes and sediment are updated in place: pass A of row `t` reads the
    /// old water of row `t − 1` before pass B overwrites it, and `d₁` and the
    /// post-erosion sediment live in four-row rings. What a chunk needs of
    /// the rows just outside it (old water, `d₁`, new fluxes, post-erosion
    /// sediment) is computed first, from the untouched state, by [`halo`].
    fn step_fused(&mut self, c: &Consts, hf: &HeightField) {
        let nx = self.nx;
        let chunks = self.chunks();
        let periodic = self.p.edges == Edges::Periodic;
        let bed = hf.heights().as_slice();
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        // Halo index of the boundary below each chunk (none below row 0 unless periodic).
        let mut bounds = Vec::new();
        let mut below = Vec::with_capacity(chunks.len());
        for &(y0, _) in &chunks {
            if y0 > 0 || periodic {
                below.push(Some(bounds.len()));
                bounds.push(y0);
            } else {
                below.push(None);
            }
        }
        let halos: Vec<Halo> = {
            let st = Planes {
                water: &self.water,
                sediment: &self.sediment,
                flux: &self.flux,
                bed,
                erod,
            };
            par::run(bounds, |yb| halo(c, &st, yb))
        };
        let [u, v] = &mut self.vel;
        let [f0, f1, f2, f3] = &mut self.flux;
        let planes = [
            self.water.as_mut_slice(),
            self.sediment.as_mut_slice(),
            f0.as_mut_slice(),
            f1.as_mut_slice(),
            f2.as_mut_slice(),
            f3.as_mut_slice(),
            self.bed.as_mut_slice(),
            u.as_mut_slice(),
            v.as_mut_slice(),
        ];
        let mut parts = planes.map(|p| split_rows(p, nx, &chunks).into_iter());
        let n = chunks.len();
        let jobs: Vec<_> = (0..n)
            .map(|k| {
                let planes: [&mut [f32]; 9] =
                    std::array::from_fn(|i| parts[i].next().expect("one part per chunk"));
                let lower = below[k].map(|h| &halos[h]);
                let upper = if k + 1 < n {
                    below[k + 1].map(|h| &halos[h])
                } else {
                    below[0].map(|h| &halos[h])
                };
                (chunks[k], planes, lower, upper)
            })
            .collect();
        let results = par::run(jobs, |((y0, y1), planes, lower, upper)| {
            sweep(c, y0, y1, planes, bed, erod, lower, upper)
        });
        let (mut out_w, mut out_s) = (Vec::new(), Vec::new());
        for (e, w, s) in results {
            self.ledger.evaporated += e;
            out_w.extend(w);
            out_s.extend(s);
        }
        replay(&mut self.ledger.outflow_water, &out_w);
        replay(&mut self.ledger.outflow_sediment, &out_s);
    }

    /// The step as three passes over the grid (rain and fluxes; depth,
    /// velocity, erosion and evaporation; sediment transport), each a gather
    /// over row bands. `simd` sends the interior of each row through the
    /// slice kernels; without it every cell takes the general path (the
    /// oracle of the tests).
    fn step_passes(&mut self, c: &Consts, hf: &HeightField, simd: bool) {
        let (nx, ny) = (self.nx, self.ny);
        self.water1.resize(nx * ny, 0.0);
        self.sediment1.resize(nx * ny, 0.0);
        let bed = hf.heights().as_slice();
        // ---- pass A: rain and outflow fluxes (in place: each cell owns its 4 pipes).
        {
            let water = &self.water;
            let [fl, fr, fb, ft] = &mut self.flux;
            let outs = [
                self.water1.as_mut_slice(),
                fl.as_mut_slice(),
                fr.as_mut_slice(),
                fb.as_mut_slice(),
                ft.as_mut_slice(),
            ];
            par::map_bands(nx, ny, outs, |y0, y1, [d1o, fl, fr, fb, ft]| {
                for y in y0..y1 {
                    let r = (y - y0) * nx..(y - y0 + 1) * nx;
                    a_row(
                        c,
                        simd,
                        c.rows(water, y),
                        c.rows(bed, y),
                        [
                            &mut fl[r.clone()],
                            &mut fr[r.clone()],
                            &mut fb[r.clone()],
                            &mut ft[r.clone()],
                        ],
                        &mut d1o[r],
                    );
                }
            });
        }
        // ---- pass B: depth, velocity, erosion / deposition, evaporation.
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        // The three passes always compute u and v (the semi-Lagrangian transport reads them).
        for p in &mut self.vel {
            p.resize(nx * ny, 0.0);
        }
        let results: Vec<(f64, Vec<(usize, f64)>)> = {
            let d1 = &self.water1;
            let f = &self.flux;
            let s0 = &self.sediment;
            let [u, v] = &mut self.vel;
            let outs = [
                self.water.as_mut_slice(),
                self.bed.as_mut_slice(),
                self.sediment1.as_mut_slice(),
                u.as_mut_slice(),
                v.as_mut_slice(),
            ];
            par::map_bands(nx, ny, outs, |y0, y1, [wo, bo, so, uo, vo]| {
                let mut evaporated = 0.0f64;
                let mut out_w = Vec::new();
                for y in y0..y1 {
                    let r = (y - y0) * nx..(y - y0 + 1) * nx;
                    let g = y * nx..(y + 1) * nx;
                    let ins = BIn {
                        d1: &d1[g.clone()],
                        f: std::array::from_fn(|k| c.rows(&f[k], y)),
                        s0: &s0[g.clone()],
                        bed: c.rows(bed, y),
                        erod: erod.map(|e| &e[g.clone()]),
                    };
                    let outs = [
                        &mut wo[r.clone()],
                        &mut bo[r.clone()],
                        &mut so[r.clone()],
                        &mut uo[r.clone()],
                        &mut vo[r],
                    ];
                    evaporated += b_row(c, simd, &ins, outs, y, &mut out_w);
                }
                (evaporated, out_w)
            })
        };
        let mut out_w = Vec::new();
        for (e, o) in results {
            self.ledger.evaporated += e;
            out_w.extend(o);
        }
        replay(&mut self.ledger.outflow_water, &out_w);
        // ---- pass C: sediment transport.
        let s1 = &self.sediment1;
        let d1 = &self.water1;
        let f = &self.flux;
        let (u, v) = (&self.vel[0], &self.vel[1]);
        let transport = self.p.transport;
        let outflow_s: Vec<Vec<(usize, f64)>> =
            par::map_bands(nx, ny, [self.sediment.as_mut_slice()], |y0, y1, [so]| {
                let mut out_s = Vec::new();
                for y in y0..y1 {
                    let row = &mut so[(y - y0) * nx..(y - y0 + 1) * nx];
                    match transport {
                        SedimentTransport::Conservative => c_row(
                            c,
                            simd,
                            c.rows(d1, y),
                            std::array::from_fn(|k| c.rows(&f[k], y)),
                            c.rows(s1, y),
                            row,
                            y,
                            &mut out_s,
                        ),
                        SedimentTransport::SemiLagrangian => sl_row(c, simd, u, v, s1, y, row),
                    }
                }
                out_s
            });
        replay(&mut self.ledger.outflow_sediment, &outflow_s.concat());
    }
}

/// Adds per-cell outflows (`(row, amount)`, in row order) to a ledger the way
/// the band passes sum them: per band of [`par::BAND_ROWS`] rows from zero,
/// then band by band, so every path gives the same ledger bit for bit.
fn replay(ledger: &mut f64, contributions: &[(usize, f64)]) {
    let mut i = 0;
    while i < contributions.len() {
        let band = contributions[i].0 / par::BAND_ROWS;
        let mut acc = 0.0f64;
        while i < contributions.len() && contributions[i].0 / par::BAND_ROWS == band {
            acc += contributions[i].1;
            i += 1;
        }
        *ledger += acc;
    }
}

/// Splits a row-major plane `nx` wide into the rows of each chunk.
fn split_rows<'a>(
    mut p: &'a mut [f32],
    nx: usize,
    chunks: &[(usize, usize)],
) -> Vec<&'a mut [f32]> {
    let mut parts = Vec::with_capacity(chunks.len());
    if p.is_empty() {
        // A plane not kept (u, v): an empty part per chunk.
        parts.resize_with(chunks.len(), || &mut [][..]);
        return parts;
    }
    for &(y0, y1) in chunks {
        let (a, b) = std::mem::take(&mut p).split_at_mut((y1 - y0) * nx);
        parts.push(a);
        p = b;
    }
    parts
}

/// The state a halo is computed from (untouched during the halo pass).
struct Planes<'a> {
    water: &'a [f32],
    sediment: &'a [f32],
    flux: &'a [Vec<f32>; 4],
    bed: &'a [f32],
    erod: Option<&'a [f32]>,
}

/// What the chunks on either side of the boundary below row `yb` need of
/// each other's rows: rows `yb − 1` (index 0) and `yb` (index 1, wrapped) of
/// the old water, `d₁`, the new fluxes and the post-erosion sediment.
struct Halo {
    w: [Vec<f32>; 2],
    d1: [Vec<f32>; 2],
    f: [[Vec<f32>; 4]; 2],
    s1: [Vec<f32>; 2],
}

/// Computes the halo of the boundary below row `yb` from the untouched
/// state: pass A on rows `yb − 2 … yb + 1` (those that exist) and pass B on
/// rows `yb − 1` and `yb`, with the same row functions as the sweep, so the
/// values are bit-identical to the ones the owning chunk computes.
fn halo(c: &Consts, st: &Planes<'_>, yb: usize) -> Halo {
    let nx = c.nx;
    let row = |g: &[f32], j: usize| g[j * nx..(j + 1) * nx].to_vec();
    let rs: [Option<usize>; 4] = std::array::from_fn(|s| c.row_at(yb as isize + s as isize - 2));
    let mut fa: [Option<[Vec<f32>; 4]>; 4] = Default::default();
    let mut d1a: [Vec<f32>; 4] = Default::default();
    for s in 0..4 {
        if let Some(r) = rs[s] {
            let mut f = st.flux.each_ref().map(|p| row(p, r));
            let mut d1 = vec![0.0f32; nx];
            let [a, b, cc, d] = &mut f;
            a_row(
                c,
                true,
                c.rows(st.water, r),
                c.rows(st.bed, r),
                [a, b, cc, d],
                &mut d1,
            );
            fa[s] = Some(f);
            d1a[s] = d1;
        }
    }
    let mut s1: [Vec<f32>; 2] = Default::default();
    for (h, s) in [(0usize, 1usize), (1, 2)] {
        let r = rs[s].expect("the rows on both sides of a boundary exist");
        let frows = |k: usize| Rows {
            b: fa[s - 1].as_ref().map(|f| f[k].as_slice()),
            c: fa[s].as_ref().map_or(&[][..], |f| f[k].as_slice()),
            t: fa[s + 1].as_ref().map(|f| f[k].as_slice()),
        };
        let g = r * nx..(r + 1) * nx;
        let ins = BIn {
            d1: &d1a[s],
            f: std::array::from_fn(frows),
            s0: &st.sediment[g.clone()],
            bed: c.rows(st.bed, r),
            erod: st.erod.map(|e| &e[g.clone()]),
        };
        let mut scratch: [Vec<f32>; 2] = std::array::from_fn(|_| vec![0.0f32; nx]);
        let mut out = vec![0.0f32; nx];
        let [w, b] = &mut scratch;
        b_row(
            c,
            true,
            &ins,
            [w, b, &mut out, &mut [], &mut []],
            r,
            &mut Vec::new(),
        );
        s1[h] = out;
    }
    let rl = rs[1].expect("row below the boundary");
    let rh = rs[2].expect("row above the boundary");
    let [_, f1, f2, _] = fa;
    Halo {
        w: [row(st.water, rl), row(st.water, rh)],
        d1: [std::mem::take(&mut d1a[1]), std::mem::take(&mut d1a[2])],
        f: [
            f1.expect("row below the boundary"),
            f2.expect("row above the boundary"),
        ],
        s1,
    }
}

/// One chunk `[y0, y1)` of the fused step (see [`PipeModel::step_fused`]);
/// `planes` are the chunk's rows of water, sediment, the four fluxes, the
/// new bed, u and v (empty when not kept). Returns the water evaporated and the
/// per-cell water and sediment outflows through open edges, in row order.
#[allow(clippy::too_many_arguments)]
fn sweep(
    c: &Consts,
    y0: usize,
    y1: usize,
    planes: [&mut [f32]; 9],
    bed: &[f32],
    erod: Option<&[f32]>,
    lower: Option<&Halo>,
    upper: Option<&Halo>,
) -> (f64, Outflows, Outflows) {
    let nx = c.nx;
    let [w, s, f0, f1, f2, f3, bn, u, v] = planes;
    let mut f = [f0, f1, f2, f3];
    let mut d1r = vec![0.0f32; 4 * nx];
    let mut s1r = vec![0.0f32; 4 * nx];
    let loc = |y: usize| (y - y0) * nx..(y - y0 + 1) * nx;
    let ring = |y: usize| (y % 4) * nx..(y % 4 + 1) * nx;
    // A plane's rows around `y` from the chunk (`inside`, indexed by `at`) or the halos.
    fn around<'a>(
        y: usize,
        y0: usize,
        y1: usize,
        inside: &'a [f32],
        at: impl Fn(usize) -> std::ops::Range<usize>,
        lo: Option<&'a [f32]>,
        hi: Option<&'a [f32]>,
    ) -> Rows<'a> {
        Rows {
            b: if y == y0 {
                lo
            } else {
                Some(&inside[at(y - 1)])
            },
            c: &inside[at(y)],
            t: if y + 1 == y1 {
                hi
            } else {
                Some(&inside[at(y + 1)])
            },
        }
    }
    let mut evaporated = 0.0f64;
    let (mut out_w, mut out_s) = (Vec::new(), Vec::new());
    for t in y0..y1 + 2 {
        if t < y1 {
            // Pass A on row t (reads the old water of rows t − 1 … t + 1).
            let wr = around(
                t,
                y0,
                y1,
                w,
                loc,
                lower.map(|h| h.w[0].as_slice()),
                upper.map(|h| h.w[1].as_slice()),
            );
            let [a, b, cc, d] = &mut f;
            a_row(
                c,
                true,
                wr,
                c.rows(bed, t),
                [
                    &mut a[loc(t)],
                    &mut b[loc(t)],
                    &mut cc[loc(t)],
                    &mut d[loc(t)],
                ],
                &mut d1r[ring(t)],
            );
        }
        if t > y0 && t - 1 < y1 {
            // Pass B on row y = t − 1 (new fluxes of rows y − 1 … y + 1 are known).
            let y = t - 1;
            let ins = BIn {
                d1: &d1r[ring(y)],
                f: std::array::from_fn(|k| {
                    around(
                        y,
                        y0,
                        y1,
                        f[k],
                        loc,
                        lower.map(|h| h.f[0][k].as_slice()),
                        upper.map(|h| h.f[1][k].as_slice()),
                    )
                }),
                s0: &s[loc(y)],
                bed: c.rows(bed, y),
                erod: erod.map(|e| &e[y * nx..(y + 1) * nx]),
            };
            let outs = [
                &mut w[loc(y)],
                &mut bn[loc(y)],
                &mut s1r[ring(y)],
                opt_rows(u, loc(y)),
                opt_rows(v, loc(y)),
            ];
            evaporated += b_row(c, true, &ins, outs, y, &mut out_w);
        }
        if t >= y0 + 2 {
            // Pass C on row y = t − 2 (post-erosion sediment of rows y − 1 … y + 1 is known).
            let y = t - 2;
            let d1 = around(
                y,
                y0,
                y1,
                &d1r,
                ring,
                lower.map(|h| h.d1[0].as_slice()),
                upper.map(|h| h.d1[1].as_slice()),
            );
            let fr = std::array::from_fn(|k| {
                around(
                    y,
                    y0,
                    y1,
                    f[k],
                    loc,
                    lower.map(|h| h.f[0][k].as_slice()),
                    upper.map(|h| h.f[1][k].as_slice()),
                )
            });
            let s1 = around(
                y,
                y0,
                y1,
                &s1r,
                ring,
                lower.map(|h| h.s1[0].as_slice()),
                upper.map(|h| h.s1[1].as_slice()),
            );
            c_row(c, true, d1, fr, s1, &mut s[loc(y)], y, &mut out_s);
        }
    }
    (evaporated, out_w, out_s)
}

/// `p[r]`, or `p` itself if it is empty (a plane not kept).
#[inline]
fn opt_rows(p: &mut [f32], r: std::ops::Range<usize>) -> &mut [f32] {
    if p.is_empty() { p } else { &mut p[r] }
}

/// Per-cell outflows through open edges, `(row, amount)` in row order.
type Outflows = Vec<(usize, f64)>;

/// Rows `y − 1`, `y` and `y + 1` of a plane; `None` beyond a closed or open
/// edge (periodic edges give the wrapped row).
#[derive(Clone, Copy)]
struct Rows<'a> {
    b: Option<&'a [f32]>,
    c: &'a [f32],
    t: Option<&'a [f32]>,
}

impl<'a> Rows<'a> {
    /// The interior cells `1..nx − 1` and their four neighbours, if both
    /// neighbouring rows exist.
    #[inline]
    fn around(self) -> Option<Around<'a>> {
        let (b, t) = (self.b?, self.t?);
        let n = self.c.len();
        Some(Around {
            c: &self.c[1..n - 1],
            l: &self.c[..n - 2],
            r: &self.c[2..],
            b: &b[1..n - 1],
            t: &t[1..n - 1],
        })
    }
}

/// Pass A over a row: `d₁` and the in-place update of the row's fluxes.
fn a_row(c: &Consts, simd: bool, w: Rows<'_>, bed: Rows<'_>, f: [&mut [f32]; 4], d1o: &mut [f32]) {
    let nx = c.nx;
    let [fl, fr, fb, ft] = f;
    if let (true, Some(wa), Some(ba)) = (simd, w.around(), bed.around()) {
        for x in [0, nx - 1] {
            d1o[x] = c.flux_cell(x, w, bed, [&mut fl[x], &mut fr[x], &mut fb[x], &mut ft[x]]);
        }
        let m = 1..nx - 1;
        flux_row(
            c,
            wa,
            ba,
            [
                &mut d1o[m.clone()],
                &mut fl[m.clone()],
                &mut fr[m.clone()],
                &mut fb[m.clone()],
                &mut ft[m],
            ],
        );
    } else {
        for x in 0..nx {
            d1o[x] = c.flux_cell(x, w, bed, [&mut fl[x], &mut fr[x], &mut fb[x], &mut ft[x]]);
        }
    }
}

/// Pass-B inputs of one row.
#[derive(Clone, Copy)]
struct BIn<'a> {
    d1: &'a [f32],
    f: [Rows<'a>; 4],
    s0: &'a [f32],
    bed: Rows<'a>,
    erod: Option<&'a [f32]>,
}

/// Pass B over row `y`: writes water, bed, post-erosion sediment and (unless
/// their slices are empty) u and v; returns the water evaporated and appends each
/// cell's outflow through open edges to `out`.
fn b_row(
    c: &Consts,
    simd: bool,
    ins: &BIn<'_>,
    outs: [&mut [f32]; 5],
    y: usize,
    out: &mut Vec<(usize, f64)>,
) -> f64 {
    let nx = c.nx;
    let [wo, bo, so, uo, vo] = outs;
    let vel = !uo.is_empty();
    let mut evaporated = 0.0f64;
    let mut cell = |x: usize| {
        let (lost, o, [u, v]) = c.update_cell(x, ins, [&mut wo[x], &mut bo[x], &mut so[x]]);
        if vel {
            (uo[x], vo[x]) = (u, v);
        }
        evaporated += f64::from(lost);
        if o != 0.0 {
            out.push((y, o));
        }
    };
    let f = ins.f.map(Rows::around);
    if let (true, [Some(fl), Some(fr), Some(fb), Some(ft)], Some(bed)) = (simd, f, ins.bed.around())
    {
        cell(0);
        cell(nx - 1);
        let m = 1..nx - 1;
        let ui = UpdateIn {
            d1: &ins.d1[m.clone()],
            f: [fl, fr, fb, ft],
            s0: &ins.s0[m.clone()],
            bed,
        };
        let outs = [
            &mut wo[m.clone()],
            &mut bo[m.clone()],
            &mut so[m.clone()],
            opt_rows(uo, m.clone()),
            opt_rows(vo, m.clone()),
        ];
        evaporated += match ins.erod {
            Some(e) => update_row_erodible(c, &ui, &e[m], outs),
            None => update_row_uniform(c, &ui, outs),
        };
    } else {
        (0..nx).for_each(cell);
    }
    evaporated
}

/// Conservative transport over row `y`; appends each cell's sediment
/// outflow through open edges to `out`.
#[allow(clippy::too_many_arguments)]
fn c_row(
    c: &Consts,
    simd: bool,
    d1: Rows<'_>,
    f: [Rows<'_>; 4],
    s1: Rows<'_>,
    so: &mut [f32],
    y: usize,
    out: &mut Vec<(usize, f64)>,
) {
    let nx = c.nx;
    let mut cell = |x: usize| {
        let (s, o) = c.conservative_cell(x, d1, &f, s1);
        so[x] = s;
        if o != 0.0 {
            out.push((y, o));
        }
    };
    let fa = f.map(Rows::around);
    if let (true, Some(da), [Some(fl), Some(fr), Some(fb), Some(ft)], Some(sa)) =
        (simd, d1.around(), fa, s1.around())
    {
        cell(0);
        cell(nx - 1);
        conservative_row(c, da, [fl, fr, fb, ft], sa, &mut so[1..nx - 1]);
    } else {
        (0..nx).for_each(cell);
    }
}

/// Semi-Lagrangian transport over row `y` (interior cells of interior rows
/// through the slice kernel).
fn sl_row(c: &Consts, simd: bool, u: &[f32], v: &[f32], s1: &[f32], y: usize, so: &mut [f32]) {
    let (nx, ny) = (c.nx, c.ny);
    let wrap = c.edges == Edges::Periodic;
    let mut cell = |x: usize| {
        let i = y * nx + x;
        let px = x as f32 - u[i] * c.sl_step;
        let py = y as f32 - v[i] * c.sl_step;
        so[x] = sample(s1, nx, ny, px, py, wrap);
    };
    if simd && y > 0 && y + 1 < ny {
        cell(0);
        cell(nx - 1);
        let i0 = y * nx + 1;
        let m = nx - 2;
        semi_lagrangian_row(c, &u[i0..i0 + m], &v[i0..i0 + m], s1, y, &mut so[1..nx - 1]);
    } else {
        (0..nx).for_each(cell);
    }
}

/// Step constants shared by the general and the fast paths.
#[derive(Clone, Copy, Debug)]
struct Consts {
    nx: usize,
    ny: usize,
    edges: Edges,
    rain: f32,
    kflux: f32,
    dt: f32,
    area: f32,
    cell: f32,
    kc: f32,
    ks: f32,
    kd: f32,
    evap: f32,
    min_tilt: f32,
    inv_dref: f32,
    /// `Δt / l²`.
    dt_area: f32,
    /// `1 / (2l)`.
    inv_2cell: f32,
    vmax: f32,
    sl_step: f32,
}

impl Consts {
    fn new(p: &PipeParams, l: f32, nx: usize, ny: usize) -> Self {
        let dt = p.dt as f32;
        Self {
            nx,
            ny,
            edges: p.edges,
            rain: (p.rain_m_per_s * p.dt) as f32,
            kflux: (p.dt * p.pipe_area * p.gravity / f64::from(l)) as f32,
            dt,
            area: l * l,
            cell: l,
            kc: p.k_c as f32,
            ks: p.k_s as f32,
            kd: p.k_d as f32,
            evap: (p.k_e * p.dt) as f32,
            min_tilt: p.min_tilt as f32,
            inv_dref: 1.0 / p.depth_ref as f32,
            dt_area: (p.dt / (f64::from(l) * f64::from(l))) as f32,
            inv_2cell: (0.5 / f64::from(l)) as f32,
            vmax: l / dt,
            sl_step: dt / l,
        }
    }

    /// Row `y` (which may lie outside `0..ny`) resolved through the edges.
    #[inline]
    fn row_at(&self, y: isize) -> Option<usize> {
        let ny = self.ny as isize;
        if (0..ny).contains(&y) {
            Some(y as usize)
        } else if self.edges == Edges::Periodic {
            Some(y.rem_euclid(ny) as usize)
        } else {
            None
        }
    }

    /// Rows `y − 1`, `y`, `y + 1` of the full plane `g`.
    #[inline]
    fn rows<'a>(&self, g: &'a [f32], y: usize) -> Rows<'a> {
        let nx = self.nx;
        let row = |j: usize| &g[j * nx..(j + 1) * nx];
        Rows {
            b: self.row_at(y as isize - 1).map(row),
            c: row(y),
            t: self.row_at(y as isize + 1).map(row),
        }
    }

    /// Neighbour `k` (L, R, B, T) of cell `x` of the centre row of `p`, resolved through the edges.
    #[inline]
    fn nb(&self, p: Rows<'_>, x: usize, k: usize) -> Option<f32> {
        let nx = self.nx;
        let periodic = self.edges == Edges::Periodic;
        match k {
            L if x > 0 => Some(p.c[x - 1]),
            L => periodic.then(|| p.c[nx - 1]),
            R if x + 1 < nx => Some(p.c[x + 1]),
            R => periodic.then(|| p.c[0]),
            B => p.b.map(|r| r[x]),
            _ => p.t.map(|r| r[x]),
        }
    }

    /// Pass A for one cell: returns `d₁` and updates the cell's four fluxes.
    #[inline]
    fn flux_cell(&self, x: usize, water: Rows<'_>, bed: Rows<'_>, f: [&mut f32; 4]) -> f32 {
        let d1 = water.c[x] + self.rain;
        let h = bed.c[x] + d1;
        let open = self.edges == Edges::Open;
        let hn: [f32; 4] =
            std::array::from_fn(|k| match (self.nb(bed, x, k), self.nb(water, x, k)) {
                (Some(b), Some(w)) => b + w + self.rain,
                _ if open => bed.c[x],
                _ => f32::INFINITY,
            });
        let mut nf = [0.0f32; 4];
        let mut sum = 0.0;
        for k in 0..4 {
            let v = fmax(*f[k] + self.kflux * (h - hn[k]), 0.0);
            nf[k] = v;
            sum += v;
        }
        let scale = flux_scale(sum, d1, self.dt, self.area);
        for (o, v) in f.into_iter().zip(nf) {
            *o = v * scale;
        }
        d1
    }

    /// Pass B for one cell: writes water, bed and sediment; returns the water
    /// evaporated, the water lost through open edges and the velocity.
    #[inline]
    fn update_cell(
        &self,
        x: usize,
        ins: &BIn<'_>,
        [wo, bo, so]: [&mut f32; 3],
    ) -> (f32, f64, [f32; 2]) {
        let f = &ins.f;
        let get = |k: usize, dir: usize| self.nb(f[dir], x, k).unwrap_or(0.0);
        let in_l = get(L, R);
        let in_r = get(R, L);
        let in_b = get(B, T);
        let in_t = get(T, B);
        let mut out_w = 0.0f64;
        if self.edges == Edges::Open {
            for k in 0..4 {
                if self.nb(ins.bed, x, k).is_none() {
                    out_w += f64::from(f[k].c[x] * self.dt / self.area);
                }
            }
        }
        let bed = ins.bed.c[x];
        let bn = |k: usize| self.nb(ins.bed, x, k).unwrap_or(bed);
        let cell = CellIn {
            d1: ins.d1[x],
            fo: [f[L].c[x], f[R].c[x], f[B].c[x], f[T].c[x]],
            fin: [in_l, in_r, in_b, in_t],
            s: ins.s0[x],
            bed,
            bn: [bn(L), bn(R), bn(B), bn(T)],
            ks: ins.erod.map_or(self.ks, |e| self.ks * e[x]),
        };
        let o = self.update(&cell);
        [*wo, *bo, *so] = [o.w, o.b, o.s];
        (o.lost, out_w, [o.u, o.v])
    }
    /// The arithmetic of pass B for one cell, shared by both paths.
    #[inline(always)]
    fn update(&self, c: &CellIn) -> CellOut {
        let [fl, fr, fb, ft] = c.fo;
        let [in_l, in_r, in_b, in_t] = c.fin;
        let out = fl + fr + fb + ft;
        let d2 = fmax(c.d1 + (in_l + in_r + in_b + in_t - out) * self.dt_area, 0.0);
        let mean_d = 0.5 * (c.d1 + d2);
        let wx = 0.5 * (in_l - fl + fr - in_r);
        let wy = 0.5 * (in_b - fb + ft - in_t);
        let wet = mean_d > 1e-6;
        // One division for both components, computed for every cell and
        // masked by a multiply: a division under the `wet` condition is
        // turned into a branch that keeps the AVX2 build scalar. (A dry
        // cell's velocity is ±0.)
        let inv = 1.0 / (self.cell * if wet { mean_d } else { 1.0 });
        let inv = inv * if wet { 1.0 } else { 0.0 };
        let vu = wx * inv;
        let vv = wy * inv;
        let vu = clamp(vu, self.vmax);
        let vv = clamp(vv, self.vmax);
        // Local tilt from central differences of the bed.
        let [bl, br, bb, bt] = c.bn;
        let gx = (br - bl) * self.inv_2cell;
        let gy = (bt - bb) * self.inv_2cell;
        let g2 = gx * gx + gy * gy;
        let sin_a = fmax((g2 / (1.0 + g2)).sqrt(), self.min_tilt);
        let speed = (vu * vu + vv * vv).sqrt();
        let cap = self.kc * sin_a * speed * fmin(d2 * self.inv_dref, 1.0);
        let s = c.s;
        let e = c.ks * (cap - s);
        let dep = self.kd * (s - cap);
        let erode = cap > s;
        let lost = d2 * self.evap;
        CellOut {
            w: d2 - lost,
            b: if erode { c.bed - e } else { c.bed + dep },
            s: if erode { s + e } else { s - dep },
            u: vu,
            v: vv,
            lost,
        }
    }

    /// Conservative transport for one cell: the new sediment and what left through open edges.
    #[inline]
    fn conservative_cell(
        &self,
        x: usize,
        d1: Rows<'_>,
        f: &[Rows<'_>; 4],
        s1: Rows<'_>,
    ) -> (f32, f64) {
        let mut out_s = 0.0f64;
        let mut keep = 1.0f32;
        let mut gained = 0.0f32;
        for k in 0..4 {
            let fo = self.frac(d1.c[x], f[k].c[x]);
            keep -= fo;
            match (
                self.nb(d1, x, k),
                self.nb(f[k ^ 1], x, k),
                self.nb(s1, x, k),
            ) {
                (Some(dj), Some(fj), Some(sj)) => gained += sj * self.frac(dj, fj),
                _ => out_s += f64::from(s1.c[x] * fo),
            }
        }
        (s1.c[x] * fmax(keep, 0.0) + gained, out_s)
    }
    /// Fraction of a cell's water `d1` that leaves through a pipe of flux `f` this step.
    #[inline(always)]
    fn frac(&self, d1: f32, f: f32) -> f32 {
        fmin(f * self.per_flux(d1), 1.0)
    }

    /// `Δt / (d₁·l²)`, the fraction of a cell's water a unit flux carries
    /// away in one step (0 for a dry cell): one division per cell, shared by
    /// its four pipes.
    #[inline(always)]
    fn per_flux(&self, d1: f32) -> f32 {
        // Divided unconditionally (a dry cell's infinity is selected away):
        // a division under a condition keeps the AVX2 build scalar.
        let q = self.dt_area / d1;
        if d1 > 0.0 { q } else { 0.0 }
    }
}

/// `a.min(b)` for non-NaN operands as one compare and select: `f32::min`'s
/// NaN rule costs a blend sequence per vector on AVX2, enough for LLVM to
/// leave whole kernels scalar there.
#[inline(always)]
fn fmin(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// `a.max(b)` for non-NaN operands as one compare and select (see [`fmin`]).
#[inline(always)]
fn fmax(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// `x.clamp(-m, m)` without `clamp`'s bounds assertion (which blocks
/// vectorisation); the same comparisons, so NaN passes through alike.
#[inline(always)]
fn clamp(x: f32, m: f32) -> f32 {
    let x = if x < -m { -m } else { x };
    if x > m { m } else { x }
}

/// The outflow scale `K = min(1, d₁·l²/(Σf·Δt))` that keeps a cell from
/// sending more water than it holds.
#[inline(always)]
fn flux_scale(sum: f32, d1: f32, dt: f32, area: f32) -> f32 {
    // Divided unconditionally (see `Consts::per_flux`).
    let k = d1 * area / (sum * dt);
    if sum * dt > d1 * area { k } else { 1.0 }
}

/// Pass-B inputs of one cell.
struct CellIn {
    d1: f32,
    /// The cell's outflows to L, R, B, T.
    fo: [f32; 4],
    /// Inflows from the L, R, B, T neighbours.
    fin: [f32; 4],
    s: f32,
    bed: f32,
    /// Bed of the L, R, B, T neighbours (the cell's own across an edge).
    bn: [f32; 4],
    ks: f32,
}

/// Pass-B outputs of one cell.
struct CellOut {
    w: f32,
    b: f32,
    s: f32,
    u: f32,
    v: f32,
    lost: f32,
}

/// A plane's values at the cells `i0..i0 + m` of one interior row and at their
/// left, right, lower and upper neighbours.
#[derive(Clone, Copy)]
struct Around<'a> {
    c: &'a [f32],
    l: &'a [f32],
    r: &'a [f32],
    b: &'a [f32],
    t: &'a [f32],
}

impl<'a> Around<'a> {
    /// The same view restricted to the cells `a..b` of the row.
    #[inline(always)]
    fn sub(&self, a: usize, b: usize) -> Self {
        Self {
            c: &self.c[a..b],
            l: &self.l[a..b],
            r: &self.r[a..b],
            b: &self.b[a..b],
            t: &self.t[a..b],
        }
    }
}

natura_core::simd::multiversion! {
/// Pass A over the interior cells of a row (every neighbour exists).
fn flux_row<'a>(c: &'a Consts, w: Around<'a>, bd: Around<'a>, outs: [&'a mut [f32]; 5]) {
    let [d1o, fl, fr, fb, ft] = outs;
    let m = d1o.len();
    let (fl, fr, fb, ft) = (&mut fl[..m], &mut fr[..m], &mut fb[..m], &mut ft[..m]);
    let (wc, wl, wr, wb, wt) = (&w.c[..m], &w.l[..m], &w.r[..m], &w.b[..m], &w.t[..m]);
    let (bc, bl, br, bb, bt) = (&bd.c[..m], &bd.l[..m], &bd.r[..m], &bd.b[..m], &bd.t[..m]);
    let (rain, kflux) = (c.rain, c.kflux);
    for k in 0..m {
        let d1 = wc[k] + rain;
        let h = bc[k] + d1;
        let vl = fmax(fl[k] + kflux * (h - (bl[k] + wl[k] + rain)), 0.0);
        let vr = fmax(fr[k] + kflux * (h - (br[k] + wr[k] + rain)), 0.0);
        let vb = fmax(fb[k] + kflux * (h - (bb[k] + wb[k] + rain)), 0.0);
        let vt = fmax(ft[k] + kflux * (h - (bt[k] + wt[k] + rain)), 0.0);
        let mut sum = 0.0;
        sum += vl;
        sum += vr;
        sum += vb;
        sum += vt;
        let scale = flux_scale(sum, d1, c.dt, c.area);
        fl[k] = vl * scale;
        fr[k] = vr * scale;
        fb[k] = vb * scale;
        ft[k] = vt * scale;
        d1o[k] = d1;
    }
}
}

/// Pass-B inputs of one interior row.
struct UpdateIn<'a> {
    d1: &'a [f32],
    f: [Around<'a>; 4],
    s0: &'a [f32],
    bed: Around<'a>,
}

/// Cells per block of [`update_row`] (the evaporation of a block is summed on the stack).
const BLOCK: usize = 128;

natura_core::simd::multiversion! {
/// Pass B over the interior cells of a row (uniform `K_s`); returns the water evaporated.
fn update_row_uniform<'a>(c: &'a Consts, ins: &'a UpdateIn<'a>, outs: [&'a mut [f32]; 5]) -> f64 {
    update_row::<false>(c, ins, &[], outs)
}
}

natura_core::simd::multiversion! {
/// Pass B over the interior cells of a row with an erodibility map; returns the water evaporated.
fn update_row_erodible<'a>(c: &'a Consts, ins: &'a UpdateIn<'a>, erod: &'a [f32], outs: [&'a mut [f32]; 5]) -> f64 {
    update_row::<true>(c, ins, erod, outs)
}
}

/// Pass B over the interior cells of a row; returns the water evaporated.
/// `u` and `v` are stored only if their slices are not empty.
#[inline(always)]
fn update_row<const ERODIBILITY: bool>(
    c: &Consts,
    ins: &UpdateIn<'_>,
    erod: &[f32],
    outs: [&mut [f32]; 5],
) -> f64 {
    let [wo, bo, so, uo, vo] = outs;
    let m = wo.len();
    let vel = !uo.is_empty();
    let mut total = 0.0f64;
    let mut lost = [0.0f32; BLOCK];
    let mut a = 0;
    while a < m {
        let b = (a + BLOCK).min(m);
        let n = b - a;
        let d1 = &ins.d1[a..b];
        let [fl, fr, fb, ft] = ins.f.map(|p| p.sub(a, b));
        let s0 = &ins.s0[a..b];
        let bed = ins.bed.sub(a, b);
        let er = if ERODIBILITY { &erod[a..b] } else { &[][..] };
        let (wo, bo, so) = (&mut wo[a..b], &mut bo[a..b], &mut so[a..b]);
        let (uo, vo) = (opt_rows(uo, a..b), opt_rows(vo, a..b));
        let lost = &mut lost[..n];
        // Lanes of LANES cells through local arrays (no aliasing between the
        // row slices for the vectoriser to check); the last one padded.
        let mut k0 = 0;
        while k0 < n {
            let w = (n - k0).min(LANES);
            let g = |s: &[f32]| take::<LANES>(s, k0, w);
            let (dd, s) = (g(d1), g(s0));
            let (flc, frc, fbc, ftc) = (g(fl.c), g(fr.c), g(fb.c), g(ft.c));
            let (frl, flr, ftb, fbt) = (g(fr.l), g(fl.r), g(ft.b), g(fb.t));
            let (bc, bl, br, bb, bt) = (g(bed.c), g(bed.l), g(bed.r), g(bed.b), g(bed.t));
            let e = if ERODIBILITY { g(er) } else { [1.0f32; LANES] };
            let ks = if ERODIBILITY {
                lane(|k| c.ks * e[k])
            } else {
                [c.ks; LANES]
            };
            // The arithmetic of `Consts::update`, stage by stage over the
            // lane arrays: every stage is a plain map (its choices are bit
            // blends), which the AVX2 build vectorises too; the operations
            // and their order per cell are those of `update`.
            let out = lane(|k| flc[k] + frc[k] + fbc[k] + ftc[k]);
            let d2 = lane(|k| {
                let inflow = frl[k] + flr[k] + ftb[k] + fbt[k];
                fmax(dd[k] + (inflow - out[k]) * c.dt_area, 0.0)
            });
            let mean_d = lane(|k| 0.5 * (dd[k] + d2[k]));
            let inv = lane(|k| {
                let wet = mean_d[k] > 1e-6;
                let inv = 1.0 / (c.cell * pick(wet, mean_d[k], 1.0));
                inv * pick(wet, 1.0, 0.0)
            });
            let vu = lane(|k| clamp(0.5 * (frl[k] - flc[k] + frc[k] - flr[k]) * inv[k], c.vmax));
            let vv = lane(|k| clamp(0.5 * (ftb[k] - fbc[k] + ftc[k] - fbt[k]) * inv[k], c.vmax));
            let sin_a = lane(|k| {
                let gx = (br[k] - bl[k]) * c.inv_2cell;
                let gy = (bt[k] - bb[k]) * c.inv_2cell;
                let g2 = gx * gx + gy * gy;
                fmax((g2 / (1.0 + g2)).sqrt(), c.min_tilt)
            });
            let cap = lane(|k| {
                let speed = (vu[k] * vu[k] + vv[k] * vv[k]).sqrt();
                c.kc * sin_a[k] * speed * fmin(d2[k] * c.inv_dref, 1.0)
            });
            let ero = lane(|k| ks[k] * (cap[k] - s[k]));
            let dep = lane(|k| c.kd * (s[k] - cap[k]));
            let lost_k = lane(|k| d2[k] * c.evap);
            let o = [
                lane(|k| d2[k] - lost_k[k]),
                lane(|k| pick(cap[k] > s[k], bc[k] - ero[k], bc[k] + dep[k])),
                lane(|k| pick(cap[k] > s[k], s[k] + ero[k], s[k] - dep[k])),
                lost_k,
            ];
            for (d, v) in [&mut *wo, &mut *bo, &mut *so, &mut *lost]
                .into_iter()
                .zip(&o)
            {
                put(d, k0, w, v);
            }
            if vel {
                put(uo, k0, w, &vu);
                put(vo, k0, w, &vv);
            }
            k0 += w;
        }
        // Summed in f64 (eight partial sums) like the per-cell path's ledger.
        let mut acc = [0.0f64; 8];
        let mut chunks = lost.chunks_exact(8);
        for ch in &mut chunks {
            for (s, &x) in acc.iter_mut().zip(ch) {
                *s += f64::from(x);
            }
        }
        for (s, &x) in acc.iter_mut().zip(chunks.remainder()) {
            *s += f64::from(x);
        }
        total += acc.iter().sum::<f64>();
        a = b;
    }
    total
}

natura_core::simd::multiversion! {
/// Conservative transport over the interior cells of a row.
fn conservative_row<'a>(c: &'a Consts, d1: Around<'a>, f: [Around<'a>; 4], s1: Around<'a>, so: &'a mut [f32]) {
    let m = so.len();
    let d1 = d1.sub(0, m);
    let [fl, fr, fb, ft] = f.map(|p| p.sub(0, m));
    let s1 = s1.sub(0, m);
    let frac = |q: f32, f: f32| fmin(f * q, 1.0);
    // Lanes of LANES cells through local arrays (no aliasing between the
    // row slices for the vectoriser to check); the last one padded.
    let mut a = 0;
    while a < m {
        let w = (m - a).min(LANES);
        let g = |s: &[f32]| take::<LANES>(s, a, w);
        let (dc, dl, dr, db, dt) = (g(d1.c), g(d1.l), g(d1.r), g(d1.b), g(d1.t));
        let (sc, sl, sr, sb, st) = (g(s1.c), g(s1.l), g(s1.r), g(s1.b), g(s1.t));
        let (flc, frc, fbc, ftc) = (g(fl.c), g(fr.c), g(fb.c), g(ft.c));
        let (frl, flr, ftb, fbt) = (g(fr.l), g(fl.r), g(ft.b), g(fb.t));
        let mut out = [0.0f32; LANES];
        for k in 0..LANES {
            let q = c.per_flux(dc[k]);
            let mut keep = 1.0f32;
            let mut gained = 0.0f32;
            keep -= frac(q, flc[k]);
            gained += sl[k] * frac(c.per_flux(dl[k]), frl[k]);
            keep -= frac(q, frc[k]);
            gained += sr[k] * frac(c.per_flux(dr[k]), flr[k]);
            keep -= frac(q, fbc[k]);
            gained += sb[k] * frac(c.per_flux(db[k]), ftb[k]);
            keep -= frac(q, ftc[k]);
            gained += st[k] * frac(c.per_flux(dt[k]), fbt[k]);
            out[k] = sc[k] * fmax(keep, 0.0) + gained;
        }
        put(so, a, w, &out);
        a += w;
    }
}
}

/// Cells per lane group of the pass-B and transport kernels (a multiple of
/// the 8 and 16 `f32` lanes of AVX2 and AVX-512).
const LANES: usize = 16;

/// One stage of a lane-group kernel: `f` applied to every lane.
#[inline(always)]
fn lane(mut f: impl FnMut(usize) -> f32) -> [f32; LANES] {
    // A plain loop: `std::array::from_fn` leaves its closure call out of line.
    let mut x = [0.0f32; LANES];
    for (k, v) in x.iter_mut().enumerate() {
        *v = f(k);
    }
    x
}

/// `if m { a } else { b }` as a bit blend: a select LLVM keeps as a vector
/// blend on AVX2 instead of turning it into a branch.
#[inline(always)]
fn pick(m: bool, a: f32, b: f32) -> f32 {
    let mask = u32::from(m).wrapping_neg();
    f32::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// `s[a..a + n]` in a local array, padded with zeros (`n ≤ N`): every lane
/// group has a fixed width, and a padded lane's result is never stored.
#[inline(always)]
fn take<const N: usize>(s: &[f32], a: usize, n: usize) -> [f32; N] {
    let mut x = [0.0f32; N];
    if n == N {
        x.copy_from_slice(&s[a..a + N]);
    } else {
        x[..n].copy_from_slice(&s[a..a + n]);
    }
    x
}

/// Stores the first `n` lanes of `x` at `d[a..a + n]`.
#[inline(always)]
fn put<const N: usize>(d: &mut [f32], a: usize, n: usize, x: &[f32; N]) {
    if n == N {
        d[a..a + N].copy_from_slice(x);
    } else {
        d[a..a + n].copy_from_slice(&x[..n]);
    }
}

natura_core::simd::multiversion! {
/// Semi-Lagrangian transport over the interior cells `1..nx − 1` of row `y`:
/// the back-traced point lies within about one cell (velocities are capped at
/// one cell per step), so one clamp (or wrap) per index suffices.
fn semi_lagrangian_row<'a>(c: &'a Consts, u: &'a [f32], v: &'a [f32], s1: &'a [f32], y: usize, so: &'a mut [f32]) {
    let (nx, ny) = (c.nx as i64, c.ny as i64);
    let wrap = c.edges == Edges::Periodic;
    let m = so.len();
    let (u, v) = (&u[..m], &v[..m]);
    let fix = |i: i64, n: i64| {
        if wrap {
            if i < 0 {
                i + n
            } else if i >= n {
                i - n
            } else {
                i
            }
        } else {
            i.clamp(0, n - 1)
        }
    };
    let g = |x: i64, y: i64| s1[(y * nx + x) as usize];
    for k in 0..m {
        let px = (k + 1) as f32 - u[k] * c.sl_step;
        let py = y as f32 - v[k] * c.sl_step;
        let (fx, fy) = (px.floor(), py.floor());
        let (tx, ty) = (px - fx, py - fy);
        let (ix, iy) = (fx as i64, fy as i64);
        let (x0, x1) = (fix(ix, nx), fix(ix + 1, nx));
        let (y0, y1) = (fix(iy, ny), fix(iy + 1, ny));
        let a = g(x0, y0) + (g(x1, y0) - g(x0, y0)) * tx;
        let b = g(x0, y1) + (g(x1, y1) - g(x0, y1)) * tx;
        so[k] = a + (b - a) * ty;
    }
}
}

/// Bilinear sample of a row-major grid in cell units, clamped (or wrapped).
fn sample(g: &[f32], nx: usize, ny: usize, x: f32, y: f32, wrap: bool) -> f32 {
    let (fx, fy) = (x.floor(), y.floor());
    let (tx, ty) = (x - fx, y - fy);
    let idx = |i: i64, n: usize| {
        if wrap {
            i.rem_euclid(n as i64) as usize
        } else {
            i.clamp(0, n as i64 - 1) as usize
        }
    };
    let (x0, x1) = (idx(fx as i64, nx), idx(fx as i64 + 1, nx));
    let (y0, y1) = (idx(fy as i64, ny), idx(fy as i64 + 1, ny));
    let a = g[y0 * nx + x0] + (g[y0 * nx + x1] - g[y0 * nx + x0]) * tx;
    let b = g[y1 * nx + x0] + (g[y1 * nx + x1] - g[y1 * nx + x0]) * tx;
    a + (b - a) * ty
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::{NoProgress, Seed};

    fn hills(n: usize) -> HeightField {
        let s = Seed(2);
        HeightField::from_fn(n, n, 2.0, |i, j| {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            30.0 * (3.0 * x).sin() * (2.0 * y).cos()
                + 40.0 * x
                + s.gaussian2(i as i64, j as i64) as f32
        })
        .unwrap()
    }

    #[test]
    fn conserves_mass_closed_and_open() {
        for edges in [Edges::Closed, Edges::Open, Edges::Periodic] {
            let mut hf = hills(40);
            let mut m = PipeModel::new(
                PipeParams {
                    edges,
                    ..Default::default()
                },
                &hf,
            )
            .unwrap();
            let mat0 = hf.heights().sum();
            m.run(&mut hf, 500, &NoProgress).unwrap();
            let l = m.ledger();
            let mat = hf.heights().sum() + m.total_sediment() + l.outflow_sediment;
            assert!(
                (mat - mat0).abs() <= 1e-4 * mat0.abs(),
                "{edges:?}: material {mat0} → {mat}"
            );
            let water = m.total_water();
            let budget = l.rain - l.evaporated - l.outflow_water;
            assert!(
                (water - budget).abs() <= 1e-4 * l.rain,
                "{edges:?}: water {water} vs {budget}"
            );
            assert!(m.water.iter().all(|&w| w >= 0.0) && m.sediment.iter().all(|&s| s >= 0.0));
            if edges == Edges::Open {
                assert!(l.outflow_water > 0.0);
            }
        }
    }

    /// The row kernels (interior cells) against the general per-cell path on
    /// rough random fields with random water and sediment, for every edge
    /// mode, both transports and with an erodibility map: same operations in
    /// the same order, so every field must match bit for bit (±0 aside), and
    /// the ledgers (summed in a different order) to 1e-9.
    #[test]
    fn fast_interior_path_equals_general_path() {
        let s = Seed(11);
        for (case, (edges, transport, erodible)) in [
            (Edges::Closed, SedimentTransport::Conservative, false),
            (Edges::Open, SedimentTransport::Conservative, true),
            (Edges::Periodic, SedimentTransport::Conservative, false),
            (Edges::Closed, SedimentTransport::SemiLagrangian, true),
            (Edges::Open, SedimentTransport::SemiLagrangian, false),
            (Edges::Periodic, SedimentTransport::SemiLagrangian, true),
        ]
        .into_iter()
        .enumerate()
        {
            // Odd sizes and more than one block of the row kernel (129 > 128 interior cells).
            let (nx, ny) = [(37, 23), (131, 9), (5, 40)][case % 3];
            let g =
                |k: i64, i: usize, j: usize| s.derive_index(k as u64).uniform2(i as i64, j as i64);
            let hf = HeightField::from_fn(nx, ny, 1.5, |i, j| 20.0 * g(1, i, j) as f32).unwrap();
            let water = Grid2::from_fn(nx, ny, |i, j| {
                let w = g(2, i, j);
                if w < 0.2 { 0.0 } else { 2.0 * w as f32 }
            })
            .unwrap();
            let p = PipeParams {
                edges,
                transport,
                dt: 0.2,
                k_c: 0.5,
                ..Default::default()
            };
            let build = |fast: bool| {
                let mut m = PipeModel::new(p.clone(), &hf).unwrap();
                if erodible {
                    let e = Grid2::from_fn(nx, ny, |i, j| 0.5 + g(3, i, j) as f32).unwrap();
                    m = m.with_erodibility(Erodibility::new(e).unwrap()).unwrap();
                }
                m.set_water(&water).unwrap();
                m.fast = fast;
                m.record_velocity = true;
                let mut h = hf.clone();
                m.run(&mut h, 40, &NoProgress).unwrap();
                (m, h)
            };
            let (fast, hf_fast) = build(true);
            let (slow, hf_slow) = build(false);
            let same = |what: &str, a: &[f32], b: &[f32]| {
                for (k, (x, y)) in a.iter().zip(b).enumerate() {
                    assert!(x == y, "case {case}: {what}[{k}] fast {x} vs general {y}");
                }
            };
            same(
                "bed",
                hf_fast.heights().as_slice(),
                hf_slow.heights().as_slice(),
            );
            same("water", &fast.water, &slow.water);
            same("sediment", &fast.sediment, &slow.sediment);
            same("deposit", &fast.deposit, &slow.deposit);
            same("u", &fast.vel[0], &slow.vel[0]);
            same("v", &fast.vel[1], &slow.vel[1]);
            for k in 0..4 {
                same("flux", &fast.flux[k], &slow.flux[k]);
            }
            assert!(fast.total_sediment() > 0.0, "case {case}: nothing eroded");
            let (a, b) = (fast.ledger(), slow.ledger());
            assert_eq!(a.rain, b.rain);
            assert_eq!(a.outflow_water, b.outflow_water);
            assert_eq!(a.outflow_sediment, b.outflow_sediment);
            assert!(
                (a.evaporated - b.evaporated).abs() <= 1e-9 * b.evaporated.max(1.0),
                "case {case}: evaporated {} vs {}",
                a.evaporated,
                b.evaporated
            );
        }
    }

    /// The fused sweep (chunks, halos, in-place updates, row rings) against
    /// the previous three-pass path, with and without the row kernels, on
    /// rough random fields for every edge mode, with and without an
    /// erodibility map, for chunkings from one row per chunk to one chunk
    /// (and grids only three rows tall): every field must match bit for bit,
    /// the outflow ledgers exactly and the evaporation ledger to 1e-7 (the row
    /// kernel sums it in `f32` blocks). The
    /// fused sweep must also give the same bits on one and on two threads.
    #[test]
    fn fused_sweep_equals_three_pass_path() {
        let s = Seed(23);
        let g = |k: u64, i: usize, j: usize| s.derive_index(k).uniform2(i as i64, j as i64);
        let cases = [
            (Edges::Closed, false, 41, 57, 7),
            (Edges::Open, true, 40, 57, 9),
            (Edges::Periodic, false, 19, 50, 6),
            (Edges::Open, false, 23, 11, 1),
            (Edges::Periodic, true, 17, 3, 1),
            (Edges::Closed, true, 9, 3, 64),
            (Edges::Periodic, false, 21, 30, 64),
            (Edges::Open, true, 6, 70, 64),
        ];
        for (case, &(edges, erodible, nx, ny, chunk_rows)) in cases.iter().enumerate() {
            let hf = HeightField::from_fn(nx, ny, 1.5, |i, j| 20.0 * g(1, i, j) as f32).unwrap();
            let water = Grid2::from_fn(nx, ny, |i, j| {
                let w = g(2, i, j);
                if w < 0.2 { 0.0 } else { 2.0 * w as f32 }
            })
            .unwrap();
            let p = PipeParams {
                edges,
                dt: 0.2,
                k_c: 0.5,
                ..Default::default()
            };
            let build = |fast: bool, fused: bool, threads: usize| {
                let mut m = PipeModel::new(p.clone(), &hf).unwrap();
                if erodible {
                    let e = Grid2::from_fn(nx, ny, |i, j| 0.5 + g(3, i, j) as f32).unwrap();
                    m = m.with_erodibility(Erodibility::new(e).unwrap()).unwrap();
                }
                m.set_water(&water).unwrap();
                m.fast = fast;
                m.fused = fused;
                m.record_velocity = true;
                m.chunk_rows = chunk_rows;
                let mut h = hf.clone();
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| m.run(&mut h, 30, &NoProgress)).unwrap();
                (m, h)
            };
            let (fused, hf_fused) = build(true, true, 2);
            for (what, (other, hf_other)) in [
                ("three passes", build(true, false, 2)),
                ("general", build(false, false, 1)),
                ("fused, 1 thread", build(true, true, 1)),
            ] {
                let same = |field: &str, a: &[f32], b: &[f32]| {
                    for (k, (x, y)) in a.iter().zip(b).enumerate() {
                        assert!(
                            x.to_bits() == y.to_bits() || (*x == 0.0 && *y == 0.0),
                            "case {case}: {field}[{k}] fused {x} vs {what} {y}"
                        );
                    }
                };
                same(
                    "bed",
                    hf_fused.heights().as_slice(),
                    hf_other.heights().as_slice(),
                );
                same("water", &fused.water, &other.water);
                same("sediment", &fused.sediment, &other.sediment);
                same("deposit", &fused.deposit, &other.deposit);
                same("u", &fused.vel[0], &other.vel[0]);
                same("v", &fused.vel[1], &other.vel[1]);
                for k in 0..4 {
                    same("flux", &fused.flux[k], &other.flux[k]);
                }
                let (a, b) = (fused.ledger(), other.ledger());
                assert_eq!(a.rain, b.rain);
                assert_eq!(a.outflow_water, b.outflow_water, "case {case}: {what}");
                assert_eq!(
                    a.outflow_sediment, b.outflow_sediment,
                    "case {case}: {what}"
                );
                // The row kernel sums evaporation in f32 per block of cells.
                assert!(
                    (a.evaporated - b.evaporated).abs() <= 1e-7 * b.evaporated.max(1.0),
                    "case {case}: evaporated {} vs {what} {}",
                    a.evaporated,
                    b.evaporated
                );
            }
            assert!(fused.total_sediment() > 0.0, "case {case}: nothing eroded");
            if edges == Edges::Open {
                assert!(fused.ledger().outflow_sediment > 0.0, "case {case}");
            }
        }
    }

    /// Recording the velocity changes nothing else (bit for bit, fused and
    /// three-pass paths); without it `velocity()` is a typed error. The
    /// deposit mirrors the bed: after runs and single steps (split in several
    /// calls) it equals the field's change since the model was built to
    /// within the rounding of the heights, and calls that split the same steps
    /// differently agree to that rounding too.
    #[test]
    fn velocity_on_request_and_deposit_from_the_bed() {
        let s = Seed(31);
        let (nx, ny) = (45, 38);
        let g = |k: u64, i: usize, j: usize| s.derive_index(k).uniform2(i as i64, j as i64);
        let hf0 = HeightField::from_fn(nx, ny, 1.5, |i, j| 20.0 * g(1, i, j) as f32).unwrap();
        let water = Grid2::from_fn(nx, ny, |i, j| 2.0 * g(2, i, j) as f32).unwrap();
        for edges in [Edges::Closed, Edges::Open, Edges::Periodic] {
            let p = PipeParams {
                edges,
                dt: 0.2,
                k_c: 0.5,
                ..Default::default()
            };
            let build = |record: bool, fused: bool, calls: &[u32]| {
                let mut m = PipeModel::new(p.clone(), &hf0)
                    .unwrap()
                    .with_velocity(record);
                m.set_water(&water).unwrap();
                m.fused = fused;
                m.chunk_rows = 8;
                let mut h = hf0.clone();
                for &n in calls {
                    if n == 0 {
                        m.step(&mut h).unwrap();
                    } else {
                        m.run(&mut h, n, &NoProgress).unwrap();
                    }
                }
                (m, h)
            };
            let (plain, h_plain) = build(false, true, &[25]);
            assert!(
                plain.velocity().is_err(),
                "{edges:?}: velocity not recorded"
            );
            assert!(plain.vel[0].is_empty() && plain.vel[1].is_empty());
            for (what, (m, h)) in [
                ("recorded", build(true, true, &[25])),
                ("three passes", build(false, false, &[25])),
            ] {
                let same = |field: &str, a: &[f32], b: &[f32]| {
                    assert_eq!(a.len(), b.len());
                    for (k, (x, y)) in a.iter().zip(b).enumerate() {
                        assert!(
                            x.to_bits() == y.to_bits(),
                            "{edges:?}: {field}[{k}] {x} vs {what} {y}"
                        );
                    }
                };
                same("bed", h_plain.heights().as_slice(), h.heights().as_slice());
                same("water", &plain.water, &m.water);
                same("sediment", &plain.sediment, &m.sediment);
                same("deposit", &plain.deposit, &m.deposit);
                for k in 0..4 {
                    same("flux", &plain.flux[k], &m.flux[k]);
                }
            }
            let (rec, _) = build(true, true, &[25]);
            let (u, v) = rec.velocity().unwrap();
            assert!(u.as_slice().iter().chain(v.as_slice()).any(|&x| x != 0.0));
            // The deposit against the field's change, for one call and for several.
            let (split, h_split) = build(false, true, &[0, 7, 0, 0, 16]);
            same_to_rounding(&plain.deposit, &h_plain, &hf0, edges);
            same_to_rounding(&split.deposit, &h_split, &hf0, edges);
            let eroded = plain.deposit.iter().filter(|&&d| d < 0.0).count();
            assert!(eroded > 0, "{edges:?}: nothing eroded");
        }
        /// `dep = h − h₀` cell by cell, to a few roundings of the heights
        /// (the field is at most 20 m high: an ulp of 2⁻¹⁹ m).
        fn same_to_rounding(dep: &[f32], h: &HeightField, h0: &HeightField, edges: Edges) {
            let tol = 6.0 * 2f32.powi(-19);
            for (k, ((&d, &a), &b)) in dep
                .iter()
                .zip(h.heights().as_slice())
                .zip(h0.heights().as_slice())
                .enumerate()
            {
                assert!(
                    (d - (a - b)).abs() <= tol,
                    "{edges:?}: deposit[{k}] {d} vs change {}",
                    a - b
                );
            }
        }
    }

    /// A few steps at 1024² (`PIPE_N`, `PIPE_STEPS` to change) on a spectral
    /// terrain, for profilers (`valgrind --tool=callgrind` runs the AVX2 build):
    /// `cargo test --release -p natura-terrain --lib pipe_profile_run -- --ignored`.
    #[test]
    #[ignore = "profiling harness"]
    fn pipe_profile_run() {
        let var = |k: &str, d: usize| {
            std::env::var(k)
                .ok()
                .and_then(|v| v.parse().ok())
                .unwrap_or(d)
        };
        let n = var("PIPE_N", 1024);
        let sp = crate::synth::SpectralParams {
            sigma_m: 200.0,
            ..Default::default()
        };
        let mut hf = crate::synth::spectral_synthesis(n, n, 10.0, &sp, Seed(1)).unwrap();
        let mut m = PipeModel::new(PipeParams::default(), &hf).unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let t0 = std::time::Instant::now();
        let steps = var("PIPE_STEPS", 5) as u32;
        pool.install(|| m.run(&mut hf, steps, &NoProgress)).unwrap();
        let s = t0.elapsed().as_secs_f64();
        eprintln!(
            "{:.1} M cell-steps/s",
            (n * n) as f64 * f64::from(steps) / s / 1e6
        );
    }

    #[test]
    fn extreme_params_stay_finite_or_are_refused() {
        let mut hf = hills(16);
        for p in [
            PipeParams {
                dt: 10.0,
                rain_m_per_s: 1.0,
                k_e: 0.0,
                ..Default::default()
            },
            PipeParams {
                k_c: 100.0,
                k_s: 1.0,
                ..Default::default()
            },
            PipeParams {
                transport: SedimentTransport::SemiLagrangian,
                dt: 5.0,
                ..Default::default()
            },
        ] {
            let mut m = PipeModel::new(p, &hf).unwrap();
            m.run(&mut hf, 100, &NoProgress).unwrap();
            assert!(hf.check_finite().is_ok());
            assert!(m.water.iter().all(|w| w.is_finite() && *w >= 0.0));
        }
        for p in [
            PipeParams {
                dt: 0.0,
                ..Default::default()
            },
            PipeParams {
                dt: -1.0,
                ..Default::default()
            },
            PipeParams {
                dt: 1e9,
                ..Default::default()
            },
            PipeParams {
                k_s: 2.0,
                ..Default::default()
            },
            PipeParams {
                rain_m_per_s: -1.0,
                ..Default::default()
            },
        ] {
            assert!(PipeModel::new(p, &hf).is_err());
        }
    }
}
