//! Stream-power fluvial erosion with tectonic uplift, solved implicitly in O(n)
//! per step (Braun & Willett 2013, "A very efficient O(n), implicit and parallel
//! method to solve the stream power equation governing fluvial incision and
//! landscape evolution", Geomorphology 180-181). Not in the seed documents:
//! it realises the "orogenesis" wish of Musgrave 1993, §2.4.4 and
//! the fractal drainage networks Musgrave et al. 1989, §2.2 and Musgrave 2001 call for.
//!
//! `∂z/∂t = U − K·A^m·S^n`, with `A` the drainage area (m²), `S` the slope to
//! the steepest-descent receiver. Each step: uplift, D8 receivers, depression
//! handling (see [`crate::analysis::flow`]) so rivers reach the edge, the
//! stack order, drainage areas, then the implicit update from the outlets
//! upstream: for `n = 1`,
//! `z_i ← (z_i + U·Δt + F·z_r) / (1 + F)`, `F = K·A^m·Δt / L`,
//! which is unconditionally stable; for `n ≠ 1` a Newton iteration solves the
//! same implicit equation. Edge cells are base level (fixed, no uplift).
//! At steady state `S = (U / (K·A^m))^(1/n)` exactly: the slope–area law.
//! Time is in **years** (geological rates), lengths in metres.

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use natura_core::{Grid2, HeightField};

use super::{Erodibility, check_erodibility, check_model_size};
pub use crate::analysis::flow::Depressions;
use crate::analysis::flow::{FlowGraph, next_up};
use crate::bands;
use crate::error::{Result, in_range, invalid, non_negative, positive};

/// Parameters of [`StreamPower`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct StreamPowerParams {
    /// Erodibility `K`, in m^(1−2m)/yr for `n = 1`. Default 2·10⁻⁵.
    pub k: f64,
    /// Area exponent `m`. Default 0.5 (m/n ≈ 0.5 is typical).
    pub m: f64,
    /// Slope exponent `n`. Default 1.
    pub n: f64,
    /// Uplift rate `U`, metres per year (uniform). Default 5·10⁻⁴ (0.5 mm/yr).
    pub uplift_m_per_yr: f64,
    /// Time step, years. Default 5000 (the implicit scheme is stable for any step).
    pub dt_yr: f64,
    /// How pits are handled. Default [`Depressions::Fill`] (lakes fill with sediment).
    pub depressions: Depressions,
}

impl Default for StreamPowerParams {
    fn default() -> Self {
        Self {
            k: 2e-5,
            m: 0.5,
            n: 1.0,
            uplift_m_per_yr: 5e-4,
            dt_yr: 5000.0,
            depressions: Depressions::Fill,
        }
    }
}

impl StreamPowerParams {
    /// `K ∈ [0, 1]`, `m ∈ [0, 2]`, `n ∈ [0.5, 4]`, `U ≥ 0` (≤ 1 m/yr), `Δt ∈ (0, 10⁷]` years,
    /// and `Keep` refused (rivers must reach the edge).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        // K beyond 1 is five orders of magnitude past any fitted river and
        // overflows the implicit update's K·Δt·A^m factor on large basins.
        in_range("StreamPowerParams::k", self.k, 0.0, 1.0)?;
        in_range("StreamPowerParams::m", self.m, 0.0, 2.0)?;
        in_range("StreamPowerParams::n", self.n, 0.5, 4.0)?;
        non_negative("StreamPowerParams::uplift_m_per_yr", self.uplift_m_per_yr)?;
        in_range(
            "StreamPowerParams::uplift_m_per_yr",
            self.uplift_m_per_yr,
            0.0,
            1.0,
        )?;
        positive("StreamPowerParams::dt_yr", self.dt_yr)?;
        if self.dt_yr > 1e7 {
            return Err(invalid(
                "StreamPowerParams::dt_yr",
                self.dt_yr,
                "must be ≤ 1e7 years",
            ));
        }
        if self.depressions == Depressions::Keep {
            return Err(invalid(
                "StreamPowerParams::depressions",
                "Keep",
                "pits must be routed or filled so rivers reach the edge",
            ));
        }
        Ok(())
    }
}

/// Stream-power erosion with uplift on a field of fixed size.
#[derive(Debug)]
pub struct StreamPower {
    p: StreamPowerParams,
    nx: usize,
    ny: usize,
    erodibility: Option<Erodibility>,
    graph: Option<FlowGraph>,
    /// Net deposit per cell, `f32` bits: the group tasks of a step read and
    /// write their own (disjoint) cells through relaxed atomics, which are
    /// plain loads and stores.
    sediment: Vec<AtomicU32>,
    /// Cell area of the last step, m² (drainage areas are kept in stack order).
    cell_area: f32,
    /// Per-step scratch in stack order.
    ord: Ordered,
}

/// Per-step buffers: entry `k` of the stack-ordered ones is cell `stack[k]`.
#[derive(Debug, Default)]
struct Ordered {
    /// Filled and solved heights per stack entry.
    z: Vec<[f32; 2]>,
    /// Drainage area per stack entry, cells.
    area: Vec<f32>,
    /// New height per cell (`f32` bits), written by the group tasks and
    /// copied back to the grid in raster order.
    h: Vec<AtomicU32>,
}

impl StreamPower {
    /// A model for fields the size of `hf`.
    ///
    /// # Errors
    ///
    /// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`](crate::TerrainError::BadSize) if
    /// `hf` is smaller than 3 × 3 samples, and [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) or
    /// [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming `height` for a NaN, infinite or
    /// out-of-range height (beyond ±[`MAX_HEIGHT`](crate::erosion::MAX_HEIGHT)).
    pub fn new(p: StreamPowerParams, hf: &HeightField) -> Result<Self> {
        p.validate()?;
        check_model_size("stream-power erosion", hf)?;
        let n = hf.nx() * hf.ny();
        Ok(Self {
            p,
            nx: hf.nx(),
            ny: hf.ny(),
            erodibility: None,
            graph: None,
            sediment: (0..n).map(|_| AtomicU32::new(0)).collect(),
            cell_area: 0.0,
            ord: Ordered::default(),
        })
    }

    /// Scales `K` per cell (rock strata, Musgrave 1993, §2.4.4).
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

    /// Drainage area of the last step, m² (zero before the first step).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the grid cannot be allocated.
    pub fn drainage_area(&self) -> Result<Grid2<f32>> {
        let mut a = vec![0.0f32; self.nx * self.ny];
        if let Some(g) = &self.graph {
            // The step keeps the areas in stack order; scatter them here.
            for (&i, &v) in g.stack.iter().zip(&self.ord.area) {
                a[i as usize] = v * self.cell_area;
            }
        }
        Ok(Grid2::from_vec(self.nx, self.ny, a)?)
    }

    /// Net deposition (positive, metres: depressions filled) minus erosion since the
    /// model was built, uplift excluded.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the grid cannot be allocated.
    pub fn deposition(&self) -> Result<Grid2<f32>> {
        let s = self
            .sediment
            .iter()
            .map(|v| f32::from_bits(v.load(Relaxed)))
            .collect();
        Ok(Grid2::from_vec(self.nx, self.ny, s)?)
    }

    /// The flow graph of the last step.
    #[must_use]
    pub fn flow_graph(&self) -> Option<&FlowGraph> {
        self.graph.as_ref()
    }

    stepped_model!("stream-power erosion", "stream power", "One step.");

    fn step_unchecked(&mut self, hf: &mut HeightField) {
        let (nx, ny) = (self.nx, self.ny);
        let cell = f64::from(hf.cell_size());
        let p = &self.p;
        let up = (p.uplift_m_per_yr * p.dt_yr) as f32;
        let h = hf.heights_mut().as_mut_slice();
        // Uplift everything but the base level.
        bands::map_bands(nx, ny, [&mut *h], |y0, y1, [hb]| {
            for y in y0.max(1)..y1.min(ny - 1) {
                let r = (y - y0) * nx;
                for v in &mut hb[r + 1..r + nx - 1] {
                    *v += up;
                }
            }
        });
        // Reuse the last step's graph buffers.
        let mut g = self.graph.take().unwrap_or_else(FlowGraph::empty);
        g.rebuild_graph(h, nx, ny, p.depressions);
        let c = SolveConsts {
            fill: p.depressions == Depressions::Fill,
            route: p.depressions == Depressions::Route,
            cell,
            cell_area: (cell * cell) as f32,
            kdt: p.k * p.dt_yr,
            m: p.m,
            n: p.n,
        };
        let erodibility = self.erodibility.take();
        let erod = erodibility.as_ref().map(|e| e.map().as_slice());
        self.solve_ordered(&g, h, erod, &c);
        self.erodibility = erodibility;
        self.graph = Some(g);
    }

    /// Fill, drainage area and the implicit solve in stack order, run per
    /// outlet group of the stack in parallel (the groups hold whole drainage
    /// trees, so they share no cell). Each group task reads its cells'
    /// heights and deposits from the grid and writes their new values back
    /// in stack order (neighbouring cells, so few cache misses); a raster
    /// pass then copies the new heights into the grid. The same operations
    /// in the same order per cell as the serial passes
    /// ([`fill_along`](crate::analysis::flow), area accumulation, the solve
    /// loop), so the results are bit-identical to them on any thread count.
    fn solve_ordered(
        &mut self,
        g: &FlowGraph,
        h: &mut [f32],
        erod: Option<&[f32]>,
        c: &SolveConsts,
    ) {
        let n = h.len();
        let o = &mut self.ord;
        o.z.resize(n, [0.0; 2]);
        o.area.resize(n, 0.0);
        if o.h.len() != n {
            o.h = (0..n).map(|_| AtomicU32::new(0)).collect();
        }
        self.cell_area = c.cell_area;
        {
            let grid = Grid {
                h,
                dist: &g.distance,
                erod,
                sediment: &self.sediment,
                out_h: &o.h,
            };
            let mut jobs = Vec::with_capacity(g.groups.len());
            let (mut zs, mut asr) = (o.z.as_mut_slice(), o.area.as_mut_slice());
            for w in g.groups.windows(2) {
                let len = w[1] - w[0];
                let (a, rest) = std::mem::take(&mut zs).split_at_mut(len);
                zs = rest;
                let (b, rest) = std::mem::take(&mut asr).split_at_mut(len);
                asr = rest;
                let seg = w[0]..w[1];
                jobs.push((&g.stack[seg.clone()], &g.rpos[seg], a, b));
            }
            bands::run(jobs, |(stack, rpos, z, area)| {
                solve_group(c, stack, rpos, &grid, z, area);
            });
        }
        let out = &o.h;
        bands::map_bands(self.nx, self.ny, [h], |y0, _y1, [hb]| {
            let src = &out[y0 * self.nx..y0 * self.nx + hb.len()];
            for (d, s) in hb.iter_mut().zip(src) {
                *d = f32::from_bits(s.load(Relaxed));
            }
        });
    }
}

/// What the group tasks read and write per cell (raster order).
struct Grid<'a> {
    /// Heights before the solve.
    h: &'a [f32],
    /// Receiver distances, cells.
    dist: &'a [f32],
    /// Erodibility factors.
    erod: Option<&'a [f32]>,
    /// Deposits, updated in place (each cell by its own group).
    sediment: &'a [AtomicU32],
    /// New heights.
    out_h: &'a [AtomicU32],
}

/// Constants of the ordered passes.
struct SolveConsts {
    fill: bool,
    route: bool,
    cell: f64,
    cell_area: f32,
    kdt: f64,
    m: f64,
    n: f64,
}

/// One outlet group: sums the drainage areas from the leaves down (in
/// cells, into `area`), then in one pass from the outlets up fills (raising
/// every entry not strictly above its receiver's filled height to just above
/// it) and solves the implicit stream-power equation against the receiver's
/// new height, keeping both heights per entry in `z` and writing the new
/// height and deposit of each cell to `grid`.
fn solve_group(
    c: &SolveConsts,
    stack: &[u32],
    rpos: &[u32],
    grid: &Grid<'_>,
    z: &mut [[f32; 2]],
    area: &mut [f32],
) {
    let len = stack.len();
    let (rpos, z, area) = (&rpos[..len], &mut z[..len], &mut area[..len]);
    area.fill(1.0);
    for k in (0..len).rev() {
        let r = rpos[k] as usize;
        if r != k {
            area[r] += area[k];
        }
    }
    for k in 0..len {
        let i = stack[k] as usize;
        let r = rpos[k] as usize;
        let h0 = grid.h[i];
        let (mut hf, mut hs) = (h0, h0);
        // The fill raise and the solve change (added to the deposit even when
        // zero, as the serial passes do; a deposit is never −0).
        let (mut filled, mut solved) = (0.0f32, 0.0f32);
        if r != k {
            let [rf, rs] = z[r];
            if c.fill && hf <= rf {
                let up = next_up(rf);
                filled = up - hf;
                hf = up;
            }
            hs = hf;
            let zr = f64::from(rs);
            let z0 = f64::from(hf);
            // Inside a lake (routing): no incision.
            if !(c.route && zr >= z0) {
                let kf = factor(
                    c,
                    area[k] * c.cell_area,
                    grid.dist[i],
                    grid.erod.map(|e| e[i]),
                );
                let zn = implicit(z0, zr, kf, c.n).max(zr) as f32;
                solved = zn - hf;
                hs = zn;
            }
        }
        z[k] = [hf, hs];
        grid.out_h[i].store(hs.to_bits(), Relaxed);
        let s = &grid.sediment[i];
        let d = (f32::from_bits(s.load(Relaxed)) + filled) + solved;
        s.store(d.to_bits(), Relaxed);
    }
}

/// The implicit factor `F = K·A^m·Δt / L^n` of a cell of drainage area `a`
/// (m²), receiver distance `d` (cells) and erodibility `e`.
#[inline]
fn factor(c: &SolveConsts, a: f32, d: f32, e: Option<f32>) -> f64 {
    let len = f64::from(d) * c.cell;
    // A^m: a square root for the default m = ½ (no `powf`).
    let a = f64::from(a);
    let am = if c.m == 0.5 {
        a.sqrt()
    } else if c.m == 1.0 {
        a
    } else {
        a.powf(c.m)
    };
    let ln = if c.n == 1.0 { len } else { len.powf(c.n) };
    c.kdt * e.map_or(1.0, f64::from) * am / ln
}

/// The implicit update of a cell at `z0` above a receiver at `zr` (already
/// updated): for `n = 1` in closed form, otherwise by Newton on
/// `z − z0 + F·(z − zr)^n = 0` over `(zr, z0]`.
#[inline]
fn implicit(z0: f64, zr: f64, kf: f64, n: f64) -> f64 {
    if n == 1.0 {
        (z0 + kf * zr) / (1.0 + kf)
    } else {
        let mut z = z0;
        for _ in 0..50 {
            let d = (z - zr).max(0.0);
            let f = z - z0 + kf * d.powf(n);
            let df = 1.0 + kf * n * d.powf(n - 1.0);
            let next = (z - f / df).max(zr);
            if (next - z).abs() <= 1e-9 * (1.0 + z.abs()) {
                z = next;
                break;
            }
            z = next;
        }
        z
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::{NoProgress, Seed};

    /// The drainage areas (m²) and deposits of [`step_reference`].
    struct Serial {
        area: Vec<f32>,
        sediment: Vec<f32>,
    }

    /// The serial step the group-parallel one replaced: fill along the whole
    /// stack, areas by one reverse walk, the factors per cell, one solve walk.
    fn step_reference(sp: &mut StreamPower, hf: &mut HeightField, out: &mut Serial) {
        let (nx, ny) = (sp.nx, sp.ny);
        let cell = f64::from(hf.cell_size());
        let p = sp.p.clone();
        let up = (p.uplift_m_per_yr * p.dt_yr) as f32;
        let h = hf.heights_mut().as_mut_slice();
        for y in 1..ny - 1 {
            for v in &mut h[y * nx + 1..y * nx + nx - 1] {
                *v += up;
            }
        }
        let mut g = sp.graph.take().unwrap_or_else(FlowGraph::empty);
        g.rebuild_with_fill(h, nx, ny, p.depressions, Some(&mut out.sediment));
        g.area_into(&mut out.area);
        let cell_area = (cell * cell) as f32;
        for a in &mut out.area {
            *a *= cell_area;
        }
        let c = SolveConsts {
            fill: false,
            route: p.depressions == Depressions::Route,
            cell,
            cell_area,
            kdt: p.k * p.dt_yr,
            m: p.m,
            n: p.n,
        };
        let erod = sp.erodibility.as_ref().map(|e| e.map().as_slice().to_vec());
        let kf: Vec<f64> = (0..nx * ny)
            .map(|i| factor(&c, out.area[i], g.distance[i], erod.as_ref().map(|e| e[i])))
            .collect();
        for &i in &g.stack {
            let i = i as usize;
            let r = g.receiver[i] as usize;
            if r == i {
                continue;
            }
            let (zr, z0) = (f64::from(h[r]), f64::from(h[i]));
            if c.route && zr >= z0 {
                continue;
            }
            let z = implicit(z0, zr, kf[i], p.n).max(zr) as f32;
            out.sediment[i] += z - h[i];
            h[i] = z;
        }
        sp.graph = Some(g);
    }

    /// The group-parallel fill, areas and solve against the serial passes
    /// ([`step_reference`]) on rough random terrains full of pits, for fill
    /// and lake routing, `n = 1` and `n = 2`, with and without an
    /// erodibility map, on one and two threads: heights, deposits and areas
    /// bit for bit after several steps (new pits appear as the terrain erodes).
    #[test]
    fn group_parallel_passes_equal_serial_passes() {
        let s = Seed(17);
        for (case, (nx, ny, depressions, n, erodible)) in [
            (61usize, 47usize, Depressions::Fill, 1.0, false),
            (40, 64, Depressions::Route, 1.0, true),
            (33, 35, Depressions::Fill, 2.0, true),
            (130, 9, Depressions::Fill, 1.0, false),
        ]
        .into_iter()
        .enumerate()
        {
            let hf = HeightField::from_fn(nx, ny, 30.0, |i, j| {
                (50.0 * s.derive_index(case as u64).gaussian2(i as i64, j as i64)) as f32
            })
            .unwrap();
            let p = StreamPowerParams {
                depressions,
                n,
                k: if n == 1.0 { 1e-4 } else { 1e-7 },
                ..Default::default()
            };
            let build = || {
                let mut sp = StreamPower::new(p.clone(), &hf).unwrap();
                if erodible {
                    let e = Grid2::from_fn(nx, ny, |i, j| {
                        0.5 + s.derive_index(99).uniform2(i as i64, j as i64) as f32
                    })
                    .unwrap();
                    sp = sp.with_erodibility(Erodibility::new(e).unwrap()).unwrap();
                }
                sp
            };
            let mut reference = build();
            let mut serial = Serial {
                area: vec![0.0; nx * ny],
                sediment: vec![0.0; nx * ny],
            };
            let mut hr = hf.clone();
            for _ in 0..6 {
                step_reference(&mut reference, &mut hr, &mut serial);
            }
            for threads in [1, 2] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut sp = build();
                let mut h = hf.clone();
                pool.install(|| sp.run(&mut h, 6, &NoProgress)).unwrap();
                let same = |what: &str, a: &[f32], b: &[f32]| {
                    for (k, (x, y)) in a.iter().zip(b).enumerate() {
                        assert!(
                            x.to_bits() == y.to_bits(),
                            "case {case}, {threads} threads: {what}[{k}] {x} vs serial {y}"
                        );
                    }
                };
                same("height", h.heights().as_slice(), hr.heights().as_slice());
                same(
                    "deposit",
                    sp.deposition().unwrap().as_slice(),
                    &serial.sediment,
                );
                same("area", sp.drainage_area().unwrap().as_slice(), &serial.area);
                let (g, gr) = (sp.flow_graph().unwrap(), reference.flow_graph().unwrap());
                assert_eq!(g.receiver, gr.receiver, "case {case}");
                assert_eq!(g.stack, gr.stack, "case {case}");
            }
            assert!(
                depressions == Depressions::Route || serial.sediment.iter().any(|&d| d > 0.0),
                "case {case}: nothing filled"
            );
            assert!(
                serial.sediment.iter().any(|&d| d < 0.0),
                "case {case}: nothing eroded"
            );
        }
    }

    /// Wall and CPU time per step at 4096² (`SP_N` to change) on the bench's
    /// terrain, two threads: `cargo test --release -p natura-terrain --lib
    /// stream_power_step_times -- --ignored --nocapture`.
    #[test]
    #[ignore = "timing harness"]
    fn stream_power_step_times() {
        let cpu = || {
            let s = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
            let f: Vec<&str> = s
                .rsplit(')')
                .next()
                .unwrap_or("")
                .split_whitespace()
                .collect();
            f.get(11..13).map_or(0.0, |v| {
                v.iter()
                    .map(|x| x.parse::<f64>().unwrap_or(0.0))
                    .sum::<f64>()
                    / 100.0
            })
        };
        let n: usize = std::env::var("SP_N")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(4096);
        let sp = crate::synth::SpectralParams {
            sigma_m: 200.0,
            ..Default::default()
        };
        let mut hf = crate::synth::spectral_synthesis(n, n, 10.0, &sp, Seed(1)).unwrap();
        let mut m = StreamPower::new(StreamPowerParams::default(), &hf).unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        for step in 0..6 {
            let (t0, c0) = (std::time::Instant::now(), cpu());
            pool.install(|| m.step(&mut hf)).unwrap();
            let (w, c) = (t0.elapsed().as_secs_f64(), cpu() - c0);
            eprintln!("step {step}: wall {:.0} ms, cpu {:.0} ms", w * 1e3, c * 1e3);
        }
        let sum: f64 = hf.heights().as_slice().iter().map(|&v| f64::from(v)).sum();
        eprintln!("checksum {sum}");
    }

    #[test]
    fn steady_state_follows_slope_area_law() {
        let n = 48;
        let s = Seed(3);
        let mut hf = HeightField::from_fn(n, n, 100.0, |i, j| {
            let edge = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            if edge {
                0.0
            } else {
                1.0 + s.uniform2(i as i64, j as i64) as f32
            }
        })
        .unwrap();
        let p = StreamPowerParams {
            dt_yr: 20_000.0,
            ..Default::default()
        };
        let mut sp = StreamPower::new(p.clone(), &hf).unwrap();
        sp.run(&mut hf, 3000, &NoProgress).unwrap();
        // One more step must change nothing (steady state) and S = U / (K A^m).
        let before = hf.clone();
        sp.step(&mut hf).unwrap();
        let g = sp.flow_graph().unwrap();
        let area = sp.drainage_area().unwrap();
        let mut worst = 0.0f64;
        for i in 0..n * n {
            let r = g.receiver[i] as usize;
            if r == i {
                continue;
            }
            let slope = f64::from(hf.heights().as_slice()[i] - hf.heights().as_slice()[r])
                / (f64::from(g.distance[i]) * 100.0);
            let want = p.uplift_m_per_yr / (p.k * f64::from(area.as_slice()[i]).powf(p.m));
            worst = worst.max((slope / want - 1.0).abs());
        }
        assert!(worst < 0.02, "slope–area misfit {worst}");
        let change = hf
            .heights()
            .as_slice()
            .iter()
            .zip(before.heights().as_slice())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(change < 1e-3, "not steady: {change}");
    }

    #[test]
    fn nonlinear_n_and_route_mode_stay_finite() {
        let s = Seed(1);
        for p in [
            StreamPowerParams {
                n: 2.0,
                k: 1e-7,
                ..Default::default()
            },
            StreamPowerParams {
                depressions: Depressions::Route,
                ..Default::default()
            },
            StreamPowerParams {
                dt_yr: 1e7,
                ..Default::default()
            },
        ] {
            let mut hf = HeightField::from_fn(24, 24, 50.0, |i, j| {
                100.0 * s.uniform2(i as i64, j as i64) as f32
            })
            .unwrap();
            StreamPower::new(p, &hf)
                .unwrap()
                .run(&mut hf, 20, &NoProgress)
                .unwrap();
            assert!(hf.check_finite().is_ok());
        }
        assert!(
            StreamPowerParams {
                dt_yr: 0.0,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            StreamPowerParams {
                k: -1.0,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            StreamPowerParams {
                depressions: Depressions::Keep,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
    }
}
