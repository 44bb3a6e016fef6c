//! The cache's photons: the sun's beam traced through the cells (see the
//! parent module's "How it is traced").

use glam::Vec3;
use natura_core::Seed;

use super::super::MediumParams;
use super::super::cells::{Flight, written_zeros};
use super::super::harmonics::MAX_CELL;
use super::{CacheParams, ScatterCache};
use crate::animate::unit;

/// Photon chunks (each its own random stream and grid; summed in order).
const CHUNKS: usize = 4;
/// Most scattering events one photon is followed through.
const MAX_EVENTS_PER_PHOTON: u32 = 1 << 20;

/// An optical depth past which a line's chance of a collision,
/// `1 − e^{−τ}`, is 1 in `f32` (it is from `τ ≈ 17.4`), and past which no
/// forced collision's depth `−ln(1 − u)` reaches (`u < 1 − 2⁻²⁴` gives
/// under 16.7): a sun photon's line is walked only this deep, with the same
/// weight and the same collision as the whole line's.
pub(super) const OPAQUE: f32 = 24.0;

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

impl ScatterCache {
    /// Traces the photons and sets the moments (per unit irradiance).
    pub(super) fn trace(&mut self, medium: &MediumParams, sun: Vec3, params: &CacheParams) {
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
            let mut grid = written_zeros(self.coeffs.len(), 0.0f32);
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
