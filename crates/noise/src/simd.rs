//! SIMD levels and run-time dispatch for the f32 batch kernels.
//!
//! The batch kernels are written once as plain loops over `f32`/`u32` lanes
//! (no intrinsics) and instantiated inside functions compiled with
//! `#[target_feature]` for each level, so LLVM vectorises the same source to
//! 512-bit (AVX-512), 256-bit (AVX2 + FMA) or 128-bit (SSE4.1) code, or runs
//! it scalar. The arithmetic is identical at every level (Rust never contracts
//! `a * b + c` into an FMA on its own), so **every level gives bit-identical
//! results**, and the tests check that.
//!
//! **Detection.** With the default `std` feature, [`Simd::best`] asks the CPU at
//! run time (`is_x86_feature_detected!`, cached by std). Without `std` there is
//! no portable run-time detector in `core`, so the best level is the one the
//! crate was compiled for (`-C target-cpu=native` or `-C target-feature=+avx2`
//! …); the portable build then runs the scalar/SSE path. We chose this over a
//! cpuid-based detector dependency to keep the `no_std` build dependency-free.
//!
//! A [`Simd`] value is a proof that its level is supported by the running CPU:
//! it can only be obtained from detection, which is what makes the dispatch's
//! calls into `#[target_feature]` functions sound.

/// An instruction-set level for the f32 batch kernels, lowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum SimdLevel {
    /// Portable scalar code (one lane at a time).
    Scalar,
    /// x86-64 SSE4.1: 4 f32 lanes.
    Sse41,
    /// x86-64 AVX2 + FMA: 8 f32 lanes.
    Avx2,
    /// x86-64 AVX-512 (F, VL, DQ, BW): 16 f32 lanes.
    Avx512,
}

impl SimdLevel {
    /// All levels, lowest first.
    pub const ALL: [SimdLevel; 4] = [
        SimdLevel::Scalar,
        SimdLevel::Sse41,
        SimdLevel::Avx2,
        SimdLevel::Avx512,
    ];

    /// Returns whether the running CPU (or, without `std`, the compilation
    /// target) supports this level.
    #[must_use]
    pub fn is_supported(self) -> bool {
        match self {
            SimdLevel::Scalar => true,
            #[cfg(all(target_arch = "x86_64", feature = "std"))]
            SimdLevel::Sse41 => std::is_x86_feature_detected!("sse4.1"),
            #[cfg(all(target_arch = "x86_64", feature = "std"))]
            SimdLevel::Avx2 => {
                std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
            }
            #[cfg(all(target_arch = "x86_64", feature = "std"))]
            SimdLevel::Avx512 => {
                std::is_x86_feature_detected!("avx512f")
                    && std::is_x86_feature_detected!("avx512vl")
                    && std::is_x86_feature_detected!("avx512dq")
                    && std::is_x86_feature_detected!("avx512bw")
                    && std::is_x86_feature_detected!("avx2")
                    && std::is_x86_feature_detected!("fma")
            }
            #[cfg(all(target_arch = "x86_64", not(feature = "std")))]
            SimdLevel::Sse41 => cfg!(target_feature = "sse4.1"),
            #[cfg(all(target_arch = "x86_64", not(feature = "std")))]
            SimdLevel::Avx2 => cfg!(all(target_feature = "avx2", target_feature = "fma")),
            #[cfg(all(target_arch = "x86_64", not(feature = "std")))]
            SimdLevel::Avx512 => cfg!(all(
                target_feature = "avx512f",
                target_feature = "avx512vl",
                target_feature = "avx512dq",
                target_feature = "avx512bw",
                target_feature = "avx2",
                target_feature = "fma"
            )),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }
}

/// A SIMD level that the running CPU supports: the token every batch fill takes.
///
/// Obtain one with [`Simd::best`] (what the plain `fill_*` methods use),
/// [`Simd::scalar`], [`Simd::new`] or [`Simd::supported`] (to force each level,
/// as the tests do).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Simd(SimdLevel);

impl Simd {
    /// The widest level the CPU supports (detected once and cached by std).
    #[must_use]
    pub fn best() -> Simd {
        SimdLevel::ALL
            .iter()
            .rev()
            .copied()
            .find(|l| l.is_supported())
            .map_or(Simd(SimdLevel::Scalar), Simd)
    }

    /// The portable scalar level (always available).
    #[must_use]
    pub const fn scalar() -> Simd {
        Simd(SimdLevel::Scalar)
    }

    /// The token for `level`, or `None` if this CPU does not support it.
    #[must_use]
    pub fn new(level: SimdLevel) -> Option<Simd> {
        level.is_supported().then_some(Simd(level))
    }

    /// Every supported level, lowest first.
    pub fn supported() -> impl Iterator<Item = Simd> {
        SimdLevel::ALL.into_iter().filter_map(Simd::new)
    }

    /// The level this token stands for.
    #[must_use]
    pub const fn level(self) -> SimdLevel {
        self.0
    }
}

impl Default for Simd {
    fn default() -> Self {
        Simd::best()
    }
}

/// Runs `f` compiled for the token's instruction set.
///
/// `f` should be a closure calling `#[inline(always)]` kernels: LLVM inlines it
/// into the `#[target_feature]` trampoline and vectorises it for that level.
#[inline(always)]
pub(crate) fn run<R>(simd: Simd, f: impl FnOnce() -> R) -> R {
    match simd.0 {
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx512 => {
            #[allow(unsafe_code)]
            // SAFETY: a `Simd` holding `Avx512` is only constructed after
            // `SimdLevel::is_supported` confirmed every feature the trampoline
            // enables, so executing it on this CPU is sound.
            unsafe {
                x86::avx512(f)
            }
        }
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx2 => {
            #[allow(unsafe_code)]
            // SAFETY: as above, AVX2 and FMA were detected before the token was made.
            unsafe {
                x86::avx2(f)
            }
        }
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Sse41 => {
            #[allow(unsafe_code)]
            // SAFETY: as above, SSE4.1 was detected before the token was made.
            unsafe {
                x86::sse41(f)
            }
        }
        _ => f(),
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    //! `#[target_feature]` trampolines: each inlines the closure and compiles it
    //! for one instruction set.

    #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma,bmi1,bmi2,popcnt")]
    #[inline]
    pub(super) fn avx512<R>(f: impl FnOnce() -> R) -> R {
        f()
    }

    #[target_feature(enable = "avx2,fma")]
    #[inline]
    pub(super) fn avx2<R>(f: impl FnOnce() -> R) -> R {
        f()
    }

    #[target_feature(enable = "sse4.1")]
    #[inline]
    pub(super) fn sse41<R>(f: impl FnOnce() -> R) -> R {
        f()
    }
}

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
#[inline(always)]
#[must_use]
pub(crate) fn split(x: f64) -> (u32, f64) {
    if x.abs() < 2_251_799_813_685_248.0 {
        split_fast(x)
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

    #[test]
    fn scalar_always_supported_and_best_is_supported() {
        assert!(SimdLevel::Scalar.is_supported());
        assert!(Simd::best().level().is_supported());
        assert_eq!(Simd::supported().next(), Some(Simd::scalar()));
    }
}
