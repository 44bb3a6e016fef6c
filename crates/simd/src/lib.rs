//! Run-time SIMD levels and dispatch: the floor every natura crate with hot
//! loops stands on.
//!
//! natura's batch kernels are written once, as plain loops over `f32`/`u32`
//! lanes or row slices (no intrinsics, safe code). [`run`] calls such a kernel
//! inside a function compiled with `#[target_feature]` for the level a
//! [`Simd`] token names, so LLVM vectorises the same source to 512-bit
//! (AVX-512), 256-bit (AVX2 + FMA) or 128-bit (SSE4.1) code, or leaves it at
//! the target's baseline. Rust never contracts `a * b + c` into a fused
//! multiply-add on its own, and `sqrt`, division and float ↔ int conversions
//! are exactly rounded at every width, so **every level computes bit-identical
//! results**; each crate's tests run its kernels at every [`Simd::supported`]
//! level and compare them.
//!
//! There is one mechanism, in three spellings:
//!
//! - a kernel value: a struct implementing [`Kernel`] whose `call` is
//!   `#[inline(always)]`, passed to [`run`] (closures implement [`Kernel`]
//!   too, for short bodies);
//! - [`multiversion!`], which writes that struct for a function body;
//! - [`Simd::best`] for the widest level this CPU supports.
//!
//! A [`Simd`] value is a proof that its level is supported by the running
//! CPU: it can only be obtained from detection, which is what makes the
//! calls into the `#[target_feature]` trampolines sound.
//!
//! **Detection.** With the default `std` feature, detection asks the CPU at
//! run time (`is_x86_feature_detected!`, cached by std). Without `std` there
//! is no run-time detector in `core`, so the supported levels are those the
//! crate was compiled for (`-C target-cpu=native`, `-C target-feature=+avx2`,
//! …); the portable build then runs the baseline path. Results are identical
//! either way.
//!
//! **One primitive with intrinsics.** A lookup of a small table by lane
//! index has no portable spelling that vectorises well: LLVM lowers
//! `table[index[l]]` to a gather (about 8 cycles per 16 lanes on a Xeon,
//! more where the gather microcode mitigation is loaded), where AVX2's
//! variable permute takes one. [`lookup16`] is that lookup, with the
//! permute at the AVX2 and AVX-512 levels and plain indexing below; every
//! level returns the same values (a lookup copies, it does not round).
//!
//! **Why not `wide` or `std::simd`?** `wide` picks its lane implementation at
//! compile time, so a portable build would run its `f32x8` as two SSE halves
//! even on an AVX-512 machine; `std::simd` is not stable. Plain loops inside
//! target-feature trampolines give the full width of the running CPU from
//! one portable binary.

#![no_std]
#![warn(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

/// An instruction-set level for the batch kernels, lowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum SimdLevel {
    /// The compilation target's baseline (SSE2 on x86-64; the only level on
    /// other architectures).
    Baseline,
    /// x86-64 SSE4.1: 4 `f32` lanes with rounding instructions.
    Sse41,
    /// x86-64 AVX2 + FMA: 8 `f32` lanes.
    Avx2,
    /// x86-64 AVX-512 (F, VL, DQ, BW) with AVX2 + FMA: 16 `f32` lanes.
    Avx512,
}

impl SimdLevel {
    /// All levels, lowest first.
    pub const ALL: [SimdLevel; 4] = [
        SimdLevel::Baseline,
        SimdLevel::Sse41,
        SimdLevel::Avx2,
        SimdLevel::Avx512,
    ];

    /// Returns the level's short name (`"baseline"`, `"sse4.1"`, `"avx2"`,
    /// `"avx512"`), as benchmarks and logs print it.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            SimdLevel::Baseline => "baseline",
            SimdLevel::Sse41 => "sse4.1",
            SimdLevel::Avx2 => "avx2",
            SimdLevel::Avx512 => "avx512",
        }
    }

    /// Returns the number of `f32` lanes in one vector register at this level.
    #[must_use]
    pub const fn f32_lanes(self) -> usize {
        match self {
            SimdLevel::Baseline | SimdLevel::Sse41 => 4,
            SimdLevel::Avx2 => 8,
            SimdLevel::Avx512 => 16,
        }
    }

    /// Returns whether the running CPU (or, without the `std` feature, the
    /// compilation target) supports this level.
    #[must_use]
    pub fn is_supported(self) -> bool {
        match self {
            SimdLevel::Baseline => true,
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
                    && std::is_x86_feature_detected!("bmi1")
                    && std::is_x86_feature_detected!("bmi2")
                    && std::is_x86_feature_detected!("popcnt")
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
                target_feature = "fma",
                target_feature = "bmi1",
                target_feature = "bmi2",
                target_feature = "popcnt"
            )),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }
}

impl core::fmt::Display for SimdLevel {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// A SIMD level that the running CPU supports: the token every batch kernel
/// takes.
///
/// Obtain one with [`Simd::best`] (what the plain batch methods use),
/// [`Simd::baseline`], [`Simd::new`] or [`Simd::supported`] (to force each
/// level, as the bit-identity tests do).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Simd(SimdLevel);

impl Simd {
    /// Returns the token for the widest level the CPU supports.
    ///
    /// The answer is detected once and cached (one relaxed atomic load per
    /// later call), so a per-point kernel can afford to ask on every call.
    #[must_use]
    #[inline]
    pub fn best() -> Simd {
        #[cfg(target_has_atomic = "8")]
        {
            use core::sync::atomic::{AtomicU8, Ordering};
            /// Index into [`SimdLevel::ALL`] of the best level, or `u8::MAX`
            /// before the first detection.
            static BEST: AtomicU8 = AtomicU8::new(u8::MAX);
            if let Some(&level) = SimdLevel::ALL.get(usize::from(BEST.load(Ordering::Relaxed))) {
                return Simd(level);
            }
            let best = Self::detect_best();
            let index = SimdLevel::ALL.iter().position(|&l| l == best.0);
            BEST.store(index.map_or(u8::MAX, |i| i as u8), Ordering::Relaxed);
            best
        }
        #[cfg(not(target_has_atomic = "8"))]
        Self::detect_best()
    }

    /// The widest supported level, asked of the detector.
    fn detect_best() -> Simd {
        let mut best = Simd(SimdLevel::Baseline);
        for level in SimdLevel::ALL {
            if level.is_supported() {
                best = Simd(level);
            }
        }
        best
    }

    /// Returns the token for the baseline level (always available).
    #[must_use]
    pub const fn baseline() -> Simd {
        Simd(SimdLevel::Baseline)
    }

    /// Returns the token for `level`, or `None` if this CPU does not support it.
    #[must_use]
    pub fn new(level: SimdLevel) -> Option<Simd> {
        level.is_supported().then_some(Simd(level))
    }

    /// Returns every supported level's token, lowest first.
    pub fn supported() -> impl Iterator<Item = Simd> {
        SimdLevel::ALL.into_iter().filter_map(Simd::new)
    }

    /// Returns the level this token stands for.
    #[must_use]
    pub const fn level(self) -> SimdLevel {
        self.0
    }
}

impl Default for Simd {
    /// The widest supported level, as [`Simd::best`].
    fn default() -> Self {
        Simd::best()
    }
}

/// A batch kernel: a value whose [`Kernel::call`] is inlined into each
/// `#[target_feature]` trampoline of [`run`] and so compiled for that
/// instruction set.
///
/// Implement it on a small struct holding the kernel's arguments, with
/// `#[inline(always)]` on `call` (or let [`multiversion!`] write the struct).
/// A closure is a `Kernel` too, which suits short bodies; a large closure
/// called from several trampolines may not be inlined, and then runs at the
/// baseline level, because a closure cannot be marked `#[inline(always)]` on
/// stable Rust.
pub trait Kernel {
    /// What the kernel returns.
    type Out;
    /// Runs the kernel; implementations should be `#[inline(always)]`.
    fn call(self) -> Self::Out;
}

impl<R, F: FnOnce() -> R> Kernel for F {
    type Out = R;
    #[inline(always)]
    fn call(self) -> R {
        self()
    }
}

/// Runs kernel `k` compiled for the instruction set of `simd`.
///
/// Safe to call: a [`Simd`] token is only made after detection, so the
/// instruction set it names is supported by the running CPU.
#[inline(always)]
pub fn run<K: Kernel>(simd: Simd, k: K) -> K::Out {
    match simd.0 {
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx512 => {
            #[allow(unsafe_code)]
            // SAFETY: a `Simd` holding `Avx512` is only constructed after
            // `SimdLevel::is_supported` detected every feature the trampoline
            // enables, so executing it on this CPU is sound.
            unsafe {
                x86::avx512(k)
            }
        }
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx2 => {
            #[allow(unsafe_code)]
            // SAFETY: as above: AVX2 and FMA were detected before the token was made.
            unsafe {
                x86::avx2(k)
            }
        }
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Sse41 => {
            #[allow(unsafe_code)]
            // SAFETY: as above: SSE4.1 was detected before the token was made.
            unsafe {
                x86::sse41(k)
            }
        }
        _ => k.call(),
    }
}

/// Looks up lane `l` of `index` (modulo 16) in each of the `N` tables:
/// `out[t][l] = tables[t][index[l] & 15]`.
///
/// Inlined into a kernel compiled for AVX2 or AVX-512 (a [`run`] trampoline
/// or a [`multiversion!`] level) with a token of that level, the lookups are
/// AVX2 variable permutes (two 8-entry permutes and a blend per 8 lanes);
/// otherwise plain indexing. The values are the same at every level.
///
/// ```
/// use natura_simd::{Simd, lookup16};
/// let squares: [f32; 16] = core::array::from_fn(|i| (i * i) as f32);
/// let index: [u32; 16] = core::array::from_fn(|l| (l as u32 * 7) % 16 + 16 * (l as u32 % 2));
/// for simd in Simd::supported() {
///     let [got] = lookup16(simd, [&squares], &index);
///     for l in 0..16 {
///         assert_eq!(got[l], squares[(index[l] % 16) as usize]);
///     }
/// }
/// ```
#[inline(always)]
#[must_use]
pub fn lookup16<const N: usize>(
    simd: Simd,
    tables: [&[f32; 16]; N],
    index: &[u32; 16],
) -> [[f32; 16]; N] {
    #[cfg(target_arch = "x86_64")]
    if simd.level() >= SimdLevel::Avx512 {
        #[allow(unsafe_code)]
        // SAFETY: a token of the AVX-512 level is only made after detection
        // found AVX-512 F.
        return unsafe { x86::lookup16_avx512(tables, index) };
    }
    #[cfg(target_arch = "x86_64")]
    if simd.level() >= SimdLevel::Avx2 {
        #[allow(unsafe_code)]
        // SAFETY: a token of the AVX2 level or above is only made after
        // detection found AVX2.
        return unsafe { x86::lookup16_avx2(tables, index) };
    }
    let _ = simd;
    tables.map(|t| core::array::from_fn(|l| t[(index[l] & 15) as usize]))
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    //! `#[target_feature]` trampolines: each inlines the kernel and compiles
    //! it for one instruction set. And [`lookup16_avx2`], the one primitive
    //! written with intrinsics.

    use super::Kernel;
    use core::arch::x86_64::{
        __m256i, _mm256_blendv_ps, _mm256_castsi256_ps, _mm256_loadu_ps, _mm256_loadu_si256,
        _mm256_permutevar8x32_ps, _mm256_slli_epi32, _mm256_storeu_ps,
    };

    /// [`super::lookup16`] with one AVX-512 permute per table.
    #[target_feature(enable = "avx512f")]
    #[inline]
    #[allow(unsafe_code)]
    pub(super) unsafe fn lookup16_avx512<const N: usize>(
        tables: [&[f32; 16]; N],
        index: &[u32; 16],
    ) -> [[f32; 16]; N] {
        use core::arch::x86_64::{
            _mm512_loadu_epi32, _mm512_loadu_ps, _mm512_permutexvar_ps, _mm512_storeu_ps,
        };
        let mut out = [[0.0f32; 16]; N];
        // SAFETY: every load and store is of 16 lanes of a 16-element array.
        unsafe {
            let idx = _mm512_loadu_epi32(index.as_ptr().cast::<i32>());
            for (t, o) in tables.iter().zip(out.iter_mut()) {
                let v = _mm512_permutexvar_ps(idx, _mm512_loadu_ps(t.as_ptr()));
                _mm512_storeu_ps(o.as_mut_ptr(), v);
            }
        }
        out
    }

    /// [`super::lookup16`] with AVX2 permutes: each half of the index picks
    /// from the table's low and high eight entries, and bit 3 of the index
    /// (shifted into the sign bit) chooses between them.
    #[target_feature(enable = "avx2")]
    #[inline]
    #[allow(unsafe_code)]
    pub(super) unsafe fn lookup16_avx2<const N: usize>(
        tables: [&[f32; 16]; N],
        index: &[u32; 16],
    ) -> [[f32; 16]; N] {
        let mut out = [[0.0f32; 16]; N];
        // SAFETY: every load and store is of 8 lanes inside a 16-element
        // array (offsets 0 and 8); unaligned access is allowed.
        unsafe {
            let ptr = index.as_ptr().cast::<__m256i>();
            let idx = [_mm256_loadu_si256(ptr), _mm256_loadu_si256(ptr.add(1))];
            let high = idx.map(|i| _mm256_castsi256_ps(_mm256_slli_epi32::<28>(i)));
            for (t, o) in tables.iter().zip(out.iter_mut()) {
                let lo = _mm256_loadu_ps(t.as_ptr());
                let hi = _mm256_loadu_ps(t.as_ptr().add(8));
                for half in 0..2 {
                    let a = _mm256_permutevar8x32_ps(lo, idx[half]);
                    let b = _mm256_permutevar8x32_ps(hi, idx[half]);
                    _mm256_storeu_ps(
                        o.as_mut_ptr().add(8 * half),
                        _mm256_blendv_ps(a, b, high[half]),
                    );
                }
            }
        }
        out
    }

    #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma,bmi1,bmi2,popcnt")]
    pub(super) fn avx512<K: Kernel>(k: K) -> K::Out {
        k.call()
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) fn avx2<K: Kernel>(k: K) -> K::Out {
        k.call()
    }

    #[target_feature(enable = "sse4.1")]
    pub(super) fn sse41<K: Kernel>(k: K) -> K::Out {
        k.call()
    }
}

/// Defines a function whose body runs compiled for a SIMD level.
///
/// ```
/// natura_simd::multiversion! {
///     /// Adds `b` into `a`, lane by lane.
///     pub fn add_rows<'a>(a: &'a mut [f32], b: &'a [f32]) {
///         for (x, y) in a.iter_mut().zip(b) {
///             *x += *y;
///         }
///     }
/// }
/// let mut a = [1.0_f32; 19];
/// add_rows(&mut a, &[2.0; 19]);
/// assert_eq!(a, [3.0; 19]);
/// ```
///
/// Without a token argument the function runs at [`Simd::best`]. If the first
/// argument's type is written `Simd` (`simd: Simd`, with `Simd` in scope), the
/// caller chooses the level (and the body can read the token too):
///
/// ```
/// use natura_simd::{multiversion, Simd};
/// multiversion! {
///     /// Returns the sum of squares of `a`.
///     pub fn sum_sq<'a>(simd: Simd, a: &'a [f32]) -> f32 {
///         a.iter().map(|x| x * x).sum()
///     }
/// }
/// for simd in Simd::supported() {
///     assert_eq!(sum_sq(simd, &[1.0, 2.0, 3.0]), 14.0);
/// }
/// ```
///
/// Every borrowed argument type names the one lifetime parameter (`'a`
/// above); const generic parameters may follow it (`<'a, const N: usize>`).
/// The macro writes one `#[target_feature]` function per level with the
/// same parameters, each inlining the body, and a `match` on the token that
/// calls one of them. Unlike a [`Kernel`] struct (whose reference fields
/// LLVM cannot assume unaliased), each level's function keeps the no-alias
/// guarantee of its reference parameters, which loops that write through
/// one reference and read through another need to vectorise.
#[macro_export]
macro_rules! multiversion {
    (
        $(#[$m:meta])* $vis:vis fn $name:ident<$lt:lifetime $(, const $c:ident: $ct:ty)* $(,)?>
        ($sv:ident: Simd $(, $arg:ident: $ty:ty)* $(,)?) $(-> $ret:ty)? $body:block
    ) => {
        $(#[$m])*
        $vis fn $name<$lt $(, const $c: $ct)*>($sv: Simd $(, $arg: $ty)*) $(-> $ret)? {
            $crate::multiversion!(@levels [$lt $(, const $c: $ct)*] [$($c),*]
                ($sv: Simd $(, $arg: $ty)*) ($($ret)?) $body);
            $crate::multiversion!(@dispatch $sv [$($c),*] ($sv $(, $arg)*))
        }
    };
    (
        $(#[$m:meta])* $vis:vis fn $name:ident<$lt:lifetime $(, const $c:ident: $ct:ty)* $(,)?>
        ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? $body:block
    ) => {
        $(#[$m])*
        $vis fn $name<$lt $(, const $c: $ct)*>($($arg: $ty),*) $(-> $ret)? {
            $crate::multiversion!(@levels [$lt $(, const $c: $ct)*] [$($c),*]
                ($($arg: $ty),*) ($($ret)?) $body);
            let simd = $crate::Simd::best();
            $crate::multiversion!(@dispatch simd [$($c),*] ($($arg),*))
        }
    };
    // One function per level with the caller's own parameter list (so
    // reference parameters keep their no-alias guarantee, which lets LLVM
    // vectorise loops that store through one and load through another), each
    // inlining the body.
    (@levels [$($g:tt)*] [$($c:ident),*] ($($arg:ident: $ty:ty),*) ($($ret:ty)?) $body:block) => {
        #[inline(always)]
        #[allow(unused_variables, clippy::too_many_arguments)]
        fn __body<$($g)*>($($arg: $ty),*) $(-> $ret)? $body
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma,bmi1,bmi2,popcnt")]
        #[allow(clippy::too_many_arguments)]
        fn __avx512<$($g)*>($($arg: $ty),*) $(-> $ret)? {
            __body::<$($c),*>($($arg),*)
        }
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        #[allow(clippy::too_many_arguments)]
        fn __avx2<$($g)*>($($arg: $ty),*) $(-> $ret)? {
            __body::<$($c),*>($($arg),*)
        }
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "sse4.1")]
        #[allow(clippy::too_many_arguments)]
        fn __sse41<$($g)*>($($arg: $ty),*) $(-> $ret)? {
            __body::<$($c),*>($($arg),*)
        }
    };
    (@dispatch $simd:ident [$($c:ident),*] ($($arg:ident),*)) => {
        match $simd.level() {
            #[cfg(target_arch = "x86_64")]
            $crate::SimdLevel::Avx512 => {
                #[allow(unsafe_code)]
                // SAFETY: a `Simd` token of this level is only made after
                // detection found every feature the function enables.
                unsafe { __avx512::<$($c),*>($($arg),*) }
            }
            #[cfg(target_arch = "x86_64")]
            $crate::SimdLevel::Avx2 => {
                #[allow(unsafe_code)]
                // SAFETY: as above (AVX2 and FMA were detected).
                unsafe { __avx2::<$($c),*>($($arg),*) }
            }
            #[cfg(target_arch = "x86_64")]
            $crate::SimdLevel::Sse41 => {
                #[allow(unsafe_code)]
                // SAFETY: as above (SSE4.1 was detected).
                unsafe { __sse41::<$($c),*>($($arg),*) }
            }
            _ => __body::<$($c),*>($($arg),*),
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn baseline_always_supported_and_best_is_supported() {
        assert!(SimdLevel::Baseline.is_supported());
        assert!(Simd::best().level().is_supported());
        assert_eq!(Simd::supported().next(), Some(Simd::baseline()));
        assert_eq!(Simd::default(), Simd::best());
        assert_eq!(Simd::supported().last(), Some(Simd::best()));
    }

    #[test]
    fn lookups_agree_at_every_level() {
        let a: [f32; 16] = core::array::from_fn(|i| i as f32 * 1.5 - 7.0);
        let b: [f32; 16] = core::array::from_fn(|i| -(i as f32).powi(3));
        let mut state = 12345u32;
        for _ in 0..200 {
            let index: [u32; 16] = core::array::from_fn(|_| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                state >> 7
            });
            let want = [a, b].map(|t| index.map(|i| t[(i % 16) as usize].to_bits()));
            for simd in Simd::supported() {
                let got = lookup16(simd, [&a, &b], &index).map(|t| t.map(f32::to_bits));
                assert_eq!(got, want, "{simd:?}");
            }
        }
    }

    #[test]
    fn tokens_only_for_supported_levels() {
        for level in SimdLevel::ALL {
            assert_eq!(Simd::new(level).is_some(), level.is_supported());
        }
    }

    multiversion! {
        /// A kernel with a const generic and a token: a horizontal sum.
        fn scaled_sum<'a, const K: usize>(simd: Simd, a: &'a [f32]) -> f32 {
            let mut acc = [0.0f32; 16];
            for chunk in a.chunks(16) {
                for (s, x) in acc.iter_mut().zip(chunk) {
                    *s += *x * K as f32;
                }
            }
            acc.iter().sum()
        }
    }

    multiversion! {
        /// A kernel without a token or return value.
        fn square_in_place<'a>(a: &'a mut [f32]) {
            for x in a.iter_mut() {
                *x = *x * *x + 0.5;
            }
        }
    }

    #[test]
    fn every_level_gives_bit_identical_results() {
        let data: [f32; 203] = core::array::from_fn(|i| ((i * 7919) % 1000) as f32 * 0.37 - 150.0);
        let want = scaled_sum::<3>(Simd::baseline(), &data);
        for simd in Simd::supported() {
            assert_eq!(
                scaled_sum::<3>(simd, &data).to_bits(),
                want.to_bits(),
                "{simd:?}"
            );
            let mut a = data;
            let mut b = data;
            square_in_place(&mut a);
            run(simd, || {
                for x in b.iter_mut() {
                    *x = *x * *x + 0.5;
                }
            });
            assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits));
        }
    }
}
