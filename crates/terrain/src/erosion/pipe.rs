//! Virtual-pipe shallow-water hydraulic erosion (Mei, Decaudin & Hu 2007,
//! "Fast Hydraulic Erosion Simulation and Visualization on GPU"; the pipe model
//! is O'Brien & Hodgins 1995). Not in the seed documents: spec `terrain.md`
//! §7.2 names it as the stable successor of MKM's scheme (§3.1) and it keeps
//! MKM's `K_c / K_s / K_d` naming.
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
use crate::{par, simd};

/// How suspended sediment moves with the water.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SedimentTransport {
    /// Through the pipes with the water: conserves mass (default).
    Conservative,
    /// Semi-Lagrangian back-tracing along the velocity field, as Mei et al.
    /// publish it: smoother, but does not conserve sediment.
    SemiLagrangian,
}

/// Parameters of [`PipeModel`].
#[derive(Clone, Debug, PartialEq)]
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
    vel: [Vec<f32>; 2],
    /// The next step's bed (swapped with the field's heights after each step).
    bed: Grid2<f32>,
    erodibility: Option<Erodibility>,
    ledger: PipeLedger,
    deposit: Vec<f32>,
    /// Interior cells through the row kernels (false only in tests: every
    /// cell through the general per-cell path, the fast path's oracle).
    fast: bool,
}

const L: usize = 0;
const R: usize = 1;
const B: usize = 2;
const T: usize = 3;

impl PipeModel {
    /// A dry model for fields the size of `hf`.
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
            water1: z(),
            sediment: z(),
            sediment1: z(),
            flux: [z(), z(), z(), z()],
            vel: [z(), z()],
            bed: Grid2::from_vec(hf.nx(), hf.ny(), z())?,
            erodibility: None,
            ledger: PipeLedger {
                initial_material: hf.heights().sum(),
                ..Default::default()
            },
            deposit: z(),
            fast: true,
        })
    }

    /// Scales `K_s` per cell.
    pub fn with_erodibility(mut self, e: Erodibility) -> Result<Self> {
        check_erodibility(Some(&e), self.nx, self.ny)?;
        if f64::from(e.max()) * self.p.k_s > 1.0 {
            return Err(invalid("erodibility", e.max(), "max × k_s must be ≤ 1"));
        }
        self.erodibility = Some(e);
        Ok(self)
    }

    /// Sets the water depth (metres ≥ 0, finite).
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
    pub fn water(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.water.clone())?)
    }

    /// Suspended sediment, metres.
    pub fn sediment(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.sediment.clone())?)
    }

    /// Net deposition since the model was built (positive: material laid down), metres.
    pub fn deposition(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.deposit.clone())?)
    }

    /// Water velocity `(u, v)` of the last step, m/s.
    pub fn velocity(&self) -> Result<(Grid2<f32>, Grid2<f32>)> {
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
    pub fn run(&mut self, hf: &mut HeightField, steps: u32, progress: &dyn Progress) -> Result<()> {
        check_field("pipe-model erosion", hf, self.nx, self.ny)?;
        progress.start("pipe model", u64::from(steps));
        for _ in 0..steps {
            self.step_unchecked(hf);
            progress.advance(1);
        }
        progress.finish();
        Ok(())
    }

    /// One step.
    pub fn step(&mut self, hf: &mut HeightField) -> Result<()> {
        check_field("pipe-model erosion", hf, self.nx, self.ny)?;
        self.step_unchecked(hf);
        Ok(())
    }

    /// One step. Every pass is a gather over row bands: the interior of each
    /// row runs through branch-free slice kernels (vectorised at the CPU's
    /// widest SIMD level), the grid's edge cells through the general per-cell
    /// code that resolves closed, open and periodic neighbours. Both compute
    /// the same operations in the same order, so the split changes no bit of
    /// the fields (only the order in which the evaporation ledger is summed).
    #[allow(clippy::too_many_lines)]
    fn step_unchecked(&mut self, hf: &mut HeightField) {
        let (nx, ny) = (self.nx, self.ny);
        let c = Consts::new(&self.p, self.cell, nx, ny);
        let fast = self.fast;
        let interior = |y: usize| fast && y > 0 && y + 1 < ny;
        // ---- pass A: rain and outflow fluxes (in place: each cell owns its 4 pipes).
        {
            let bed = hf.heights().as_slice();
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
                {
                    for y in y0..y1 {
                        let r0 = (y - y0) * nx;
                        let mut cell = |x: usize| {
                            let r = r0 + x;
                            d1o[r] = c.flux_cell(
                                water,
                                bed,
                                x,
                                y,
                                [&mut fl[r], &mut fr[r], &mut fb[r], &mut ft[r]],
                            );
                        };
                        if !interior(y) {
                            (0..nx).for_each(&mut cell);
                            continue;
                        }
                        cell(0);
                        cell(nx - 1);
                        let (a, b) = (r0 + 1, r0 + nx - 1);
                        let i0 = y * nx + 1;
                        flux_row(
                            &c,
                            Around::new(water, i0, nx, nx - 2),
                            Around::new(bed, i0, nx, nx - 2),
                            [
                                &mut d1o[a..b],
                                &mut fl[a..b],
                                &mut fr[a..b],
                                &mut fb[a..b],
                                &mut ft[a..b],
                            ],
                        );
                    }
                };
            });
        }
        self.ledger.rain += f64::from(c.rain) * (nx * ny) as f64;
        // ---- pass B: depth, velocity, erosion / deposition, evaporation.
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        let results: Vec<(f64, f64)> = {
            let bed = hf.heights().as_slice();
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
                self.deposit.as_mut_slice(),
            ];
            par::map_bands(nx, ny, outs, |y0, y1, [wo, bo, so, uo, vo, depo]| {
                let mut evaporated = 0.0f64;
                let mut out_w = 0.0f64;
                for y in y0..y1 {
                    let r0 = (y - y0) * nx;
                    let mut cell = |x: usize| {
                        let r = r0 + x;
                        let (lost, o) = c.update_cell(
                            d1,
                            f,
                            s0,
                            bed,
                            erod,
                            x,
                            y,
                            [
                                &mut wo[r],
                                &mut bo[r],
                                &mut so[r],
                                &mut uo[r],
                                &mut vo[r],
                                &mut depo[r],
                            ],
                        );
                        evaporated += f64::from(lost);
                        out_w += o;
                    };
                    if !interior(y) {
                        (0..nx).for_each(&mut cell);
                        continue;
                    }
                    cell(0);
                    cell(nx - 1);
                    let (a, b) = (r0 + 1, r0 + nx - 1);
                    let (i0, m) = (y * nx + 1, nx - 2);
                    let ins = UpdateIn {
                        d1: &d1[i0..i0 + m],
                        f: [
                            Around::new(&f[L], i0, nx, m),
                            Around::new(&f[R], i0, nx, m),
                            Around::new(&f[B], i0, nx, m),
                            Around::new(&f[T], i0, nx, m),
                        ],
                        s0: &s0[i0..i0 + m],
                        bed: Around::new(bed, i0, nx, m),
                    };
                    let outs = [
                        &mut wo[a..b],
                        &mut bo[a..b],
                        &mut so[a..b],
                        &mut uo[a..b],
                        &mut vo[a..b],
                        &mut depo[a..b],
                    ];
                    evaporated += match erod {
                        Some(e) => update_row_erodible(&c, &ins, &e[i0..i0 + m], outs),
                        None => update_row_uniform(&c, &ins, outs),
                    };
                }
                (evaporated, out_w)
            })
        };
        for (e, o) in results {
            self.ledger.evaporated += e;
            self.ledger.outflow_water += o;
        }
        // ---- pass C: sediment transport.
        let s1 = &self.sediment1;
        let d1 = &self.water1;
        let f = &self.flux;
        let (u, v) = (&self.vel[0], &self.vel[1]);
        let transport = self.p.transport;
        let outflow_s: Vec<f64> =
            par::map_bands(nx, ny, [self.sediment.as_mut_slice()], |y0, y1, [so]| {
                let mut out_s = 0.0f64;
                for y in y0..y1 {
                    let r0 = (y - y0) * nx;
                    let mut cell = |x: usize| {
                        let (s, o) = c.transport_cell(transport, d1, f, s1, u, v, x, y);
                        so[r0 + x] = s;
                        out_s += o;
                    };
                    if !interior(y) {
                        (0..nx).for_each(&mut cell);
                        continue;
                    }
                    cell(0);
                    cell(nx - 1);
                    let (i0, m) = (y * nx + 1, nx - 2);
                    let out = &mut so[r0 + 1..r0 + nx - 1];
                    match transport {
                        SedimentTransport::Conservative => conservative_row(
                            &c,
                            Around::new(d1, i0, nx, m),
                            [
                                Around::new(&f[L], i0, nx, m),
                                Around::new(&f[R], i0, nx, m),
                                Around::new(&f[B], i0, nx, m),
                                Around::new(&f[T], i0, nx, m),
                            ],
                            Around::new(s1, i0, nx, m),
                            out,
                        ),
                        SedimentTransport::SemiLagrangian => {
                            semi_lagrangian_row(&c, &u[i0..i0 + m], &v[i0..i0 + m], s1, y, out)
                        }
                    }
                }
                out_s
            });
        self.ledger.outflow_sediment += outflow_s.iter().sum::<f64>();
        // The new bed becomes the field's heights; the old heights become scratch.
        std::mem::swap(hf.heights_mut(), &mut self.bed);
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
            vmax: l / dt,
            sl_step: dt / l,
        }
    }

    /// Neighbour `k` (L, R, B, T) of `(x, y)`, resolved through the edges.
    #[inline]
    fn nb(&self, x: usize, y: usize, k: usize) -> Option<usize> {
        let (dx, dy) = [(-1, 0), (1, 0), (0, -1), (0, 1)][k];
        self.edges.resolve(x, y, dx, dy, self.nx, self.ny)
    }

    /// Pass A for one cell: returns `d₁` and updates the cell's four fluxes.
    #[inline]
    fn flux_cell(&self, water: &[f32], bed: &[f32], x: usize, y: usize, f: [&mut f32; 4]) -> f32 {
        let i = y * self.nx + x;
        let d1 = water[i] + self.rain;
        let h = bed[i] + d1;
        let open = self.edges == Edges::Open;
        let hn: [f32; 4] = std::array::from_fn(|k| match self.nb(x, y, k) {
            Some(j) => bed[j] + water[j] + self.rain,
            None if open => bed[i],
            None => f32::INFINITY,
        });
        let mut nf = [0.0f32; 4];
        let mut sum = 0.0;
        for k in 0..4 {
            let v = (*f[k] + self.kflux * (h - hn[k])).max(0.0);
            nf[k] = v;
            sum += v;
        }
        let scale = flux_scale(sum, d1, self.dt, self.area);
        for (o, v) in f.into_iter().zip(nf) {
            *o = v * scale;
        }
        d1
    }

    /// Pass B for one cell: writes water, bed, sediment, u, v and updates the
    /// deposit; returns the water evaporated and the water lost through open edges.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn update_cell(
        &self,
        d1: &[f32],
        f: &[Vec<f32>; 4],
        s0: &[f32],
        bed: &[f32],
        erod: Option<&[f32]>,
        x: usize,
        y: usize,
        [wo, bo, so, uo, vo, depo]: [&mut f32; 6],
    ) -> (f32, f64) {
        let i = y * self.nx + x;
        let nb = |k: usize| self.nb(x, y, k);
        let get = |k: usize, dir: usize| nb(k).map_or(0.0, |j| f[dir][j]);
        let in_l = get(L, R);
        let in_r = get(R, L);
        let in_b = get(B, T);
        let in_t = get(T, B);
        let mut out_w = 0.0f64;
        if self.edges == Edges::Open {
            for k in 0..4 {
                if nb(k).is_none() {
                    out_w += f64::from(f[k][i] * self.dt / self.area);
                }
            }
        }
        let bn = |k: usize| nb(k).map_or(bed[i], |j| bed[j]);
        let cell = CellIn {
            d1: d1[i],
            fo: [f[L][i], f[R][i], f[B][i], f[T][i]],
            fin: [in_l, in_r, in_b, in_t],
            s: s0[i],
            bed: bed[i],
            bn: [bn(L), bn(R), bn(B), bn(T)],
            ks: erod.map_or(self.ks, |e| self.ks * e[i]),
        };
        let o = self.update(&cell, *depo);
        [*wo, *bo, *so, *uo, *vo, *depo] = [o.w, o.b, o.s, o.u, o.v, o.dep];
        (o.lost, out_w)
    }

    /// The arithmetic of pass B for one cell, shared by both paths.
    #[inline(always)]
    fn update(&self, c: &CellIn, dep0: f32) -> CellOut {
        let [fl, fr, fb, ft] = c.fo;
        let [in_l, in_r, in_b, in_t] = c.fin;
        let out = fl + fr + fb + ft;
        let d2 = (c.d1 + self.dt * (in_l + in_r + in_b + in_t - out) / self.area).max(0.0);
        let mean_d = 0.5 * (c.d1 + d2);
        let wx = 0.5 * (in_l - fl + fr - in_r);
        let wy = 0.5 * (in_b - fb + ft - in_t);
        let wet = mean_d > 1e-6;
        let vu = if wet { wx / (self.cell * mean_d) } else { 0.0 };
        let vv = if wet { wy / (self.cell * mean_d) } else { 0.0 };
        let vu = clamp(vu, self.vmax);
        let vv = clamp(vv, self.vmax);
        // Local tilt from central differences of the bed.
        let [bl, br, bb, bt] = c.bn;
        let gx = (br - bl) / (2.0 * self.cell);
        let gy = (bt - bb) / (2.0 * self.cell);
        let g2 = gx * gx + gy * gy;
        let sin_a = (g2 / (1.0 + g2)).sqrt().max(self.min_tilt);
        let speed = (vu * vu + vv * vv).sqrt();
        let cap = self.kc * sin_a * speed * (d2 * self.inv_dref).min(1.0);
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
            dep: if erode { dep0 - e } else { dep0 + dep },
            lost,
        }
    }

    /// Pass C for one cell: the new sediment and what left through open edges.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn transport_cell(
        &self,
        transport: SedimentTransport,
        d1: &[f32],
        f: &[Vec<f32>; 4],
        s1: &[f32],
        u: &[f32],
        v: &[f32],
        x: usize,
        y: usize,
    ) -> (f32, f64) {
        let i = y * self.nx + x;
        match transport {
            SedimentTransport::Conservative => {
                let frac = |j: usize, k: usize| self.frac(d1[j], f[k][j]);
                let mut out_s = 0.0f64;
                let mut keep = 1.0f32;
                let mut gained = 0.0f32;
                for k in 0..4 {
                    let fo = frac(i, k);
                    keep -= fo;
                    match self.nb(x, y, k) {
                        Some(j) => gained += s1[j] * frac(j, k ^ 1),
                        None => out_s += f64::from(s1[i] * fo),
                    }
                }
                (s1[i] * keep.max(0.0) + gained, out_s)
            }
            SedimentTransport::SemiLagrangian => {
                let px = x as f32 - u[i] * self.sl_step;
                let py = y as f32 - v[i] * self.sl_step;
                let wrap = self.edges == Edges::Periodic;
                (sample(s1, self.nx, self.ny, px, py, wrap), 0.0)
            }
        }
    }

    /// Fraction of a cell's water `d1` that leaves through a pipe of flux `f` this step.
    #[inline(always)]
    fn frac(&self, d1: f32, f: f32) -> f32 {
        let q = (f * self.dt / (d1 * self.area)).min(1.0);
        if d1 > 0.0 { q } else { 0.0 }
    }
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
    if sum * dt > d1 * area {
        d1 * area / (sum * dt)
    } else {
        1.0
    }
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
    dep: f32,
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
    /// `g` row-major with width `nx`; needs `nx ≤ i0 − 1` and `i0 + m + nx ≤ g.len()`.
    #[inline(always)]
    fn new(g: &'a [f32], i0: usize, nx: usize, m: usize) -> Self {
        Self {
            c: &g[i0..i0 + m],
            l: &g[i0 - 1..i0 - 1 + m],
            r: &g[i0 + 1..i0 + 1 + m],
            b: &g[i0 - nx..i0 - nx + m],
            t: &g[i0 + nx..i0 + nx + m],
        }
    }

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

simd::multiversion! {
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
        let vl = (fl[k] + kflux * (h - (bl[k] + wl[k] + rain))).max(0.0);
        let vr = (fr[k] + kflux * (h - (br[k] + wr[k] + rain))).max(0.0);
        let vb = (fb[k] + kflux * (h - (bb[k] + wb[k] + rain))).max(0.0);
        let vt = (ft[k] + kflux * (h - (bt[k] + wt[k] + rain))).max(0.0);
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

simd::multiversion! {
/// Pass B over the interior cells of a row (uniform `K_s`); returns the water evaporated.
fn update_row_uniform<'a>(c: &'a Consts, ins: &'a UpdateIn<'a>, outs: [&'a mut [f32]; 6]) -> f64 {
    update_row::<false>(c, ins, &[], outs)
}
}

simd::multiversion! {
/// Pass B over the interior cells of a row with an erodibility map; returns the water evaporated.
fn update_row_erodible<'a>(c: &'a Consts, ins: &'a UpdateIn<'a>, erod: &'a [f32], outs: [&'a mut [f32]; 6]) -> f64 {
    update_row::<true>(c, ins, erod, outs)
}
}

/// Pass B over the interior cells of a row; returns the water evaporated.
#[inline(always)]
fn update_row<const ERODIBILITY: bool>(
    c: &Consts,
    ins: &UpdateIn<'_>,
    erod: &[f32],
    outs: [&mut [f32]; 6],
) -> f64 {
    let [wo, bo, so, uo, vo, depo] = outs;
    let m = wo.len();
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
        let (uo, vo, depo) = (&mut uo[a..b], &mut vo[a..b], &mut depo[a..b]);
        let lost = &mut lost[..n];
        for k in 0..n {
            let cell = CellIn {
                d1: d1[k],
                fo: [fl.c[k], fr.c[k], fb.c[k], ft.c[k]],
                fin: [fr.l[k], fl.r[k], ft.b[k], fb.t[k]],
                s: s0[k],
                bed: bed.c[k],
                bn: [bed.l[k], bed.r[k], bed.b[k], bed.t[k]],
                ks: if ERODIBILITY { c.ks * er[k] } else { c.ks },
            };
            let o = c.update(&cell, depo[k]);
            wo[k] = o.w;
            bo[k] = o.b;
            so[k] = o.s;
            uo[k] = o.u;
            vo[k] = o.v;
            depo[k] = o.dep;
            lost[k] = o.lost;
        }
        let mut acc = [0.0f32; 8];
        let mut chunks = lost.chunks_exact(8);
        for ch in &mut chunks {
            for (s, &x) in acc.iter_mut().zip(ch) {
                *s += x;
            }
        }
        for (s, &x) in acc.iter_mut().zip(chunks.remainder()) {
            *s += x;
        }
        total += acc.iter().map(|&x| f64::from(x)).sum::<f64>();
        a = b;
    }
    total
}

simd::multiversion! {
/// Conservative transport over the interior cells of a row.
fn conservative_row<'a>(c: &'a Consts, d1: Around<'a>, f: [Around<'a>; 4], s1: Around<'a>, so: &'a mut [f32]) {
    let m = so.len();
    let d1 = d1.sub(0, m);
    let [fl, fr, fb, ft] = f.map(|p| p.sub(0, m));
    let s1 = s1.sub(0, m);
    for k in 0..m {
        let mut keep = 1.0f32;
        let mut gained = 0.0f32;
        keep -= c.frac(d1.c[k], fl.c[k]);
        gained += s1.l[k] * c.frac(d1.l[k], fr.l[k]);
        keep -= c.frac(d1.c[k], fr.c[k]);
        gained += s1.r[k] * c.frac(d1.r[k], fl.r[k]);
        keep -= c.frac(d1.c[k], fb.c[k]);
        gained += s1.b[k] * c.frac(d1.b[k], ft.b[k]);
        keep -= c.frac(d1.c[k], ft.c[k]);
        gained += s1.t[k] * c.frac(d1.t[k], fb.t[k]);
        so[k] = s1.c[k] * keep.max(0.0) + gained;
    }
}
}

simd::multiversion! {
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
