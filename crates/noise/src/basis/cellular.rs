//! Worley (Voronoi, cellular) noise: distances to the nearest feature points.
//!
//! MojoWorld's Voronoi basis [M 477-486] (Worley 1996): one feature point per
//! unit lattice cell, at `cell + ½ + jitter·(u − ½)` with `u` uniform from the
//! cell's hash. The value is the distance to the 1st…4th nearest feature point
//! (`F1…F4`) or a difference of neighbours (`F2 − F1`, …) under a chosen metric.
//! "Distance" gives conical pits, "distance squared" parabolic ones [M 484].
//!
//! The search is **exact** for every feature and jitter: cells are visited in
//! rings of growing Chebyshev radius until the ring's nearest possible point
//! is farther than the current `F_k`. The batch kernels search the 3×3 (3×3×3)
//! block in SIMD lanes and redo the rare lanes that may need the next ring
//! with the exact point path, so batch and point agree.
//!
//! Values are distances in lattice units (not re-centred to `[-1, 1]`, since
//! the ridge structure is what users want from them); [`Field::bound`] is the
//! largest possible value.

use glam::{DVec2, DVec3};

use crate::error::{NoiseError, Result};
use crate::field::Field;
use crate::hash::{corner, rehash, row2, row3, seed32, unit_hi, unit_lo};
use crate::lanes::{Simd, run, split, split_fast};

/// The distance metric between a point and a feature point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Metric {
    /// Straight-line distance: conical pits, straight ridges. The default.
    #[default]
    Euclidean,
    /// Squared Euclidean distance: smooth parabolic pits [M 484].
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
pub struct WorleyParams {
    /// Which distance is returned.
    pub feature: WorleyFeature,
    /// The distance metric.
    pub metric: Metric,
    /// How far feature points stray from their cell centres, in `[0, 1]`:
    /// 0 is a regular grid, 1 fills the whole cell (the default).
    pub jitter: f64,
}

impl Default for WorleyParams {
    fn default() -> Self {
        Self {
            feature: WorleyFeature::F1,
            metric: Metric::Euclidean,
            jitter: 1.0,
        }
    }
}

impl WorleyParams {
    /// Checks that the jitter lies in `[0, 1]`.
    pub fn validate(&self) -> Result<()> {
        if !(0.0..=1.0).contains(&self.jitter) {
            return Err(NoiseError::InvalidParam {
                name: "jitter",
                value: self.jitter,
                expected: "must be in [0, 1]",
            });
        }
        Ok(())
    }
}

const SALT: u64 = 0x574F_524C; // "WORL"

/// Worley cellular noise (F1–F4 and differences; Euclidean, squared,
/// Manhattan or Chebyshev distance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Worley {
    seed: u64,
    s: u32,
    params: WorleyParams,
}

/// Sorted insertion of `d` into the `k` smallest so far (with payload index).
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
    pub fn new(seed: u64, params: WorleyParams) -> Result<Self> {
        params.validate()?;
        Ok(Self {
            seed,
            s: seed32(seed, SALT),
            params,
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
        let h = corner(i, row2(j, self.s));
        let jt = self.params.jitter;
        (
            0.5 + jt * (f64::from(unit_lo(h)) - 0.5),
            0.5 + jt * (f64::from(unit_hi(h)) - 0.5),
        )
    }

    #[inline(always)]
    fn point3(&self, i: u32, j: u32, k: u32) -> [f64; 3] {
        let h = corner(i, row3(j, k, self.s));
        let jt = self.params.jitter;
        [
            0.5 + jt * (f64::from(unit_lo(h)) - 0.5),
            0.5 + jt * (f64::from(unit_hi(h)) - 0.5),
            0.5 + jt * (f64::from(unit_hi(rehash(h))) - 0.5),
        ]
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
        let base = match self.params.metric {
            Metric::Euclidean | Metric::Chebyshev => 1.0,
            Metric::Manhattan => libm::sqrt(n as f64),
            Metric::EuclideanSquared => 2.0 * 2.0 * libm::sqrt(n as f64),
        };
        match self.params.feature {
            WorleyFeature::F1 | WorleyFeature::F2 | WorleyFeature::F3 | WorleyFeature::F4 => base,
            _ => 2.0 * base,
        }
    }
}

impl Field for Worley {
    fn eval2(&self, p: DVec2) -> f64 {
        self.value_from(self.search2(p).0, !p.is_finite())
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.value_from(self.search3(p).0, !p.is_finite())
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        let (best, at) = self.search2(p);
        let g = self.grad_from(&at, 2);
        (
            self.value_from(best, !p.is_finite()),
            DVec2::new(g[0], g[1]),
        )
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        let (best, at) = self.search3(p);
        (
            self.value_from(best, !p.is_finite()),
            DVec3::from_array(self.grad_from(&at, 3)),
        )
    }
    fn bound(&self) -> f64 {
        self.max_distance(3)
    }
    fn lipschitz2(&self) -> f64 {
        self.lipschitz_n(2)
    }
    fn lipschitz3(&self) -> f64 {
        self.lipschitz_n(3)
    }

    fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        if !crate::basis::row_in_fast_range(origin.x, step, out.len())
            || !origin.y.is_finite()
            || origin.y.abs() > 1e15
        {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval2(DVec2::new(origin.x + i as f64 * step, origin.y)) as f32;
            }
            return;
        }
        let mut flags = [0u8; 64];
        for (c, chunk) in out.chunks_mut(64).enumerate() {
            let x0 = origin.x + (c * 64) as f64 * step;
            let fl = &mut flags[..chunk.len()];
            run(
                simd,
                #[inline(always)]
                || worley_dispatch!(self, worley2_row(self, x0, origin.y, step, chunk, fl)),
            );
            if fl.iter().any(|&f| f != 0) {
                for (i, (o, &f)) in chunk.iter_mut().zip(fl.iter()).enumerate() {
                    if f != 0 {
                        *o = self.eval2(DVec2::new(x0 + i as f64 * step, origin.y)) as f32;
                    }
                }
            }
        }
    }

    fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        if !crate::basis::row_in_fast_range(origin.x, step, out.len())
            || !origin.is_finite()
            || origin.y.abs().max(origin.z.abs()) > 1e15
        {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval3(DVec3::new(origin.x + i as f64 * step, origin.y, origin.z)) as f32;
            }
            return;
        }
        let mut flags = [0u8; 64];
        for (c, chunk) in out.chunks_mut(64).enumerate() {
            let x0 = origin.x + (c * 64) as f64 * step;
            let o = DVec3::new(x0, origin.y, origin.z);
            let fl = &mut flags[..chunk.len()];
            run(
                simd,
                #[inline(always)]
                || worley_dispatch!(self, worley3_row(self, o, step, chunk, fl)),
            );
            if fl.iter().any(|&f| f != 0) {
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

/// `√v` for f32 lanes in `core` (no `sqrt` there, and a libm call would stop
/// vectorisation): the bit-trick reciprocal square root refined by three
/// Newton steps (relative error below f32 rounding), times `v`.
#[inline(always)]
pub(crate) fn sqrt32(v: f32) -> f32 {
    let mut y = f32::from_bits(0x5F37_59DF_u32.wrapping_sub(v.to_bits() >> 1));
    for _ in 0..3 {
        y *= 1.5 - 0.5 * v * y * y;
    }
    v * y
}

/// Sorted insertion into the K smallest (a min/max network; branch-free).
#[inline(always)]
fn insert32<const K: usize>(best: &mut [f32; K], d: f32) {
    let mut d = d;
    for b in best.iter_mut() {
        let lo = b.min(d);
        d = b.max(d);
        *b = lo;
    }
}

/// The metric as a lane function (Euclidean kept squared until the end),
/// whether the ring bound must be squared, and whether to take a root at the end.
macro_rules! with_metric {
    ($m:expr, |$dist:ident, $sqb:ident, $root:ident| $body:expr) => {
        match $m {
            Metric::Euclidean => {
                let $dist = |x: f32, y: f32, z: f32| x * x + y * y + z * z;
                let ($sqb, $root) = (true, true);
                $body
            }
            Metric::EuclideanSquared => {
                let $dist = |x: f32, y: f32, z: f32| x * x + y * y + z * z;
                let ($sqb, $root) = (true, false);
                $body
            }
            Metric::Manhattan => {
                let $dist = |x: f32, y: f32, z: f32| x.abs() + y.abs() + z.abs();
                let ($sqb, $root) = (false, false);
                $body
            }
            Metric::Chebyshev => {
                let $dist = |x: f32, y: f32, z: f32| x.abs().max(y.abs()).max(z.abs());
                let ($sqb, $root) = (false, false);
                $body
            }
        }
    };
}

/// Monomorphises a row kernel for the feature (rank K and pick) and metric.
macro_rules! worley_dispatch {
    ($w:expr, $kernel:ident($($arg:expr),*)) => {{
        let w = $w;
        with_metric!(w.params.metric, |dist, sqb, root| match w.params.feature {
            WorleyFeature::F1 => $kernel::<1>($($arg,)* dist, |d: &[f32; 1]| d[0], sqb, root),
            WorleyFeature::F2 => $kernel::<2>($($arg,)* dist, |d: &[f32; 2]| d[1], sqb, root),
            WorleyFeature::F3 => $kernel::<3>($($arg,)* dist, |d: &[f32; 3]| d[2], sqb, root),
            WorleyFeature::F4 => $kernel::<4>($($arg,)* dist, |d: &[f32; 4]| d[3], sqb, root),
            WorleyFeature::F2MinusF1 => $kernel::<2>($($arg,)* dist, |d: &[f32; 2]| d[1] - d[0], sqb, root),
            WorleyFeature::F3MinusF2 => $kernel::<3>($($arg,)* dist, |d: &[f32; 3]| d[2] - d[1], sqb, root),
            WorleyFeature::F4MinusF3 => $kernel::<4>($($arg,)* dist, |d: &[f32; 4]| d[3] - d[2], sqb, root),
        })
    }};
}
pub(crate) use {with_metric, worley_dispatch};

/// 3×3 SIMD search over a 2-D row chunk. Sets `flags[i] = 1` for lanes whose
/// ring-2 bound does not clear `F_K` (they are redone by the exact point path).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn worley2_row<const K: usize>(
    w: &Worley,
    x0: f64,
    y: f64,
    step: f64,
    out: &mut [f32],
    flags: &mut [u8],
    dist: impl Fn(f32, f32, f32) -> f32,
    pick: impl Fn(&[f32; K]) -> f32,
    square_bound: bool,
    root: bool,
) {
    let (iy, fy) = split_fast(y);
    let fy32 = fy as f32;
    let rows = [
        row2(iy.wrapping_sub(1), w.s),
        row2(iy, w.s),
        row2(iy.wrapping_add(1), w.s),
    ];
    let jt = w.params.jitter as f32;
    let margin = 0.5 - 0.5 * jt;
    let edge_y = fy32.min(1.0 - fy32);
    for (n, (o, flag)) in out.iter_mut().zip(flags.iter_mut()).enumerate() {
        let x = x0 + (n as i32) as f64 * step;
        let (ix, fx) = split_fast(x);
        let fx = fx as f32;
        let mut best = [f32::INFINITY; K];
        for (r, &row) in rows.iter().enumerate() {
            let dy = fy32 - (r as f32 - 0.5);
            for dxi in 0..3u32 {
                let h = corner(ix.wrapping_add(dxi).wrapping_sub(1), row);
                let px = fx - (dxi as f32 - 0.5 + jt * (unit_lo(h) - 0.5));
                let py = dy - jt * (unit_hi(h) - 0.5);
                insert32(&mut best, dist(px, py, 0.0));
            }
        }
        let b = 1.0 + margin + fx.min(1.0 - fx).min(edge_y);
        let b = if square_bound { b * b } else { b };
        // A small tolerance so f32 rounding never hides a needed ring.
        *flag = u8::from(best[K - 1] >= b * 0.999_9);
        if root {
            for v in best.iter_mut() {
                *v = sqrt32(*v);
            }
        }
        *o = pick(&best);
    }
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn worley3_row<const K: usize>(
    w: &Worley,
    origin: DVec3,
    step: f64,
    out: &mut [f32],
    flags: &mut [u8],
    dist: impl Fn(f32, f32, f32) -> f32,
    pick: impl Fn(&[f32; K]) -> f32,
    square_bound: bool,
    root: bool,
) {
    let (iy, fy) = split_fast(origin.y);
    let (iz, fz) = split_fast(origin.z);
    let (fy32, fz32) = (fy as f32, fz as f32);
    let mut rows = [0u32; 9];
    for (r, row) in rows.iter_mut().enumerate() {
        let (dy, dz) = ((r % 3) as u32, (r / 3) as u32);
        *row = row3(
            iy.wrapping_add(dy).wrapping_sub(1),
            iz.wrapping_add(dz).wrapping_sub(1),
            w.s,
        );
    }
    let jt = w.params.jitter as f32;
    let margin = 0.5 - 0.5 * jt;
    let edge_yz = fy32.min(1.0 - fy32).min(fz32.min(1.0 - fz32));
    for (n, (o, flag)) in out.iter_mut().zip(flags.iter_mut()).enumerate() {
        let x = origin.x + (n as i32) as f64 * step;
        let (ix, fx) = split_fast(x);
        let fx = fx as f32;
        let mut best = [f32::INFINITY; K];
        for (r, &row) in rows.iter().enumerate() {
            let dy = fy32 - ((r % 3) as f32 - 0.5);
            let dz = fz32 - ((r / 3) as f32 - 0.5);
            for dxi in 0..3u32 {
                let h = corner(ix.wrapping_add(dxi).wrapping_sub(1), row);
                let px = fx - (dxi as f32 - 0.5 + jt * (unit_lo(h) - 0.5));
                let py = dy - jt * (unit_hi(h) - 0.5);
                let pz = dz - jt * (unit_hi(rehash(h)) - 0.5);
                insert32(&mut best, dist(px, py, pz));
            }
        }
        let b = 1.0 + margin + fx.min(1.0 - fx).min(edge_yz);
        let b = if square_bound { b * b } else { b };
        *flag = u8::from(best[K - 1] >= b * 0.999_9);
        if root {
            for v in best.iter_mut() {
                *v = sqrt32(*v);
            }
        }
        *o = pick(&best);
    }
}
