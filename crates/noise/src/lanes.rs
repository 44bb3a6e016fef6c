//! Lane arithmetic shared by the f32 batch kernels: splitting a coordinate
//! into its lattice index and fraction, block rebasing, and the fades.
//!
//! The kernels themselves run through natura-simd's dispatch (one
//! `#[target_feature]` trampoline per level, chosen at run time); every level
//! computes bit-identical results, and the tests check that.

pub(crate) use natura_simd::{Kernel, Simd, run};

/// `floor` for `f64` in `core` (no std): exact for all finite inputs.
#[inline(always)]
#[must_use]
pub(crate) fn floor64(x: f64) -> f64 {
    libm::floor(x)
}

/// Splits `x` into its floor, as the wrapped `i32` lattice index, and fraction.
///
/// Branch-free and vectorisable; exact for `|x| < 2^51` (the batch kernels
/// check their rows stay far inside that). Uses the 1.5·2^52 magic constant:
/// `x + M` rounds `x` to an integer whose two's-complement low bits sit in the
/// mantissa.
#[inline(always)]
#[must_use]
pub(crate) fn split_fast(x: f64) -> (u32, f64) {
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    let t = x + MAGIC;
    let r = t - MAGIC;
    let c = r > x;
    let lo = (t.to_bits() as u32).wrapping_sub(c as u32);
    let fl = if c { r - 1.0 } else { r };
    (lo, x - fl)
}

/// Splits `x` into its floor (as the wrapped lattice index) and fraction, for
/// any `x`: the point path's twin of [`split_fast`], identical where both apply.
///
/// The same rounding as [`split_fast`], with the correction done on the
/// integer: the rounded value's integer comes from the bits of `x + M`, the
/// comparison `round(x) > x` becomes a 0/1 integer, and the floor is
/// converted back exactly. No floating-point select, so no branch for a
/// scalar caller to mispredict on points of random sign.
#[inline(always)]
#[must_use]
pub(crate) fn split(x: f64) -> (u32, f64) {
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    if x.abs() < 2_251_799_813_685_248.0 {
        let t = x + MAGIC;
        let ri = (t.to_bits() as i64).wrapping_sub(MAGIC.to_bits() as i64);
        let fi = ri - i64::from((ri as f64) > x);
        (fi as u32, x - fi as f64)
    } else {
        let fl = floor64(x);
        (crate::hash::wrap(fl), x - fl)
    }
}

/// Points per block of a rebased row kernel (see [`LaneOffsets`]).
pub(crate) const BLOCK: usize = 32;

/// The offsets `m·step` of the lanes `m < BLOCK` of a row block, each split
/// into whole cells and an f32 fraction in `[0, 1]`.
///
/// The row kernels rebase every block of [`BLOCK`] points to a local origin:
/// the block's first point is split once in f64 (exact lattice index, f64
/// fraction rounded to f32), and each lane adds its precomputed offset with
/// [`rebase`]. The per-lane work is then pure f32/u32 at the full lane count,
/// while the lattice index stays exact at any coordinate the f64 path handles
/// (the fraction is within ≈ 2·10⁻⁷ of the f64 one, whatever the row's
/// position or length). The table depends only on `step`, so it is built once
/// per row.
pub(crate) struct LaneOffsets {
    /// Whole cells of `m·step` (floor, wrapped like the lattice index).
    pub(crate) cell: [u32; BLOCK],
    /// Fraction of `m·step`, rounded to f32.
    pub(crate) frac: [f32; BLOCK],
}

impl LaneOffsets {
    /// The table for lattice step `step` (finite, `|BLOCK·step| < 2⁵¹`).
    #[inline(always)]
    pub(crate) fn new(step: f64) -> Self {
        let mut cell = [0u32; BLOCK];
        let mut frac = [0.0f32; BLOCK];
        for (m, (c, f)) in cell.iter_mut().zip(frac.iter_mut()).enumerate() {
            let (i, t) = split_fast(m as f64 * step);
            *c = i;
            *f = t as f32;
        }
        Self { cell, frac }
    }

    /// Splits the block origin `x` (f64) into its lattice index and f32 fraction.
    #[inline(always)]
    pub(crate) fn base(x: f64) -> (u32, f32) {
        let (i, t) = split_fast(x);
        (i, t as f32)
    }
}

/// Adds a lane offset `(cell, frac)` to a block base `(index, fraction)`:
/// the lane's lattice index and its fraction (in `[0, 1]`; a fraction of
/// exactly 1 can only arise from rounding and names the same point as 0 in
/// the next cell, where every basis is continuous).
#[inline(always)]
#[must_use]
pub(crate) fn rebase(index: u32, fraction: f32, cell: u32, frac: f32) -> (u32, f32) {
    let s = fraction + frac;
    let carry = s >= 1.0;
    (
        index.wrapping_add(cell).wrapping_add(u32::from(carry)),
        if carry { s - 1.0 } else { s },
    )
}

/// The arithmetic a model's formula needs, for `f64` (the point paths) and
/// `f32` (the batch lanes): a model written once against it serves both.
pub(crate) trait Real:
    Copy
    + PartialOrd
    + core::ops::Add<Output = Self>
    + core::ops::Sub<Output = Self>
    + core::ops::Mul<Output = Self>
{
    /// `v` as this type (exact for `v < 2²⁴`).
    fn of_u32(v: u32) -> Self;
    /// `v` rounded to this type.
    fn of_f64(v: f64) -> Self;
}

impl Real for f64 {
    #[inline(always)]
    fn of_u32(v: u32) -> Self {
        f64::from(v)
    }
    #[inline(always)]
    fn of_f64(v: f64) -> Self {
        v
    }
}

impl Real for f32 {
    #[inline(always)]
    fn of_u32(v: u32) -> Self {
        v as f32
    }
    #[inline(always)]
    fn of_f64(v: f64) -> Self {
        v as f32
    }
}

/// The smaller of `a` and `b` as one compare and select (`minsd`/`minps`):
/// `b` when either is NaN, which the callers rule out or handle.
#[inline(always)]
#[must_use]
pub(crate) fn min_fast<T: Real>(a: T, b: T) -> T {
    if a < b { a } else { b }
}

/// The larger of `a` and `b` as one compare and select (see [`min_fast`]).
#[inline(always)]
#[must_use]
pub(crate) fn max_fast<T: Real>(a: T, b: T) -> T {
    if a > b { a } else { b }
}

/// Quintic fade `6t⁵ − 15t⁴ + 10t³` in f32.
#[inline(always)]
#[must_use]
pub(crate) fn quintic32(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Cubic fade `3t² − 2t³` in f32.
#[inline(always)]
#[must_use]
pub(crate) fn cubic32(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_matches_floor() {
        for &x in &[
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999_999,
            -3.000_001,
            1e9 + 0.25,
            -1e12 - 0.75,
            1e17,
        ] {
            let (i, f) = split(x);
            if x.abs() < 1e15 {
                assert_eq!((i, f), split_fast(x), "{x}");
            }
            let fl = libm::floor(x);
            assert_eq!(i, crate::hash::wrap(fl), "{x}");
            assert_eq!(f, x - fl, "{x}");
        }
    }
}
