//! Run-time instruction-set dispatch for the erosion row kernels.
//!
//! The kernels are plain loops over `f32` row slices (no intrinsics).
//! [`multiversion`] compiles each inside functions with `#[target_feature]` for
//! AVX-512 and for AVX2 + FMA and calls the widest one the CPU supports, so LLVM
//! vectorises the same source to 512- or 256-bit code; other CPUs run the
//! portable build. Rust never contracts `a * b + c` into an FMA on
//! its own, so every level computes bit-identical results.

/// The widest level the running CPU supports (detection is cached by std).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Level {
    Portable,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

pub(crate) fn level() -> Level {
    #[cfg(target_arch = "x86_64")]
    {
        let avx2 = std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma");
        if avx2
            && std::is_x86_feature_detected!("avx512f")
            && std::is_x86_feature_detected!("avx512vl")
            && std::is_x86_feature_detected!("avx512dq")
            && std::is_x86_feature_detected!("avx512bw")
        {
            return Level::Avx512;
        }
        if avx2 {
            return Level::Avx2;
        }
    }
    Level::Portable
}

/// Defines `fn $name(args) -> ret` that runs `$body` compiled for the widest
/// instruction set the CPU supports: the body is an `#[inline(always)]`
/// function instantiated inside an AVX-512 and an AVX2 + FMA
/// `#[target_feature]` function, and called directly elsewhere.
macro_rules! multiversion {
    ($(#[$m:meta])* $vis:vis fn $name:ident($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? $body:block) => {
        $(#[$m])*
        $vis fn $name($($arg: $ty),*) $(-> $ret)? {
            #[inline(always)]
            #[allow(clippy::too_many_arguments)]
            fn inner($($arg: $ty),*) $(-> $ret)? $body
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
            #[allow(clippy::too_many_arguments)]
            fn avx512($($arg: $ty),*) $(-> $ret)? {
                inner($($arg),*)
            }
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2,fma")]
            #[allow(clippy::too_many_arguments)]
            fn avx2($($arg: $ty),*) $(-> $ret)? {
                inner($($arg),*)
            }
            match $crate::simd::level() {
                #[cfg(target_arch = "x86_64")]
                $crate::simd::Level::Avx512 => {
                    #[allow(unsafe_code)]
                    // SAFETY: `level` returned `Avx512` only after run-time
                    // detection confirmed every feature `avx512` enables.
                    unsafe {
                        avx512($($arg),*)
                    }
                }
                #[cfg(target_arch = "x86_64")]
                $crate::simd::Level::Avx2 => {
                    #[allow(unsafe_code)]
                    // SAFETY: AVX2 and FMA were detected at run time.
                    unsafe {
                        avx2($($arg),*)
                    }
                }
                $crate::simd::Level::Portable => inner($($arg),*),
            }
        }
    };
}
pub(crate) use multiversion;
