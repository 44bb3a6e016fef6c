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

use natura_core::{Grid2, HeightField, Progress};

use super::{Edges, Erodibility, check_erodibility, check_field, check_model_size};
use crate::error::{Result, in_range, invalid, non_negative, positive};
use crate::par;

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
    bed: Vec<f32>,
    erodibility: Option<Erodibility>,
    ledger: PipeLedger,
    deposit: Vec<f32>,
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
            bed: z(),
            erodibility: None,
            ledger: PipeLedger {
                initial_material: hf.heights().sum(),
                ..Default::default()
            },
            deposit: z(),
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

    #[allow(clippy::too_many_lines, clippy::needless_range_loop)]
    fn step_unchecked(&mut self, hf: &mut HeightField) {
        let (nx, ny) = (self.nx, self.ny);
        let p = &self.p;
        let l = self.cell;
        let area = l * l;
        let dt = p.dt as f32;
        let rain = (p.rain_m_per_s * p.dt) as f32;
        let kflux = (p.dt * p.pipe_area * p.gravity / f64::from(l)) as f32;
        let edges = p.edges;
        let open = edges == Edges::Open;
        let periodic = edges == Edges::Periodic;
        let nb = |x: usize, y: usize, k: usize| -> Option<usize> {
            if x > 0 && y > 0 && x < nx - 1 && y < ny - 1 {
                // Interior: no edge handling needed.
                let i = y * nx + x;
                return Some([i - 1, i + 1, i - nx, i + nx][k]);
            }
            let (dx, dy) = [(-1, 0), (1, 0), (0, -1), (0, 1)][k];
            edges.resolve(x, y, dx, dy, nx, ny)
        };
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
                    let r0 = (y - y0) * nx;
                    let interior_row = y > 0 && y < ny - 1;
                    if interior_row && !periodic {
                        // Fast path: neighbours exist except at x = 0 and x = nx − 1.
                        let i0 = y * nx;
                        for x in 0..nx {
                            let i = i0 + x;
                            let d1 = water[i] + rain;
                            let h = bed[i] + d1;
                            let hl = if x > 0 {
                                bed[i - 1] + water[i - 1] + rain
                            } else if open {
                                bed[i]
                            } else {
                                f32::INFINITY
                            };
                            let hr = if x + 1 < nx {
                                bed[i + 1] + water[i + 1] + rain
                            } else if open {
                                bed[i]
                            } else {
                                f32::INFINITY
                            };
                            let hb = bed[i - nx] + water[i - nx] + rain;
                            let ht = bed[i + nx] + water[i + nx] + rain;
                            let r = r0 + x;
                            flux_update(
                                d1,
                                h,
                                [hl, hr, hb, ht],
                                [&mut fl[r], &mut fr[r], &mut fb[r], &mut ft[r]],
                                kflux,
                                dt,
                                area,
                            );
                            d1o[r] = d1;
                        }
                    } else {
                        for x in 0..nx {
                            let i = y * nx + x;
                            let d1 = water[i] + rain;
                            let h = bed[i] + d1;
                            let hn: [f32; 4] = std::array::from_fn(|k| match nb(x, y, k) {
                                Some(j) => bed[j] + water[j] + rain,
                                None if open => bed[i],
                                None => f32::INFINITY,
                            });
                            let r = r0 + x;
                            flux_update(
                                d1,
                                h,
                                hn,
                                [&mut fl[r], &mut fr[r], &mut fb[r], &mut ft[r]],
                                kflux,
                                dt,
                                area,
                            );
                            d1o[r] = d1;
                        }
                    }
                }
            });
        }
        self.ledger.rain += f64::from(rain) * (nx * ny) as f64;
        // ---- pass B: depth, velocity, erosion / deposition, evaporation.
        let (kc, ks, kd) = (p.k_c as f32, p.k_s as f32, p.k_d as f32);
        let evap = (p.k_e * p.dt) as f32;
        let min_tilt = p.min_tilt as f32;
        let inv_dref = 1.0 / p.depth_ref as f32;
        let vmax = l / dt;
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        let cell = l;
        let results: Vec<(f64, f64)> = {
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
                    for x in 0..nx {
                        let i = y * nx + x;
                        let r = (y - y0) * nx + x;
                        let get = |k: usize, dir: usize| nb(x, y, k).map_or(0.0, |j| f[dir][j]);
                        let in_l = get(L, R);
                        let in_r = get(R, L);
                        let in_b = get(B, T);
                        let in_t = get(T, B);
                        let out = f[L][i] + f[R][i] + f[B][i] + f[T][i];
                        let d1i = d1[i];
                        let d2 = (d1i + dt * (in_l + in_r + in_b + in_t - out) / area).max(0.0);
                        // Outflow through open edges.
                        if open {
                            for k in 0..4 {
                                if nb(x, y, k).is_none() {
                                    out_w += f64::from(f[k][i] * dt / area);
                                }
                            }
                        }
                        let mean_d = 0.5 * (d1i + d2);
                        let (mut vu, mut vv) = if mean_d > 1e-6 {
                            let wx = 0.5 * (in_l - f[L][i] + f[R][i] - in_r);
                            let wy = 0.5 * (in_b - f[B][i] + f[T][i] - in_t);
                            (wx / (cell * mean_d), wy / (cell * mean_d))
                        } else {
                            (0.0, 0.0)
                        };
                        vu = vu.clamp(-vmax, vmax);
                        vv = vv.clamp(-vmax, vmax);
                        // Local tilt from central differences of the bed.
                        let bx0 = nb(x, y, L).map_or(bed[i], |j| bed[j]);
                        let bx1 = nb(x, y, R).map_or(bed[i], |j| bed[j]);
                        let by0 = nb(x, y, B).map_or(bed[i], |j| bed[j]);
                        let by1 = nb(x, y, T).map_or(bed[i], |j| bed[j]);
                        let gx = (bx1 - bx0) / (2.0 * cell);
                        let gy = (by1 - by0) / (2.0 * cell);
                        let g2 = gx * gx + gy * gy;
                        let sin_a = (g2 / (1.0 + g2)).sqrt().max(min_tilt);
                        let speed = (vu * vu + vv * vv).sqrt();
                        let cap = kc * sin_a * speed * (d2 * inv_dref).min(1.0);
                        let s = s0[i];
                        let (mut b, mut s_new) = (bed[i], s);
                        if cap > s {
                            let k = erod.map_or(ks, |e| ks * e[i]);
                            let e = k * (cap - s);
                            b -= e;
                            s_new += e;
                            depo[r] -= e;
                        } else {
                            let dep = kd * (s - cap);
                            b += dep;
                            s_new -= dep;
                            depo[r] += dep;
                        }
                        let lost = d2 * evap;
                        evaporated += f64::from(lost);
                        wo[r] = d2 - lost;
                        bo[r] = b;
                        so[r] = s_new;
                        uo[r] = vu;
                        vo[r] = vv;
                    }
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
        let outflow_s: Vec<f64> = match p.transport {
            SedimentTransport::Conservative => {
                let d1 = &self.water1;
                let f = &self.flux;
                par::map_bands(nx, ny, [self.sediment.as_mut_slice()], |y0, y1, [so]| {
                    let mut out_s = 0.0f64;
                    for y in y0..y1 {
                        for x in 0..nx {
                            let i = y * nx + x;
                            // Fraction of a cell's water that leaves through pipe k this step.
                            let frac = |j: usize, k: usize| {
                                if d1[j] > 0.0 {
                                    (f[k][j] * dt / (d1[j] * area)).min(1.0)
                                } else {
                                    0.0
                                }
                            };
                            let mut keep = 1.0f32;
                            let mut gained = 0.0f32;
                            for k in 0..4 {
                                let fo = frac(i, k);
                                keep -= fo;
                                match nb(x, y, k) {
                                    Some(j) => gained += s1[j] * frac(j, k ^ 1),
                                    None => out_s += f64::from(s1[i] * fo),
                                }
                            }
                            so[(y - y0) * nx + x] = s1[i] * keep.max(0.0) + gained;
                        }
                    }
                    out_s
                })
            }
            SedimentTransport::SemiLagrangian => {
                let (u, v) = (&self.vel[0], &self.vel[1]);
                let step = dt / cell;
                par::map_bands(nx, ny, [self.sediment.as_mut_slice()], |y0, y1, [so]| {
                    for y in y0..y1 {
                        for x in 0..nx {
                            let i = y * nx + x;
                            let px = x as f32 - u[i] * step;
                            let py = y as f32 - v[i] * step;
                            so[(y - y0) * nx + x] = sample(s1, nx, ny, px, py, periodic);
                        }
                    }
                    0.0
                })
            }
        };
        self.ledger.outflow_sediment += outflow_s.iter().sum::<f64>();
        hf.heights_mut().as_mut_slice().copy_from_slice(&self.bed);
    }
}

/// Updates the four outflow fluxes of a cell of depth `d1` and surface `h`
/// towards neighbours of surfaces `hn` (∞ = wall) and rescales them so the
/// outflow never exceeds the water present.
#[inline(always)]
fn flux_update(d1: f32, h: f32, hn: [f32; 4], f: [&mut f32; 4], kflux: f32, dt: f32, area: f32) {
    let mut nf = [0.0f32; 4];
    let mut sum = 0.0;
    for k in 0..4 {
        let v = (*f[k] + kflux * (h - hn[k])).max(0.0);
        nf[k] = v;
        sum += v;
    }
    let scale = if sum * dt > d1 * area {
        d1 * area / (sum * dt)
    } else {
        1.0
    };
    for k in 0..4 {
        *f[k] = nf[k] * scale;
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
