//! How Worley noise's feature points are distributed over the lattice
//! cells: one jittered point per cell, or one of MojoWorld's "seed tables"
//! (Musgrave 2001, "The Seed Tables"), and the exact search over them.
//!
//! The source names the tables by a density ("the ones with larger numbers
//! have a denser spatial distribution"), a "v" for "variable" ("more dense
//! some areas and less dense in others") and a "g" for "Gaussian"
//! ("heterogeneous heterogeneity"), and gives no definitions. The ones here
//! are ours, chosen to read as the source describes and to keep the search
//! exact:
//!
//! * **n**: the number of points in a cell is Poisson-distributed with mean
//!   `n`, the points uniform in the cell, as Worley 1996 draws its
//!   feature points: a Poisson process of intensity `n` per unit area or
//!   volume.
//! * **nv**: the same with the mean modulated in space, `n·m(x)`, with
//!   `m = 1 + 0.8·clamp(2·P(c/8), −1, 1)` at the cell's centre `c`, `P` the
//!   crate's Perlin noise (a period of about 8 cells): `m ∈ [0.2, 1.8]`, and
//!   its average over space is 1 (Perlin noise takes `v` and `−v` equally
//!   often), so the overall density stays `n`.
//! * **ng**: clusters (a Thomas process, Thomas 1949): cluster centres are a
//!   Poisson process of `n/4` per cell, each with a Poisson number of points
//!   of mean 4 scattered about it by a Gaussian of its own standard
//!   deviation `σ`, log-uniform in `[0.05, 0.3]` cells. The clustering is
//!   the heterogeneity; that some clusters are tight and some loose is its
//!   heterogeneity. The Gaussian is truncated at `3σ` (each axis offset is
//!   below `0.9` cells), so a cell's points stay near it.
//!
//! Every draw is a stateless hash of the cell and the seed, so a point's
//! value does not depend on evaluation order, and nothing is allocated.
//! With a random number of points a cell may be empty: the search visits
//! rings of cells until no unvisited point can be nearer than the current
//! `F_k`, and stops for good where that distance reaches [`CAP_DISTANCE`]
//! lattice units: the value is `min(F_k, C)`, `C` the metric's value at that
//! distance. For the least density allowed, the chance that `F_4` reaches
//! the cap is below `10⁻¹²`.

use glam::{DVec2, DVec3};

use crate::basis::cellular::{Metric, Worley, insert};
use crate::basis::perlin::Perlin;
use crate::error::{NoiseError, Result};
use crate::field::Field;
use crate::hash::{corner, mix32, mix64, row2, row3};
use crate::lattice_math::split;

/// The least mean density (points per cell) of the seed tables: low enough
/// for sparse cells, high enough that the search's cap is never reached in
/// practice (see [`CAP_DISTANCE`]).
pub const MIN_DENSITY: f64 = 0.5;

/// The largest mean density (points per cell) of the seed tables.
pub const MAX_DENSITY: f64 = 16.0;

/// The distance (lattice units; its square under
/// [`Metric::EuclideanSquared`]) at which the search of the seed tables
/// stops: values are `min(F_k, C)` with `C` this distance under the metric,
/// so `C` is their [`Field::bound`].
///
/// A Manhattan ball of radius 24 holds every cell within 6 (3-D) or 10
/// (2-D) cells of the point's cell even with the Gaussian table's spill, at
/// least 441 cells; at the least local density (0.1 points per cell, the
/// variable table at [`MIN_DENSITY`]) fewer than 4 points in them has
/// probability below `10⁻¹⁵`, and fewer than 4 in the clustered table
/// (cluster centres 0.125 per cell) below `10⁻²⁰`.
pub const CAP_DISTANCE: f64 = 24.0;

/// How Worley noise's feature points are spread over the lattice cells:
/// one per cell (the default) or one of MojoWorld's random "seed tables"
/// (Musgrave 2001, "The Seed Tables"), whose exact definitions the source
/// leaves open; the module documentation states the ones chosen here.
///
/// Densities are mean points per unit cell, in
/// [[`MIN_DENSITY`], [`MAX_DENSITY`]]. With the `serde` feature a
/// distribution is written as `"one_per_cell"` or, for example,
/// `{ poisson = { density = 4.0 } }` (TOML).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum FeaturePoints {
    /// Exactly one point per cell, at `cell + ½ + jitter·(u − ½)` (Worley
    /// noise as it is usually made): the fastest, with SIMD batch rows. The
    /// default.
    #[default]
    OnePerCell,
    /// Table "n": a Poisson number of points per cell with mean `density`,
    /// uniform in the cell (Worley 1996). Larger means smaller cells.
    Poisson {
        /// Mean points per cell, in `[0.5, 16]`.
        density: f64,
    },
    /// Table "nv": as [`Poisson`](Self::Poisson) with the mean multiplied by
    /// a smooth field `m ∈ [0.2, 1.8]` of average 1 and a period of about 8
    /// cells: regions of small cells beside regions of large ones.
    Variable {
        /// Mean points per cell over all space, in `[0.5, 16]`.
        density: f64,
    },
    /// Table "ng": points in clusters of mean 4 about centres spread
    /// `density/4` per cell, each cluster Gaussian with its own spread
    /// (0.05 to 0.3 cells): tight knots of tiny cells among looser ones.
    Gaussian {
        /// Mean points per cell over all space, in `[0.5, 16]`.
        density: f64,
    },
}

impl FeaturePoints {
    /// Checks that a table's density is in `[MIN_DENSITY, MAX_DENSITY]`.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] naming `points.density` when it is NaN
    /// or outside `[0.5, 16]` (zero and negative densities included).
    pub fn validate(&self) -> Result<()> {
        match *self {
            FeaturePoints::OnePerCell => Ok(()),
            FeaturePoints::Poisson { density }
            | FeaturePoints::Variable { density }
            | FeaturePoints::Gaussian { density } => {
                if (MIN_DENSITY..=MAX_DENSITY).contains(&density) {
                    Ok(())
                } else {
                    Err(NoiseError::InvalidParam {
                        name: "points.density",
                        value: density,
                        expected: "must be in [0.5, 16] points per cell",
                    })
                }
            }
        }
    }
}

/// Largest point count drawn for one cell (or one cluster): far beyond any
/// allowed mean (at most 28.8 per cell), so the truncation never shows.
const MAX_COUNT: u32 = 96;

/// Period of the variable table's modulation, in cells.
const VARIABLE_PERIOD: f64 = 8.0;
/// Gain on Perlin noise before clamping to `[−1, 1]`.
const VARIABLE_GAIN: f64 = 2.0;
/// Swing of the modulation about 1: `m ∈ [1 − 0.8, 1 + 0.8]`.
const VARIABLE_SWING: f64 = 0.8;

/// Mean points per cluster of the Gaussian table.
const CLUSTER_SIZE: f64 = 4.0;
/// Least and largest standard deviation of a cluster, in cells.
const SIGMA_MIN: f64 = 0.05;
const SIGMA_MAX: f64 = 0.3;
/// Truncation of the cluster Gaussian, in standard deviations.
const TRUNCATION: f64 = 3.0;

/// Salt of the cells' draw streams.
const STREAM_SALT: u32 = 0x5345_4544; // "SEED"
/// Salt of the variable table's modulation seed.
const MODULATION_SALT: u64 = 0x4D4F_4455; // "MODU"

/// A seed table ready to draw from: its kind and the constants of its
/// draws, computed once per field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Table {
    kind: Kind,
    /// Mean point (Poisson, Variable) or cluster (Gaussian) count per cell.
    mean: f64,
    /// `e^{−mean}`, the Poisson probability of an empty cell.
    exp_neg_mean: f64,
    /// `e^{−CLUSTER_SIZE}`.
    exp_neg_cluster: f64,
    /// The variable table's modulation.
    modulation: Perlin,
    /// How far a cell's points may lie outside it, per axis (cells).
    pub(crate) spill: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Poisson,
    Variable,
    Gaussian,
}

/// A cell's stream of 32-bit draws (a Weyl sequence through `mix32`).
struct Draws(u32);

impl Draws {
    #[inline]
    fn next(&mut self) -> u32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9);
        mix32(self.0)
    }

    /// Uniform in `[0, 1)`.
    #[inline]
    fn unit(&mut self) -> f64 {
        f64::from(self.next()) * (1.0 / 4_294_967_296.0)
    }

    /// A Poisson count of mean `mean` (`e^{−mean}` given) by inversion of
    /// its distribution function, at most [`MAX_COUNT`].
    #[inline]
    fn poisson(&mut self, mean: f64, exp_neg_mean: f64) -> u32 {
        let u = self.unit();
        let (mut k, mut p, mut cdf) = (0u32, exp_neg_mean, exp_neg_mean);
        while u >= cdf && k < MAX_COUNT {
            k += 1;
            p *= mean / f64::from(k);
            cdf += p;
        }
        k
    }

    /// Two Gaussian offsets of standard deviation `sigma`, truncated to the
    /// disc of radius [`TRUNCATION`]`·sigma` (Box–Muller with the radius
    /// drawn from the truncated Rayleigh distribution).
    #[inline]
    fn gaussian_pair(&mut self, sigma: f64) -> [f64; 2] {
        // 1 − e^{−T²/2}: the Rayleigh mass inside the truncation radius.
        let inside = 1.0 - libm::exp(-0.5 * TRUNCATION * TRUNCATION);
        let r = sigma * libm::sqrt(-2.0 * libm::log(1.0 - self.unit() * inside));
        let (s, c) = libm::sincos(core::f64::consts::TAU * self.unit());
        [r * c, r * s]
    }
}

impl Table {
    /// The table for `points` (validated) and the field's seed, or `None`
    /// for one point per cell.
    pub(crate) fn new(points: FeaturePoints, seed: u64) -> Option<Self> {
        let (kind, density) = match points {
            FeaturePoints::OnePerCell => return None,
            FeaturePoints::Poisson { density } => (Kind::Poisson, density),
            FeaturePoints::Variable { density } => (Kind::Variable, density),
            FeaturePoints::Gaussian { density } => (Kind::Gaussian, density),
        };
        let mean = if kind == Kind::Gaussian {
            density / CLUSTER_SIZE
        } else {
            density
        };
        Some(Self {
            kind,
            mean,
            exp_neg_mean: libm::exp(-mean),
            exp_neg_cluster: libm::exp(-CLUSTER_SIZE),
            modulation: Perlin::new(mix64(seed ^ MODULATION_SALT)),
            spill: if kind == Kind::Gaussian {
                TRUNCATION * SIGMA_MAX
            } else {
                0.0
            },
        })
    }

    /// The variable table's density factor `m ∈ [0.2, 1.8]` at a cell
    /// centre (lattice coordinates).
    #[inline]
    pub(crate) fn modulation(&self, centre: [f64; 3], dims: usize) -> f64 {
        let s = 1.0 / VARIABLE_PERIOD;
        let v = if dims == 2 {
            self.modulation
                .eval2(DVec2::new(centre[0] * s, centre[1] * s))
        } else {
            self.modulation.eval3(DVec3::from_array(centre) * s)
        };
        1.0 + VARIABLE_SWING * (VARIABLE_GAIN * v).clamp(-1.0, 1.0)
    }

    /// Calls `f` with every feature point of the cell hashed `h`, whose
    /// corner is at `corner` (lattice coordinates, for the variable table's
    /// modulation), relative to that corner; `dims` is 2 or 3 (the third
    /// coordinate is 0 in 2-D).
    #[inline]
    pub(crate) fn for_points(
        &self,
        h: u32,
        corner: [f64; 3],
        dims: usize,
        mut f: impl FnMut([f64; 3]),
    ) {
        let mut draws = Draws(mix32(h ^ STREAM_SALT));
        let uniform = |draws: &mut Draws| {
            let x = draws.unit();
            let y = draws.unit();
            let z = if dims == 3 { draws.unit() } else { 0.0 };
            [x, y, z]
        };
        match self.kind {
            Kind::Poisson => {
                for _ in 0..draws.poisson(self.mean, self.exp_neg_mean) {
                    f(uniform(&mut draws));
                }
            }
            Kind::Variable => {
                let centre = corner.map(|c| c + 0.5);
                let mean = self.mean * self.modulation(centre, dims);
                for _ in 0..draws.poisson(mean, libm::exp(-mean)) {
                    f(uniform(&mut draws));
                }
            }
            Kind::Gaussian => {
                for _ in 0..draws.poisson(self.mean, self.exp_neg_mean) {
                    let c = uniform(&mut draws);
                    let sigma = SIGMA_MIN * libm::pow(SIGMA_MAX / SIGMA_MIN, draws.unit());
                    for _ in 0..draws.poisson(CLUSTER_SIZE, self.exp_neg_cluster) {
                        let [x, y] = draws.gaussian_pair(sigma);
                        let z = if dims == 3 {
                            draws.gaussian_pair(sigma)[0]
                        } else {
                            0.0
                        };
                        f([c[0] + x, c[1] + y, c[2] + z]);
                    }
                }
            }
        }
    }
}

impl Worley {
    /// The value over a seed table's points, kept out of line (and off the
    /// hot path's layout) so the one-point-per-cell path compiles as it did
    /// before the tables.
    #[cold]
    #[inline(never)]
    pub(super) fn table_value(&self, t: &Table, p: [f64; 3], dims: usize) -> f64 {
        let nan = !p[..dims].iter().all(|v| v.is_finite());
        self.value_from(self.search_table(t, p, dims).0, nan)
    }

    /// The 4 nearest distances (capped at the metric's value of
    /// [`CAP_DISTANCE`]) and offsets (point minus feature point; zero where
    /// capped) from `p` over a seed table's points, in `dims` = 2 or 3
    /// dimensions (`p[2]` unused in 2-D). Exact below the cap: see the
    /// module documentation.
    pub(crate) fn search_table(
        &self,
        t: &Table,
        p: [f64; 3],
        dims: usize,
    ) -> ([f64; 4], [[f64; 3]; 4]) {
        let m = self.params.metric;
        let cap = m.metric_of_axis_bound(CAP_DISTANCE);
        if !p[..dims].iter().all(|v| v.is_finite()) {
            return ([f64::NAN; 4], [[0.0; 3]; 4]);
        }
        let k = self.params.feature.rank();
        let cell: [(u32, f64); 3] = p.map(split);
        let floor = p.map(libm::floor);
        let edge = cell[..dims]
            .iter()
            .fold(f64::INFINITY, |e, &(_, t)| e.min(t.min(1.0 - t)));
        let mut best = [f64::INFINITY; 4];
        let mut at = [[0.0; 3]; 4];
        let mut r: i64 = 0;
        loop {
            if r >= 1 {
                // Every point of a cell in ring r lies at least this far
                // along the axis on which the cell is r cells away.
                let b = ((r - 1) as f64 + edge - t.spill).max(0.0);
                if m.metric_of_axis_bound(b) >= best[k - 1].min(cap) {
                    break;
                }
            }
            let zr = if dims == 3 { r } else { 0 };
            for dz in -zr..=zr {
                for dy in -r..=r {
                    for dx in -r..=r {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                            continue;
                        }
                        let d = [dx, dy, dz];
                        // The least distance to the cell's box (grown by the
                        // spill): a cell that cannot hold a point nearer than
                        // the k-th so far (or the cap) cannot change the
                        // values, so its points are not drawn.
                        let gap: [f64; 3] = core::array::from_fn(|a| {
                            let lo = d[a] as f64 - t.spill;
                            let f = cell[a].1;
                            (lo - f).max(f - (lo + 1.0 + 2.0 * t.spill)).max(0.0)
                        });
                        let near = if dims == 2 {
                            m.d2(gap[0], gap[1])
                        } else {
                            m.d3(gap[0], gap[1], gap[2])
                        };
                        if near >= best[k - 1].min(cap) {
                            continue;
                        }
                        let idx: [u32; 3] =
                            core::array::from_fn(|a| cell[a].0.wrapping_add(d[a] as u32));
                        let h = if dims == 2 {
                            corner(idx[0], row2(idx[1], self.s))
                        } else {
                            corner(idx[0], row3(idx[1], idx[2], self.s))
                        };
                        let origin: [f64; 3] = core::array::from_fn(|a| floor[a] + d[a] as f64);
                        t.for_points(h, origin, dims, |q| {
                            let o: [f64; 3] =
                                core::array::from_fn(|a| cell[a].1 - (d[a] as f64 + q[a]));
                            let dist = if dims == 2 {
                                m.d2(o[0], o[1])
                            } else {
                                m.d3(o[0], o[1], o[2])
                            };
                            let o = if dims == 2 { [o[0], o[1], 0.0] } else { o };
                            insert(&mut best, &mut at, dist, o);
                        });
                    }
                }
            }
            r += 1;
        }
        for (b, o) in best.iter_mut().zip(at.iter_mut()) {
            if *b >= cap {
                *b = cap;
                *o = [0.0; 3];
            }
        }
        (best, at)
    }
}

/// The metric's value at the cap distance: the seed tables' bound.
pub(crate) fn cap_value(m: Metric) -> f64 {
    m.metric_of_axis_bound(CAP_DISTANCE)
}

#[cfg(test)]
mod tests;
