//! Curl noise: the curl of a noise vector potential, a divergence-free
//! vector field for distortion that streaks without clumping (Bridson et
//! al. 2007, §2 "Curl noise", and §3 for the potential built from noise).
//!
//! A displacement `δ(p)` that is the gradient of a potential (Perlin's
//! [`DNoise`](crate::DNoise)) flows toward the potential's maxima: it
//! squeezes the distorted field into knots at some places and thins it out
//! at others. The curl `∇ × ψ` of a vector potential `ψ` has no divergence
//! (`∇·(∇ × ψ) = 0`), so as a velocity it neither gathers nor spreads:
//! it stirs, the way a turbulent flow does. Bridson et al. build `ψ` from
//! three independent noises; here its three components are one Perlin
//! noise at three misregistered points (the offsets of [`CURL_OFFSETS`], in
//! the manner of Musgrave's `VecNoise`, Musgrave 1998, "A Variety of fBm"):
//!
//! ```text
//! ψ(p) = (N(p + o₁), N(p + o₂), N(p + o₃))
//! ∇ × ψ = (∂ψ₃/∂y − ∂ψ₂/∂z,  ∂ψ₁/∂z − ∂ψ₃/∂x,  ∂ψ₂/∂x − ∂ψ₁/∂y)
//! ```
//!
//! In 2-D the potential is one scalar `ψ = N(p + o₁)` and the field is
//! `(∂ψ/∂y, −∂ψ/∂x)`, the stream function's velocity.
//!
//! Two evaluations: [`VectorField::eval3`] takes the analytic gradients in
//! `f64` (exactly divergence-free, up to rounding); the batch
//! [`CurlNoise::fill_points3`] takes forward differences of
//! [`CURL_STEP`] lattice units through the SIMD point kernel in `f32`,
//! nine noise values a point, a point's result independent of the others
//! in its batch. The two agree to about `CURL_STEP` times the field's
//! second derivatives (the test asserts 2 % of the bound).

use glam::{DVec2, DVec3};

use crate::Perlin;
use crate::error::Result;
use crate::vector::{Smooth, VectorField};

/// The misregistration `o₁, o₂, o₃` of the potential's three components
/// (lattice units; non-integer, so that no two components share lattice
/// zeros).
pub const CURL_OFFSETS: [DVec3; 3] = [
    DVec3::new(0.0, 0.0, 0.0),
    DVec3::new(31.416, -47.853, 12.679),
    DVec3::new(-23.141, 19.732, -38.207),
];

/// The step (lattice units) of [`CurlNoise::fill_points3`]'s forward
/// differences.
pub const CURL_STEP: f64 = 1.0 / 64.0;

/// Points per chunk of the batch (stack scratch of nine lanes a point).
const CHUNK: usize = 16;

/// The curl of the noise potential `ψ = (N(p + o₁), N(p + o₂), N(p + o₃))`
/// (see the module docs): a divergence-free vector field.
///
/// [`bound`](VectorField::bound) is `√6·L` with `L` the basis's Lipschitz
/// constant (each component is a difference of two partial derivatives,
/// and each gradient enters twice); [`lipschitz`](VectorField::lipschitz)
/// is `2√3·H` with `H` the basis's Hessian bound (the Jacobian's rows are
/// differences of Hessian rows). In 2-D both are the basis's own (`L`, `H`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurlNoise<B> {
    /// The scalar noise whose three misregistered copies are the potential.
    pub field: B,
}

impl<B: Smooth> CurlNoise<B> {
    /// Curl noise of the potential built from `field`.
    pub fn new(field: B) -> Self {
        Self { field }
    }
}

impl<B: Smooth> VectorField for CurlNoise<B> {
    fn eval3(&self, p: DVec3) -> DVec3 {
        let [o1, o2, o3] = CURL_OFFSETS;
        let g1 = self.field.eval_grad3(p + o1).1;
        let g2 = self.field.eval_grad3(p + o2).1;
        let g3 = self.field.eval_grad3(p + o3).1;
        DVec3::new(g3.y - g2.z, g1.z - g3.x, g2.x - g1.y)
    }
    fn eval2(&self, p: DVec2) -> DVec2 {
        let g = self.field.eval_grad2(p + CURL_OFFSETS[0].truncate()).1;
        DVec2::new(g.y, -g.x)
    }
    fn bound(&self) -> f64 {
        (libm::sqrt(6.0) * self.field.lipschitz3()).max(self.field.lipschitz2())
    }
    fn lipschitz(&self) -> f64 {
        2.0 * libm::sqrt(3.0) * self.field.hessian_bound()
    }
}

impl CurlNoise<Perlin> {
    /// Fills `(u[i], v[i], w[i])` with the curl at `(x[i], y[i], z[i])` by
    /// forward differences of [`CURL_STEP`] through Perlin's SIMD point
    /// kernel (see the module docs): `f32` values, each point's
    /// independent of the rest of the batch, so one point at a time and
    /// many together give the same bits.
    ///
    /// # Errors
    /// [`NoiseError::BufferLength`](crate::NoiseError::BufferLength) if a
    /// slice is not as long as `u`.
    pub fn fill_points3(
        &self,
        x: &[f64],
        y: &[f64],
        z: &[f64],
        u: &mut [f32],
        v: &mut [f32],
        w: &mut [f32],
    ) -> Result<()> {
        let n = u.len();
        for len in [x.len(), y.len(), z.len(), v.len(), w.len()] {
            if len != n {
                return Err(crate::NoiseError::BufferLength {
                    expected: n,
                    got: len,
                });
            }
        }
        for s in (0..n).step_by(CHUNK) {
            let r = s..(s + CHUNK).min(n);
            self.chunk(
                &x[r.clone()],
                &y[r.clone()],
                &z[r.clone()],
                &mut u[r.clone()],
                &mut v[r.clone()],
                &mut w[r],
            );
        }
        Ok(())
    }

    /// One chunk of at most [`CHUNK`] points: nine lookups a point, in the
    /// order `ψ₁(p), ψ₁(p + h·y), ψ₁(p + h·z), ψ₂(p), ψ₂(p + h·x),
    /// ψ₂(p + h·z), ψ₃(p), ψ₃(p + h·x), ψ₃(p + h·y)`.
    fn chunk(&self, x: &[f64], y: &[f64], z: &[f64], u: &mut [f32], v: &mut [f32], w: &mut [f32]) {
        const L: usize = 9 * CHUNK;
        let h = CURL_STEP;
        let (mut qx, mut qy, mut qz) = ([0.0f64; L], [0.0f64; L], [0.0f64; L]);
        let mut psi = [0.0f32; L];
        let m = u.len();
        for i in 0..m {
            let p = DVec3::new(x[i], y[i], z[i]);
            let [o1, o2, o3] = CURL_OFFSETS.map(|o| p + o);
            let q = [
                o1,
                o1 + DVec3::Y * h,
                o1 + DVec3::Z * h,
                o2,
                o2 + DVec3::X * h,
                o2 + DVec3::Z * h,
                o3,
                o3 + DVec3::X * h,
                o3 + DVec3::Y * h,
            ];
            for (k, q) in q.into_iter().enumerate() {
                (qx[9 * i + k], qy[9 * i + k], qz[9 * i + k]) = (q.x, q.y, q.z);
            }
        }
        let n = 9 * m;
        // The slices are equally long: no error is possible.
        let _ = self
            .field
            .fill_points3(&qx[..n], &qy[..n], &qz[..n], &mut psi[..n]);
        let inv = (1.0 / h) as f32;
        for i in 0..m {
            let s = &psi[9 * i..9 * i + 9];
            // ∂ψ₁/∂y, ∂ψ₁/∂z, ∂ψ₂/∂x, ∂ψ₂/∂z, ∂ψ₃/∂x, ∂ψ₃/∂y.
            let (d1y, d1z) = (s[1] - s[0], s[2] - s[0]);
            let (d2x, d2z) = (s[4] - s[3], s[5] - s[3]);
            let (d3x, d3y) = (s[7] - s[6], s[8] - s[6]);
            u[i] = (d3y - d2z) * inv;
            v[i] = (d1z - d3x) * inv;
            w[i] = (d2x - d1y) * inv;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points(n: usize, seed: u64) -> impl Iterator<Item = DVec3> {
        let mut s = seed;
        let mut next = move || {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n).map(move |_| DVec3::new(next(), next(), next()) * 40.0 - DVec3::splat(20.0))
    }

    /// The divergence by central differences of the analytic field is zero
    /// to the differences' own error, far below the field's Jacobian.
    #[test]
    fn the_curl_has_no_divergence() {
        let c = CurlNoise::new(Perlin::new(7));
        let h = 1e-4;
        let (mut div, mut jac) = (0.0f64, 0.0f64);
        for p in points(2000, 1) {
            let d = [DVec3::X, DVec3::Y, DVec3::Z]
                .map(|e| (c.eval3(p + e * h) - c.eval3(p - e * h)) / (2.0 * h));
            div = div.max((d[0].x + d[1].y + d[2].z).abs());
            jac = jac.max(d[0].length().max(d[1].length()).max(d[2].length()));
        }
        assert!(jac > 1.0, "{jac}");
        assert!(div < 1e-5 * jac, "divergence {div} against Jacobian {jac}");
    }

    /// A gradient field, the control, has a divergence of the Jacobian's
    /// order: the test above could fail.
    #[test]
    fn a_gradient_field_has_divergence() {
        let c = crate::DNoise(Perlin::new(7));
        let h = 1e-4;
        let div = points(2000, 1)
            .map(|p| {
                let d = [DVec3::X, DVec3::Y, DVec3::Z]
                    .map(|e| (c.eval3(p + e * h) - c.eval3(p - e * h)) / (2.0 * h));
                (d[0].x + d[1].y + d[2].z).abs()
            })
            .fold(0.0, f64::max);
        assert!(div > 1.0, "{div}");
    }

    /// The `f32` batch by forward differences agrees with the `f64`
    /// analytic curl to 2 % of the bound, and one point at a time gives the
    /// batch's bits.
    #[test]
    fn the_batch_matches_the_analytic_curl() {
        let c = CurlNoise::new(Perlin::new(11));
        let p: std::vec::Vec<DVec3> = points(1000, 2).collect();
        let (x, y, z): (std::vec::Vec<f64>, std::vec::Vec<f64>, std::vec::Vec<f64>) = (
            p.iter().map(|p| p.x).collect(),
            p.iter().map(|p| p.y).collect(),
            p.iter().map(|p| p.z).collect(),
        );
        let (mut u, mut v, mut w) = (
            std::vec![0.0f32; p.len()],
            std::vec![0.0f32; p.len()],
            std::vec![0.0f32; p.len()],
        );
        c.fill_points3(&x, &y, &z, &mut u, &mut v, &mut w).unwrap();
        let mut worst = 0.0f64;
        for (i, q) in p.iter().enumerate() {
            let exact = c.eval3(*q);
            let fast = DVec3::new(f64::from(u[i]), f64::from(v[i]), f64::from(w[i]));
            worst = worst.max((fast - exact).length());
            let (mut a, mut b, mut d) = ([0.0f32], [0.0f32], [0.0f32]);
            c.fill_points3(&[q.x], &[q.y], &[q.z], &mut a, &mut b, &mut d)
                .unwrap();
            assert_eq!(
                [a[0], b[0], d[0]].map(f32::to_bits),
                [u[i], v[i], w[i]].map(f32::to_bits)
            );
        }
        std::eprintln!(
            "batch against analytic: {worst:.2e}, bound {:.2}",
            c.bound()
        );
        assert!(worst < 0.02 * c.bound(), "{worst} against {}", c.bound());
    }

    /// The bound and the Lipschitz constant hold over random points.
    #[test]
    fn bound_and_lipschitz_hold() {
        let c = CurlNoise::new(Perlin::new(3));
        let (b, l) = (c.bound(), c.lipschitz());
        let mut last = c.eval3(DVec3::ZERO);
        let mut prev = DVec3::ZERO;
        for p in points(5000, 3) {
            let v = c.eval3(p);
            assert!(v.length() <= b, "{} > {b}", v.length());
            let q = prev + (p - prev).normalize() * 1e-3;
            let vq = c.eval3(q);
            assert!((vq - last).length() <= l * 1e-3 * (1.0 + 1e-9));
            (prev, last) = (p, v);
        }
        let v2 = c.eval2(DVec2::new(0.3, 0.7));
        assert!(v2.length() <= b);
        // NaN in, NaN out, on both paths.
        assert!(c.eval3(DVec3::new(f64::NAN, 0.0, 0.0)).is_nan());
        let (mut u, mut v, mut w) = ([0.0f32], [0.0f32], [0.0f32]);
        c.fill_points3(&[f64::NAN], &[0.0], &[0.0], &mut u, &mut v, &mut w)
            .unwrap();
        assert!(u[0].is_nan() || v[0].is_nan() || w[0].is_nan());
    }

    /// Unequal slices are refused with the lengths.
    #[test]
    fn unequal_slices_are_refused() {
        let c = CurlNoise::new(Perlin::new(1));
        let (mut u, mut v, mut w) = ([0.0f32; 2], [0.0f32; 2], [0.0f32; 1]);
        let e = c
            .fill_points3(&[0.0; 2], &[0.0; 2], &[0.0; 2], &mut u, &mut v, &mut w)
            .unwrap_err();
        assert_eq!(
            e,
            crate::NoiseError::BufferLength {
                expected: 2,
                got: 1
            }
        );
    }
}
