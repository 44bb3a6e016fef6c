//! Stream-power fluvial erosion with tectonic uplift, solved implicitly in O(n)
//! per step (Braun & Willett 2013, "A very efficient O(n), implicit and parallel
//! method to solve the stream power equation governing fluvial incision and
//! landscape evolution", Geomorphology 180-181). Not in the seed documents:
//! spec `terrain.md` §7.2; it realises the "orogenesis" wish of DIS:L1192 and
//! the fractal drainage networks MKM:L77-83 and SIM:L325 call for.
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

use natura_core::{Grid2, HeightField, Progress};

use super::{Erodibility, check_erodibility, check_field, check_model_size};
pub use crate::analysis::flow::Depressions;
use crate::analysis::flow::FlowGraph;
use crate::error::{Result, in_range, invalid, non_negative, positive};
use crate::par;

/// Parameters of [`StreamPower`].
#[derive(Clone, Debug, PartialEq)]
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
    /// `K ≥ 0`, `m ∈ [0, 2]`, `n ∈ [0.5, 4]`, `U ≥ 0` (≤ 1 m/yr), `Δt ∈ (0, 10⁷]` years,
    /// and `Keep` refused (rivers must reach the edge).
    pub fn validate(&self) -> Result<()> {
        non_negative("StreamPowerParams::k", self.k)?;
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
    area: Vec<f32>,
    graph: Option<FlowGraph>,
    sediment: Vec<f32>,
    /// `F / (1 + …)` factors `K·A^m·Δt / L^n` per cell (scratch).
    kf: Vec<f64>,
}

impl StreamPower {
    /// A model for fields the size of `hf`.
    pub fn new(p: StreamPowerParams, hf: &HeightField) -> Result<Self> {
        p.validate()?;
        check_model_size("stream-power erosion", hf)?;
        let n = hf.nx() * hf.ny();
        Ok(Self {
            p,
            nx: hf.nx(),
            ny: hf.ny(),
            erodibility: None,
            area: vec![0.0; n],
            graph: None,
            sediment: vec![0.0; n],
            kf: Vec::new(),
        })
    }

    /// Scales `K` per cell (rock strata, DIS:L1190).
    pub fn with_erodibility(mut self, e: Erodibility) -> Result<Self> {
        check_erodibility(Some(&e), self.nx, self.ny)?;
        self.erodibility = Some(e);
        Ok(self)
    }

    /// Drainage area of the last step, m².
    pub fn drainage_area(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.area.clone())?)
    }

    /// Net deposition (positive, metres: depressions filled) minus erosion since the
    /// model was built, uplift excluded.
    pub fn deposition(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.sediment.clone())?)
    }

    /// The flow graph of the last step.
    #[must_use]
    pub fn flow_graph(&self) -> Option<&FlowGraph> {
        self.graph.as_ref()
    }

    /// Runs `steps` steps.
    pub fn run(&mut self, hf: &mut HeightField, steps: u32, progress: &dyn Progress) -> Result<()> {
        check_field("stream-power erosion", hf, self.nx, self.ny)?;
        progress.start("stream power", u64::from(steps));
        for _ in 0..steps {
            self.step_unchecked(hf);
            progress.advance(1);
        }
        progress.finish();
        Ok(())
    }

    /// One step.
    pub fn step(&mut self, hf: &mut HeightField) -> Result<()> {
        check_field("stream-power erosion", hf, self.nx, self.ny)?;
        self.step_unchecked(hf);
        Ok(())
    }

    fn step_unchecked(&mut self, hf: &mut HeightField) {
        let (nx, ny) = (self.nx, self.ny);
        let cell = f64::from(hf.cell_size());
        let p = &self.p;
        let up = (p.uplift_m_per_yr * p.dt_yr) as f32;
        let h = hf.heights_mut().as_mut_slice();
        // Uplift everything but the base level.
        par::map_bands(nx, ny, [&mut *h], |y0, y1, [hb]| {
            for y in y0.max(1)..y1.min(ny - 1) {
                let r = (y - y0) * nx;
                for v in &mut hb[r + 1..r + nx - 1] {
                    *v += up;
                }
            }
        });
        // Reuse the last step's graph buffers; filling deposits into `sediment`.
        let mut g = self.graph.take().unwrap_or_else(FlowGraph::empty);
        g.rebuild_with_fill(h, nx, ny, p.depressions, Some(&mut self.sediment));
        g.area_into(&mut self.area);
        let cell_area = (cell * cell) as f32;
        for a in &mut self.area {
            *a *= cell_area;
        }
        // The implicit factors F = K·A^m·Δt / L^n, in parallel (pure per cell).
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        let kdt = p.k * p.dt_yr;
        let (m, n) = (p.m, p.n);
        self.kf.resize(nx * ny, 0.0);
        {
            let (area, rec, dist) = (&self.area, &g.receiver, &g.distance);
            par::map_bands(nx, ny, [self.kf.as_mut_slice()], |y0, _y1, [kf]| {
                let base = y0 * nx;
                for (k, f) in kf.iter_mut().enumerate() {
                    let i = base + k;
                    if rec[i] as usize == i {
                        continue;
                    }
                    let len = f64::from(dist[i]) * cell;
                    // A^m: a square root for the default m = ½ (no `powf`).
                    let a = f64::from(area[i]);
                    let am = if m == 0.5 {
                        a.sqrt()
                    } else if m == 1.0 {
                        a
                    } else {
                        a.powf(m)
                    };
                    let ln = if n == 1.0 { len } else { len.powf(n) };
                    *f = kdt * erod.map_or(1.0, |e| f64::from(e[i])) * am / ln;
                }
            });
        }
        let route = p.depressions == Depressions::Route;
        for &i in &g.stack {
            let i = i as usize;
            let r = g.receiver[i] as usize;
            if r == i {
                continue;
            }
            let zr = f64::from(h[r]);
            let z0 = f64::from(h[i]);
            if route && zr >= z0 {
                continue; // inside a lake: no incision
            }
            let kf = self.kf[i];
            let z = if n == 1.0 {
                (z0 + kf * zr) / (1.0 + kf)
            } else {
                // Solve z − z0 + kf·(z − zr)^n = 0 on (zr, z0] by Newton from z0.
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
            };
            let z = z.max(zr) as f32;
            self.sediment[i] += z - h[i];
            h[i] = z;
        }
        self.graph = Some(g);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::{NoProgress, Seed};

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
