//! Particle ("droplet") hydraulic erosion (Beyer 2015, "Implementation of a
//! method for hydraulic erosion", BSc thesis, TU München). Not in the seed
//! documents: spec `terrain.md` §7.2.
//!
//! Each droplet carries position, direction, speed, water and sediment. Per
//! step: `dir ← dir·inertia − ∇h·(1 − inertia)` (normalised), move one cell,
//! capacity `max(−Δh, min_slope)·speed·water·K_capacity`; over capacity (or
//! moving uphill) deposit at the old position (bilinear weights; uphill it
//! fills at most the rise), under capacity erode `min((cap − s)·K_erode, −Δh)`
//! with a radial brush of `radius` cells; `speed² ← speed² − Δh·g`;
//! `water ← water·(1 − K_evaporate)`. A droplet lives `lifetime` steps.
//!
//! **Determinism and parallelism.** Droplets run in batches of `batch`: every
//! droplet of a batch is simulated in parallel against the terrain as it was
//! at the start of the batch, recording its height changes; the changes are
//! then applied in droplet order. Batches depend only on the droplet index,
//! never on the thread count, so results are bit-identical on any number of
//! threads. The default `batch = 1` is Beyer's sequential algorithm exactly.
//! Larger batches are an approximation: droplets of one batch do not see each
//! other, so several can dig the same rim or fill the same pit, each up to
//! its own limit; where many droplets meet (dense batches on small maps) this
//! over-digs and can run away. Keep `batch` far below
//! `cells / (lifetime · brush area)`. Mass is conserved: sediment still carried when a droplet dies is
//! deposited where it stops; sediment carried off the edge is counted.

use natura_core::{Grid2, HeightField, Progress, Seed};

use super::{Erodibility, check_erodibility, check_field, check_model_size};
use crate::error::{Result, in_range, invalid, non_negative, positive};
use crate::par;

/// Parameters of [`DropletErosion`]; defaults are Beyer's (2015).
#[derive(Clone, Debug, PartialEq)]
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
    /// Droplets simulated together against a frozen terrain (1..=65536). Default 1
    /// (sequential, exact); see the module docs before raising it.
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
        if !(1..=65536).contains(&self.batch) {
            return Err(invalid(
                "DropletParams::batch",
                self.batch,
                "must lie in [1, 65536]",
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
}

impl DropletErosion {
    /// A model for fields the size of `hf`; droplet `k` starts at a position
    /// indexed by `(seed, k)`.
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
        })
    }

    /// Scales erosion per cell.
    pub fn with_erodibility(mut self, e: Erodibility) -> Result<Self> {
        check_erodibility(Some(&e), self.nx, self.ny)?;
        self.erodibility = Some(e);
        Ok(self)
    }

    /// Net height change from droplets so far (positive: deposition), metres.
    pub fn deposition(&self) -> Result<Grid2<f32>> {
        Ok(Grid2::from_vec(self.nx, self.ny, self.deposition.clone())?)
    }

    /// Sediment carried off the edge so far (sum of heights, metres).
    #[must_use]
    pub fn outflow(&self) -> f64 {
        self.outflow
    }

    /// Simulates `droplets` more droplets.
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

    fn batch(&mut self, hf: &mut HeightField, first: u64, count: u64) {
        if count == 1 {
            // Sequential: no thread hand-off for a single droplet.
            let mut deltas = Vec::with_capacity(1024);
            let out = self.simulate(hf.heights().as_slice(), first, &mut deltas);
            let hm = hf.heights_mut().as_mut_slice();
            for (i, d) in deltas {
                hm[i as usize] += d;
                self.deposition[i as usize] += d;
            }
            self.outflow += out;
            return;
        }
        let h = hf.heights().as_slice();
        let ids: Vec<u64> = (first..first + count).collect();
        let chunks: Vec<Vec<u64>> = ids.chunks(16).map(<[u64]>::to_vec).collect();
        let this = &*self;
        let results: Vec<(Vec<(u32, f32)>, f64)> = par::run(chunks, |ids| {
            let mut deltas = Vec::new();
            let mut out = 0.0;
            for id in ids {
                out += this.simulate(h, id, &mut deltas);
            }
            (deltas, out)
        });
        let hm = hf.heights_mut().as_mut_slice();
        for (deltas, out) in results {
            for (i, d) in deltas {
                hm[i as usize] += d;
                self.deposition[i as usize] += d;
            }
            self.outflow += out;
        }
    }

    /// Height and gradient at `(x, y)` (cell units) by bilinear interpolation.
    #[inline]
    fn height_grad(&self, h: &[f32], x: f32, y: f32) -> (f32, f32, f32) {
        let nx = self.nx;
        let (ix, iy) = (x as usize, y as usize);
        let (u, v) = (x - ix as f32, y - iy as f32);
        let i = iy * nx + ix;
        let (h00, h10, h01, h11) = (h[i], h[i + 1], h[i + nx], h[i + nx + 1]);
        let gx = (h10 - h00) * (1.0 - v) + (h11 - h01) * v;
        let gy = (h01 - h00) * (1.0 - u) + (h11 - h10) * u;
        let z =
            h00 * (1.0 - u) * (1.0 - v) + h10 * u * (1.0 - v) + h01 * (1.0 - u) * v + h11 * u * v;
        (z, gx, gy)
    }

    /// Runs droplet `id`, appending height changes; returns sediment lost off the edge.
    fn simulate(&self, h: &[f32], id: u64, deltas: &mut Vec<(u32, f32)>) -> f64 {
        let p = &self.p;
        let (nx, ny) = (self.nx, self.ny);
        let (wmax, hmax) = ((nx - 1) as f32, (ny - 1) as f32);
        let key = id as i64;
        let mut x = self.seed.uniform2(key, 0) as f32 * wmax;
        let mut y = self.seed.uniform2(key, 1) as f32 * hmax;
        let (mut dx, mut dy) = (0.0f32, 0.0f32);
        let mut speed = p.initial_speed as f32;
        let mut water = p.initial_water as f32;
        let mut sed = 0.0f32;
        let inertia = p.inertia as f32;
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        let deposit_at = |x: f32, y: f32, amount: f32, deltas: &mut Vec<(u32, f32)>| {
            let (ix, iy) = (x as usize, y as usize);
            let (u, v) = (x - ix as f32, y - iy as f32);
            let i = (iy * nx + ix) as u32;
            deltas.push((i, amount * (1.0 - u) * (1.0 - v)));
            deltas.push((i + 1, amount * u * (1.0 - v)));
            deltas.push((i + nx as u32, amount * (1.0 - u) * v));
            deltas.push((i + nx as u32 + 1, amount * u * v));
        };
        for step in 0..p.lifetime {
            let (z, gx, gy) = self.height_grad(h, x, y);
            dx = dx * inertia - gx * (1.0 - inertia);
            dy = dy * inertia - gy * (1.0 - inertia);
            let len = (dx * dx + dy * dy).sqrt();
            if len > 1e-12 {
                dx /= len;
                dy /= len;
            } else {
                let a =
                    self.seed.uniform(&[key, i64::from(step), 2]) as f32 * std::f32::consts::TAU;
                dx = a.cos();
                dy = a.sin();
            }
            let (nxp, nyp) = (x + dx, y + dy);
            if !(nxp >= 0.0 && nyp >= 0.0 && nxp < wmax && nyp < hmax) {
                return f64::from(sed); // carried off the map
            }
            let (nz, _, _) = self.height_grad(h, nxp, nyp);
            let dh = nz - z;
            let cap = (-dh).max(p.min_slope as f32) * speed * water * p.capacity as f32;
            if sed > cap || dh > 0.0 {
                let amount = if dh > 0.0 {
                    dh.min(sed)
                } else {
                    (sed - cap) * p.deposit as f32
                };
                if amount > 0.0 {
                    sed -= amount;
                    deposit_at(x, y, amount, deltas);
                }
            } else {
                let want = ((cap - sed) * p.erode as f32).min(-dh);
                let (cx, cy) = (x as i32, y as i32);
                let mut wsum = 0.0f32;
                for &(bx, by, w) in &self.brush {
                    let (px, py) = (cx + bx, cy + by);
                    if px >= 0 && py >= 0 && (px as usize) < nx && (py as usize) < ny {
                        wsum += w;
                    }
                }
                if wsum > 0.0 && want > 0.0 {
                    for &(bx, by, w) in &self.brush {
                        let (px, py) = (cx + bx, cy + by);
                        if px >= 0 && py >= 0 && (px as usize) < nx && (py as usize) < ny {
                            let i = py as usize * nx + px as usize;
                            let k = erod.map_or(1.0, |e| e[i]);
                            let amount = want * w / wsum * k;
                            if amount > 0.0 {
                                deltas.push((i as u32, -amount));
                                sed += amount;
                            }
                        }
                    }
                }
            }
            speed = (speed * speed - dh * p.gravity as f32).max(0.0).sqrt();
            water *= 1.0 - p.evaporate as f32;
            x = nxp;
            y = nyp;
        }
        if sed > 0.0 {
            deposit_at(x, y, sed, deltas);
        }
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::NoProgress;

    fn cone(n: usize) -> HeightField {
        let s = Seed(6);
        HeightField::from_fn(n, n, 1.0, |i, j| {
            let (x, y) = (i as f32 - n as f32 / 2.0, j as f32 - n as f32 / 2.0);
            60.0 - (x * x + y * y).sqrt() + 0.5 * s.gaussian2(i as i64, j as i64) as f32
        })
        .unwrap()
    }

    #[test]
    fn conserves_mass_and_changes_terrain() {
        let mut hf = cone(64);
        let m0 = hf.heights().sum();
        let mut d = DropletErosion::new(DropletParams::default(), &hf, Seed(1)).unwrap();
        d.run(&mut hf, 5000, &NoProgress).unwrap();
        let m1 = hf.heights().sum() + d.outflow();
        assert!((m1 - m0).abs() < 1e-4 * m0, "{m0} → {m1}");
        assert!(
            d.deposition()
                .unwrap()
                .as_slice()
                .iter()
                .any(|&v| v < -0.01)
        );
        assert!(hf.check_finite().is_ok());
    }

    #[test]
    fn refuses_bad_params() {
        let hf = cone(16);
        for p in [
            DropletParams {
                inertia: 1.0,
                ..Default::default()
            },
            DropletParams {
                radius: 0,
                ..Default::default()
            },
            DropletParams {
                erode: -0.1,
                ..Default::default()
            },
            DropletParams {
                lifetime: 0,
                ..Default::default()
            },
            DropletParams {
                capacity: f64::NAN,
                ..Default::default()
            },
        ] {
            assert!(DropletErosion::new(p, &hf, Seed(1)).is_err());
        }
    }
}
