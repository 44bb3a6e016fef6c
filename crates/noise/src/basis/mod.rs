//! Basis ("noise") functions: the band-limited building blocks that fractals sum.
//!
//! MojoWorld's basis contract (Musgrave 2001, "The Basis Function"): a simple
//! shape, values within `[-1, 1]`, mean 0. Gradient, value and simplex noise
//! are normalised so their documented [`Field::bound`](crate::Field::bound) is
//! exactly their supremum (found by maximising over every gradient choice, see
//! each type), so `|N| ≤ 1` and the bound is attained.

pub mod cellular;
pub(crate) mod cellular_rows;
pub mod checker;
pub(crate) mod lattice;
pub mod perlin;
pub mod simplex;
pub mod sine;
pub mod sparse;
pub mod steps;
pub mod value;
pub(crate) mod window;

/// The interpolant ("fade") used across a lattice cell.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Fade {
    /// `3t² − 2t³`, the sources' interpolant (Musgrave 1993, §2.3.1; Musgrave
    /// et al. 1989, §3.2). The assembled noise is C¹ only: its second
    /// derivative jumps by 12 across cell faces, although the sources call it
    /// C² (corrected here: the cubic is kept for reproducing the sources'
    /// figures, the quintic is the default). Use it to reproduce the sources'
    /// figures.
    Cubic,
    /// `6t⁵ − 15t⁴ + 10t³` (Perlin 2002, outside the sources): C², the default.
    #[default]
    Quintic,
}

impl Fade {
    /// The fade weight at `t ∈ [0, 1]`.
    #[inline(always)]
    #[must_use]
    pub fn eval(self, t: f64) -> f64 {
        match self {
            Fade::Cubic => t * t * (3.0 - 2.0 * t),
            Fade::Quintic => t * t * t * (t * (t * 6.0 - 15.0) + 10.0),
        }
    }

    /// The derivative of the fade at `t`.
    #[inline(always)]
    #[must_use]
    pub fn deriv(self, t: f64) -> f64 {
        match self {
            Fade::Cubic => 6.0 * t * (1.0 - t),
            Fade::Quintic => 30.0 * t * t * (t * (t - 2.0) + 1.0),
        }
    }
}

/// Applies `f` for the f32 fade selected at run time, so kernels monomorphise
/// one inner loop per fade.
macro_rules! with_fade32 {
    ($fade:expr, |$f:ident| $body:expr) => {
        match $fade {
            $crate::basis::Fade::Quintic => {
                let $f = $crate::lattice_math::quintic32;
                $body
            }
            $crate::basis::Fade::Cubic => {
                let $f = $crate::lattice_math::cubic32;
                $body
            }
        }
    };
}
pub(crate) use with_fade32;

/// Largest lattice step for which a row is evaluated span by span (≥ 16
/// points per cell, so the per-cell set-up is amortised).
pub(crate) const SPAN_MAX_STEP: f64 = 1.0 / 16.0;

/// Whether a batch row of `n` points from `x0` with spacing `step` stays in the
/// range where the branch-free floor is exact (and everything is finite).
#[inline]
pub(crate) fn row_in_fast_range(x0: f64, step: f64, n: usize) -> bool {
    const LIMIT: f64 = 1.0e15;
    x0.is_finite()
        && step.is_finite()
        && x0.abs() + step.abs() * n as f64 <= LIMIT
        && n < i32::MAX as usize
}
