//! Volume shadows: the optical depth toward a light by direct ray marching,
//! and Ebert's three-dimensional shadow tables (Ebert 2001, "Volume
//! rendering": "fast, efficient; 10 to 15 times faster than ray-traced
//! shadows"), which store that optical depth on a lattice over the volume so
//! the eye march looks it up instead of marching toward the light at every
//! sample.
//!
//! The source cites the table's construction without describing it; here
//! each node marches toward the light with steps of one table cell (with
//! empty space skipped), so the table costs one short march per node, at
//! the table's resolution, instead of one per eye sample. (A single sweep
//! from the light's side, interpolating each slice from the previous one, is
//! cheaper, but its repeated interpolation blurs the optical depth, and the
//! blur darkens the shadows of broken cloud: `e^{−mean τ} < mean e^{−τ}`.)
//!
//! A node in clear air, with no medium between it and the light, stores
//! the optical depth below the medium's lit surface continued across the
//! surface (negative, and 0 when no medium lies within a few cells against
//! the light), and a lookup clamps the blend at 0, so trilinear
//! interpolation finds the lit surface where it is instead of a cell too
//! far out: with 0 at such nodes the lit layer of a dense medium (a mean
//! free path deep or less, often thinner than a cell) was darkened by up to
//! a cell's optical depth.
//!
//! The nodes' marches sample the density a cell apart, so detail finer than
//! a cell (the noise octaves of [`crate::detail::Detailed`]) could only
//! alias into the table; they sample it through
//! [`Density::density_batch_spaced`], which leaves such octaves out and
//! keeps their mean. That also spares the table the octaves' cost.

use glam::Vec3;
use natura_core::{Aabb, NoProgress, Progress};

use crate::density::{Density, check_bounds, fill_densities_spaced, ray_box};
use crate::error::{Result, VolumeError, positive};

/// Optical depth `∫ σ·ρ ds` from `p` along the unit direction `l` to the
/// edge of the density's bounds, by the midpoint rule with steps of `step`
/// metres (the "ray-traced shadow" the tables replace).
#[must_use]
pub fn optical_depth_ray(
    density: &dyn Density,
    extinction: f32,
    p: Vec3,
    l: Vec3,
    step: f32,
) -> f32 {
    optical_depth_spaced(density, extinction, p, l, step, 0.0)
}

/// [`optical_depth_ray`] whose density samples leave out detail finer
/// than `spacing` metres ([`Density::density_batch_spaced`]).
pub(crate) fn optical_depth_spaced(
    density: &dyn Density,
    extinction: f32,
    p: Vec3,
    l: Vec3,
    step: f32,
    spacing: f32,
) -> f32 {
    let Some((t0, t1)) = ray_box(p, l.recip(), &density.bounds()) else {
        return 0.0;
    };
    let n = ((t1 - t0) / step).ceil().max(1.0) as usize;
    let dt = (t1 - t0) / n as f32;
    let mut tau = 0.0;
    // Blocks of 8 steps where the density is zero are skipped (they would
    // add zeros): those off the density's runs along the ray where it knows
    // them, else those whose box it bounds by zero.
    let mut run = density.clear_along(p, l, t0, t1);
    let mut i = 0;
    while i < n {
        let end = (i + 8).min(n);
        let (ta, tb) = (t0 + i as f32 * dt, t0 + end as f32 * dt);
        let filled = match run.as_mut() {
            Some(r) => {
                // The runs are zero between them: the first that ends past
                // the block's start decides.
                while r.1 <= ta && r.0 < t1 {
                    *r = density
                        .clear_along(p, l, r.1.max(ta), t1)
                        .unwrap_or((ta, t1));
                }
                r.0 < tb
            }
            None => {
                let (a, b) = (p + l * ta, p + l * tb);
                density.bound_in(&Aabb {
                    min: a.min(b),
                    max: a.max(b),
                }) > 0.0
            }
        };
        if filled {
            // The block's densities in one batch (the same bits as one by one).
            let (mut x, mut y, mut z, mut rho) =
                ([0.0f32; 8], [0.0f32; 8], [0.0f32; 8], [0.0f32; 8]);
            let m = end - i;
            for (k, j) in (i..end).enumerate() {
                let q = p + l * (t0 + (j as f32 + 0.5) * dt);
                (x[k], y[k], z[k]) = (q.x, q.y, q.z);
            }
            fill_densities_spaced(density, &x[..m], &y[..m], &z[..m], spacing, &mut rho[..m]);
            for &r in &rho[..m] {
                tau += r;
            }
        }
        i = end;
    }
    tau * dt * extinction
}

/// How far (in the table's longest cells) a node in clear air looks away
/// from the light for the medium's lit surface ([`lit_side_depth`]).
const LIT_SIDE_REACH: f32 = 4.0;

/// Samples of that look, `LIT_SIDE_REACH` cells in `LIT_SIDE_SAMPLES` steps.
const LIT_SIDE_SAMPLES: usize = 32;

/// What a node in clear air (no medium between it and the light) stores:
/// the optical depth below the medium's lit surface carried on linearly
/// across the surface, `−σ·s`, where `s` is the node's distance from the
/// surface against the light and `σ` the extinction just below it; 0 when
/// no medium lies within `reach` metres against the light.
///
/// A table that stored 0 there would interpolate, between such a node and
/// the first node inside, an optical depth that is already positive at the
/// surface and reaches its true value only at the inner node: the lit layer
/// of a dense medium, a mean free path deep or less, would be darkened by
/// up to a cell's optical depth. With the depth continued across the
/// surface, trilinear interpolation is exact for a flat surface of
/// constant density at any orientation (the optical depth is then linear
/// in space), and the lookup clamps the result at 0. The samples leave out
/// detail finer than `spacing`, as the nodes' marches do.
fn lit_side_depth(
    density: &dyn Density,
    extinction: f32,
    p: Vec3,
    l: Vec3,
    reach: f32,
    spacing: f32,
) -> f32 {
    const N: usize = LIT_SIDE_SAMPLES;
    let dt = reach / N as f32;
    let far = p - l * (reach + 3.0 * dt);
    if density.bound_in(&Aabb {
        min: p.min(far),
        max: p.max(far),
    }) <= 0.0
    {
        return 0.0;
    }
    let (mut x, mut y, mut z, mut rho) = (
        [0.0f32; N + 3],
        [0.0f32; N + 3],
        [0.0f32; N + 3],
        [0.0f32; N + 3],
    );
    for j in 0..N + 3 {
        let q = p - l * ((j as f32 + 0.5) * dt);
        (x[j], y[j], z[j]) = (q.x, q.y, q.z);
    }
    fill_densities_spaced(density, &x, &y, &z, spacing, &mut rho);
    let Some(j) = rho[..N].iter().position(|&r| r > 0.0) else {
        return 0.0;
    };
    // The surface lies between samples j − 1 and j; σ is the mean of the
    // first three samples below it.
    let sigma = extinction * (rho[j] + rho[j + 1] + rho[j + 2]) / 3.0;
    -sigma * (j as f32 * dt)
}

/// Ebert's 3-D shadow table: the optical depth toward one directional light
/// on a lattice of nodes spanning the density's bounds.
#[derive(Clone, Debug)]
pub struct ShadowTable {
    bounds: Aabb,
    dims: [usize; 3],
    cell: Vec3,
    inv_cell: Vec3,
    light: Vec3,
    tau: Vec<f32>,
}

/// Most nodes a table may hold (64 Mi, 256 MiB of `f32`).
pub const MAX_TABLE_NODES: usize = 1 << 26;

impl ShadowTable {
    /// Builds the table of `density` (scaled by `extinction`, 1/m per unit
    /// density) toward the unit direction `light` (pointing at the light),
    /// with `dims` nodes per axis over the density's bounds.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] for fewer than 2 or too many nodes,
    /// a non-finite or zero light direction or a bad extinction;
    /// [`VolumeError::InvalidBounds`] for bad density bounds.
    pub fn build(
        density: &dyn Density,
        extinction: f32,
        light: Vec3,
        dims: [usize; 3],
    ) -> Result<Self> {
        Self::build_with_solids(density, extinction, light, dims, &[])
    }

    /// [`ShadowTable::build`] with opaque spheres: nodes whose path to the
    /// light is blocked store [`BLOCKED_DEPTH`](super::BLOCKED_DEPTH).
    ///
    /// # Errors
    ///
    /// As [`ShadowTable::build`].
    pub fn build_with_solids(
        density: &dyn Density,
        extinction: f32,
        light: Vec3,
        dims: [usize; 3],
        solids: &[super::Solid],
    ) -> Result<Self> {
        Self::build_reporting(density, extinction, light, dims, solids, &NoProgress)
    }

    /// [`ShadowTable::build_with_solids`], advancing `progress` by one unit
    /// per finished row of `dims[0]` nodes (`dims[1] · dims[2]` in all); the
    /// caller starts and finishes the stage.
    pub(crate) fn build_reporting(
        density: &dyn Density,
        extinction: f32,
        light: Vec3,
        dims: [usize; 3],
        solids: &[super::Solid],
        progress: &dyn Progress,
    ) -> Result<Self> {
        crate::error::non_negative("extinction", extinction)?;
        let light = unit("light", light)?;
        let bounds = density.bounds();
        check_bounds("density bounds", &bounds)?;
        let total = dims.iter().try_fold(1usize, |a, &n| a.checked_mul(n));
        if dims.iter().any(|&n| n < 2) || total.is_none_or(|t| t > MAX_TABLE_NODES) {
            return Err(VolumeError::InvalidParameter {
                name: "dims",
                value: format!("{dims:?}"),
                expected: "at least 2 nodes per axis and at most 2^26 nodes",
            });
        }
        let size = bounds.max - bounds.min;
        let cell = size
            / Vec3::new(
                (dims[0] - 1) as f32,
                (dims[1] - 1) as f32,
                (dims[2] - 1) as f32,
            );
        let mut t = Self {
            bounds,
            dims,
            cell,
            inv_cell: cell.recip(),
            light,
            tau: vec![0.0; total.unwrap_or(0)],
        };
        t.fill(density, extinction, solids, progress);
        Ok(t)
    }

    fn node(&self, c: [usize; 3]) -> Vec3 {
        self.bounds.min + Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) * self.cell
    }

    fn fill(
        &mut self,
        density: &dyn Density,
        extinction: f32,
        solids: &[super::Solid],
        progress: &dyn Progress,
    ) {
        let (nx, ny) = (self.dims[0], self.dims[1]);
        let step = self.cell.min_element();
        let reach = LIT_SIDE_REACH * self.cell.max_element();
        let light = self.light;
        let this = &*self;
        let tau = map_rows(self.dims[2] * ny, |row| {
            let (y, z) = (row % ny, row / ny);
            let nodes: Vec<f32> = (0..nx)
                .map(|x| {
                    let p = this.node([x, y, z]);
                    // A node inside a solid looks past that solid, so lookups near its
                    // lit surface are not darkened by the nodes within it.
                    if solids
                        .iter()
                        .any(|s| !s.contains(p) && s.hit(p, light).is_some())
                    {
                        super::BLOCKED_DEPTH
                    } else {
                        optical_depth_spaced(density, extinction, p, light, step, step)
                    }
                })
                .collect();
            progress.advance(1);
            nodes
        });
        // Nodes in clear air take the depth continued across the lit surface
        // only where a neighbour (of the 26) holds a positive depth: a cell
        // whose eight corners are all clear blends to 0 whatever they hold.
        let nz = self.dims[2];
        let positive_near = |x: usize, y: usize, z: usize| {
            let r = |c: usize, n: usize| c.saturating_sub(1)..=(c + 1).min(n - 1);
            r(z, nz).any(|k| r(y, ny).any(|j| r(x, nx).any(|i| tau[(k * ny + j) * nx + i] > 0.0)))
        };
        let tau = map_rows(nz * ny, |row| {
            let (y, z) = (row % ny, row / ny);
            (0..nx)
                .map(|x| {
                    let t = tau[row * nx + x];
                    if t == 0.0 && positive_near(x, y, z) {
                        let p = this.node([x, y, z]);
                        lit_side_depth(density, extinction, p, light, reach, step)
                    } else {
                        t
                    }
                })
                .collect()
        });
        self.tau = tau;
    }

    /// The direction toward the light.
    #[must_use]
    pub fn light(&self) -> Vec3 {
        self.light
    }

    /// The optical depth toward the light at `p`, trilinear in the table
    /// and clamped at 0 (nodes in clear air hold the depth continued across
    /// the lit surface, which is negative); a point outside the bounds is
    /// first carried along the light direction to where it enters them (no
    /// density lies outside), and is 0 if it never does.
    #[inline]
    #[must_use]
    pub fn optical_depth(&self, p: Vec3) -> f32 {
        let mut q = p;
        if !self.bounds.contains(p) {
            match ray_box(p, self.light.recip(), &self.bounds) {
                Some((t0, _)) => q = p + self.light * t0,
                None => return 0.0,
            }
        }
        let g = ((q - self.bounds.min) * self.inv_cell).max(Vec3::ZERO);
        let (nx, ny, nz) = (self.dims[0], self.dims[1], self.dims[2]);
        let x0 = (g.x as usize).min(nx - 2);
        let y0 = (g.y as usize).min(ny - 2);
        let z0 = (g.z as usize).min(nz - 2);
        let f = (g - Vec3::new(x0 as f32, y0 as f32, z0 as f32)).clamp(Vec3::ZERO, Vec3::ONE);
        let at = |x: usize, y: usize, z: usize| self.tau[(z * ny + y) * nx + x];
        let l = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let c00 = l(at(x0, y0, z0), at(x0 + 1, y0, z0), f.x);
        let c10 = l(at(x0, y0 + 1, z0), at(x0 + 1, y0 + 1, z0), f.x);
        let c01 = l(at(x0, y0, z0 + 1), at(x0 + 1, y0, z0 + 1), f.x);
        let c11 = l(at(x0, y0 + 1, z0 + 1), at(x0 + 1, y0 + 1, z0 + 1), f.x);
        l(l(c00, c10, f.y), l(c01, c11, f.y), f.z).max(0.0)
    }

    /// The transmittance `exp(−τ)` toward the light at `p`.
    #[inline]
    #[must_use]
    pub fn transmittance(&self, p: Vec3) -> f32 {
        (-self.optical_depth(p)).exp()
    }
}

/// Nodes per axis for a table over `bounds` whose longest axis has `n` nodes
/// (cells as cubic as the box allows, at least 2 per axis).
#[must_use]
pub fn table_dims(bounds: &Aabb, n: usize) -> [usize; 3] {
    let s = bounds.max - bounds.min;
    let h = s.max_element() / (n.max(2) - 1) as f32;
    let f = |x: f32| ((x / h).ceil() as usize + 1).clamp(2, n.max(2));
    [f(s.x), f(s.y), f(s.z)]
}

/// Checks `v` is finite and non-zero, and normalises it.
pub(crate) fn unit(name: &'static str, v: Vec3) -> Result<Vec3> {
    crate::error::finite3(name, v)?;
    positive(name, v.length()).map_err(|_| VolumeError::InvalidParameter {
        name,
        value: format!("{v:?}"),
        expected: "a non-zero direction",
    })?;
    Ok(v.normalize())
}

/// `(0..rows).flat_map(f)` with the rows computed in parallel when the
/// `parallel` feature is on (the result does not depend on scheduling).
pub(crate) fn map_rows(rows: usize, f: impl Fn(usize) -> Vec<f32> + Sync + Send) -> Vec<f32> {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        (0..rows).into_par_iter().flat_map_iter(f).collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        (0..rows).flat_map(f).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::GridDensity;
    use natura_core::{Grid3, Seed};

    /// A density that hides its runs ([`Density::clear_along`]).
    struct Boxed<'a>(&'a dyn Density);

    impl Density for Boxed<'_> {
        fn density(&self, p: Vec3) -> f32 {
            self.0.density(p)
        }
        fn bounds(&self) -> Aabb {
            self.0.bounds()
        }
        fn bound_in(&self, region: &Aabb) -> f32 {
            self.0.bound_in(region)
        }
        fn max_density(&self) -> f32 {
            self.0.max_density()
        }
        fn density_batch(
            &self,
            x: &[f32],
            y: &[f32],
            z: &[f32],
            out: &mut [f32],
        ) -> crate::Result<()> {
            self.0.density_batch(x, y, z, out)
        }
    }

    #[test]
    fn the_runs_skip_only_zeros() {
        // Puffs of density in a mostly empty grid: the optical depth of a
        // ray is the same bits whether its empty blocks of steps are found
        // by the grid's runs or by bounding their boxes.
        let mut rng = Seed(4).rng();
        let mut u = || crate::animate::unit(&mut rng);
        let centres: Vec<Vec3> = (0..30)
            .map(|_| Vec3::new(u() * 48.0, u() * 40.0, u() * 16.0))
            .collect();
        let g = Grid3::from_fn(48, 40, 16, |x, y, z| {
            let p = Vec3::new(x as f32, y as f32, z as f32);
            centres
                .iter()
                .map(|c| (1.0 - p.distance(*c) / 3.0).max(0.0))
                .sum::<f32>()
        })
        .unwrap();
        let grid = GridDensity::new(g, Vec3::new(10.0, -20.0, 500.0), 20.0).unwrap();
        let b = grid.bounds();
        let (mut same, mut lit) = (0, 0);
        for _ in 0..400 {
            let p = b.min + (b.max - b.min) * Vec3::new(u(), u(), u());
            let l = Vec3::new(u() - 0.5, u() - 0.5, u() * 0.5 + 0.05).normalize();
            let step = 5.0 + 30.0 * u();
            let fast = optical_depth_spaced(&grid, 0.03, p, l, step, 10.0);
            let boxed = optical_depth_spaced(&Boxed(&grid), 0.03, p, l, step, 10.0);
            assert_eq!(fast.to_bits(), boxed.to_bits(), "{p} {l} {step}");
            same += 1;
            lit += usize::from(fast > 0.0);
        }
        assert_eq!(same, 400);
        assert!(lit > 100 && lit < 390, "{lit}");
    }
}
