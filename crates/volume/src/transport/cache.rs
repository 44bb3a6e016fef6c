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
//! and an axis gets as many as two cells per mean free path of the
//! medium's mean extinction take, up to the longest axis's count.
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
//! `crates/volume/tests/it/scatter_matrix.rs`; the figures are in
//! `docs/performance.md`.

use glam::Vec3;
use natura_core::Aabb;

use super::MediumParams;
use super::cells::{CellGrid, written_zeros};
use super::harmonics::{MAX_CELL, dot, zonal_basis};
pub use super::harmonics::{
    MAX_COEFFS, MAX_ORDER, MAX_ZONAL, legendre_moments, sh_basis, sigma_factor,
};
use crate::density::Density;
use crate::error::{Result, VolumeError};

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
            coeffs: written_zeros(count * per, 0.0),
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
}

mod trace;

#[cfg(test)]
mod tests;
