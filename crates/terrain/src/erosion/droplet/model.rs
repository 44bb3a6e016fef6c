//! One droplet's life (Beyer 2015): the equations of the module docs of
//! [`super`], on the live terrain of its band. [`super::DropletErosion`]
//! schedules the droplets; everything a droplet computes is here.

use super::DropletParams;
use natura_core::Seed;

/// The rows of the field a set of droplets may change, in metres, with the
/// deposition map beside them; indices are global (`offset` is the first
/// sample's index). The model works in cell units (heights / cell size).
pub(super) struct Ground<'a> {
    pub(super) h: &'a mut [f32],
    pub(super) deposition: &'a mut [f32],
    pub(super) offset: usize,
    pub(super) cell: f32,
}

impl Ground<'_> {
    /// Height of sample `i`, cell units.
    #[inline]
    pub(super) fn height(&self, i: usize) -> f32 {
        self.h[i - self.offset] / self.cell
    }

    /// Adds `d` (cell units) to sample `i`.
    #[inline]
    pub(super) fn add(&mut self, i: usize, d: f32) {
        let d = d * self.cell;
        self.h[i - self.offset] += d;
        self.deposition[i - self.offset] += d;
    }

    /// Lowers sample `i` by `a` (cell units) as [`add`](Self::add) with
    /// `-a` does, but never below `floor_m` (metres, at most its height):
    /// returns the depth taken (cell units), `a` itself unless the floor
    /// held. A bound that holds in exact arithmetic can fail by a rounding
    /// of the metres-to-cells conversion; repeated over many droplets, those
    /// roundings dug a pit step by step below the terrain's lowest point.
    #[inline]
    pub(super) fn dig(&mut self, i: usize, a: f32, floor_m: f32) -> f32 {
        let j = i - self.offset;
        let d = -a * self.cell;
        if self.h[j] + d >= floor_m {
            self.h[j] += d;
            self.deposition[j] += d;
            return a;
        }
        let d = (floor_m - self.h[j]).min(0.0);
        self.h[j] += d;
        self.deposition[j] += d;
        -d / self.cell
    }
}

/// What one droplet needs of the model: its parameters and the field's shape.
pub(super) struct DropletModel<'a> {
    pub(super) p: &'a DropletParams,
    pub(super) nx: usize,
    pub(super) ny: usize,
    pub(super) seed: Seed,
    pub(super) brush: &'a [(i32, i32, f32)],
    /// The brush's largest offset along either axis, cells.
    pub(super) brush_reach: i32,
    /// The brush's weights summed in order.
    pub(super) brush_total: f32,
    pub(super) erodibility: Option<&'a [f32]>,
    pub(super) cell: f32,
}

impl DropletModel<'_> {
    /// Start position of droplet `id` (cell units), indexed by `(seed, id)`.
    pub(super) fn start(&self, id: u64) -> (f32, f32) {
        let key = id as i64;
        let (wmax, hmax) = ((self.nx - 1) as f32, (self.ny - 1) as f32);
        (
            self.seed.uniform2(key, 0) as f32 * wmax,
            self.seed.uniform2(key, 1) as f32 * hmax,
        )
    }

    /// Rows per band: twice the farthest a droplet reaches from its start
    /// (one cell per step, the brush, the interpolation corners and rounding).
    pub(super) fn band_rows(&self) -> usize {
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
    pub(super) fn simulate(&self, g: &mut Ground<'_>, id: u64) -> f64 {
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
            let next = Corners::at(nxp, nyp, nx, ny);
            let (nz, _, _) = next.height_grad(|i| g.height(i));
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
                    // The lowest corner where the droplet flows to, metres:
                    // below `nz` in exact arithmetic, and a height the
                    // terrain already has, so no rounding takes a cell
                    // lower than the terrain's lowest point.
                    let floor = next
                        .cells
                        .into_iter()
                        .map(|c| g.h[c - g.offset])
                        .fold(f32::INFINITY, f32::min);
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
                            sed += g.dig(i, amount, floor);
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
pub(super) fn reach(brush: &[(i32, i32, f32)]) -> i32 {
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
pub(super) struct Corners {
    pub(super) cells: [usize; 4],
    pub(super) weights: [f32; 4],
    pub(super) u: f32,
    pub(super) v: f32,
}

impl Corners {
    #[inline]
    pub(super) fn at(x: f32, y: f32, nx: usize, ny: usize) -> Self {
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
    pub(super) fn height_grad(&self, h: impl Fn(usize) -> f32) -> (f32, f32, f32) {
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
    pub(super) fn deposit(&self, amount: f32, ceiling: f32, g: &mut Ground<'_>) -> f32 {
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
