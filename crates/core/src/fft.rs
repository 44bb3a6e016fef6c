//! Fast Fourier transforms: the one place the natura crates plan them.
//!
//! The ocean's spectral synthesis, the fluids' periodic solvers and the
//! terrain's spectral synthesis all transform with [`rustfft`] (and
//! [`realfft`] for real input). These functions plan a transform of any
//! length and hand back a shared trait object, so a caller holds an
//! `Arc<dyn Fft<_>>` and never names rustfft's generic planner itself.
//!
//! That matters for more than tidiness. rustfft's planner is generic over
//! the float type, and a crate that calls it compiles its whole family of
//! algorithms (every butterfly, Rader's and Bluestein's, each for scalar,
//! SSE and AVX code) for that type once more. Planning here compiles them
//! once, in this crate, for `f32` and `f64`; everything above links that
//! code. The plans and their results are rustfft's own: the same planner
//! chooses the same algorithms for the same length and CPU, so the same
//! input gives the same bits as calling rustfft directly.
//!
//! Every call plans through one planner per kind and float type, shared by
//! the whole process: a length asked for again is handed the plan made the
//! first time (rustfft's planners keep what they plan), so the three axes of
//! a cubic fluid grid, or the rows and columns of a square ocean patch, share
//! one plan. The plans of every length a process has asked for stay in
//! memory until it ends (each holds its twiddle factors: O(length)).
//!
//! Transforms are unnormalised, as rustfft's are: a forward transform
//! followed by an inverse one multiplies the data by its length.
//!
//! ```
//! use natura_core::fft::{self, Complex, FftDirection};
//!
//! let n = 12;
//! let mut data: Vec<Complex<f64>> = (0..n).map(|i| Complex::new(i as f64, 0.0)).collect();
//! let original = data.clone();
//! fft::plan_f64(n, FftDirection::Forward).process(&mut data);
//! // The zero-frequency term is the sum of the input.
//! assert!((data[0].re - 66.0).abs() < 1e-12 && data[0].im.abs() < 1e-12);
//! fft::plan_f64(n, FftDirection::Inverse).process(&mut data);
//! for (a, b) in data.iter().zip(&original) {
//!     assert!((a.re / n as f64 - b.re).abs() < 1e-12);
//! }
//! ```

use std::sync::{Arc, LazyLock, Mutex, MutexGuard, PoisonError};

use realfft::RealFftPlanner;
use rustfft::FftPlanner;

pub use realfft::{ComplexToReal, RealToComplex};
pub use rustfft::num_complex::Complex;
pub use rustfft::{Fft, FftDirection};

/// A planner shared by every call of this module, created on first use.
type Shared<P> = LazyLock<Mutex<P>>;

static COMPLEX_F32: Shared<FftPlanner<f32>> = LazyLock::new(|| Mutex::new(FftPlanner::new()));
static COMPLEX_F64: Shared<FftPlanner<f64>> = LazyLock::new(|| Mutex::new(FftPlanner::new()));
static REAL_F32: Shared<RealFftPlanner<f32>> = LazyLock::new(|| Mutex::new(RealFftPlanner::new()));
static REAL_F64: Shared<RealFftPlanner<f64>> = LazyLock::new(|| Mutex::new(RealFftPlanner::new()));

/// The planner behind `shared`. A thread that panicked while planning
/// leaves a planner whose cache holds only complete plans, so a poisoned
/// lock is taken as it is.
fn lock<P>(shared: &Mutex<P>) -> MutexGuard<'_, P> {
    shared.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A complex transform of `len` single-precision values in `direction`.
///
/// Any length is planned (lengths with large prime factors through
/// Rader's or Bluestein's algorithm); a length of 0 gives a transform that
/// does nothing.
#[must_use]
pub fn plan_f32(len: usize, direction: FftDirection) -> Arc<dyn Fft<f32>> {
    lock(&COMPLEX_F32).plan_fft(len, direction)
}

/// A complex transform of `len` double-precision values in `direction`
/// (as [`plan_f32`]).
#[must_use]
pub fn plan_f64(len: usize, direction: FftDirection) -> Arc<dyn Fft<f64>> {
    lock(&COMPLEX_F64).plan_fft(len, direction)
}

/// The forward transform of `len` real single-precision values to their
/// `len / 2 + 1` non-negative frequencies.
#[must_use]
pub fn plan_real_forward_f32(len: usize) -> Arc<dyn RealToComplex<f32>> {
    lock(&REAL_F32).plan_fft_forward(len)
}

/// The forward transform of `len` real double-precision values to their
/// `len / 2 + 1` non-negative frequencies.
#[must_use]
pub fn plan_real_forward_f64(len: usize) -> Arc<dyn RealToComplex<f64>> {
    lock(&REAL_F64).plan_fft_forward(len)
}

/// The inverse of [`plan_real_forward_f32`]: `len / 2 + 1` frequencies back
/// to `len` real values (unnormalised), as [`plan_real_inverse_f64`].
#[must_use]
pub fn plan_real_inverse_f32(len: usize) -> Arc<dyn ComplexToReal<f32>> {
    lock(&REAL_F32).plan_fft_inverse(len)
}

/// The inverse of [`plan_real_forward_f64`]: `len / 2 + 1` frequencies back
/// to `len` real values (unnormalised). The imaginary parts of the zero
/// frequency, and of the Nyquist frequency for an even `len`, must be zero
/// (they are for the spectrum of real data); realfft reports an error
/// otherwise, after transforming as if they were.
#[must_use]
pub fn plan_real_inverse_f64(len: usize) -> Arc<dyn ComplexToReal<f64>> {
    lock(&REAL_F64).plan_fft_inverse(len)
}
