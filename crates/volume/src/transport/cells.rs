//! The grid of cells the fast mode's photon caches score into: the
//! medium's extinction averaged over each cell, the 3-D DDA that walks a
//! ray through the cells (Amanatides & Woo 1987), free flights through
//! them, and the trilinear lookup between cell centres. The caches
//! ([`super::cache`] for the sun's light, [`super::local`] for the light of
//! the scene's surfaces and glow) keep what they store per cell; nothing
//! here knows about light.

use glam::Vec3;
use natura_core::Aabb;

use crate::density::{Density, fill_densities_spaced, ray_box};
use crate::error::{Result, VolumeError};

/// Fewest cells along a thin axis (see [`CellGrid::new`]).
const MIN_THIN_CELLS: usize = 16;

/// Most cells a grid may have.
const MAX_GRID_CELLS: usize = 1 << 26;

/// The most mean optical depth a cell may span along an axis, while that
/// axis has fewer cells than the grid's longest (see [`CellGrid::new`]):
/// half a mean free path. The light a viewer sees from a thick medium's
/// lit face comes from its first mean free path along the eye ray, where
/// the multiply scattered light is still rising from the face and leaving
/// it; a cell a whole path deep averages that layer away (a slab of optical
/// thickness 50, albedo 0.999, Henyey–Greenstein 0.6 lit from ahead read
/// −5.2 % against the reference with a cell per path, −3.0 … −4.2 % over
/// four photon seeds with two).
pub(crate) const MAX_CELL_DEPTH: f32 = 0.5;

/// Cubic cells over a density's bounds and the medium's mean extinction in
/// each.
#[derive(Clone, Debug)]
pub(crate) struct CellGrid {
    pub(crate) origin: Vec3,
    /// Cell size per axis (m).
    pub(crate) h: Vec3,
    pub(crate) dims: [usize; 3],
    /// Per cell: extinction (1/m) of the transport medium.
    pub(crate) sigma: Vec<f32>,
}

/// A photon's flight through the grid: where it collides, if it does.
pub(crate) enum Flight {
    Collided(Vec3),
    Left,
}

impl CellGrid {
    /// Cubes of `cells` along the bounds' longest axis over `density`, a
    /// thin axis keeping at least 16 (a cloud layer kilometres wide and one
    /// thick still resolves its height); each cell's extinction is the mean
    /// of `2³` samples times `extinction`. An axis whose cells would each
    /// span more than [`MAX_CELL_DEPTH`] of the medium's mean optical depth
    /// (its mean extinction over the cells it fills) gets more cells, up to
    /// `cells`: a thick slab's lit face needs cells no deeper than half a
    /// mean free path along its thin axis, where cubes would leave it a few.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] naming `cache.cells` when the grid
    /// would pass 2²⁶ cells.
    pub(crate) fn new(density: &dyn Density, extinction: f32, cells: u32) -> Result<Self> {
        let b = density.bounds();
        let size = b.max - b.min;
        let cube = size.max_element() / cells as f32;
        let n = |x: f32| {
            ((x / cube).ceil() as usize)
                .max(MIN_THIN_CELLS.min(cells as usize))
                .max(1)
        };
        let grid = Self::voxelized(
            density,
            extinction,
            b.min,
            size,
            [n(size.x), n(size.y), n(size.z)],
        )?;
        let filled: Vec<f32> = grid.sigma.iter().copied().filter(|&s| s > 0.0).collect();
        if filled.is_empty() {
            return Ok(grid);
        }
        let mean = filled.iter().map(|&s| f64::from(s)).sum::<f64>() / filled.len() as f64;
        let mut dims = grid.dims;
        for (a, d) in dims.iter_mut().enumerate() {
            let want = (f64::from(size[a]) * mean / f64::from(MAX_CELL_DEPTH)).ceil() as usize;
            *d = (*d).max(want.min(cells as usize));
        }
        if dims == grid.dims {
            return Ok(grid);
        }
        Self::voxelized(density, extinction, b.min, size, dims)
    }

    /// The grid of `dims` cells over the box at `origin` of `size`, its
    /// extinction voxelized.
    fn voxelized(
        density: &dyn Density,
        extinction: f32,
        origin: Vec3,
        size: Vec3,
        dims: [usize; 3],
    ) -> Result<Self> {
        if dims[0] * dims[1] * dims[2] > MAX_GRID_CELLS {
            return Err(VolumeError::InvalidParameter {
                name: "cache.cells",
                value: dims.iter().max().copied().unwrap_or(0).to_string(),
                expected: "a grid of at most 2^26 cells",
            });
        }
        let h = size / Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32);
        let mut grid = Self {
            origin,
            h,
            dims,
            sigma: Vec::new(),
        };
        // The samples lie half a cell apart: detail finer than that would
        // only alias into the cells' means, which keep its mean instead.
        let spacing = 0.5 * h.min_element();
        grid.sigma = grid.mean_per_cell(|xs, ys, zs, out| {
            fill_densities_spaced(density, xs, ys, zs, spacing, out);
        });
        for s in &mut grid.sigma {
            *s *= extinction;
        }
        Ok(grid)
    }

    /// The number of cells.
    #[inline]
    pub(crate) fn count(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// The volume of one cell (m³).
    #[inline]
    pub(crate) fn cell_volume(&self) -> f32 {
        self.h.x * self.h.y * self.h.z
    }

    /// The grid's bounds.
    pub(crate) fn bounds(&self) -> Aabb {
        let n = Vec3::new(
            self.dims[0] as f32,
            self.dims[1] as f32,
            self.dims[2] as f32,
        );
        Aabb {
            min: self.origin,
            max: self.origin + n * self.h,
        }
    }

    /// The lower corner of cell `c`.
    #[inline]
    pub(crate) fn cell_corner(&self, c: usize) -> Vec3 {
        let (nx, ny) = (self.dims[0], self.dims[1]);
        let (x, y, z) = (c % nx, (c / nx) % ny, c / (nx * ny));
        self.origin + Vec3::new(x as f32, y as f32, z as f32) * self.h
    }

    /// Each cell's mean of a field over `2³` points inside it, the field
    /// evaluated by `f(xs, ys, zs, out)` on one row of cells at a time (rows
    /// in parallel with the `parallel` feature).
    pub(crate) fn mean_per_cell(
        &self,
        f: impl Fn(&[f32], &[f32], &[f32], &mut [f32]) + Sync + Send,
    ) -> Vec<f32> {
        let [nx, ny, nz] = self.dims;
        let row = |r: usize| -> Vec<f32> {
            let (y, z) = (r % ny, r / ny);
            let mut xs = Vec::with_capacity(nx * 8);
            let (mut ys, mut zs) = (Vec::with_capacity(nx * 8), Vec::with_capacity(nx * 8));
            for x in 0..nx {
                for s in 0..8 {
                    let o = Vec3::new(
                        (s & 1) as f32 * 0.5 + 0.25,
                        ((s >> 1) & 1) as f32 * 0.5 + 0.25,
                        ((s >> 2) & 1) as f32 * 0.5 + 0.25,
                    );
                    let p = self.origin + (Vec3::new(x as f32, y as f32, z as f32) + o) * self.h;
                    xs.push(p.x);
                    ys.push(p.y);
                    zs.push(p.z);
                }
            }
            let mut v = vec![0.0f32; nx * 8];
            f(&xs, &ys, &zs, &mut v);
            v.chunks(8).map(|c| c.iter().sum::<f32>() / 8.0).collect()
        };
        super::shadow::map_rows(ny * nz, row)
    }

    /// The eight cells round `p` (the lower corner's index per axis, the
    /// upper's, and the weights toward the upper), trilinear between cell
    /// centres and clamped to the grid.
    #[inline]
    pub(crate) fn corners(&self, p: Vec3) -> ([usize; 3], [usize; 3], [f32; 3]) {
        let g = (p - self.origin) / self.h - Vec3::splat(0.5);
        let mut i = [0usize; 3];
        let mut j = [0usize; 3];
        let mut w = [0.0f32; 3];
        for a in 0..3 {
            let hi = (self.dims[a] - 1) as f32;
            let x = g[a].clamp(0.0, hi);
            let k = x as usize;
            i[a] = k.min(self.dims[a] - 1);
            j[a] = (k + 1).min(self.dims[a] - 1);
            w[a] = x - k as f32;
        }
        (i, j, w)
    }

    /// The indices of the eight cells round a lower corner `i` (upper `j`),
    /// `x` fastest.
    #[inline]
    pub(crate) fn corner_cells(&self, i: [usize; 3], j: [usize; 3]) -> [usize; 8] {
        let mut v = [0usize; 8];
        for (c, out) in v.iter_mut().enumerate() {
            let x = if c & 1 == 0 { i[0] } else { j[0] };
            let y = if c & 2 == 0 { i[1] } else { j[1] };
            let z = if c & 4 == 0 { i[2] } else { j[2] };
            *out = self.index(x, y, z);
        }
        v
    }

    /// The centre of the cell of indices `i`.
    #[inline]
    pub(crate) fn centre(&self, i: [usize; 3]) -> Vec3 {
        self.origin + (Vec3::new(i[0] as f32, i[1] as f32, i[2] as f32) + 0.5) * self.h
    }

    /// The trilinear blend of eight corner values.
    #[inline]
    pub(crate) fn blend<T>(v: &[T; 8], w: [f32; 3]) -> T
    where
        T: Copy
            + std::ops::Add<Output = T>
            + std::ops::Sub<Output = T>
            + std::ops::Mul<f32, Output = T>,
    {
        let lerp = |a: T, b: T, t: f32| a + (b - a) * t;
        let x0 = lerp(v[0], v[1], w[0]);
        let x1 = lerp(v[2], v[3], w[0]);
        let x2 = lerp(v[4], v[5], w[0]);
        let x3 = lerp(v[6], v[7], w[0]);
        lerp(lerp(x0, x1, w[1]), lerp(x2, x3, w[1]), w[2])
    }

    #[inline]
    pub(crate) fn index(&self, x: usize, y: usize, z: usize) -> usize {
        (z * self.dims[1] + y) * self.dims[0] + x
    }

    /// Calls `f(cell, t_in, t_out)` for each cell the ray from `o` along
    /// unit `d` crosses inside the grid before distance `t_max`, in order,
    /// until `f` returns false.
    pub(crate) fn cross(
        &self,
        o: Vec3,
        d: Vec3,
        t_max: f32,
        mut f: impl FnMut(usize, f32, f32) -> bool,
    ) {
        let inv = d.recip();
        let Some((t0, t1)) = ray_box(o, inv, &self.bounds()) else {
            return;
        };
        let t1 = t1.min(t_max);
        let mut t = t0.max(0.0);
        if t >= t1 {
            return;
        }
        let p = (o + d * t - self.origin) / self.h;
        let h = self.h;
        let mut c = [0i64; 3];
        let mut step = [0i64; 3];
        let mut next = [f32::INFINITY; 3];
        let mut delta = [f32::INFINITY; 3];
        for a in 0..3 {
            let n = self.dims[a] as i64;
            c[a] = (natura_core::floor_f32(p[a]) as i64).clamp(0, n - 1);
            if d[a] > 0.0 {
                step[a] = 1;
                delta[a] = h[a] * inv[a];
                next[a] = t + ((c[a] + 1) as f32 - p[a]) * h[a] * inv[a];
            } else if d[a] < 0.0 {
                step[a] = -1;
                delta[a] = -h[a] * inv[a];
                next[a] = t + (c[a] as f32 - p[a]) * h[a] * inv[a];
            }
        }
        loop {
            let a = if next[0] <= next[1] && next[0] <= next[2] {
                0
            } else if next[1] <= next[2] {
                1
            } else {
                2
            };
            let t_out = next[a].min(t1).max(t);
            let cell = self.index(c[0] as usize, c[1] as usize, c[2] as usize);
            if !f(cell, t, t_out) || t_out >= t1 {
                return;
            }
            t = t_out;
            c[a] += step[a];
            if c[a] < 0 || c[a] >= self.dims[a] as i64 {
                return;
            }
            next[a] += delta[a];
        }
    }

    /// The optical depth of the ray from `o` along unit `d` through the grid.
    pub(crate) fn optical_depth(&self, o: Vec3, d: Vec3) -> f32 {
        let mut tau = 0.0;
        self.cross(o, d, f32::INFINITY, |c, a, b| {
            tau += self.sigma[c] * (b - a);
            true
        });
        tau
    }

    /// The cells the ray from `o` along unit `d` crosses, as
    /// `(cell, t_in, t_out)` into `line` (cleared first), and the ray's
    /// optical depth, the same bits as [`optical_depth`](Self::optical_depth):
    /// a photon that needs its line's depth before it flies along it
    /// ([`fly_line`](Self::fly_line)) walks the grid once. The walk stops at
    /// the first cell that takes the depth to `cap` or beyond, and the depth
    /// so far is returned: a depth past which nothing the caller computes
    /// from it changes need not be walked to its end.
    pub(crate) fn line(
        &self,
        o: Vec3,
        d: Vec3,
        cap: f32,
        line: &mut Vec<(usize, f32, f32)>,
    ) -> f32 {
        line.clear();
        let mut tau = 0.0;
        self.cross(o, d, f32::INFINITY, |c, a, b| {
            tau += self.sigma[c] * (b - a);
            line.push((c, a, b));
            tau < cap
        });
        tau
    }

    /// [`fly`](Self::fly) without scoring along a ray's recorded `line`
    /// ([`line`](Self::line)) from `o` along `d`: the same collision, bit
    /// for bit.
    pub(crate) fn fly_line(
        &self,
        o: Vec3,
        d: Vec3,
        target: f32,
        line: &[(usize, f32, f32)],
    ) -> Flight {
        let mut left = target;
        for &(c, a, b) in line {
            let s = self.sigma[c];
            let len = b - a;
            if s * len >= left {
                return Flight::Collided(o + d * (a + left / s));
            }
            left -= s * len;
        }
        Flight::Left
    }

    /// Flies from `o` along unit `d` until optical depth `target` is used up
    /// or distance `t_max` is reached, calling `score(cell, length)` for
    /// each stretch flown.
    pub(crate) fn fly(
        &self,
        o: Vec3,
        d: Vec3,
        target: f32,
        t_max: f32,
        mut score: impl FnMut(usize, f32),
    ) -> Flight {
        let mut left = target;
        let mut hit = None;
        self.cross(o, d, t_max, |c, a, b| {
            let s = self.sigma[c];
            let len = b - a;
            if s * len >= left {
                let l = left / s;
                score(c, l);
                hit = Some(o + d * (a + l));
                return false;
            }
            left -= s * len;
            score(c, len);
            true
        });
        hit.map_or(Flight::Left, Flight::Collided)
    }
}

/// `n` copies of `zero` written into fresh memory: a grid that photons
/// score into.
///
/// `vec![0.0; n]` takes zeroed pages from the system that are mapped only
/// when first touched, and a grid's first touch is the read of a `+=`: the
/// page is mapped read-only to the shared zero page, and the write that
/// follows copies it and flushes it from every other core's address
/// translations (an interrupt to each). Over the tens of megabytes of a
/// cache's chunks that took a sixth of its tracing time; pages written
/// first are mapped once, writable.
pub(crate) fn written_zeros<T: Copy>(n: usize, zero: T) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    v.resize(n, zero);
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::density::Homogeneous;

    #[test]
    fn a_thin_axis_gets_two_cells_per_mean_free_path_up_to_the_longest_axis_count() {
        // A 4 × 4 × 1 m slab: cubes of 4/64 m leave its height 16 cells.
        let slab = Homogeneous::new(
            Aabb {
                min: Vec3::new(-2.0, -2.0, 0.0),
                max: Vec3::new(2.0, 2.0, 1.0),
            },
            1.0,
        )
        .unwrap();
        let dims = |extinction: f32| CellGrid::new(&slab, extinction, 64).unwrap().dims;
        // Optically thin across its height: cubes.
        assert_eq!(dims(5.0), [64, 64, 16]);
        // 10 and 20 mean free paths high: two cells per path.
        assert_eq!(dims(10.0), [64, 64, 20]);
        assert_eq!(dims(20.0), [64, 64, 40]);
        assert_eq!(dims(50.0), [64, 64, 64]);
        // 500: no more cells than the longest axis has.
        assert_eq!(dims(500.0), [64, 64, 64]);
        // Refined, the cells still hold the medium's extinction.
        let g = CellGrid::new(&slab, 50.0, 64).unwrap();
        assert!(g.sigma.iter().all(|&s| (s - 50.0).abs() < 1e-3));
        let tau = g.optical_depth(Vec3::new(0.1, 0.2, 2.0), -Vec3::Z);
        assert!((tau - 50.0).abs() < 1e-2, "{tau}");
    }
}
