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

#[cfg(target_arch = "x86_64")]
mod x86 {
    //! `#[target_feature]` trampolines: each inlines the kernel and compiles
    //! it for one instruction set.

    use super::Kernel;

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
