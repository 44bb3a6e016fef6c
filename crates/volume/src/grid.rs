//! Voxel grids as densities: trilinear sampling of a `Grid3<f32>` placed in
//! world space, with a block majorant for empty-space skipping; a fluid
//! solver's smoke (density, and temperature for emission); and baking any
//! [`Density`] into a grid.

use glam::Vec3;
use natura_core::simd::Simd;
use natura_core::{Aabb, Grid3, NoProgress, Progress, floor_f32};

use crate::density::{Density, check_batch, check_bounds};
use crate::error::{Result, VolumeError, finite3, positive};

mod clear;
mod lanes;

/// Trilinear interpolation of the eight corners `c` (x fastest: `c[0]` at
/// the lowest corner, `c[1]` one voxel along x, `c[2]` along y, `c[4]`
/// along z) with weights `t`, clamped below at 0: the one formula of
/// [`GridDensity::sample`] and of its batch path.
#[inline(always)]
fn trilinear(c: [f32; 8], t: Vec3) -> f32 {
    let l = |a: f32, b: f32, s: f32| a + (b - a) * s;
    let [c00, c10, c01, c11] = [
        l(c[0], c[1], t.x),
        l(c[2], c[3], t.x),
        l(c[4], c[5], t.x),
        l(c[6], c[7], t.x),
    ];
    l(l(c00, c10, t.y), l(c01, c11, t.y), t.z).max(0.0)
}

/// Edge of a majorant block, in voxels.
const BLOCK: usize = 8;

/// Edge of a fine majorant block, in voxels: the bound of a short segment
/// (a march's step) without the coarse blocks' reach.
const FINE: usize = 2;

/// The most fine blocks along an axis of a region bounded with the fine
/// majorants (larger regions read the coarse ones).
const FINE_SPAN: f32 = 4.0;

/// The majorants of `grid`'s blocks of `b` voxels: each covers its voxels
/// and the one-voxel rim that trilinear interpolation inside the block can
/// reach.
fn majorants(grid: &Grid3<f32>, b: usize) -> Result<Grid3<f32>> {
    let (nx, ny, nz) = grid.dims();
    Ok(Grid3::from_fn(
        nx.div_ceil(b),
        ny.div_ceil(b),
        nz.div_ceil(b),
        |i, j, k| {
            let r = |i: usize, n: usize| (i * b).saturating_sub(1)..((i + 1) * b + 1).min(n);
            let mut m = 0.0f32;
            for z in r(k, nz) {
                for y in r(j, ny) {
                    for &v in &grid.row(y, z)[r(i, nx)] {
                        m = m.max(v);
                    }
                }
            }
            m
        },
    )?)
}

/// The largest of `blocks` (blocks of `b` voxels of edge `cell`, from
/// `origin`) over those `region` overlaps, or `None` when that is more
/// than `span` blocks along an axis.
fn block_bound(
    blocks: &Grid3<f32>,
    b: usize,
    origin: Vec3,
    inv_cell: f32,
    region: &Aabb,
    span: f32,
) -> Option<f32> {
    let s = inv_cell / b as f32;
    let floor = |v: Vec3| Vec3::new(floor_f32(v.x), floor_f32(v.y), floor_f32(v.z));
    let lo = floor((region.min - origin) * s);
    let hi = floor((region.max - origin) * s);
    let (bx, by, bz) = blocks.dims();
    let clampi = |v: f32, n: usize| (v.max(0.0) as usize).min(n - 1);
    if hi.x < 0.0 || hi.y < 0.0 || hi.z < 0.0 {
        return Some(0.0);
    }
    if lo.x >= bx as f32 || lo.y >= by as f32 || lo.z >= bz as f32 {
        return Some(0.0);
    }
    if (hi - lo).max_element() >= span {
        return None;
    }
    let mut m = 0.0f32;
    for z in clampi(lo.z, bz)..=clampi(hi.z, bz) {
        for y in clampi(lo.y, by)..=clampi(hi.y, by) {
            for &v in &blocks.row(y, z)[clampi(lo.x, bx)..=clampi(hi.x, bx)] {
                m = m.max(v);
            }
        }
    }
    Some(m)
}

/// A density on a regular grid of cubic voxels: voxel `(i, j, k)` holds the
/// value at its centre `origin + (i + ½, j + ½, k + ½)·cell`, sampled
/// trilinearly (beyond the outermost centres, toward zero half a voxel past
/// the faces), and zero outside the box `[origin, origin + n·cell)`, the
/// box of [`bounds`](Density::bounds).
#[derive(Clone, Debug)]
pub struct GridDensity {
    grid: Grid3<f32>,
    origin: Vec3,
    cell: f32,
    inv_cell: f32,
    max: f32,
    blocks: Grid3<f32>,
    fine: Grid3<f32>,
    /// Each fine block's majorant with its 26 neighbours': the bound of
    /// any point within a fine block's edge of a point in the block.
    near: Grid3<f32>,
}

impl GridDensity {
    /// The grid `grid` with minimum corner `origin` and voxel edge `cell` (m).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] for a non-finite origin or a cell that
    /// is not finite and positive; [`VolumeError::BadVoxel`] for the first NaN,
    /// infinite or negative voxel.
    pub fn new(grid: Grid3<f32>, origin: Vec3, cell: f32) -> Result<Self> {
        finite3("origin", origin)?;
        positive("cell", cell)?;
        let (nx, ny, _) = grid.dims();
        for (n, &v) in grid.as_slice().iter().enumerate() {
            if !(v.is_finite() && v >= 0.0) {
                return Err(VolumeError::BadVoxel {
                    name: "density",
                    x: n % nx,
                    y: (n / nx) % ny,
                    z: n / (nx * ny),
                    value: v,
                });
            }
        }
        let max = grid.as_slice().iter().fold(0.0f32, |a, &b| a.max(b));
        let blocks = majorants(&grid, BLOCK)?;
        let fine = majorants(&grid, FINE)?;
        let (fx, fy, fz) = fine.dims();
        let around = |i: usize, n: usize| i.saturating_sub(1)..(i + 2).min(n);
        let near = Grid3::from_fn(fx, fy, fz, |i, j, k| {
            let mut m = 0.0f32;
            for z in around(k, fz) {
                for y in around(j, fy) {
                    for &v in &fine.row(y, z)[around(i, fx)] {
                        m = m.max(v);
                    }
                }
            }
            m
        })?;
        let g = Self {
            grid,
            origin,
            cell,
            inv_cell: 1.0 / cell,
            max,
            blocks,
            fine,
            near,
        };
        check_bounds("grid", &g.bounds())?;
        Ok(g)
    }

    /// The voxels.
    #[must_use]
    pub fn grid(&self) -> &Grid3<f32> {
        &self.grid
    }

    /// The minimum corner (m).
    #[must_use]
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The voxel edge (m).
    #[must_use]
    pub fn cell(&self) -> f32 {
        self.cell
    }

    /// Trilinear sample at `p` (world metres).
    #[inline]
    #[must_use]
    pub fn sample(&self, p: Vec3) -> f32 {
        // `u`: voxel units from the minimum corner; the box is `0 <= u < n`.
        let u = (p - self.origin) * self.inv_cell;
        let q = u - Vec3::splat(0.5);
        let (nx, ny, nz) = self.grid.dims();
        // Zero outside the box (the interpolation toward the zero beyond the
        // faces would reach half a voxel past them, where `bounds` and the
        // majorants say there is nothing), and for NaN.
        let n = Vec3::new(nx as f32, ny as f32, nz as f32);
        if !(u.cmpge(Vec3::ZERO).all() && u.cmplt(n).all()) {
            return 0.0;
        }
        let f = Vec3::new(floor_f32(q.x), floor_f32(q.y), floor_f32(q.z));
        let (x0, y0, z0) = (f.x as i64, f.y as i64, f.z as i64);
        let t = q - f;
        let d = self.grid.as_slice();
        let inside = x0 >= 0
            && y0 >= 0
            && z0 >= 0
            && x0 + 1 < nx as i64
            && y0 + 1 < ny as i64
            && z0 + 1 < nz as i64;
        let c = if inside {
            // All eight corners in the grid (most lookups): no checks per corner.
            let (sy, sz) = (nx, nx * ny);
            let i = (z0 as usize * ny + y0 as usize) * nx + x0 as usize;
            let (a, b, c) = (i + sy, i + sz, i + sy + sz);
            [
                d[i],
                d[i + 1],
                d[a],
                d[a + 1],
                d[b],
                d[b + 1],
                d[c],
                d[c + 1],
            ]
        } else {
            let at = |x: i64, y: i64, z: i64| -> f32 {
                if x < 0 || y < 0 || z < 0 || x >= nx as i64 || y >= ny as i64 || z >= nz as i64 {
                    0.0
                } else {
                    d[(z as usize * ny + y as usize) * nx + x as usize]
                }
            };
            let (x1, y1, z1) = (x0 + 1, y0 + 1, z0 + 1);
            [
                at(x0, y0, z0),
                at(x1, y0, z0),
                at(x0, y1, z0),
                at(x1, y1, z0),
                at(x0, y0, z1),
                at(x1, y0, z1),
                at(x0, y1, z1),
                at(x1, y1, z1),
            ]
        };
        trilinear(c, t)
    }

    /// Where the voxels are, for the batch path's lanes, or `None` for a
    /// grid too large for their `i32` indices (it is sampled point by point).
    fn layout(&self) -> Option<lanes::Layout> {
        let (nx, ny, nz) = self.grid.dims();
        lanes::Layout::fits(nx, ny, nz).then(|| lanes::Layout {
            origin: self.origin,
            inv_cell: self.inv_cell,
            dims: [nx as f32, ny as f32, nz as f32],
            sy: nx as i32,
            sz: (nx * ny) as i32,
        })
    }

    /// Bakes `density` into a grid over its bounds with voxel edge `cell`,
    /// evaluating at voxel centres (in parallel over z slices).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] for a bad `cell` or a grid over
    /// `natura_core::MAX_GRID_BYTES`; as [`GridDensity::new`].
    pub fn bake(density: &dyn Density, cell: f32) -> Result<Self> {
        Self::bake_with_progress(density, cell, &NoProgress)
    }

    /// [`GridDensity::bake`], reporting to `progress` as the stage `"bake"`
    /// with one unit per finished z slice (slices finish in any order when
    /// baking in parallel; the grid is the same).
    ///
    /// # Errors
    ///
    /// As [`GridDensity::bake`]; nothing is reported when `cell` or the
    /// bounds are refused.
    pub fn bake_with_progress(
        density: &dyn Density,
        cell: f32,
        progress: &dyn Progress,
    ) -> Result<Self> {
        positive("cell", cell)?;
        let b = density.bounds();
        check_bounds("density bounds", &b)?;
        let n = ((b.max - b.min) / cell).ceil();
        if n.is_nan() || n.max_element() >= 1e6 {
            return Err(VolumeError::InvalidParameter {
                name: "cell",
                value: cell.to_string(),
                expected: "must give fewer than 1e6 voxels per axis over the bounds",
            });
        }
        let (nx, ny, nz) = (
            n.x.max(1.0) as usize,
            n.y.max(1.0) as usize,
            n.z.max(1.0) as usize,
        );
        let mut grid = Grid3::new(nx, ny, nz, 0.0f32)?;
        let origin = b.min;
        let fill = |k: usize, slice: &mut [f32]| {
            for (r, row) in slice.chunks_mut(nx).enumerate() {
                for (i, v) in row.iter_mut().enumerate() {
                    let p = origin + (Vec3::new(i as f32, r as f32, k as f32) + 0.5) * cell;
                    *v = density.density(p);
                }
            }
            progress.advance(1);
        };
        progress.start("bake", nz as u64);
        #[cfg(feature = "parallel")]
        grid.par_slices_mut(fill);
        #[cfg(not(feature = "parallel"))]
        for k in 0..nz {
            fill(k, grid.slice_z_mut(k));
        }
        progress.finish();
        Self::new(grid, origin, cell)
    }
}

impl Density for GridDensity {
    #[inline]
    fn density(&self, p: Vec3) -> f32 {
        self.sample(p)
    }
    fn bounds(&self) -> Aabb {
        let (nx, ny, nz) = self.grid.dims();
        Aabb {
            min: self.origin,
            max: self.origin + Vec3::new(nx as f32, ny as f32, nz as f32) * self.cell,
        }
    }
    fn bound_in(&self, region: &Aabb) -> f32 {
        // A short segment reads the fine blocks; a long one, the coarse.
        let at = |blocks, b, span| block_bound(blocks, b, self.origin, self.inv_cell, region, span);
        at(&self.fine, FINE, FINE_SPAN)
            .or_else(|| at(&self.blocks, BLOCK, f32::INFINITY))
            .unwrap_or(self.max)
    }
    fn bound_near(&self, centre: Vec3, radius: f32) -> f32 {
        // Within a fine block's edge of the centre: one lookup of the
        // centre's block with its neighbours.
        let b = FINE as f32;
        if radius <= b * self.cell {
            let q = (centre - self.origin) * (self.inv_cell / b);
            let (fx, fy, fz) = self.near.dims();
            let inside = |v: f32, n: usize| v >= 0.0 && v < n as f32;
            if inside(q.x, fx) && inside(q.y, fy) && inside(q.z, fz) {
                return *self
                    .near
                    .get(q.x as usize, q.y as usize, q.z as usize)
                    .unwrap_or(&self.max);
            }
        }
        self.bound_in(&Aabb {
            min: centre - Vec3::splat(radius),
            max: centre + Vec3::splat(radius),
        })
    }
    /// A walk over the fine majorant blocks the ray crosses (see
    /// `grid/clear.rs`): never `None`.
    fn clear_along(&self, o: Vec3, d: Vec3, t: f32, t_max: f32) -> Option<(f32, f32)> {
        Some(self.clear_run(o, d, t, t_max))
    }
    fn max_density(&self) -> f32 {
        self.max
    }
    /// [`sample`](GridDensity::sample) at every point, bit for bit, in
    /// SIMD lanes (the interpolation of interior points vectorised).
    ///
    /// # Errors
    ///
    /// [`VolumeError::SizeMismatch`] if the slices differ in length.
    fn density_batch(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> Result<()> {
        check_batch(x, y, z, out)?;
        if let Some(layout) = self.layout() {
            lanes::samples(
                Simd::best(),
                &layout,
                self.grid.as_slice(),
                x,
                y,
                z,
                out,
                |p| self.sample(p),
            );
        } else {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.sample(Vec3::new(x[i], y[i], z[i]));
            }
        }
        Ok(())
    }
}

/// A fluid smoke's density and temperature as a renderable volume: the
/// density scatters, and the temperature above ambient emits.
#[derive(Clone, Debug)]
pub struct SmokeVolume {
    /// The smoke density.
    pub density: GridDensity,
    /// The temperature (K), sampled on the same grid.
    pub temperature: GridDensity,
    /// Ambient temperature (K): no emission at or below it.
    pub ambient: f32,
}

impl SmokeVolume {
    /// The density and temperature grids of a fluid solver's smoke
    /// (cell-centred samples `cell` metres apart, origin at 0; for
    /// natura-fluid's `Smoke`: `smoke.density()`, `smoke.temperature()`,
    /// `smoke.h()` and `smoke.params().ambient_temperature`). Advection
    /// undershoots leave tiny negative densities in a solver's grid; those
    /// read as empty (0), as a density cannot be negative. NaN and infinite
    /// voxels are still refused.
    ///
    /// # Errors
    ///
    /// [`VolumeError::SizeMismatch`] if the grids differ in size; as
    /// [`GridDensity::new`] (a NaN or infinite voxel, a bad cell size).
    pub fn from_solver(
        density: &Grid3<f32>,
        temperature: Grid3<f32>,
        cell: f32,
        ambient: f32,
    ) -> Result<Self> {
        Self::from_grids(
            density.map(|&v| if v < 0.0 { 0.0 } else { v }),
            Some(temperature),
            Vec3::ZERO,
            cell,
            ambient,
        )
    }

    /// A volume from a density grid and an optional temperature grid of the same size.
    ///
    /// # Errors
    ///
    /// [`VolumeError::SizeMismatch`] if the grids differ in size; as [`GridDensity::new`].
    pub fn from_grids(
        density: Grid3<f32>,
        temperature: Option<Grid3<f32>>,
        origin: Vec3,
        cell: f32,
        ambient: f32,
    ) -> Result<Self> {
        positive("ambient", ambient)?;
        let dims = density.dims();
        let temperature = match temperature {
            Some(t) if t.dims() != dims => {
                return Err(VolumeError::SizeMismatch {
                    name: "temperature",
                    expected: format!("{dims:?}"),
                    actual: format!("{:?}", t.dims()),
                });
            }
            Some(t) => t,
            None => Grid3::new(dims.0, dims.1, dims.2, ambient)?,
        };
        Ok(Self {
            density: GridDensity::new(density, origin, cell)?,
            temperature: GridDensity::new(temperature, origin, cell)?,
            ambient,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trilinear_is_exact_at_centres_and_linear_between() {
        let g = Grid3::from_fn(4, 3, 2, |i, j, k| (i + 2 * j + 3 * k) as f32).unwrap();
        let d = GridDensity::new(g, Vec3::new(1.0, 2.0, 3.0), 0.5).unwrap();
        let c =
            |i: f32, j: f32, k: f32| Vec3::new(1.0, 2.0, 3.0) + (Vec3::new(i, j, k) + 0.5) * 0.5;
        assert_eq!(d.sample(c(2.0, 1.0, 1.0)), 7.0);
        assert!((d.sample(c(1.5, 0.5, 0.5)) - 4.0).abs() < 1e-5);
        assert_eq!(d.sample(Vec3::ZERO), 0.0);
        // The block majorant bounds every sample.
        for i in 0..200 {
            let p = c(
                i as f32 * 0.02 - 0.5,
                (i % 7) as f32 * 0.4 - 0.5,
                (i % 3) as f32 * 0.6 - 0.5,
            );
            let r = Aabb { min: p, max: p };
            assert!(d.sample(p) <= d.bound_in(&r) + 1e-6);
        }
    }

    /// Trilinear interpolation with every corner checked, zero outside
    /// the box: the definition the fast interior path must match bit for bit.
    fn checked_trilinear(d: &GridDensity, p: Vec3) -> f32 {
        let u = (p - d.origin) * d.inv_cell;
        let q = u - Vec3::splat(0.5);
        let f = q.floor();
        let t = q - f;
        let (nx, ny, nz) = d.grid.dims();
        let within = |v: f32, n: usize| v >= 0.0 && v < n as f32;
        if !(within(u.x, nx) && within(u.y, ny) && within(u.z, nz)) {
            return 0.0;
        }
        let at = |x: f32, y: f32, z: f32| -> f32 {
            let inside = |v: f32, n: usize| v >= 0.0 && v < n as f32;
            if inside(x, nx) && inside(y, ny) && inside(z, nz) {
                d.grid[(x as usize, y as usize, z as usize)]
            } else {
                0.0
            }
        };
        let l = |a: f32, b: f32, s: f32| a + (b - a) * s;
        let c = |y: f32, z: f32| l(at(f.x, y, z), at(f.x + 1.0, y, z), t.x);
        let y1 = f.y + 1.0;
        let z1 = f.z + 1.0;
        l(
            l(c(f.y, f.z), c(y1, f.z), t.y),
            l(c(f.y, z1), c(y1, z1), t.y),
            t.z,
        )
        .max(0.0)
    }

    #[test]
    fn sampling_matches_checked_trilinear_inside_at_the_edges_and_outside() {
        let g = Grid3::from_fn(7, 5, 4, |i, j, k| {
            (((i * 31 + j * 17 + k * 7) % 11) as f32 * 0.3 - 0.5).max(0.0)
        })
        .unwrap();
        let d = GridDensity::new(g, Vec3::new(-1.0, 0.5, 2.0), 0.25).unwrap();
        let b = d.bounds();
        // A lattice of points (a step no cell divides evenly) over a margin
        // of a cell and a half round the bounds: every corner case, the
        // cell boundaries' neighbourhoods included.
        let lo = b.min - Vec3::splat(0.375);
        let n = ((b.max - b.min + Vec3::splat(0.75)) / 0.0613).ceil();
        let points = (0..n.z as usize).flat_map(move |k| {
            (0..n.y as usize).flat_map(move |j| {
                (0..n.x as usize)
                    .map(move |i| lo + Vec3::new(i as f32, j as f32, k as f32) * 0.0613)
            })
        });
        for p in points {
            let (a, e) = (d.sample(p), checked_trilinear(&d, p));
            assert_eq!(a.to_bits(), e.to_bits(), "at {p:?}: {a} against {e}");
        }
    }

    /// Nothing beyond the faces: the interpolation toward the zero past
    /// them stops at the box, which is what `bounds`, `bound_in` and
    /// `bound_near` promise (a voxel on the top layer once showed 0.001 a
    /// fifth of a voxel above the box, where both bounds were 0).
    #[test]
    fn the_density_is_zero_outside_its_box() {
        let mut g = Grid3::new(24, 20, 12, 0.0f32).unwrap();
        g.row_mut(0, 11)[0] = 0.01;
        g.row_mut(19, 0)[23] = 2.0;
        let d = GridDensity::new(g, Vec3::new(-3.0, 2.0, -1.0), 0.5).unwrap();
        let b = d.bounds();
        let top = d.origin() + Vec3::new(0.25, 0.25, 6.0);
        // Inside the top face, half the voxel's value; past it, nothing.
        assert!(d.sample(top - Vec3::Z * 1e-3) > 0.004);
        for dz in [1e-4, 0.05, 0.1, 0.2, 0.249] {
            let p = top + Vec3::Z * dz;
            assert_eq!(d.sample(p), 0.0, "{dz}");
        }
        // The far corner's voxel, every face out: zero beyond each.
        let far = b.max - Vec3::new(0.25, 0.25, 6.0 - 0.25);
        assert!(d.sample(far) > 1.9);
        for out in [
            Vec3::new(b.max.x + 0.1, far.y, far.z),
            Vec3::new(far.x, b.max.y + 0.1, far.z),
            Vec3::new(far.x, far.y, b.min.z - 0.1),
            Vec3::new(b.max.x, far.y, far.z),
            Vec3::new(f32::NAN, far.y, far.z),
        ] {
            assert_eq!(d.sample(out), 0.0, "{out:?}");
        }
        // The minimum faces are in the box.
        let low = Vec3::new(b.max.x - 0.25, b.max.y - 0.25, b.min.z);
        assert!(d.sample(low) > 0.9);
    }

    /// The batch path at every SIMD level this CPU has equals the point
    /// path bit for bit: interior points, the edges, outside, a NaN and
    /// infinite coordinates, in batches of every length round the chunk.
    #[test]
    fn batch_lanes_match_the_point_path_at_every_level() {
        let g = Grid3::from_fn(9, 6, 5, |i, j, k| {
            (((i * 31 + j * 17 + k * 7) % 13) as f32 * 0.37 - 0.6).max(0.0)
        })
        .unwrap();
        let d = GridDensity::new(g, Vec3::new(-1.0, 0.5, 2.0), 0.25).unwrap();
        let b = d.bounds();
        let mut rng = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 40) as f32 / (1u64 << 24) as f32
        };
        let span = b.max - b.min + Vec3::splat(1.0);
        let mut pts: Vec<Vec3> = (0..997)
            .map(|_| b.min - Vec3::splat(0.5) + Vec3::new(next(), next(), next()) * span)
            .collect();
        pts.extend([
            Vec3::new(f32::NAN, 1.0, 2.5),
            Vec3::new(0.0, f32::INFINITY, 2.5),
            Vec3::new(f32::NEG_INFINITY, 1.0, 2.5),
            b.min,
            b.max,
            (b.min + b.max) * 0.5,
        ]);
        let (x, y, z): (Vec<f32>, Vec<f32>, Vec<f32>) = (
            pts.iter().map(|p| p.x).collect(),
            pts.iter().map(|p| p.y).collect(),
            pts.iter().map(|p| p.z).collect(),
        );
        let layout = d.layout().unwrap();
        let mut interior = 0;
        for simd in Simd::supported() {
            for len in [1, 5, 15, 16, 17, 33, pts.len()] {
                let mut out = vec![-1.0f32; len];
                lanes::samples(
                    simd,
                    &layout,
                    d.grid.as_slice(),
                    &x[..len],
                    &y[..len],
                    &z[..len],
                    &mut out,
                    |p| d.sample(p),
                );
                for (i, o) in out.iter().enumerate() {
                    let e = d.sample(pts[i]);
                    assert_eq!(
                        o.to_bits(),
                        e.to_bits(),
                        "{simd:?}, {:?}: {o} against {e}",
                        pts[i]
                    );
                }
            }
        }
        let mut out = vec![0.0f32; pts.len()];
        d.density_batch(&x, &y, &z, &mut out).unwrap();
        for (i, o) in out.iter().enumerate() {
            assert_eq!(o.to_bits(), d.sample(pts[i]).to_bits());
            interior += usize::from(*o > 0.0);
        }
        // The points reach the interior, where the lanes do the work (a
        // quarter of them fall in the box, 218 where the density is not 0).
        assert!(interior > 150, "{interior}");
        assert!(d.density_batch(&x, &y[..3], &z, &mut out).is_err());
    }

    #[test]
    fn bake_reports_one_unit_per_slice_and_bakes_the_same_grid() {
        let ball = crate::density::Ball::new(Vec3::new(0.5, 0.0, 1.0), 1.0, 2.0).unwrap();
        let progress = natura_core::CountingProgress::new();
        let reported = GridDensity::bake_with_progress(&ball, 0.25, &progress).unwrap();
        let plain = GridDensity::bake(&ball, 0.25).unwrap();
        let nz = plain.grid().dims().2;
        assert_eq!(progress.stages(), vec![("bake".to_owned(), nz as u64)]);
        assert_eq!(progress.advanced(), nz as u64);
        assert_eq!(progress.finished(), 1);
        assert_eq!(reported.grid(), plain.grid());
        // A refused cell reports nothing.
        let none = natura_core::CountingProgress::new();
        assert!(GridDensity::bake_with_progress(&ball, 0.0, &none).is_err());
        assert!(none.stages().is_empty());
    }

    #[test]
    fn bad_grids_are_refused() {
        let mut g = Grid3::new(2, 2, 2, 0.5f32).unwrap();
        g[(1, 1, 1)] = f32::NAN;
        assert!(matches!(
            GridDensity::new(g, Vec3::ZERO, 1.0),
            Err(VolumeError::BadVoxel {
                x: 1,
                y: 1,
                z: 1,
                ..
            })
        ));
        let g = Grid3::new(2, 2, 2, 0.5f32).unwrap();
        assert!(GridDensity::new(g.clone(), Vec3::ZERO, 0.0).is_err());
        let t = Grid3::new(3, 2, 2, 300.0f32).unwrap();
        assert!(matches!(
            SmokeVolume::from_grids(g, Some(t), Vec3::ZERO, 1.0, 293.0),
            Err(VolumeError::SizeMismatch { .. })
        ));
    }
}
