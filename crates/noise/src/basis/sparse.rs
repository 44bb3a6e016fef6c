//! Sparse convolution noise (Lewis 1989): random impulses convolved with a
//! kernel.

use glam::{DVec2, DVec3};

use crate::error::{NoiseError, Result};
use crate::field::Field;
use crate::hash::{corner, mix32, row2, row3, seed32, signed_unit, unit_hi, unit_lo};
use crate::lattice_math::split;

/// The kernel splatted at each impulse (radius 1 lattice cell).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum SparseKernel {
    /// `1 − r`: the cone of MojoWorld's Figure 19 (Musgrave 2001, "Sparse
    /// Convolution"). The default.
    #[default]
    Cone,
    /// `(1 − r²)²`: smooth (C¹) bumps.
    Quartic,
}

impl SparseKernel {
    #[inline]
    fn eval(self, r2: f64) -> (f64, f64) {
        // Returns k and dk/d(r²)·2 (so ∇k = that · d, with d the offset).
        match self {
            SparseKernel::Cone => {
                let r = libm::sqrt(r2);
                if r > 0.0 {
                    (1.0 - r, -1.0 / r)
                } else {
                    (1.0, 0.0)
                }
            }
            SparseKernel::Quartic => {
                let t = 1.0 - r2;
                (t * t, -4.0 * t)
            }
        }
    }

    /// `∫ k² dV` over the unit disc (2-D) or ball (3-D).
    fn energy(self, dims: usize) -> f64 {
        use core::f64::consts::PI;
        match (self, dims) {
            (SparseKernel::Cone, 2) => PI / 6.0,
            (SparseKernel::Cone, _) => 2.0 * PI / 15.0,
            (SparseKernel::Quartic, 2) => PI / 5.0,
            // 4π ∫ r²(1 − r²)⁴ dr = 4π · 128/3465.
            (SparseKernel::Quartic, _) => 4.0 * PI * 128.0 / 3465.0,
        }
    }

    fn max_slope(self) -> f64 {
        match self {
            SparseKernel::Cone => 1.0,
            // max 4r(1 − r²) at r = 1/√3.
            SparseKernel::Quartic => 8.0 / (3.0 * libm::sqrt(3.0)),
        }
    }
}

/// Parameters of [`SparseConvolution`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct SparseParams {
    /// Impulses per unit cell, 1 to 16 (MojoWorld's seed tables "1" and "4"
    /// Musgrave 2001, "The Seed Tables"); more impulses give a finer, more
    /// Gaussian texture.
    pub density: u32,
    /// The kernel shape.
    pub kernel: SparseKernel,
}

impl Default for SparseParams {
    fn default() -> Self {
        Self {
            density: 4,
            kernel: SparseKernel::Cone,
        }
    }
}

impl SparseParams {
    /// Checks `1 ≤ density ≤ 16`.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] naming the first parameter that is NaN, infinite or outside its domain.
    pub fn validate(&self) -> Result<()> {
        if !(1..=16).contains(&self.density) {
            return Err(NoiseError::InvalidParam {
                name: "density",
                value: f64::from(self.density),
                expected: "must be an integer in [1, 16]",
            });
        }
        Ok(())
    }
}

const SALT: u64 = 0x5350_4152; // "SPAR"

/// Sparse convolution noise: `K·Σ_i w_i·k(|p − x_i|)` over impulses `x_i`
/// uniformly placed, `density` per lattice cell, with weights `w_i` uniform in
/// `[-1, 1)` (Musgrave 2001, "Sparse Convolution"; Musgrave 1998, "A Variety of
/// fBm"; Musgrave 1993, §6.2.1.1.3). "The slowest, technically 'best' and most
/// flexible" basis (Musgrave 2001, "Sparse Convolution"). Plain uniform
/// placement, as Musgrave 1993, §6.2.1.1.3 suggests (no efficient
/// Poisson-disk generator is known, Musgrave 1993, §6.2.1.1.3).
///
/// `K` makes the standard deviation 0.25 (variance `density·E[w²]·∫k²`), so
/// values mostly lie within `[-1, 1]`; the exact [`bound`](Field::bound) is
/// `K·3ⁿ·density` (every impulse of the 3ⁿ neighbouring cells at full weight).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SparseConvolution {
    seed: u64,
    s: u32,
    params: SparseParams,
}

impl SparseConvolution {
    /// Sparse convolution noise with `seed` and `params` (validated).
    ///
    /// # Errors
    /// As the parameters' `validate`.
    pub fn new(seed: u64, params: SparseParams) -> Result<Self> {
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

    fn scale(&self, dims: usize) -> f64 {
        let var = f64::from(self.params.density) / 3.0 * self.params.kernel.energy(dims);
        0.25 / libm::sqrt(var)
    }

    /// Impulse `m` of the cell hashed `h`: position in the cell and weight.
    #[inline]
    fn impulse(h: u32, m: u32) -> ([f64; 3], f64) {
        let a = mix32(h ^ m.wrapping_mul(0x9E37_79B9));
        let b = mix32(a ^ 0x85EB_CA6B);
        (
            [
                f64::from(unit_lo(a)),
                f64::from(unit_hi(a)),
                f64::from(unit_lo(b)),
            ],
            f64::from(signed_unit(mix32(b))),
        )
    }

    fn sum<const N: usize>(&self, p: [f64; N]) -> (f64, [f64; N]) {
        let mut base = [0u32; N];
        let mut f = [0.0; N];
        for a in 0..N {
            let (i, t) = split(p[a]);
            base[a] = i;
            f[a] = t;
        }
        let mut v = 0.0;
        let mut g = [0.0; N];
        let cells = 3usize.pow(N as u32);
        for c in 0..cells {
            let mut off = [0i64; N];
            let mut rest = c;
            for o in off.iter_mut() {
                *o = (rest % 3) as i64 - 1;
                rest /= 3;
            }
            let idx: [u32; N] = core::array::from_fn(|a| base[a].wrapping_add(off[a] as u32));
            let h = match N {
                2 => corner(idx[0], row2(idx[1], self.s)),
                _ => corner(idx[0], row3(idx[1], idx[2], self.s)),
            };
            for m in 0..self.params.density {
                let (pos, w) = Self::impulse(h, m);
                let d: [f64; N] = core::array::from_fn(|a| f[a] - (off[a] as f64 + pos[a]));
                let r2: f64 = d.iter().map(|x| x * x).sum();
                if r2 < 1.0 {
                    let (k, dk) = self.params.kernel.eval(r2);
                    v += w * k;
                    for a in 0..N {
                        g[a] += w * dk * d[a];
                    }
                }
            }
        }
        let k = self.scale(N);
        (v * k, g.map(|x| x * k))
    }
}

impl Field for SparseConvolution {
    fn eval2(&self, p: DVec2) -> f64 {
        if !p.is_finite() {
            return f64::NAN;
        }
        self.sum::<2>(p.to_array()).0
    }
    fn eval3(&self, p: DVec3) -> f64 {
        if !p.is_finite() {
            return f64::NAN;
        }
        self.sum::<3>(p.to_array()).0
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        let (v, g) = self.sum::<2>(p.to_array());
        (
            if p.is_finite() { v } else { f64::NAN },
            DVec2::from_array(g),
        )
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        let (v, g) = self.sum::<3>(p.to_array());
        (
            if p.is_finite() { v } else { f64::NAN },
            DVec3::from_array(g),
        )
    }
    fn bound(&self) -> f64 {
        self.scale(2).max(self.scale(3)) * 27.0 * f64::from(self.params.density)
    }
    fn lipschitz2(&self) -> f64 {
        self.scale(2) * 9.0 * f64::from(self.params.density) * self.params.kernel.max_slope()
    }
    fn lipschitz3(&self) -> f64 {
        self.scale(3) * 27.0 * f64::from(self.params.density) * self.params.kernel.max_slope()
    }
}
