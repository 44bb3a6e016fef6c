//! The light the sun leaves in a medium after scattering at least once,
//! traced once per scene and stored on a grid: the fast mode's model of
//! multiple scattering.
//!
//! **What is stored.** For the light that has scattered at least once,
//! per unit irradiance of the sun, each cell holds its radiance's
//! projection on the real spherical harmonics of bands `0..=L`,
//! `c_lm = ∫ L Y_lm dω` (band 0 is the fluence over `√(4π)`, band 1 the net
//! flux). A phase function acts on band `l` as a factor, its Legendre
//! moment `χ_l = 2π ∫ p(μ) P_l(μ) dμ` (the Funk–Hecke theorem; for
//! Henyey–Greenstein `χ_l = g^l`, the generating function of the Legendre
//! polynomials), so the light it scatters toward the eye, propagating along
//! `ω_o`, is `Σ σ_l χ_l c_lm Y_lm(ω_o)`, clamped at zero. The cut series
//! rings (Gibbs' phenomenon), and a forward-peaked radiance seen sideways
//! or backwards would swing negative; Lanczos' σ-factors `σ_l` damp that
//! ([`sigma_factor`]). The march adds `σ_s·E` times the sum to its exact
//! single scattering: single scattering keeps the full phase function and
//! the exact shadows; only the orders beyond the first come from the grid.
//! With `L = 1` this is the `P₁` (diffusion) approximation.
//!
//! **The zonal tail.** Light that has scattered once or twice in a
//! forward-scattering medium is still peaked about the sun's beam, and a
//! peak needs many bands: a cut series spreads it sideways (the cut series
//! darkens a view toward the sun and brightens one across it). Such a
//! peak is nearly symmetric about the beam, and the part of band `l` that
//! is symmetric about an axis is one number, its zonal coefficient
//! `∫ L Y_l0 dω` in a frame whose pole is that axis, with
//! `Y_l0(ω) = √((2l+1)/(4π))·P_l(ω·axis)` (the addition theorem of the
//! spherical harmonics). So bands `L+1 ..= Z` (`CacheParams::zonal`) may
//! be stored by that one coefficient each, about the sun's beam: the full
//! series keeps the light's low-order shape in every direction, the tail
//! its peak toward and away from the sun, for `Z − L` more numbers a cell
//! where the full series to `Z` would take `(Z+1)² − (L+1)²`. The tail
//! drops what in those bands is not symmetric about the beam. The σ-factors
//! are those of the series cut after `Z`.
//!
//! **How it is traced.** Photons of the sun's beam start on a plane across
//! the volume's bounds, at uniform random points taken in the order of a
//! Z-order curve over the plane, so that photons following one another
//! cross the same cells. Each is forced to collide once inside the medium
//! (weight `1 − e^{−τ}` of its line; no photon is wasted on a thin
//! medium), scatters with the albedo as weight, and is then followed through
//! free flights and scatterings sampled as the reference path tracer
//! samples them (Pharr et al. 2023, §14.1; Russian roulette below a tenth
//! of the photon's first weight). Every flight after the first scattering
//! is scored by its track length in each cell it crosses (the track-length
//! estimator of the fluence; Lux & Koblinger 1991, ch. 5), with its
//! direction for the flux. The flights cross the grid's cells by the
//! 3-D DDA of Amanatides & Woo 1987, through the medium averaged over each
//! cell: its extinction is the mean of `2³` samples per cell. Cells are
//! cubes along the bounds' longest axis; a thin axis keeps at least 16,
//! and an axis gets as many as a cell per mean free path of the medium's
//! mean extinction takes, up to the longest axis's count.
//!
//! **What it costs and what it misses.** The photons run when the renderer
//! is built, in fixed chunks with their own random streams (the grid is
//! the same on any number of threads), and the march reads eight cells per
//! sample (their dot products with the eye's factors are kept while an eye
//! ray stays among the same cells).
//!
//! **Within a cell.** A cell holds the mean of the light over its volume;
//! in an optically thick medium, where a cell spans several mean free
//! paths, the fluence falls steeply across it, and blending the eight
//! cells' means linearly over-brightens the side that faces away from the
//! light (the fluence's profile is convex). There the light is diffuse and
//! Fick's law of the diffusion approximation ties its net flux to the
//! fluence's gradient, `F = −∇φ/(3σ'_t)` with `σ'_t = σ_t(1 − ωg)` (Jensen
//! et al. 2001, §2.3, the diffusion approximation), so band 1 gives each
//! cell its own relative gradient, `∇φ/φ = −√3·σ'_t·(c₁₁, c₁₋₁, c₁₀)/c₀₀`,
//! at no cost in memory: each cell's light is carried from its centre
//! `x_c` to the sample by `1 + ∇φ/φ·(p − x_c)` (kept within `[0, 3]`)
//! before the trilinear blend. In thin cells `σ'_t·h ≪ 1` and the factor
//! is 1. Over the scene matrix this took the isotropic ball lit from ahead
//! (τ 20) from +5.2 % to +4.6 % and the 5 µm slab behind the sun (τ 50,
//! albedo 0.8) from −4.8 % to +1.9 %.
//!
//! **What it still misses.** The grid smooths the multiply scattered light
//! over a cell where diffusion does not hold (near the lit face of an
//! optically thick medium), and the cut series spreads light that is still peaked after two
//! scatterings in a strongly forward medium (`g ≥ 0.8`). Both errors, and
//! the cache's noise, are measured against the reference in
//! `crates/volume/tests/scatter_matrix.rs`; the figures are in
//! `docs/performance.md`.

use glam::Vec3;
use natura_core::{Aabb, Seed};

use super::MediumParams;
use super::cells::{CellGrid, Flight};
use super::harmonics::{MAX_CELL, dot, zonal_basis};
pub use super::harmonics::{
    MAX_COEFFS, MAX_ORDER, MAX_ZONAL, legendre_moments, sh_basis, sigma_factor,
};
use crate::animate::unit;
use crate::density::Density;
use crate::error::{Result, VolumeError};

/// Photon chunks (each its own random stream and grid; summed in order).
const CHUNKS: usize = 4;
/// Most scattering events one photon is followed through.
const MAX_EVENTS_PER_PHOTON: u32 = 1 << 20;

/// An optical depth past which a line's chance of a collision,
/// `1 − e^{−τ}`, is 1 in `f32` (it is from `τ ≈ 17.4`), and past which no
/// forced collision's depth `−ln(1 − u)` reaches (`u < 1 − 2⁻²⁴` gives
/// under 16.7): a sun photon's line is walked only this deep, with the same
/// weight and the same collision as the whole line's.
const OPAQUE: f32 = 24.0;

/// The fewest and the most photons whose starting points on the beam's
/// plane are drawn at once and taken in the order of a Z-order curve across
/// the plane (see [`start_batch`]); a batch is sized to the events left at
/// the rate of events per photon so far.
const MIN_BATCH: usize = 256;
const MAX_BATCH: usize = 1 << 16;

/// `n` uniform points of the unit square, in the reverse order of their
/// places on a Z-order (Morton) curve of `2¹⁰ × 2¹⁰` squares, ties in the
/// order drawn; popped from the end, they come in the curve's order.
/// Photons that start side by side cross the same cells and collide near
/// each other, so the cells' extinction and moments they read and score
/// are still in the processor's cache: the walks are bound by memory, not
/// by arithmetic, and a random order of starts made them miss it at
/// nearly every cell.
fn start_batch(rng: &mut impl rand_core::Rng, n: usize) -> Vec<glam::Vec2> {
    /// The bits of `x < 2¹⁰` spread to the even places.
    fn spread(x: u32) -> u32 {
        let mut v = x & 0x3ff;
        v = (v | (v << 8)) & 0x00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333;
        (v | (v << 1)) & 0x5555_5555
    }
    let mut batch: Vec<(u32, u32, glam::Vec2)> = (0..n as u32)
        .map(|i| {
            let p = glam::Vec2::new(unit(rng), unit(rng));
            let q = |x: f32| ((x * 1024.0) as u32).min(1023);
            (spread(q(p.x)) | (spread(q(p.y)) << 1), i, p)
        })
        .collect();
    batch.sort_unstable_by_key(|&(key, i, _)| std::cmp::Reverse((key, i)));
    batch.into_iter().map(|(_, _, p)| p).collect()
}

/// The default highest band (see [`CacheParams::order`]).
pub const ORDER_DEFAULT: u32 = 7;

/// Settings of the multiple-scattering cache.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct CacheParams {
    /// Cells along the bounds' longest axis (4 to 1024; cells are cubes).
    pub cells: u32,
    /// Scattering events traced in all (`10⁴` to `10⁹`; photons are traced
    /// in whole batches, so the last batch may add a few more); the cache's
    /// noise falls as its inverse square root.
    pub events: u32,
    /// Highest spherical-harmonic band of the stored radiance, 1 to 7
    /// (`(order + 1)²` coefficients per cell).
    pub order: u32,
    /// Highest band of the zonal tail about the sun's beam: 0 for none, or
    /// `order + 1` to 31 (`zonal − order` more coefficients per cell; see
    /// the module docs).
    pub zonal: u32,
    /// Scattering events traced for the light of the sky and of the
    /// scene's ground, solids and glow in the medium: 0 for none (the
    /// surfaces' and glow's light is then left out, the sky's and ground's
    /// share of the environment come by the ambient term and the octaves), or
    /// `10⁴` to `10⁹` (see [`local`](super::local)).
    pub local: u32,
    /// Seed of the photons' random streams.
    pub seed: u64,
}

impl Default for CacheParams {
    /// 64 cells along the longest axis, four million events, bands up to
    /// [`ORDER_DEFAULT`] with a zonal tail about the sun's beam to band 23,
    /// a million events for the light of the scene's surfaces and glow.
    ///
    /// The zonal tail: over the 126 scenes of the fast mode's comparison
    /// with the reference (balls, slabs and a voxel blob, seven phase
    /// functions, three suns, a black and a blue sky), bands up to 7 alone
    /// leave thin forward-scattering media seen across the sun's beam a few
    /// per cent too bright (a cloud-phase slab of optical thickness 1: +6 %
    /// against +1 % with the tail), for 16 more numbers a cell (80 in all).
    fn default() -> Self {
        Self {
            cells: 64,
            events: 4_000_000,
            order: ORDER_DEFAULT,
            zonal: 23,
            local: 1_000_000,
            seed: 0x5ca7,
        }
    }
}

impl CacheParams {
    /// Checks the fields.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] naming `cache.cells` outside
    /// `4..=1024`, `cache.order` outside `1..=7`, `cache.zonal` neither 0
    /// nor in `order + 1 ..= 31`, `cache.events` outside `10⁴ ..= 10⁹`, or
    /// `cache.local` neither 0 nor in `10⁴ ..= 10⁹`.
    pub fn validate(&self) -> Result<()> {
        if !(4..=1024).contains(&self.cells) {
            return Err(VolumeError::InvalidParameter {
                name: "cache.cells",
                value: self.cells.to_string(),
                expected: "4 to 1024 cells along the longest axis",
            });
        }
        if !(1..=MAX_ORDER as u32).contains(&self.order) {
            return Err(VolumeError::InvalidParameter {
                name: "cache.order",
                value: self.order.to_string(),
                expected: "a spherical-harmonic band of 1 to 7",
            });
        }
        if self.zonal != 0 && !(self.order + 1..=MAX_ZONAL as u32).contains(&self.zonal) {
            return Err(VolumeError::InvalidParameter {
                name: "cache.zonal",
                value: self.zonal.to_string(),
                expected: "0, or a band above cache.order and at most 31",
            });
        }
        if !(10_000..=1_000_000_000).contains(&self.events) {
            return Err(VolumeError::InvalidParameter {
                name: "cache.events",
                value: self.events.to_string(),
                expected: "10000 to 1000000000 scattering events",
            });
        }
        if self.local != 0 && !(10_000..=1_000_000_000).contains(&self.local) {
            return Err(VolumeError::InvalidParameter {
                name: "cache.local",
                value: self.local.to_string(),
                expected: "0, or 10000 to 1000000000 scattering events",
            });
        }
        Ok(())
    }
}

/// The multiple-scattering cache of one scene (see the module docs).
#[derive(Clone, Debug)]
pub struct ScatterCache {
    /// The cells and the medium's extinction in each.
    grid: CellGrid,
    /// The highest band of the full series.
    order: usize,
    /// The highest band of the zonal tail (`order` when there is none).
    zonal: usize,
    /// The zonal tail's axis: the sun's beam, the direction its light travels.
    axis: Vec3,
    /// Coefficients per cell, `(order + 1)² + zonal − order`.
    n: usize,
    /// Per cell: the radiance's coefficients `∫ L Y_lm dω` per unit
    /// irradiance, then the zonal tail's `∫ L Y_l0 dω` about `axis`.
    coeffs: Vec<f32>,
    /// Per band, the phase function's Legendre moment times its σ-factor.
    band: [f32; MAX_ZONAL + 1],
    /// `1 − ωg`: the transport coefficient per unit extinction.
    transport: f32,
}

/// The factors `χ_l·Y_lm(ω_o)` of one eye direction (the light scattered
/// toward the eye is their dot product with a cell's coefficients), and the
/// last eight cells' dot products along the eye ray.
#[derive(Clone, Debug)]
pub struct EyeBasis {
    factors: [f32; MAX_CELL],
    memo: std::cell::Cell<Option<Memo>>,
}

/// What an eye ray keeps of the eight cells round its last sample: their
/// dot products with its factors, each cell's relative fluence gradient
/// and its centre.
#[derive(Clone, Copy, Debug)]
struct Memo {
    key: usize,
    dots: [f32; 8],
    gradient: [Vec3; 8],
    centre: [Vec3; 8],
}

impl ScatterCache {
    /// Traces the sun's light (unit direction `sun` toward it) through
    /// `density` with the transport `medium`.
    ///
    /// # Errors
    ///
    /// As [`CacheParams::validate`]; [`VolumeError::InvalidParameter`]
    /// naming `cache.cells` when the grid would pass 2²⁶ cells.
    pub fn new(
        density: &dyn Density,
        medium: &MediumParams,
        sun: Vec3,
        params: &CacheParams,
    ) -> Result<Self> {
        params.validate()?;
        let grid = CellGrid::new(density, medium.extinction, params.cells)?;
        Ok(Self::on_grid(grid, medium, sun, params))
    }

    /// The cache on `grid` (the transport medium's extinction per cell);
    /// `params` already checked.
    pub(crate) fn on_grid(
        grid: CellGrid,
        medium: &MediumParams,
        sun: Vec3,
        params: &CacheParams,
    ) -> Self {
        let count = grid.count();
        let order = params.order as usize;
        let zonal = (params.zonal as usize).max(order);
        let per = (order + 1) * (order + 1) + zonal - order;
        let mut cache = Self {
            grid,
            order,
            zonal,
            axis: -sun,
            n: per,
            coeffs: vec![0.0; count * per],
            band: [0.0; MAX_ZONAL + 1],
            transport: 1.0 - medium.albedo * medium.phase.mean_cosine(),
        };
        // The series is cut after its highest band, the tail's if any.
        let chi = legendre_moments(&medium.phase);
        for (l, b) in cache.band.iter_mut().enumerate().take(zonal + 1) {
            *b = chi[l] * sigma_factor(l, zonal);
        }
        if medium.albedo > 0.0 && cache.grid.sigma.iter().any(|&s| s > 0.0) {
            cache.trace(medium, sun, params);
        }
        cache
    }

    /// The grid's cells per axis.
    #[must_use]
    pub fn dims(&self) -> [usize; 3] {
        self.grid.dims
    }

    /// The grid's bounds.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.grid.bounds()
    }

    /// The factors of an eye looking along unit `d` (the light it sees
    /// travels along `−d`).
    #[must_use]
    pub fn eye_basis(&self, d: Vec3) -> EyeBasis {
        let mut y = [0.0f32; MAX_CELL];
        self.basis(-d, &mut y);
        for l in 0..=self.order {
            for v in &mut y[l * l..(l + 1) * (l + 1)] {
                *v *= self.band[l];
            }
        }
        let full = (self.order + 1) * (self.order + 1);
        for l in self.order + 1..=self.zonal {
            y[full + l - self.order - 1] *= self.band[l];
        }
        EyeBasis {
            factors: y,
            memo: std::cell::Cell::new(None),
        }
    }

    /// The stored basis at unit `d`: the full series, then the zonal tail.
    fn basis(&self, d: Vec3, out: &mut [f32; MAX_CELL]) {
        let mut y = [0.0f32; MAX_COEFFS];
        sh_basis(self.order, d, &mut y);
        let full = (self.order + 1) * (self.order + 1);
        out[..full].copy_from_slice(&y[..full]);
        zonal_basis(self.order, self.zonal, d.dot(self.axis), &mut out[full..]);
    }

    /// `f` of the coefficients of each of the eight cells round `p`, and
    /// the trilinear weights.
    #[inline]
    fn corner_values(&self, cells: &[usize; 8], f: impl Fn(&[f32]) -> f32) -> [f32; 8] {
        let mut v = [0.0f32; 8];
        for (out, &c) in v.iter_mut().zip(cells) {
            let at = c * self.n;
            *out = f(&self.coeffs[at..at + self.n]);
        }
        v
    }

    /// The fluence's relative gradient in cell `c` by Fick's law of the
    /// diffusion approximation, `∇φ/φ = −3σ_tr F/φ` with `σ_tr = σ_t(1 − ωg)`
    /// and the net flux `F` from band 1: `−√3·σ_tr·(c₁₁, c₁₋₁, c₁₀)/c₀₀`.
    fn log_gradient(&self, c: usize) -> Vec3 {
        let k = &self.coeffs[c * self.n..];
        if self.n < 4 || k[0] <= 0.0 {
            return Vec3::ZERO;
        }
        let s = self.grid.sigma[c] * self.transport;
        Vec3::new(k[3], k[1], k[2]) * (-3f32.sqrt() * s / k[0])
    }

    /// The light scattered more than once toward the eye at `p`, per unit
    /// irradiance and scattering coefficient (1/sr), for the eye's `basis`:
    /// `max(Σ χ_l c_lm Y_lm(ω_o), 0)`, each cell's value carried to `p` by
    /// its fluence gradient (see the module docs) and blended trilinearly
    /// between cell centres. The
    /// eight cells' dot products are kept in `basis` while an eye ray's
    /// samples stay among the same cells (most of its steps are far
    /// shorter than a cell).
    #[inline]
    #[must_use]
    pub fn toward_eye(&self, p: Vec3, basis: &EyeBasis) -> f32 {
        let (i, j, w) = self.grid.corners(p);
        let key = self.grid.index(i[0], i[1], i[2]);
        let m = match basis.memo.get() {
            Some(m) if m.key == key => m,
            _ => {
                let cells = self.grid.corner_cells(i, j);
                let g = cells.map(|c| self.log_gradient(c));
                // The cells' centres, corner by corner (x fastest).
                let (lo, hi) = (self.grid.centre(i), self.grid.centre(j));
                let mut centre = [Vec3::ZERO; 8];
                for (c, x) in centre.iter_mut().enumerate() {
                    *x = Vec3::new(
                        if c & 1 == 0 { lo.x } else { hi.x },
                        if c & 2 == 0 { lo.y } else { hi.y },
                        if c & 4 == 0 { lo.z } else { hi.z },
                    );
                }
                let m = Memo {
                    key,
                    dots: self.corner_values(&cells, |c| dot(c, &basis.factors)),
                    gradient: g,
                    centre,
                };
                basis.memo.set(Some(m));
                m
            }
        };
        // Each cell's light carried to `p` by its own gradient, `1 + ∇φ/φ·(p − x_c)`
        // (kept within [0, 3]), then blended as before.
        let v: [f32; 8] = std::array::from_fn(|c| {
            m.dots[c] * (1.0 + m.gradient[c].dot(p - m.centre[c])).clamp(0.0, 3.0)
        });
        CellGrid::blend(&v, w).max(0.0)
    }

    /// The same light's mean over every direction, `φ/(4π) = c₀₀·Y₀₀`.
    #[inline]
    #[must_use]
    pub fn mean(&self, p: Vec3) -> f32 {
        let (i, j, w) = self.grid.corners(p);
        let v = self.corner_values(&self.grid.corner_cells(i, j), |c| c[0]);
        CellGrid::blend(&v, w) * 0.282_094_8
    }

    /// Traces the photons and sets the moments (per unit irradiance).
    fn trace(&mut self, medium: &MediumParams, sun: Vec3, params: &CacheParams) {
        let beam = -sun;
        let (u, v) = sun.any_orthonormal_pair();
        let b = self.bounds();
        let centre = 0.5 * (b.min + b.max);
        let radius = 0.5 * (b.max - b.min).length();
        let (mut lo, mut hi) = (
            glam::Vec2::splat(f32::INFINITY),
            glam::Vec2::splat(f32::NEG_INFINITY),
        );
        for k in 0..8 {
            let c = Vec3::new(
                if k & 1 == 0 { b.min.x } else { b.max.x },
                if k & 2 == 0 { b.min.y } else { b.max.y },
                if k & 4 == 0 { b.min.z } else { b.max.z },
            ) - centre;
            let q = glam::Vec2::new(c.dot(u), c.dot(v));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let area = (hi.x - lo.x) * (hi.y - lo.y);
        let per_chunk = (u64::from(params.events) / CHUNKS as u64).max(1);
        let run = |k: usize| -> (Vec<f32>, u64) {
            let mut grid = vec![0.0f32; self.coeffs.len()];
            let per = self.n;
            let mut rng = Seed(params.seed).derive_index(k as u64).rng();
            let (mut photons, mut events) = (0u64, 0u64);
            let mut line = Vec::with_capacity(4 * self.grid.dims.iter().sum::<usize>());
            let mut starts = Vec::new();
            // Every photon of a batch is traced, so that the photons cover
            // the plane uniformly: a batch cut short would leave out the
            // end of its curve, a part of the plane.
            while events < per_chunk || !starts.is_empty() {
                if starts.is_empty() {
                    // As many as the events left take at the rate so far.
                    let left = (per_chunk - events) as f64;
                    let n = if photons == 0 {
                        MIN_BATCH
                    } else {
                        (left * photons as f64 / events as f64).ceil() as usize
                    };
                    starts = start_batch(&mut rng, n.clamp(MIN_BATCH, MAX_BATCH));
                }
                let a = lo + (hi - lo) * starts.pop().unwrap_or_default();
                photons += 1;
                let o = centre + sun * (radius * 2.0) + u * a.x + v * a.y;
                let tau = self.grid.line(o, beam, OPAQUE, &mut line);
                if tau <= 0.0 {
                    events += 1;
                    continue;
                }
                let p_hit = -(-tau).exp_m1();
                let target = -(-unit(&mut rng) * p_hit).ln_1p();
                let Flight::Collided(mut x) = self.grid.fly_line(o, beam, target.min(tau), &line)
                else {
                    events += 1;
                    continue;
                };
                let w0 = p_hit * medium.albedo;
                let (mut w, mut d) = (w0, beam);
                for _ in 0..MAX_EVENTS_PER_PHOTON {
                    events += 1;
                    d = medium.phase.sample(d, &mut || unit(&mut rng));
                    let mut y = [0.0f32; MAX_CELL];
                    self.basis(d, &mut y);
                    let target = -(1.0 - unit(&mut rng)).ln();
                    let flight = self.grid.fly(x, d, target, f32::INFINITY, |c, len| {
                        let s = w * len;
                        for (g, b) in grid[c * per..(c + 1) * per].iter_mut().zip(&y) {
                            *g += s * b;
                        }
                    });
                    match flight {
                        Flight::Left => break,
                        Flight::Collided(y) => x = y,
                    }
                    w *= medium.albedo;
                    if w < 0.1 * w0 {
                        if unit(&mut rng) < 0.5 {
                            w *= 2.0;
                        } else {
                            break;
                        }
                    }
                }
            }
            (grid, photons)
        };
        #[cfg(feature = "parallel")]
        let chunks: Vec<(Vec<f32>, u64)> = {
            use rayon::prelude::*;
            (0..CHUNKS).into_par_iter().map(run).collect()
        };
        #[cfg(not(feature = "parallel"))]
        let chunks: Vec<(Vec<f32>, u64)> = (0..CHUNKS).map(run).collect();
        let volume = self.grid.cell_volume();
        for (grid, photons) in &chunks {
            // Each chunk's photons stand for the whole beam: area·E over its count.
            let s = area / (*photons as f32 * CHUNKS as f32 * volume);
            for (m, g) in self.coeffs.iter_mut().zip(grid) {
                *m += g * s;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::density::Homogeneous;
    use crate::phase::CloudPhase;

    /// A homogeneous slab 12 m wide, `2·half` thick (unit density), and an
    /// isotropic medium of extinction 1 /m and `albedo`.
    fn isotropic_slab(half: f32, albedo: f32) -> (Homogeneous, MediumParams) {
        let region = Aabb {
            min: Vec3::new(-6.0, -6.0, -half),
            max: Vec3::new(6.0, 6.0, half),
        };
        let medium = MediumParams {
            extinction: 1.0,
            albedo,
            phase: CloudPhase::Isotropic,
        };
        (Homogeneous::new(region, 1.0).unwrap(), medium)
    }

    #[test]
    fn a_line_walked_to_the_opaque_depth_gives_the_whole_lines_collision() {
        // Lines through a ball of optical diameter 60 and past its edge: the
        // chance of a collision, and the collision of every forced depth
        // (the largest `unit` gives included), are the same bits whether the
        // line is walked to its end or only until its depth reaches OPAQUE.
        let ball = crate::density::Ball::new(Vec3::ZERO, 3.0, 1.0).unwrap();
        let grid = CellGrid::new(&ball, 10.0, 32).unwrap();
        let mut rng = Seed(5).rng();
        let (mut full, mut cut) = (Vec::new(), Vec::new());
        let mut shortened = 0;
        for _ in 0..2000 {
            let d = Vec3::new(unit(&mut rng) - 0.5, unit(&mut rng) - 0.5, 1.0).normalize();
            let (a, b) = d.any_orthonormal_pair();
            let o = (a * (unit(&mut rng) - 0.5) + b * (unit(&mut rng) - 0.5)) * 7.0 - d * 10.0;
            let tau = grid.line(o, d, f32::INFINITY, &mut full);
            let tau_cut = grid.line(o, d, OPAQUE, &mut cut);
            if cut.len() < full.len() {
                shortened += 1;
            }
            let p_hit = -(-tau).exp_m1();
            assert_eq!(p_hit.to_bits(), (-(-tau_cut).exp_m1()).to_bits());
            for u in [unit(&mut rng), 1.0 - 1.0 / (1u32 << 24) as f32] {
                let target = -(-u * p_hit).ln_1p();
                let at = |line: &[(usize, f32, f32)], tau: f32| match grid.fly_line(
                    o,
                    d,
                    target.min(tau),
                    line,
                ) {
                    Flight::Collided(x) => Some(x.to_array().map(f32::to_bits)),
                    Flight::Left => None,
                };
                assert_eq!(at(&full, tau), at(&cut, tau_cut));
            }
        }
        assert!(shortened > 500, "{shortened}");
    }

    #[test]
    fn deep_in_a_thick_slab_the_cells_gradient_is_the_diffusion_decay() {
        // A slab of optical thickness 20, isotropic, albedo 0.8, lit from
        // straight above: a few mean free paths below its lit face the
        // fluence decays as e^{−ντ}, ν = 0.71 (the transport equation's
        // asymptotic mode, `ω·artanh(ν)/ν = 1`; diffusion's own estimate is
        // √(3(1 − ω)) = 0.775), so Fick's law read from band 1 must give the
        // cells there a relative gradient pointing up, toward the light, of
        // about ν per metre; carried by it, the light falls with depth.
        let (d, medium) = isotropic_slab(10.0, 0.8);
        let params = CacheParams {
            cells: 40,
            events: 4_000_000,
            order: 1,
            zonal: 0,
            ..CacheParams::default()
        };
        let c = ScatterCache::new(&d, &medium, Vec3::Z, &params).unwrap();
        let nu = 0.71f32;
        // Four to six mean free paths below the lit face (z = 10), the mean
        // over the nine cells round the axis.
        for z in [6.0f32, 5.0, 4.0] {
            let mut g = Vec3::ZERO;
            for (dx, dy) in (-1..=1).flat_map(|a| (-1..=1).map(move |b| (a, b))) {
                let p = Vec3::new(dx as f32 * 0.5, dy as f32 * 0.5, z);
                let (i, _, _) = c.grid.corners(p);
                g += c.log_gradient(c.grid.index(i[0], i[1], i[2])) / 9.0;
            }
            assert!(
                g.x.abs() < 0.25 * nu && g.y.abs() < 0.25 * nu,
                "at z {z}: {g}"
            );
            assert!((g.z - nu).abs() < 0.25 * nu, "at z {z}: {g} against ν {nu}");
        }
        let basis = c.eye_basis(-Vec3::Z);
        let at = |z: f32| c.toward_eye(Vec3::new(0.1, 0.1, z), &basis);
        assert!(
            at(4.2) < at(4.8) && at(4.8) < at(5.4),
            "{} {} {}",
            at(4.2),
            at(4.8),
            at(5.4)
        );
    }

    #[test]
    fn an_isotropic_cache_holds_the_slab_fluence() {
        // A thin homogeneous slab lit from straight above, isotropic,
        // conservative: at its middle, the fluence of once-scattered light is
        // `(ω/2)·∫ E₁(|τ − τ'|) dτ'` over the slab (ω = 1), about 0.358 at
        // optical thickness 0.3 (within the extent's edge effects, the
        // slab is 40 times wider than thick).
        let (d, medium) = isotropic_slab(0.15, 1.0);
        let params = CacheParams {
            cells: 80,
            events: 2_000_000,
            order: 1,
            ..CacheParams::default()
        };
        let c = ScatterCache::new(&d, &medium, Vec3::Z, &params).unwrap();
        let phi = c.mean(Vec3::ZERO) * 4.0 * std::f32::consts::PI;
        // Second and higher orders add about 0.358² · … ≈ 0.1 more.
        assert!(phi > 0.36 && phi < 0.55, "fluence {phi}");
        // The same on any number of threads, and for a fixed seed.
        let again = ScatterCache::new(&d, &medium, Vec3::Z, &params).unwrap();
        assert_eq!(c.coeffs, again.coeffs);
    }

    #[test]
    fn a_zonal_tail_holds_the_bands_of_light_symmetric_about_the_beam() {
        // A wide thin slab lit from straight above scatters light that is
        // symmetric about the vertical beam at its middle: there the zonal
        // tail of bands 4..=7 must give what the full series to band 7 gives
        // (the same photons: the seed fixes them, the order only how they
        // are scored), and the series cut after band 3 must not.
        let region = Aabb {
            min: Vec3::new(-6.0, -6.0, -0.25),
            max: Vec3::new(6.0, 6.0, 0.25),
        };
        let d = crate::density::Homogeneous::new(region, 1.0).unwrap();
        let medium = MediumParams {
            extinction: 2.0,
            albedo: 0.99,
            phase: CloudPhase::HenyeyGreenstein(0.8),
        };
        let cache = |order: u32, zonal: u32| {
            let params = CacheParams {
                cells: 8,
                events: 2_000_000,
                order,
                zonal,
                ..CacheParams::default()
            };
            ScatterCache::new(&d, &medium, Vec3::Z, &params).unwrap()
        };
        let (full, tail, cut) = (cache(7, 0), cache(3, 7), cache(3, 0));
        let (mut worst_tail, mut worst_cut) = (0.0f32, 0.0f32);
        for k in 0..=12 {
            // Eye directions from straight down (the light it sees travels
            // up, against the beam) to straight up (into the beam's peak).
            let theta = std::f32::consts::PI * k as f32 / 12.0;
            let eye = Vec3::new(theta.sin(), 0.0, -theta.cos());
            let at = |c: &ScatterCache| c.toward_eye(Vec3::ZERO, &c.eye_basis(eye));
            let want = at(&full);
            assert!(want > 0.0, "{k}: {want}");
            worst_tail = worst_tail.max((at(&tail) - want).abs() / want);
            worst_cut = worst_cut.max((at(&cut) - want).abs() / want);
        }
        // The tail's difference is the cache's noise in the bands' parts
        // that are not symmetric (1.7 % at most here).
        assert!(worst_tail < 0.025, "tail {worst_tail}");
        assert!(worst_cut > 0.1, "cut {worst_cut}");
    }

    #[test]
    fn bad_settings_name_their_key() {
        for (p, key) in [
            (
                CacheParams {
                    cells: 2,
                    ..CacheParams::default()
                },
                "cache.cells",
            ),
            (
                CacheParams {
                    order: 0,
                    ..CacheParams::default()
                },
                "cache.order",
            ),
            (
                CacheParams {
                    order: 9,
                    ..CacheParams::default()
                },
                "cache.order",
            ),
            (
                CacheParams {
                    events: 10,
                    ..CacheParams::default()
                },
                "cache.events",
            ),
            (
                CacheParams {
                    order: 7,
                    zonal: 5,
                    ..CacheParams::default()
                },
                "cache.zonal",
            ),
            (
                CacheParams {
                    order: 3,
                    zonal: 32,
                    ..CacheParams::default()
                },
                "cache.zonal",
            ),
            (
                CacheParams {
                    local: 5,
                    ..CacheParams::default()
                },
                "cache.local",
            ),
        ] {
            let e = p.validate().unwrap_err().to_string();
            assert!(e.contains(key), "{e}");
        }
    }
}
