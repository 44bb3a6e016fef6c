//! Lattice arithmetic shared by the point paths and the f32 batch kernels:
//! splitting a coordinate into its lattice index and fraction, block
//! rebasing, the fades, and the `Real` trait a model is written against once
//! for `f64` points and `f32` lanes.
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
/// The same rounding as [`split_fast`], with the correction as a
/// floating-point select (`cmpsd` and a mask, no branch): the floor is
/// `round(x) − (round(x) > x ? 1 : 0)` (exact), and the index is read from
/// the bits of `floor + M`, so the comparison feeds nothing on the integer
/// side (which would make the compiler branch on it). No integer–float
/// conversion: a short dependency chain, and nothing for a scalar caller
/// to mispredict on points of random sign (the per-point paths are
/// latency-bound).
#[inline(always)]
#[must_use]
pub(crate) fn split(x: f64) -> (u32, f64) {
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    if x.abs() < 2_251_799_813_685_248.0 {
        let t = x + MAGIC;
        let r = t - MAGIC;
        let fl = r - if r > x { 1.0 } else { 0.0 };
        // `x − r` is exact (|x − r| ≤ ½ and Sterbenz), so its sign bit
        // (with `+ 0` turning a `−0` into `+0`) is the same test, read on the
        // integer side: the compiler cannot share one comparison between the
        // float select and the index (which it would turn into a branch).
        let below = (((x - r) + 0.0).to_bits() >> 63) as u32;
        ((t.to_bits() as u32).wrapping_sub(below), x - fl)
    } else {
        let fl = floor64(x);
        (crate::hash::wrap(fl), x - fl)
    }
}

/// [`split`] of every coordinate of a point, with one range check for all
/// of them and the arithmetic written lane-wise (so two or four coordinates
/// share packed instructions): the same results as [`split`] per coordinate.
#[inline(always)]
#[must_use]
pub(crate) fn split_n<const N: usize>(x: [f64; N]) -> ([u32; N], [f64; N]) {
    let (idx, frac, _) = split_floor_n(x);
    (idx, frac)
}

/// [`split_n`] that also returns each coordinate's floor as `x − fraction`
/// (the value a caller would get by subtracting; in range the floor itself,
/// as that subtraction is exact, so the caller's chain saves a step).
#[inline(always)]
#[must_use]
pub(crate) fn split_floor_n<const N: usize>(x: [f64; N]) -> ([u32; N], [f64; N], [f64; N]) {
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    let mut fast = true;
    for v in x {
        // False for NaN too.
        fast &= v.abs() < 2_251_799_813_685_248.0;
    }
    let mut idx = [0u32; N];
    let mut frac = [0.0f64; N];
    let mut floor = [0.0f64; N];
    if !fast {
        for a in 0..N {
            (idx[a], frac[a]) = split(x[a]);
            floor[a] = x[a] - frac[a];
        }
        return (idx, frac, floor);
    }
    // `t = x + M` holds round(x) in its low mantissa bits (one unit per
    // ulp at this magnitude), so the floor's index is those bits less the
    // correction, added as the comparison's all-ones mask (−1): the index
    // leaves the float domain after one rounding and one compare, with no
    // second rounding of the floor.
    for a in 0..N {
        let t = x[a] + MAGIC;
        let r = t - MAGIC;
        let mask = if r > x[a] { u64::MAX } else { 0 };
        floor[a] = r - f64::from_bits(1.0f64.to_bits() & mask);
        idx[a] = t.to_bits().wrapping_add(mask) as u32;
        frac[a] = x[a] - floor[a];
    }
    (idx, frac, floor)
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

    /// `split`, `split_n` and `split_floor_n` give the floor's index and the fraction
    /// `x − floor(x)` bit for bit (the sign of a zero fraction included; −0
    /// keeps its sign) for
    /// ties, values an ulp either side of integers, tiny negatives (whose
    /// fraction rounds), the edges of the fast range, NaN and infinities.
    #[test]
    fn split_forms_equal_the_floor_bit_for_bit() {
        let check = |x: f64| {
            // `+ 0`: the floor of −0 counts as +0, so −0's fraction is −0.
            let fl = libm::floor(x) + 0.0;
            let want = (crate::hash::wrap(fl), x - fl);
            let got = split(x);
            assert_eq!(got.0, want.0, "{x}");
            assert_eq!(got.1.to_bits(), want.1.to_bits(), "{x}");
            for y in [0.25, -7.5, f64::NAN] {
                let (i, f) = split_n([x, y]);
                let (iy, fy) = split(y);
                assert_eq!((i[0], f[0].to_bits()), (got.0, got.1.to_bits()), "{x}");
                assert_eq!((i[1], f[1].to_bits()), (iy, fy.to_bits()), "{x} {y}");
                // The floor form: the same index and fraction, and the
                // floor as `x − fraction` (the floor itself in range).
                let (j, g, fl2) = split_floor_n([x, y]);
                assert_eq!((j, g.map(f64::to_bits)), (i, f.map(f64::to_bits)), "{x}");
                assert_eq!(fl2[0].to_bits(), (x - f[0]).to_bits(), "{x}");
                assert_eq!(fl2[1].to_bits(), (y - f[1]).to_bits(), "{y}");
                if x.abs() < 2_251_799_813_685_248.0 {
                    assert_eq!(fl2[0], fl, "{x}");
                }
            }
        };
        for x in [
            -0.0,
            0.0,
            -1e-300,
            1e-300,
            -0.3,
            -2.5,
            2.5,
            -3.5,
            0.499_999_999_999_999_94,
            -0.499_999_999_999_999_94,
            2_251_799_813_685_247.5,
            -2_251_799_813_685_247.5,
            2_251_799_813_685_248.0,
            -4_503_599_627_370_495.5,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ] {
            check(x);
        }
        for k in -70i32..70 {
            let v = f64::from(k) * 0.5;
            for x in [v, v.next_up(), v.next_down()] {
                check(x);
            }
        }
        let mut h = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..2_000 {
            h = crate::hash::mix64(h);
            let scale = [1e-9, 0.7, 3.0, 1e3, 1e9, 1e15][(h % 6) as usize];
            check(((h >> 11) as f64 / 9_007_199_254_740_992.0 - 0.5) * scale);
        }
    }
}
