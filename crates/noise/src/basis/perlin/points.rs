//! Batch evaluation of 3-D Perlin noise and its band-limited fBm at
//! arbitrary points (struct-of-arrays), for renderers whose samples do not
//! lie on rows: the hit points of a sphere seen from orbit, a cube face of a
//! planet.
//!
//! Each point is split into its lattice index (exact, in `f64`) and an `f32`
//! fraction, then hashed and blended in `f32`/`u32` lanes compiled for the
//! [`Simd`] level asked for; the lattice and gradients are the point path's,
//! so values equal [`Field::eval3`] within 1e-5 and are bit-identical at
//! every level. Points outside the fast-split range (non-finite or beyond
//! 10¹⁵) take the `f64` point path.

use glam::DVec3;
use natura_simd::multiversion;

use super::Perlin;
use crate::basis::Fade;
use crate::error::{NoiseError, Result};
use crate::field::Field;
use crate::fractal::fbm::Fbm;
use crate::hash::{corner, grad3, row3};
use crate::lattice_math::{Simd, cubic32, quintic32, split_fast};

/// Points per chunk of the batch fBm (stack scratch buffers, no allocation).
const CHUNK: usize = 256;

/// Largest coordinate magnitude the lane kernel takes (the branch-free split
/// is exact far beyond it).
const FAST_LIMIT: f64 = 1.0e15;

fn check_lengths(x: &[f64], y: &[f64], z: &[f64], n: usize) -> Result<()> {
    for len in [x.len(), y.len(), z.len()] {
        if len != n {
            return Err(NoiseError::BufferLength {
                expected: n,
                got: len,
            });
        }
    }
    Ok(())
}

fn in_fast_range(v: &[f64]) -> bool {
    v.iter().all(|c| c.abs() <= FAST_LIMIT)
}

impl Perlin {
    /// Fills `out[i]` with the 3-D noise at `(x[i], y[i], z[i])`, at the
    /// best SIMD level.
    ///
    /// # Errors
    /// [`NoiseError::BufferLength`] if a coordinate slice is not as long as `out`.
    pub fn fill_points3(&self, x: &[f64], y: &[f64], z: &[f64], out: &mut [f32]) -> Result<()> {
        self.fill_points3_with(Simd::best(), x, y, z, out)
    }

    /// [`fill_points3`](Self::fill_points3) at the level `simd`.
    ///
    /// # Errors
    /// [`NoiseError::BufferLength`] if a coordinate slice is not as long as `out`.
    pub fn fill_points3_with(
        &self,
        simd: Simd,
        x: &[f64],
        y: &[f64],
        z: &[f64],
        out: &mut [f32],
    ) -> Result<()> {
        check_lengths(x, y, z, out.len())?;
        for (c, o) in out.chunks_mut(CHUNK).enumerate() {
            let r = c * CHUNK..c * CHUNK + o.len();
            self.points_chunk(simd, &x[r.clone()], &y[r.clone()], &z[r], o);
        }
        Ok(())
    }

    /// One chunk: the lane kernel if every coordinate is in range, else the
    /// point path.
    fn points_chunk(&self, simd: Simd, x: &[f64], y: &[f64], z: &[f64], out: &mut [f32]) {
        if in_fast_range(x) && in_fast_range(y) && in_fast_range(z) {
            let cubic = self.fade() == Fade::Cubic;
            points_kernel(simd, self.s, cubic, self.scale(3) as f32, x, y, z, out);
        } else {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval3(DVec3::new(x[i], y[i], z[i])) as f32;
            }
        }
    }
}

multiversion! {
    /// The lane kernel: every point hashes its own eight corners.
    #[allow(clippy::too_many_arguments)]
    fn points_kernel<'a>(
        simd: Simd,
        seed: u32,
        cubic: bool,
        scale: f32,
        x: &'a [f64],
        y: &'a [f64],
        z: &'a [f64],
        out: &'a mut [f32],
    ) {
        if cubic {
            points_loop(cubic32, seed, scale, x, y, z, out);
        } else {
            points_loop(quintic32, seed, scale, x, y, z, out);
        }
    }
}

#[inline(always)]
fn points_loop(
    fade: impl Fn(f32) -> f32,
    seed: u32,
    scale: f32,
    x: &[f64],
    y: &[f64],
    z: &[f64],
    out: &mut [f32],
) {
    for (((o, &px), &py), &pz) in out.iter_mut().zip(x).zip(y).zip(z) {
        let (ix, fx) = split_fast(px);
        let (iy, fy) = split_fast(py);
        let (iz, fz) = split_fast(pz);
        let (fx, fy, fz) = (fx as f32, fy as f32, fz as f32);
        // The row hashes of `hash::row3`: spread indices, xored.
        let (iy1, iz1) = (iy.wrapping_add(1), iz.wrapping_add(1));
        let rows = [
            row3(iy, iz, seed),
            row3(iy1, iz, seed),
            row3(iy, iz1, seed),
            row3(iy1, iz1, seed),
        ];
        let dy = [fy, fy - 1.0, fy, fy - 1.0];
        let dz = [fz, fz, fz - 1.0, fz - 1.0];
        let ix1 = ix.wrapping_add(1);
        let fx1 = fx - 1.0;
        let u = fade(fx);
        let mut plane = [0.0f32; 4];
        for c in 0..4 {
            let (ax, ay, az) = grad3(corner(ix, rows[c]));
            let (bx, by, bz) = grad3(corner(ix1, rows[c]));
            let n0 = ax * fx + ay * dy[c] + az * dz[c];
            let n1 = bx * fx1 + by * dy[c] + bz * dz[c];
            plane[c] = n0 + u * (n1 - n0);
        }
        let v = fade(fy);
        let w = fade(fz);
        let a = plane[0] + v * (plane[1] - plane[0]);
        let b = plane[2] + v * (plane[3] - plane[2]);
        *o = (a + w * (b - a)) * scale;
    }
}

multiversion! {
    /// Adds octave `kf`'s values `n` (amplitude `amp`) to `acc`, each point
    /// weighted by how much of the octave it sees (`visible` octaves, at most
    /// `total`).
    fn band_accumulate<'a>(
        simd: Simd,
        acc: &'a mut [f32],
        n: &'a [f32],
        visible: &'a [f32],
        amp: f32,
        kf: f32,
        total: f32,
    ) {
        for ((a, &n), &v) in acc.iter_mut().zip(n).zip(visible) {
            let lim = if v < total { v } else { total };
            let t = (lim - kf).clamp(0.0, 1.0);
            *a += amp * t * n;
        }
    }
}

impl Fbm<Perlin> {
    /// Fills `out[i]` with [`Fbm::eval3_band`] at `(x[i], y[i], z[i])` over
    /// `visible[i]` octaves, at the level `simd`: each octave is one batch
    /// noise pass over a chunk, skipped once no point of the chunk sees it.
    ///
    /// # Errors
    /// [`NoiseError::BufferLength`] if a slice is not as long as `out`.
    pub fn fill_points3_band_with(
        &self,
        simd: Simd,
        x: &[f64],
        y: &[f64],
        z: &[f64],
        visible: &[f32],
        out: &mut [f32],
    ) -> Result<()> {
        check_lengths(x, y, z, out.len())?;
        if visible.len() != out.len() {
            return Err(NoiseError::BufferLength {
                expected: out.len(),
                got: visible.len(),
            });
        }
        let o = self.octaves();
        let total = o.total() as f32;
        let mut sx = [0.0f64; CHUNK];
        let mut sy = [0.0f64; CHUNK];
        let mut sz = [0.0f64; CHUNK];
        let mut tmp = [0.0f32; CHUNK];
        for (c, acc) in out.chunks_mut(CHUNK).enumerate() {
            let m = acc.len();
            let r = c * CHUNK..c * CHUNK + m;
            let vis = &visible[r.clone()];
            let top = vis
                .iter()
                .fold(0.0f32, |a, &v| if v > a || v.is_nan() { v } else { a });
            acc.fill(0.0);
            for k in 0..o.band_count(f64::from(top)) {
                let f = o.frequency(k);
                for i in 0..m {
                    sx[i] = x[r.start + i] * f;
                    sy[i] = y[r.start + i] * f;
                    sz[i] = z[r.start + i] * f;
                }
                self.basis()
                    .points_chunk(simd, &sx[..m], &sy[..m], &sz[..m], &mut tmp[..m]);
                let amp = o.amplitude(k) as f32;
                let kf = k as f32;
                band_accumulate(simd, acc, &tmp[..m], vis, amp, kf, total);
            }
        }
        Ok(())
    }

    /// [`fill_points3_band_with`](Self::fill_points3_band_with) at the best level.
    ///
    /// # Errors
    /// [`NoiseError::BufferLength`] if a slice is not as long as `out`.
    pub fn fill_points3_band(
        &self,
        x: &[f64],
        y: &[f64],
        z: &[f64],
        visible: &[f32],
        out: &mut [f32],
    ) -> Result<()> {
        self.fill_points3_band_with(Simd::best(), x, y, z, visible, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Spectral;
    use std::vec;
    use std::vec::Vec;

    fn points(n: usize, r: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut s = 0x1234_5678_9ABC_DEF0u64;
        let mut next = || {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * r
        };
        let x: Vec<f64> = (0..n).map(|_| next()).collect();
        let y: Vec<f64> = (0..n).map(|_| next()).collect();
        let z: Vec<f64> = (0..n).map(|_| next()).collect();
        (x, y, z)
    }

    #[test]
    fn points_match_point_path_at_every_level() {
        for fade in [Fade::Quintic, Fade::Cubic] {
            let p = Perlin::with_fade(9, fade);
            for r in [3.0, 1e3, 6.4e8] {
                let (x, y, z) = points(700, r);
                let mut first: Option<Vec<f32>> = None;
                for simd in Simd::supported() {
                    let mut out = vec![0.0f32; 700];
                    p.fill_points3_with(simd, &x, &y, &z, &mut out).unwrap();
                    for i in 0..700 {
                        let e = p.eval3(DVec3::new(x[i], y[i], z[i]));
                        assert!(
                            (f64::from(out[i]) - e).abs() < 1e-5,
                            "{r} {i}: {} {e}",
                            out[i]
                        );
                    }
                    match &first {
                        None => first = Some(out),
                        Some(f) => assert_eq!(f, &out, "{simd:?}"),
                    }
                }
            }
        }
    }

    #[test]
    fn out_of_range_points_take_the_point_path() {
        let p = Perlin::new(2);
        let x = [1e17, f64::NAN, 0.5];
        let y = [0.25, 0.3, f64::INFINITY];
        let z = [0.1; 3];
        let mut out = [0.0f32; 3];
        p.fill_points3(&x, &y, &z, &mut out).unwrap();
        assert_eq!(out[0], p.eval3(DVec3::new(1e17, 0.25, 0.1)) as f32);
        assert!(out[1].is_nan() && out[2].is_nan());
        assert!(p.fill_points3(&x[..2], &y, &z, &mut out).is_err());
    }

    #[test]
    fn band_fbm_matches_point_path() {
        let f = Fbm::new(
            Perlin::new(4),
            Spectral::default()
                .with_lacunarity(2.0)
                .with_octaves(9.5)
                .with_h(0.5),
        )
        .unwrap();
        let (x, y, z) = points(600, 2.0);
        let visible: Vec<f32> = (0..600).map(|i| (i % 23) as f32 * 0.5).collect();
        let mut first: Option<Vec<f32>> = None;
        for simd in Simd::supported() {
            let mut out = vec![0.0f32; 600];
            f.fill_points3_band_with(simd, &x, &y, &z, &visible, &mut out)
                .unwrap();
            for i in 0..600 {
                let e = f.eval3_band(DVec3::new(x[i], y[i], z[i]), f64::from(visible[i]));
                assert!((f64::from(out[i]) - e).abs() < 1e-5 * f.bound(), "{i}");
            }
            match &first {
                None => first = Some(out),
                Some(v) => assert_eq!(v, &out),
            }
        }
        let mut out = vec![0.0f32; 600];
        assert!(
            f.fill_points3_band(&x, &y, &z, &visible[..5], &mut out)
                .is_err()
        );
    }
}
