//! Run-time SIMD dispatch for the workspace's `f32` batch kernels (the sky
//! lookups of natura-atmos, the spectrum and transpose loops of natura-ocean, …).
//!
//! The lane kernels are written once as plain loops over fixed-size `[f32; L]`
//! arrays (no intrinsics, safe code) and instantiated inside functions
//! compiled with `#[target_feature]` for AVX-512 or AVX2 + FMA, so LLVM
//! vectorises the same source 16 or 8 lanes wide; elsewhere they run with the
//! baseline instruction set (SSE2 on x86-64, 4 lanes). Rust never contracts
//! `a * b + c` into an FMA on its own, and `sqrt`, division and the
//! float → int conversions are exactly rounded at every width, so **every
//! level gives bit-identical results** (tested).
//!
//! We use this rather than the `wide` crate because `wide` picks its lane
//! implementation at compile time: a portable build would run its `f32x8` as
//! two SSE halves even on an AVX-512 machine, and run-time dispatch would need
//! these trampolines anyway.
//!
//! A [`Simd`] value is a proof that its level is supported by the running CPU:
//! it can only be obtained from detection, which makes the calls into the
//! `#[target_feature]` trampolines sound.

/// An instruction-set level for the batch kernels, lowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum SimdLevel {
    /// The compilation target's baseline (SSE2 on x86-64).
    Baseline,
    /// x86-64 AVX2 + FMA: 8 `f32` lanes.
    Avx2,
    /// x86-64 AVX-512 (F, VL, DQ, BW) with AVX2 + FMA: 16 `f32` lanes.
    Avx512,
}

impl SimdLevel {
    /// All levels, lowest first.
    pub const ALL: [SimdLevel; 3] = [SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512];

    /// Whether the running CPU supports this level.
    #[must_use]
    pub fn is_supported(self) -> bool {
        match self {
            SimdLevel::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx2 => {
                std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
            }
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx512 => {
                std::is_x86_feature_detected!("avx512f")
                    && std::is_x86_feature_detected!("avx512vl")
                    && std::is_x86_feature_detected!("avx512dq")
                    && std::is_x86_feature_detected!("avx512bw")
                    && std::is_x86_feature_detected!("avx2")
                    && std::is_x86_feature_detected!("fma")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }
}

/// A SIMD level the running CPU supports: the token the batch methods take.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Simd(SimdLevel);

impl Simd {
    /// The widest level the CPU supports (detection is cached by std).
    #[must_use]
    pub fn best() -> Simd {
        SimdLevel::ALL
            .iter()
            .rev()
            .copied()
            .find(|l| l.is_supported())
            .map_or(Simd(SimdLevel::Baseline), Simd)
    }

    /// The baseline level (always available).
    #[must_use]
    pub const fn baseline() -> Simd {
        Simd(SimdLevel::Baseline)
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

/// A batch kernel: a value whose `#[inline(always)]` [`Kernel::call`] is
/// inlined into each `#[target_feature]` trampoline and so compiled for that
/// instruction set. (A closure would not do: closures cannot be marked
/// `#[inline(always)]` on stable Rust, and a large one is not inlined.)
pub trait Kernel {
    /// What the kernel returns.
    type Out;
    /// Runs the kernel; implementations must be `#[inline(always)]`.
    fn call(self) -> Self::Out;
}

/// Runs kernel `f` compiled for the token's instruction set.
///
/// Safe to call: a [`Simd`] token can only be obtained from detection, so the
/// instruction set it names is known to be supported.
#[inline(always)]
pub fn run<K: Kernel>(simd: Simd, f: K) -> K::Out {
    match simd.0 {
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx512 => {
            #[allow(unsafe_code)]
            // SAFETY: a `Simd` holding `Avx512` is only constructed after
            // `SimdLevel::is_supported` detected every feature the trampoline
            // enables, so executing it on this CPU is sound.
            unsafe {
                x86::avx512(f)
            }
        }
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx2 => {
            #[allow(unsafe_code)]
            // SAFETY: as above: AVX2 and FMA were detected before the token was made.
            unsafe {
                x86::avx2(f)
            }
        }
        _ => f.call(),
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    //! `#[target_feature]` trampolines: each inlines the closure and compiles
    //! it for one instruction set.

    use super::Kernel;

    #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
    pub(super) fn avx512<K: Kernel>(f: K) -> K::Out {
        f.call()
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) fn avx2<K: Kernel>(f: K) -> K::Out {
        f.call()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn baseline_always_supported_and_best_is_supported() {
        assert!(SimdLevel::Baseline.is_supported());
        assert!(Simd::best().level().is_supported());
        assert_eq!(Simd::supported().next(), Some(Simd::baseline()));
    }
}
