//! Worley (Voronoi, cellular) noise: distances to the nearest feature points.
//!
//! MojoWorld's Voronoi basis (Musgrave 2001, "Voronoi") (Worley 1996): one
//! feature point per unit lattice cell, at `cell + ½ + jitter·(u − ½)` with `u`
//! uniform from the cell's hash. The value is the distance to the 1st…4th
//! nearest feature point (`F1…F4`) or a difference of neighbours (`F2 − F1`, …)
//! under a chosen metric. "Distance" gives conical pits, "distance squared"
//! parabolic ones (Musgrave 2001, "Voronoi").
//!
//! The search is **exact** for every feature and jitter: cells are visited in
//! rings of growing Chebyshev radius until the ring's nearest possible point
//! is farther than the current `F_k`. The batch kernels search the 3×3 (3×3×3)
//! block in SIMD lanes and redo the rare lanes that may need the next ring
//! with the exact point path, so batch and point agree.
//!
//! The points may instead follow one of MojoWorld's random "seed tables"
//! (Musgrave 2001, "The Seed Tables"): a Poisson number per cell of a chosen
//! mean (Worley 1996), that mean varying in space, or clusters
//! ([`FeaturePoints`]; the definitions, which the source leaves open, are in
//! its documentation). Their search is exact too, up to a distance cap
//! ([`CAP_DISTANCE`]), and their batch rows are the point values.
//!
//! Values are distances in lattice units (not re-centred to `[-1, 1]`, since
//! the ridge structure is what users want from them); [`Field::bound`] is the
//! largest possible value: with one point per cell, the largest distance to
//! a point of the 3ⁿ block around the point's cell; with a seed table, the
//! cap's distance under the metric (24, or 576 for
//! [`Metric::EuclideanSquared`]).

use glam::{DVec2, DVec3};

use crate::basis::SPAN_MAX_STEP;
use crate::basis::cellular_rows::{chunk2, chunk3};
use crate::error::{NoiseError, Result};
use crate::field::Field;
use crate::hash::{PX, PY, PZ, corner, corner_spread, row2, row3, seed32};
use crate::lattice_math::{Real, Simd, max_fast, min_fast, split};

/// The distance metric between a point and a feature point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Metric {
    /// Straight-line distance: conical pits, straight ridges. The default.
    #[default]
    Euclidean,
    /// Squared Euclidean distance: smooth parabolic pits (Musgrave 2001,
    /// "Voronoi").
    EuclideanSquared,
    /// Sum of axis distances (L1): diamond-shaped cells.
    Manhattan,
    /// Largest axis distance (L∞): square cells.
    Chebyshev,
}

impl Metric {
    #[inline(always)]
    fn d2(self, x: f64, y: f64) -> f64 {
        match self {
            Metric::Euclidean => libm::sqrt(x * x + y * y),
            Metric::EuclideanSquared => x * x + y * y,
            Metric::Manhattan => x.abs() + y.abs(),
            Metric::Chebyshev => x.abs().max(y.abs()),
        }
    }

    #[inline(always)]
    fn d3(self, x: f64, y: f64, z: f64) -> f64 {
        match self {
            Metric::Euclidean => libm::sqrt(x * x + y * y + z * z),
            Metric::EuclideanSquared => x * x + y * y + z * z,
            Metric::Manhattan => x.abs() + y.abs() + z.abs(),
            Metric::Chebyshev => x.abs().max(y.abs()).max(z.abs()),
        }
    }

    /// The metric's value for a lower bound `b` on the largest axis distance.
    #[inline(always)]
    fn metric_of_axis_bound(self, b: f64) -> f64 {
        match self {
            Metric::EuclideanSquared => b * b,
            _ => b,
        }
    }

    /// Gradient of the metric of offset `d` (point minus feature point) w.r.t. the point.
    fn grad(self, d: [f64; 3], n: usize) -> [f64; 3] {
        let mut g = [0.0; 3];
        match self {
            Metric::Euclidean => {
                let l = libm::sqrt(d[..n].iter().map(|v| v * v).sum::<f64>());
                if l > 0.0 {
                    for a in 0..n {
                        g[a] = d[a] / l;
                    }
                }
            }
            Metric::EuclideanSquared => {
                for a in 0..n {
                    g[a] = 2.0 * d[a];
                }
            }
            Metric::Manhattan => {
                for a in 0..n {
                    g[a] = crate::fractal::fbm::sign(d[a]);
                }
            }
            Metric::Chebyshev => {
                let mut best = 0;
                for a in 1..n {
                    if d[a].abs() > d[best].abs() {
                        best = a;
                    }
                }
                g[best] = crate::fractal::fbm::sign(d[best]);
            }
        }
        g
    }
}

/// Which distance (or difference of distances) the field returns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum WorleyFeature {
    /// Distance to the nearest feature point (cells with conical pits). The default.
    #[default]
    F1,
    /// Distance to the 2nd nearest.
    F2,
    /// Distance to the 3rd nearest.
    F3,
    /// Distance to the 4th nearest.
    F4,
    /// `F2 − F1`: zero on the Voronoi edges (crack patterns).
    F2MinusF1,
    /// `F3 − F2`.
    F3MinusF2,
    /// `F4 − F3`.
    F4MinusF3,
}

impl WorleyFeature {
    /// How many nearest distances the feature needs.
    fn rank(self) -> usize {
        match self {
            WorleyFeature::F1 => 1,
            WorleyFeature::F2 | WorleyFeature::F2MinusF1 => 2,
            WorleyFeature::F3 | WorleyFeature::F3MinusF2 => 3,
            WorleyFeature::F4 | WorleyFeature::F4MinusF3 => 4,
        }
    }

    /// Combines sorted distances `d` (and the indices of the points) into the value.
    #[inline(always)]
    fn pick<T: Copy + core::ops::Sub<Output = T>>(self, d: &[T; 4]) -> T {
        match self {
            WorleyFeature::F1 => d[0],
            WorleyFeature::F2 => d[1],
            WorleyFeature::F3 => d[2],
            WorleyFeature::F4 => d[3],
            WorleyFeature::F2MinusF1 => d[1] - d[0],
            WorleyFeature::F3MinusF2 => d[2] - d[1],
            WorleyFeature::F4MinusF3 => d[3] - d[2],
        }
    }
}

/// Parameters of [`Worley`] noise.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct WorleyParams {
    /// Which distance is returned.
    pub feature: WorleyFeature,
    /// The distance metric.
    pub metric: Metric,
    /// How far feature points stray from their cell centres, in `[0, 1]`:
    /// 0 is a regular grid, 1 fills the whole cell (the default). Used only
    /// with one point per cell (the seed tables' points are random).
    pub jitter: f64,
    /// How the feature points are spread over the cells: one per cell (the
    /// default) or one of MojoWorld's seed tables (Musgrave 2001, "The Seed
    /// Tables").
    pub points: FeaturePoints,
}

impl Default for WorleyParams {
    fn default() -> Self {
        Self {
            feature: WorleyFeature::F1,
            metric: Metric::Euclidean,
            jitter: 1.0,
            points: FeaturePoints::OnePerCell,
        }
    }
}

impl WorleyParams {
    /// Checks that the jitter lies in `[0, 1]` and a seed table's density
    /// in `[0.5, 16]`.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] naming the first parameter that is NaN, infinite or outside its domain.
    pub fn validate(&self) -> Result<()> {
        if !(0.0..=1.0).contains(&self.jitter) {
            return Err(NoiseError::InvalidParam {
                name: "jitter",
                value: self.jitter,
                expected: "must be in [0, 1]",
            });
        }
        self.points.validate()
    }
}

const SALT: u64 = 0x574F_524C; // "WORL"

mod place;
mod points;
pub(crate) use place::{Cheb, Dist, Euclid, EuclidSq, Placement, Taxicab, insert_k};
pub use points::{CAP_DISTANCE, FeaturePoints, MAX_DENSITY, MIN_DENSITY};
use points::{Table, cap_value};

/// Monomorphises a search for the metric and the feature (its rank `K` and
/// how the sorted distances combine), over lane type `$t`: calls
/// `$kernel::<K, D>(args…, pick)`.
macro_rules! worley_dispatch {
    ($w:expr, $t:ty, $kernel:ident, ($($arg:expr),*)) => {{
        let w = $w;
        match w.params.metric {
            Metric::Euclidean => worley_dispatch!(@feature w, $t, Euclid, $kernel, ($($arg),*)),
            Metric::EuclideanSquared => {
                worley_dispatch!(@feature w, $t, EuclidSq, $kernel, ($($arg),*))
            }
            Metric::Manhattan => worley_dispatch!(@feature w, $t, Taxicab, $kernel, ($($arg),*)),
            Metric::Chebyshev => worley_dispatch!(@feature w, $t, Cheb, $kernel, ($($arg),*)),
        }
    }};
    (@feature $w:ident, $t:ty, $d:ty, $kernel:ident, ($($arg:expr),*)) => {
        match $w.params.feature {
            WorleyFeature::F1 => $kernel::<1, $d>($($arg,)* |d: &[$t; 1]| d[0]),
            WorleyFeature::F2 => $kernel::<2, $d>($($arg,)* |d: &[$t; 2]| d[1]),
            WorleyFeature::F3 => $kernel::<3, $d>($($arg,)* |d: &[$t; 3]| d[2]),
            WorleyFeature::F4 => $kernel::<4, $d>($($arg,)* |d: &[$t; 4]| d[3]),
            WorleyFeature::F2MinusF1 => $kernel::<2, $d>($($arg,)* |d: &[$t; 2]| d[1] - d[0]),
            WorleyFeature::F3MinusF2 => $kernel::<3, $d>($($arg,)* |d: &[$t; 3]| d[2] - d[1]),
            WorleyFeature::F4MinusF3 => $kernel::<4, $d>($($arg,)* |d: &[$t; 4]| d[3] - d[2]),
        }
    };
}

/// Worley cellular noise (F1–F4 and differences; Euclidean, squared,
/// Manhattan or Chebyshev distance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Worley {
    seed: u64,
    s: u32,
    params: WorleyParams,
    /// The seed table's draws, or `None` for one point per cell.
    table: Option<Table>,
}

/// Sorted insertion of `d` into the 4 smallest so far, with the offset of
/// its feature point (the ring search's bookkeeping, for gradients).
#[inline(always)]
fn insert(best: &mut [f64; 4], at: &mut [[f64; 3]; 4], d: f64, off: [f64; 3]) {
    if d < best[3] {
        let mut i = 3;
        while i > 0 && best[i - 1] > d {
            best[i] = best[i - 1];
            at[i] = at[i - 1];
            i -= 1;
        }
        best[i] = d;
        at[i] = off;
    }
}

impl Worley {
    /// Worley noise with `seed` and `params` (validated).
    ///
    /// # Errors
    /// As the parameters' `validate`.
    pub fn new(seed: u64, params: WorleyParams) -> Result<Self> {
        params.validate()?;
        Ok(Self {
            seed,
            s: seed32(seed, SALT),
            params,
            table: Table::new(params.points, seed),
        })
    }

    /// The seed.
    #[must_use]
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &WorleyParams {
        &self.params
    }

    /// The feature point of 2-D cell `(i, j)`, relative to the cell's corner.
    #[inline(always)]
    fn point2(&self, i: u32, j: u32) -> (f64, f64) {
        let f = self.place().point(corner(i, row2(j, self.s)));
        (f[0], f[1])
    }

    #[inline(always)]
    fn point3(&self, i: u32, j: u32, k: u32) -> [f64; 3] {
        self.place().point(corner(i, row3(j, k, self.s)))
    }

    /// The feature placement for this jitter.
    #[inline(always)]
    pub(crate) fn place<T: Real>(&self) -> Placement<T> {
        Placement::new(self.params.jitter)
    }

    /// Lower bound on the largest-axis distance from a point with fractions `f`
    /// to any feature point in ring `r ≥ 1` (Chebyshev cell distance `r`).
    fn ring_bound(&self, f: &[f64], r: i64) -> f64 {
        let margin = 0.5 - self.params.jitter * 0.5;
        let edge = f
            .iter()
            .map(|&t| t.min(1.0 - t))
            .fold(f64::INFINITY, f64::min);
        (r - 1) as f64 + margin + edge
    }

    /// The k nearest distances and offsets (point minus feature point), exact.
    fn search2(&self, p: DVec2) -> ([f64; 4], [[f64; 3]; 4]) {
        let (ix, fx) = split(p.x);
        let (iy, fy) = split(p.y);
        let m = self.params.metric;
        let k = self.params.feature.rank();
        let mut best = [f64::INFINITY; 4];
        let mut at = [[0.0; 3]; 4];
        let mut r: i64 = 0;
        loop {
            if r >= 2 && m.metric_of_axis_bound(self.ring_bound(&[fx, fy], r)) > best[k - 1] {
                break;
            }
            for dy in -r..=r {
                for dx in -r..=r {
                    if dx.abs().max(dy.abs()) != r {
                        continue;
                    }
                    let (px, py) =
                        self.point2(ix.wrapping_add(dx as u32), iy.wrapping_add(dy as u32));
                    let ox = fx - (dx as f64 + px);
                    let oy = fy - (dy as f64 + py);
                    insert(&mut best, &mut at, m.d2(ox, oy), [ox, oy, 0.0]);
                }
            }
            r += 1;
            if r > 64 || !p.is_finite() {
                break;
            }
        }
        (best, at)
    }

    fn search3(&self, p: DVec3) -> ([f64; 4], [[f64; 3]; 4]) {
        let (ix, fx) = split(p.x);
        let (iy, fy) = split(p.y);
        let (iz, fz) = split(p.z);
        let m = self.params.metric;
        let k = self.params.feature.rank();
        let mut best = [f64::INFINITY; 4];
        let mut at = [[0.0; 3]; 4];
        let mut r: i64 = 0;
        loop {
            if r >= 2 && m.metric_of_axis_bound(self.ring_bound(&[fx, fy, fz], r)) > best[k - 1] {
                break;
            }
            for dz in -r..=r {
                for dy in -r..=r {
                    for dx in -r..=r {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                            continue;
                        }
                        let c = self.point3(
                            ix.wrapping_add(dx as u32),
                            iy.wrapping_add(dy as u32),
                            iz.wrapping_add(dz as u32),
                        );
                        let o = [
                            fx - (dx as f64 + c[0]),
                            fy - (dy as f64 + c[1]),
                            fz - (dz as f64 + c[2]),
                        ];
                        insert(&mut best, &mut at, m.d3(o[0], o[1], o[2]), o);
                    }
                }
            }
            r += 1;
            if r > 64 || !p.is_finite() {
                break;
            }
        }
        (best, at)
    }

    /// Inserts into `best` the kept distances from a 2-D point to the
    /// feature points of the cells `cols × rows`: each column is a spread x
    /// index with the point's x offset from the column's margin corner
    /// (`fx − dx − margin`), each row a row hash with the y offset.
    #[inline(always)]
    fn cells2<const K: usize, D: Dist<f64>, const C: usize, const R: usize>(
        &self,
        cols: [(u32, f64); C],
        rows: [(u32, f64); R],
        best: &mut [f64; K],
    ) {
        let place = self.place::<f64>();
        for (row, gy) in rows {
            for (col, gx) in cols {
                let d = place.disp(corner_spread(col, row));
                insert_k(best, D::comb(D::axis(gx - d[0]), D::axis(gy - d[1])));
            }
        }
    }

    /// As [`cells2`](Self::cells2) in 3-D: each row is a (y, z) row hash
    /// with the point's y and z offsets.
    #[inline(always)]
    fn cells3<const K: usize, D: Dist<f64>, const C: usize, const R: usize>(
        &self,
        cols: [(u32, f64); C],
        rows: [(u32, f64, f64); R],
        best: &mut [f64; K],
    ) {
        let place = self.place::<f64>();
        for (row, gy, gz) in rows {
            for (col, gx) in cols {
                let d = place.disp(corner_spread(col, row));
                let yz = D::comb(D::axis(gy - d[1]), D::axis(gz - d[2]));
                insert_k(best, D::comb(D::axis(gx - d[0]), yz));
            }
        }
    }

    /// The `K` smallest kept distances from the point with lattice cell `ix`
    /// and fractions `f` to the cells of a search set, found in stages:
    ///
    /// 1. for F1, the 2ⁿ cells toward the point's nearest cell corner: every
    ///    other feature point is at least `margin + min_a max(f_a, 1 − f_a)`
    ///    away along some axis, so a nearest distance below that is final;
    /// 2. the 3ⁿ block around the cell: every feature point two or more
    ///    cells away is at least `1 + margin + min_a min(f_a, 1 − f_a)` away;
    /// 3. otherwise `None`, and the caller runs the ring search (as for a
    ///    NaN point).
    #[inline(always)]
    fn search<const K: usize, D: Dist<f64>, const N: usize>(
        &self,
        ix: [u32; N],
        f: [f64; N],
    ) -> Option<[f64; K]> {
        const P: [u32; 3] = [PX, PY, PZ];
        let m = self.place::<f64>().margin;
        // Per axis: the own and nearer neighbour indices (spread), the
        // point's offsets from their margin corners, and the far bound.
        let own: [u32; N] = core::array::from_fn(|a| ix[a].wrapping_mul(P[a]));
        let up: [bool; N] = f.map(|t| t >= 0.5);
        let near: [(u32, f64); N] = core::array::from_fn(|a| {
            let (p, dir) = if up[a] {
                (P[a], 1.0)
            } else {
                (P[a].wrapping_neg(), -1.0)
            };
            (own[a].wrapping_add(p), f[a] - (dir + m))
        });
        let mut best = [f64::INFINITY; K];
        if K == 1 {
            let far = f
                .iter()
                .fold(f64::INFINITY, |b, &t| min_fast(b, max_fast(t, 1.0 - t)));
            let pairs: [[(u32, f64); 2]; N] =
                core::array::from_fn(|a| [(own[a], f[a] - m), near[a]]);
            self.cells_n::<K, D, N, 2>(&pairs, &mut best);
            if D::kept(m + far) > best[0] {
                return Some(best);
            }
            // Stage 2 for F1 adds only the block's cells outside the 2ⁿ
            // quadrant (the nearest is a minimum, so the result is the
            // whole block's): per axis the neighbour away from the corner.
            let mut away = [(0u32, 0.0f64); N];
            for a in 0..N {
                away[a] = if up[a] {
                    (own[a].wrapping_sub(P[a]), f[a] - (-1.0 + m))
                } else {
                    (own[a].wrapping_add(P[a]), f[a] - (1.0 + m))
                };
            }
            self.block_rest::<K, D, N>(&pairs, &away, &mut best);
        } else {
            let block: [[(u32, f64); 3]; N] = core::array::from_fn(|a| {
                let p = P[a];
                [
                    (own[a].wrapping_sub(p), f[a] - (-1.0 + m)),
                    (own[a], f[a] - m),
                    (own[a].wrapping_add(p), f[a] - (1.0 + m)),
                ]
            });
            self.cells_n::<K, D, N, 3>(&block, &mut best);
        }
        let edge = f
            .iter()
            .fold(f64::INFINITY, |e, &t| min_fast(e, min_fast(t, 1.0 - t)));
        (D::kept(1.0 + m + edge) > best[K - 1]).then_some(best)
    }

    /// The cells of the 3ⁿ block around a point that are not in the 2ⁿ
    /// quadrant `quad` (per axis the own and nearer neighbour), given per
    /// axis the neighbour `away` from the quadrant: in 2-D the `away` column
    /// (3 cells) and the quadrant's columns in the `away` row (2); in 3-D
    /// the `away` x layer (9), then the quadrant's x columns in the `away` y
    /// rows (6), then in the quadrant's y rows on the `away` z layer (4).
    #[inline(always)]
    fn block_rest<const K: usize, D: Dist<f64>, const N: usize>(
        &self,
        quad: &[[(u32, f64); 2]; N],
        away: &[(u32, f64); N],
        best: &mut [f64; K],
    ) {
        let s = self.s;
        let row3 = |ax: usize| [quad[ax][0], quad[ax][1], away[ax]];
        if N == 2 {
            let ys = row3(1).map(|(y, gy)| (y ^ s, gy));
            self.cells2::<K, D, 1, 3>([away[0]], ys, best);
            let (y, gy) = away[1];
            self.cells2::<K, D, 2, 1>(quad[0], [(y ^ s, gy)], best);
        } else {
            let ys = row3(1);
            let zs = row3(2 % N);
            let mut layer = [(0u32, 0.0f64, 0.0f64); 9];
            for (k, r) in layer.iter_mut().enumerate() {
                let ((y, gy), (z, gz)) = (ys[k % 3], zs[k / 3]);
                *r = (y ^ z ^ s, gy, gz);
            }
            self.cells3::<K, D, 1, 9>([away[0]], layer, best);
            let (y, gy) = away[1];
            let rows: [(u32, f64, f64); 3] = zs.map(|(z, gz)| (y ^ z ^ s, gy, gz));
            self.cells3::<K, D, 2, 3>(quad[0], rows, best);
            let (z, gz) = away[2 % N];
            let rows: [(u32, f64, f64); 2] = quad[1].map(|(y, gy)| (y ^ z ^ s, gy, gz));
            self.cells3::<K, D, 2, 2>(quad[0], rows, best);
        }
    }

    /// The cells `axes[0] × axes[1] (× axes[2])` of a search set, `W` per
    /// axis (see [`cells2`](Self::cells2)); the seed joins the rows.
    #[inline(always)]
    fn cells_n<const K: usize, D: Dist<f64>, const N: usize, const W: usize>(
        &self,
        axes: &[[(u32, f64); W]; N],
        best: &mut [f64; K],
    ) {
        if N == 2 {
            let rows: [(u32, f64); W] = axes[1].map(|(y, gy)| (y ^ self.s, gy));
            self.cells2::<K, D, W, W>(axes[0], rows, best);
        } else {
            let mut rows = [(0u32, 0.0f64, 0.0f64); 9];
            for (k, row) in rows.iter_mut().take(W * W).enumerate() {
                let (y, gy) = axes[1][k % W];
                let (z, gz) = axes[2 % N][k / W];
                *row = (y ^ z ^ self.s, gy, gz);
            }
            if W == 2 {
                let rows: [(u32, f64, f64); 4] = core::array::from_fn(|k| rows[k]);
                self.cells3::<K, D, W, 4>(axes[0], rows, best);
            } else {
                self.cells3::<K, D, W, 9>(axes[0], rows, best);
            }
        }
    }

    fn value_from(&self, best: [f64; 4], nan: bool) -> f64 {
        if nan {
            f64::NAN
        } else {
            self.params.feature.pick(&best)
        }
    }

    fn grad_from(&self, at: &[[f64; 3]; 4], n: usize) -> [f64; 3] {
        let m = self.params.metric;
        let g = |i: usize| m.grad(at[i], n);
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        match self.params.feature {
            WorleyFeature::F1 => g(0),
            WorleyFeature::F2 => g(1),
            WorleyFeature::F3 => g(2),
            WorleyFeature::F4 => g(3),
            WorleyFeature::F2MinusF1 => sub(g(1), g(0)),
            WorleyFeature::F3MinusF2 => sub(g(2), g(1)),
            WorleyFeature::F4MinusF3 => sub(g(3), g(2)),
        }
    }

    /// Largest possible single distance: every feature point of the 3ⁿ block
    /// around the point's cell lies within 2 cells along each axis.
    fn max_distance(&self, n: usize) -> f64 {
        let n = n as f64;
        match self.params.metric {
            Metric::Euclidean => 2.0 * libm::sqrt(n),
            Metric::EuclideanSquared => 4.0 * n,
            Metric::Manhattan => 2.0 * n,
            Metric::Chebyshev => 2.0,
        }
    }

    fn lipschitz_n(&self, n: usize) -> f64 {
        // Squared distance: the slope 2·d at the largest distance d.
        let largest = if self.table.is_some() {
            CAP_DISTANCE
        } else {
            2.0 * libm::sqrt(n as f64)
        };
        let base = match self.params.metric {
            Metric::Euclidean | Metric::Chebyshev => 1.0,
            Metric::Manhattan => libm::sqrt(n as f64),
            Metric::EuclideanSquared => 2.0 * largest,
        };
        match self.params.feature {
            WorleyFeature::F1 | WorleyFeature::F2 | WorleyFeature::F3 | WorleyFeature::F4 => base,
            _ => 2.0 * base,
        }
    }
}

impl Field for Worley {
    #[inline]
    fn eval2(&self, p: DVec2) -> f64 {
        if let Some(t) = &self.table {
            return self.table_value(t, [p.x, p.y, 0.0], 2);
        }
        worley_dispatch!(self, f64, search_block2, (self, p))
            .unwrap_or_else(|| self.value_from(self.search2(p).0, !p.is_finite()))
    }
    #[inline]
    fn eval3(&self, p: DVec3) -> f64 {
        if let Some(t) = &self.table {
            return self.table_value(t, p.to_array(), 3);
        }
        worley_dispatch!(self, f64, search_block3, (self, p))
            .unwrap_or_else(|| self.value_from(self.search3(p).0, !p.is_finite()))
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        let (best, at) = match &self.table {
            Some(t) => self.search_table(t, [p.x, p.y, 0.0], 2),
            None => self.search2(p),
        };
        let g = self.grad_from(&at, 2);
        (
            self.value_from(best, !p.is_finite()),
            DVec2::new(g[0], g[1]),
        )
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        let (best, at) = match &self.table {
            Some(t) => self.search_table(t, p.to_array(), 3),
            None => self.search3(p),
        };
        (
            self.value_from(best, !p.is_finite()),
            DVec3::from_array(self.grad_from(&at, 3)),
        )
    }
    fn bound(&self) -> f64 {
        if self.table.is_some() {
            cap_value(self.params.metric)
        } else {
            self.max_distance(3)
        }
    }
    fn lipschitz2(&self) -> f64 {
        self.lipschitz_n(2)
    }
    fn lipschitz3(&self) -> f64 {
        self.lipschitz_n(3)
    }

    fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        // The seed tables have no batch kernel: their rows are the point values.
        if self.table.is_some()
            || !crate::basis::row_in_fast_range(origin.x, step, out.len())
            || !origin.y.is_finite()
            || origin.y.abs() > 1e15
        {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval2(DVec2::new(origin.x + i as f64 * step, origin.y)) as f32;
            }
            return;
        }
        let spans = step > 0.0 && step <= SPAN_MAX_STEP;
        let mut flags = [0u8; CHUNK];
        for (c, chunk) in out.chunks_mut(CHUNK).enumerate() {
            let x0 = origin.x + (c * CHUNK) as f64 * step;
            let fl = &mut flags[..chunk.len()];
            let args = (
                self,
                DVec2::new(x0, origin.y),
                step,
                &mut *chunk,
                &mut *fl,
                spans,
            );
            worley_dispatch!(self, f32, chunk2, (simd, args));
            if fl.iter().fold(0, |a, &f| a | f) != 0 {
                for (i, (o, &f)) in chunk.iter_mut().zip(fl.iter()).enumerate() {
                    if f != 0 {
                        *o = self.eval2(DVec2::new(x0 + i as f64 * step, origin.y)) as f32;
                    }
                }
            }
        }
    }

    fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        if self.table.is_some()
            || !crate::basis::row_in_fast_range(origin.x, step, out.len())
            || !origin.is_finite()
            || origin.y.abs().max(origin.z.abs()) > 1e15
        {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval3(DVec3::new(origin.x + i as f64 * step, origin.y, origin.z)) as f32;
            }
            return;
        }
        let spans = step > 0.0 && step <= SPAN_MAX_STEP;
        let mut flags = [0u8; CHUNK];
        for (c, chunk) in out.chunks_mut(CHUNK).enumerate() {
            let x0 = origin.x + (c * CHUNK) as f64 * step;
            let o = DVec3::new(x0, origin.y, origin.z);
            let fl = &mut flags[..chunk.len()];
            let args = (self, o, step, &mut *chunk, &mut *fl, spans);
            worley_dispatch!(self, f32, chunk3, (simd, args));
            if fl.iter().fold(0, |a, &f| a | f) != 0 {
                for (i, (v, &f)) in chunk.iter_mut().zip(fl.iter()).enumerate() {
                    if f != 0 {
                        *v =
                            self.eval3(DVec3::new(x0 + i as f64 * step, origin.y, origin.z)) as f32;
                    }
                }
            }
        }
    }
}

/// The 2-D value by the staged block search ([`Worley::search`]), or `None`
/// when the point needs the ring search (a free function, for
/// [`worley_dispatch!`]).
#[inline(always)]
fn search_block2<const K: usize, D: Dist<f64>>(
    w: &Worley,
    p: DVec2,
    pick: impl Fn(&[f64; K]) -> f64,
) -> Option<f64> {
    let (ix, fx) = split(p.x);
    let (iy, fy) = split(p.y);
    let best = w.search::<K, D, 2>([ix, iy], [fx, fy])?;
    Some(pick(&best.map(D::value)))
}

/// The 3-D value by the staged block search, or `None` (see [`search_block2`]).
#[inline(always)]
fn search_block3<const K: usize, D: Dist<f64>>(
    w: &Worley,
    p: DVec3,
    pick: impl Fn(&[f64; K]) -> f64,
) -> Option<f64> {
    let (ix, fx) = split(p.x);
    let (iy, fy) = split(p.y);
    let (iz, fz) = split(p.z);
    let best = w.search::<K, D, 3>([ix, iy, iz], [fx, fy, fz])?;
    Some(pick(&best.map(D::value)))
}

/// Points per batch chunk (stack buffers for the rows' exactness flags).
const CHUNK: usize = 256;

impl Worley {
    /// The hash seed (for the batch kernels).
    #[inline(always)]
    pub(crate) fn lattice_seed(&self) -> u32 {
        self.s
    }
}

#[cfg(test)]
mod tests;
