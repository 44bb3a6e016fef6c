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

/// The rows of the field a set of droplets may change, in metres, with the
/// deposition map beside them; indices are global (`offset` is the first
/// sample's index). The model works in cell units (heights / cell size).
struct Ground<'a> {
    h: &'a mut [f32],
    deposition: &'a mut [f32],
    offset: usize,
    cell: f32,
}

impl Ground<'_> {
    /// Height of sample `i`, cell units.
    #[inline]
    fn height(&self, i: usize) -> f32 {
        self.h[i - self.offset] / self.cell
    }

    /// Adds `d` (cell units) to sample `i`.
    #[inline]
    fn add(&mut self, i: usize, d: f32) {
        let d = d * self.cell;
        self.h[i - self.offset] += d;
        self.deposition[i - self.offset] += d;
    }
}

/// What one droplet needs of the model: its parameters and the field's shape.
struct DropletModel<'a> {
    p: &'a DropletParams,
    nx: usize,
    ny: usize,
    seed: Seed,
    brush: &'a [(i32, i32, f32)],
    /// The brush's largest offset along either axis, cells.
    brush_reach: i32,
    /// The brush's weights summed in order.
    brush_total: f32,
    erodibility: Option<&'a [f32]>,
    cell: f32,
}

impl DropletModel<'_> {
    /// Start position of droplet `id` (cell units), indexed by `(seed, id)`.
    fn start(&self, id: u64) -> (f32, f32) {
        let key = id as i64;
        let (wmax, hmax) = ((self.nx - 1) as f32, (self.ny - 1) as f32);
        (
            self.seed.uniform2(key, 0) as f32 * wmax,
            self.seed.uniform2(key, 1) as f32 * hmax,
        )
    }

    /// Rows per band: twice the farthest a droplet reaches from its start
    /// (one cell per step, the brush, the interpolation corners and rounding).
    fn band_rows(&self) -> usize {
        2 * (self.p.lifetime as usize + self.p.radius as usize + 2)
    }

    /// Runs droplet `id` on `ground`; returns sediment lost off the edge (metres).
    ///
    /// Beyer's step with two bounds that keep every height inside the range
    /// the terrain already spans: erosion never lowers a cell below the height
    /// the droplet flows down to, and deposition never raises a cell above the
    /// higher end of the step. Sediment that a bound holds back stays in the
    /// droplet, so mass is conserved; what it still carries when it dies is
    /// laid down where it stops.
    fn simulate(&self, g: &mut Ground<'_>, id: u64) -> f64 {
        let p = self.p;
        let (nx, ny) = (self.nx, self.ny);
        let (wmax, hmax) = ((nx - 1) as f32, (ny - 1) as f32);
        let key = id as i64;
        let (mut x, mut y) = self.start(id);
        let (mut dx, mut dy) = (0.0f32, 0.0f32);
        let mut speed = p.initial_speed as f32;
        let mut water = p.initial_water as f32;
        let mut sed = 0.0f32;
        let inertia = p.inertia as f32;
        for step in 0..p.lifetime {
            let corners = Corners::at(x, y, nx, ny);
            let (z, gx, gy) = corners.height_grad(|i| g.height(i));
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
                return f64::from(sed * self.cell); // carried off the map
            }
            let (nz, _, _) = Corners::at(nxp, nyp, nx, ny).height_grad(|i| g.height(i));
            let dh = nz - z;
            let cap = (-dh).max(p.min_slope as f32) * speed * water * p.capacity as f32;
            if sed > cap || dh > 0.0 {
                let amount = if dh > 0.0 {
                    dh.min(sed)
                } else {
                    (sed - cap) * p.deposit as f32
                };
                if amount > 0.0 {
                    // No corner rises above the higher end of the step.
                    sed -= corners.deposit(amount, z.max(nz), g);
                }
            } else {
                let want = ((cap - sed) * p.erode as f32).min(-dh);
                let (cx, cy) = (x as i32, y as i32);
                let inside = |bx: i32, by: i32| {
                    let (px, py) = (cx + bx, cy + by);
                    (px >= 0 && py >= 0 && (px as usize) < nx && (py as usize) < ny)
                        .then(|| py as usize * nx + px as usize)
                };
                // Away from the field's edges the whole brush lies inside:
                // its weight sum is the brush's own (summed in the same
                // order, so the same bits) and no sample needs a test.
                let r = self.brush_reach;
                let interior =
                    cx >= r && cy >= r && ((cx + r) as usize) < nx && ((cy + r) as usize) < ny;
                let wsum: f32 = if interior {
                    self.brush_total
                } else {
                    self.brush
                        .iter()
                        .filter(|&&(bx, by, _)| inside(bx, by).is_some())
                        .map(|b| b.2)
                        .sum()
                };
                if wsum > 0.0 && want > 0.0 {
                    let centre = cy as isize * nx as isize + cx as isize;
                    for &(bx, by, w) in self.brush {
                        let i = if interior {
                            (centre + by as isize * nx as isize + bx as isize) as usize
                        } else if let Some(i) = inside(bx, by) {
                            i
                        } else {
                            continue;
                        };
                        let k = self.erodibility.map_or(1.0, |e| e[i]);
                        // No cell is dug below the height the droplet flows to.
                        let room = (g.height(i) - nz).max(0.0);
                        let amount = (want * w / wsum * k).min(room);
                        if amount > 0.0 {
                            g.add(i, -amount);
                            sed += amount;
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
            let corners = Corners::at(x, y, nx, ny);
            for (i, w) in corners.cells.into_iter().zip(corners.weights) {
                g.add(i, sed * w);
            }
        }
        0.0
    }
}

/// The brush's largest offset along either axis, cells.
fn reach(brush: &[(i32, i32, f32)]) -> i32 {
    brush
        .iter()
        .map(|&(x, y, _)| x.abs().max(y.abs()))
        .max()
        .unwrap_or(0)
}

/// The four samples around a point `(x, y)` (cell units) and their bilinear
/// weights. The cell index is capped at the last cell, so a point on the
/// field's far edge (`x = nx − 1` or `y = ny − 1`) is interpolated inside the last cell with
/// weight 1 on its far side instead of reading past the row.
struct Corners {
    cells: [usize; 4],
    weights: [f32; 4],
    u: f32,
    v: f32,
}

impl Corners {
    #[inline]
    fn at(x: f32, y: f32, nx: usize, ny: usize) -> Self {
        let ix = (x as usize).min(nx - 2);
        let iy = (y as usize).min(ny - 2);
        let (u, v) = (x - ix as f32, y - iy as f32);
        let i = iy * nx + ix;
        Self {
            cells: [i, i + 1, i + nx, i + nx + 1],
            weights: [(1.0 - u) * (1.0 - v), u * (1.0 - v), (1.0 - u) * v, u * v],
            u,
            v,
        }
    }

    /// Height and gradient (cell units) from the corner heights `h(i)`.
    #[inline]
    fn height_grad(&self, h: impl Fn(usize) -> f32) -> (f32, f32, f32) {
        let [h00, h10, h01, h11] = self.cells.map(h);
        let (u, v) = (self.u, self.v);
        let gx = (h10 - h00) * (1.0 - v) + (h11 - h01) * v;
        let gy = (h01 - h00) * (1.0 - u) + (h11 - h10) * u;
        let z = h00 * self.weights[0]
            + h10 * self.weights[1]
            + h01 * self.weights[2]
            + h11 * self.weights[3];
        (z, gx, gy)
    }

    /// Lays `amount` down on the corners by their weights, none above
    /// `ceiling`; returns what was laid down.
    #[inline]
    fn deposit(&self, amount: f32, ceiling: f32, g: &mut Ground<'_>) -> f32 {
        let mut laid = 0.0;
        for (&i, &w) in self.cells.iter().zip(&self.weights) {
            let add = (amount * w).min((ceiling - g.height(i)).max(0.0));
            if add > 0.0 {
                g.add(i, add);
                laid += add;
            }
        }
        laid
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

    /// A rough random field (fractal sum of lattice Gaussians) for the stability tests.
    fn rough(nx: usize, ny: usize, cell: f32, seed: u64) -> HeightField {
        let s = Seed(seed);
        HeightField::from_fn(nx, ny, cell, |i, j| {
            let mut v = 0.0;
            let (mut a, mut f) = (50.0f32, 4usize);
            while f <= 2 * nx.max(ny) {
                let (fi, fj) = ((i * f / nx) as i64, (j * f / ny) as i64);
                v += a * s.gaussian2(fi, fj + 1000 * f as i64) as f32;
                a *= 0.5;
                f *= 2;
            }
            v
        })
        .unwrap()
    }

    /// The brush's shortcut away from the edges (its weight sum taken as
    /// the whole brush's, no sample tested) changes nothing: droplets run
    /// with the shortcut and with every sample tested leave the same field
    /// and deposition, bit for bit.
    #[test]
    fn the_interior_brush_shortcut_changes_nothing() {
        let hf = rough(96, 80, 10.0, 7);
        let d = DropletErosion::new(DropletParams::default(), &hf, Seed(3)).unwrap();
        let run = |reach: i32| {
            let model = DropletModel {
                p: &d.p,
                nx: 96,
                ny: 80,
                seed: d.seed,
                brush: &d.brush,
                brush_reach: reach,
                brush_total: d.brush.iter().map(|b| b.2).sum(),
                erodibility: None,
                cell: d.cell,
            };
            let mut h = hf.heights().as_slice().to_vec();
            let mut dep = vec![0.0f32; h.len()];
            let mut g = Ground {
                h: &mut h,
                deposition: &mut dep,
                offset: 0,
                cell: d.cell,
            };
            let out: f64 = (0..3000).map(|id| model.simulate(&mut g, id)).sum();
            (h, dep, out)
        };
        // A reach no cell satisfies sends every step through the tested path.
        let (fast, slow) = (run(reach(&d.brush)), run(i32::MAX / 4));
        assert_eq!(reach(&d.brush), 2);
        assert!(
            fast.0
                .iter()
                .zip(hf.heights().as_slice())
                .any(|(a, b)| a != b)
        );
        assert!(
            fast.0
                .iter()
                .zip(&slow.0)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
        assert!(
            fast.1
                .iter()
                .zip(&slow.1)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
        assert_eq!(fast.2.to_bits(), slow.2.to_bits());
    }

    /// A droplet whose start rounds onto the field's far edge (x = nx − 1 in
    /// f32) interpolates inside the last cell instead of reading past the row.
    #[test]
    fn a_start_on_the_far_edge_stays_inside_the_field() {
        let corners = Corners::at(255.0, 255.0, 256, 256);
        assert!(corners.cells.iter().all(|&i| i < 256 * 256));
        assert_eq!(corners.weights, [0.0, 0.0, 0.0, 1.0]);
        let corners = Corners::at(255.0, 3.5, 256, 256);
        assert_eq!(corners.cells[1] % 256, 255, "same row, not the next one");
        // Find a droplet index whose start rounds to x = 255 exactly, and run it.
        let hf = rough(256, 256, 30.0, 4);
        let mut d = DropletErosion::new(DropletParams::default(), &hf, Seed(37)).unwrap();
        let model = DropletModel {
            p: &d.p,
            nx: 256,
            ny: 256,
            seed: d.seed,
            brush: &d.brush,
            brush_reach: reach(&d.brush),
            brush_total: d.brush.iter().map(|b| b.2).sum(),
            erodibility: None,
            cell: d.cell,
        };
        let id = (0..400_000_000u64)
            .find(|&id| {
                let (x, y) = model.start(id);
                x == 255.0 || y == 255.0
            })
            .expect("an edge start within 4e8 droplets");
        let mut hf2 = hf.clone();
        d.next_droplet = id;
        d.run(&mut hf2, 1, &NoProgress).unwrap();
        assert!(hf2.check_finite().is_ok());
    }

    /// Millions of droplet steps with Beyer's defaults leave every height
    /// inside the range the terrain started with (the field grows no pit and
    /// no spike): the unbounded version reached ±1e21 m here.
    #[test]
    fn default_params_stay_in_range_over_many_droplets() {
        let mut hf = rough(96, 96, 1.0, 11);
        let (lo, hi) = hf.min_max();
        let mut d = DropletErosion::new(DropletParams::default(), &hf, Seed(2)).unwrap();
        d.run(&mut hf, 150_000, &NoProgress).unwrap();
        let (a, b) = hf.min_max();
        assert!(
            a >= lo && b <= hi + 0.05 * (hi - lo),
            "{lo}..{hi} → {a}..{b}"
        );
    }

    /// Bands of droplets running at once give the same field on 1 and 2
    /// threads, and conserve mass like the sequential run.
    #[test]
    fn banded_rounds_are_thread_independent_and_conserve_mass() {
        let p = DropletParams {
            batch: 512,
            ..DropletParams::default()
        };
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut hf = rough(80, 300, 2.0, 5);
                let mut d = DropletErosion::new(p.clone(), &hf, Seed(9)).unwrap();
                d.run(&mut hf, 20_000, &NoProgress).unwrap();
                (hf, d.outflow())
            })
        };
        let (a, out_a) = run(1);
        let (b, out_b) = run(2);
        assert_eq!(a.heights().as_slice(), b.heights().as_slice());
        assert_eq!(out_a.to_bits(), out_b.to_bits());
        let m0 = rough(80, 300, 2.0, 5).heights().sum();
        let m1 = a.heights().sum() + out_a;
        assert!((m1 - m0).abs() < 1e-3 * m0.abs().max(1.0), "{m0} → {m1}");
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
        /// Any accepted parameter set on any grid size keeps heights finite
        /// and inside the starting range, plus at most what the last deposits
        /// of dying droplets add.
        #[test]
        fn any_accepted_params_stay_in_range(
            nx in 3usize..48, ny in 3usize..48, cell in 0.1f32..500.0,
            inertia in 0.0f64..0.99, capacity in 0.0f64..50.0, min_slope in 0.0f64..1.0,
            erode in 0.0f64..=1.0, deposit in 0.0f64..=1.0, evaporate in 0.0f64..0.99,
            gravity in 0.0f64..100.0, radius in 1u32..=16, lifetime in 1u32..200,
            water in 0.01f64..10.0, speed in 0.0f64..10.0, batch in 1u32..300,
            seed in 0u64..1000,
        ) {
            let p = DropletParams {
                inertia, capacity, min_slope, erode, deposit, evaporate, gravity, radius,
                lifetime, initial_water: water, initial_speed: speed, batch,
            };
            let mut hf = rough(nx, ny, cell, seed);
            let (lo, hi) = hf.min_max();
            let mut d = DropletErosion::new(p, &hf, Seed(seed)).unwrap();
            d.run(&mut hf, 3000, &NoProgress).unwrap();
            proptest::prop_assert!(hf.check_finite().is_ok());
            let (a, b) = hf.min_max();
            proptest::prop_assert!(a >= lo, "{} < {}", a, lo);
            proptest::prop_assert!(b <= hi + (hi - lo), "{} > {} + range", b, hi);
        }
    }
}
