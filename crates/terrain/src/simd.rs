//! Run-time instruction-set dispatch for the erosion row kernels.
//!
//! The kernels are plain loops over `f32` row slices (no intrinsics).
//! [`multiversion`] turns each into a [`natura_core::simd::Kernel`] run
//! through natura-core's dispatch, which compiles it inside
//! `#[target_feature]` trampolines for AVX-512 and for AVX2 + FMA and calls
//! the widest one the CPU supports, so LLVM vectorises the same source to
//! 512- or 256-bit code; other CPUs run the portable build. Rust never
//! contracts `a * b + c` into an FMA on its own, so every level computes
//! bit-identical results.

/// Defines `fn $name<'a>(args) -> ret` that runs `$body` compiled for the
/// widest instruction set the CPU supports. Every borrowed argument type
/// names the one lifetime `'a`: the arguments become the fields of a
/// kernel struct whose `#[inline(always)]` `call` holds the body (a closure
/// would not be inlined into the trampolines).
macro_rules! multiversion {
    ($(#[$m:meta])* $vis:vis fn $name:ident<$lt:lifetime>($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? $body:block) => {
        $(#[$m])*
        $vis fn $name<$lt>($($arg: $ty),*) $(-> $ret)? {
            struct Args<$lt>($($ty),*);
            impl<$lt> natura_core::simd::Kernel for Args<$lt> {
                type Out = $crate::simd::multiversion!(@out $($ret)?);
                #[inline(always)]
                fn call(self) -> Self::Out {
                    let Args($($arg),*) = self;
                    $body
                }
            }
            natura_core::simd::run(natura_core::simd::Simd::best(), Args($($arg),*))
        }
    };
    (@out) => { () };
    (@out $ret:ty) => { $ret };
}
pub(crate) use multiversion;
