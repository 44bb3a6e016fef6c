//! Monofractal fBm and turbulence.

use glam::{DVec2, DVec3};

use crate::error::Result;
use crate::field::Field;
#[cfg(doc)]
use crate::fractal::MAX_OCTAVES;
use crate::fractal::batch_rows::{GridRows2, Pt, RowSet};
use crate::fractal::{Octaves, Spectral};
use crate::lattice_math::Simd;

/// Declares a monofractal: the struct (basis, spectral parameters, octave
/// table), its validating constructor and accessors, and its [`Field`]
/// implementation as the octave sum `Σ_k w_k·n_k` (of `|n_k|` when `$abs`)
/// with the analytic gradient `Σ_k w_k f_k ∇n_k` (times `sign(n_k)` when `$abs`).
macro_rules! monofractal {
    ($(#[$attr:meta])* $ty:ident, $name:literal, $abs:literal, $new_doc:literal) => {
        $(#[$attr])*
        #[derive(Clone, Debug, PartialEq)]
        pub struct $ty<B> {
            basis: B,
            spectral: Spectral,
            oct: Octaves,
        }

        impl<B: Field> $ty<B> {
            #[doc = $new_doc]
            ///
            /// # Errors
            /// As the parameters' `validate`, and
            /// [`NoiseError::Unbounded`](crate::NoiseError::Unbounded) if they let
            /// the field's values exceed [`MAX_BOUND`](crate::MAX_BOUND).
            pub fn new(basis: B, spectral: Spectral) -> Result<Self> {
                let oct = spectral.octaves_table()?;
                let f = Self {
                    basis,
                    spectral,
                    oct,
                };
                crate::error::bounded($name, f.bound())?;
                Ok(f)
            }

            /// The basis.
            pub fn basis(&self) -> &B {
                &self.basis
            }

            /// The spectral parameters.
            pub fn spectral(&self) -> &Spectral {
                &self.spectral
            }

            /// The precomputed octave table.
            pub fn octaves(&self) -> &Octaves {
                &self.oct
            }
        }

        impl<B: Field> Field for $ty<B> {
            #[inline]
            fn eval2(&self, p: DVec2) -> f64 {
                octave_sum(&self.oct, $abs, |f, n| self.basis.eval2_scaled(p, f, n))
            }

            #[inline]
            fn eval3(&self, p: DVec3) -> f64 {
                octave_sum(&self.oct, $abs, |f, n| self.basis.eval3_scaled(p, f, n))
            }

            fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
                octave_grad(&self.basis, &self.oct, $abs, p)
            }

            fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
                octave_grad(&self.basis, &self.oct, $abs, p)
            }

            fn bound(&self) -> f64 {
                self.basis.bound() * self.oct.weight_sum()
            }

            fn lipschitz2(&self) -> f64 {
                self.basis.lipschitz2() * self.oct.weighted_frequency_sum()
            }

            fn lipschitz3(&self) -> f64 {
                self.basis.lipschitz3() * self.oct.weighted_frequency_sum()
            }

            fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
                fbm_rows(&self.basis, simd, &self.oct, origin, step, out, $abs);
            }

            fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
                fbm_rows(&self.basis, simd, &self.oct, origin, step, out, $abs);
            }

            fn fill_rows2_with(&self, simd: Simd, x0: f64, ys: &[f64], step: f64, out: &mut [f32]) {
                let rows = GridRows2 { x0, ys };
                fbm_rows(&self.basis, simd, &self.oct, rows, step, out, $abs);
            }
        }
    };
}

/// `(Σ_k w_k·n_k, Σ_k w_k f_k ∇n_k)` with `n_k = N(f_k p)`, or of `|n_k|`
/// (one-sided derivative `sign(n_k)·∇n_k`) when `abs`.
#[inline]
fn octave_grad<P: Pt, B: Field>(basis: &B, o: &Octaves, abs: bool, p: P) -> (f64, P) {
    let mut v = 0.0;
    let mut g = P::ZERO;
    for k in 0..o.count() {
        let (n, dn) = P::eval_grad(basis, p * o.frequency(k));
        if abs {
            v += o.weight(k) * n.abs();
            g += dn * (o.weight(k) * o.frequency(k) * sign(n));
        } else {
            v += o.weight(k) * n;
            g += dn * (o.weight(k) * o.frequency(k));
        }
    }
    (v, g)
}

monofractal! {
/// Fractional Brownian motion: `Σ_k w_k·N(f_k·p)` with `f_k = f₀·λ^k` and `w_k
/// = λ^(−kH)` (Musgrave 1993, §2.3.2.1; Musgrave et al. 1989, §3.3).
///
/// Math (C-H convention, fractional octaves `o = n + t`):
/// `fBm(p) = Σ_{k<n} λ^(−kH)·N(λ^k p) + t·λ^(−nH)·N(λ^n p)`.
/// The sources' loop is reproduced exactly (`result = N(p)`; each further
/// octave multiplies the point by `λ`); no rotation or offset between octaves,
/// as in the sources. The weights are precomputed once ([`Octaves`]).
/// The sources' `VERY_SMALL` early exit is not applied (it drops a tail and
/// makes the output jump by up to the tail's bound).
///
/// * [`bound`](Field::bound) = `B_N·Σ w_k`; Lipschitz = `L_N·Σ w_k f_k`.
/// * Analytic gradient: `Σ w_k f_k ∇N(f_k p)`.
///
/// ```
/// use natura_noise::{Fbm, Field, Perlin, Spectral};
/// use glam::DVec2;
/// let fbm = Fbm::new(Perlin::new(1), Spectral::default().with_h(0.8))?;
/// let v = fbm.eval2(DVec2::new(0.3, 0.7));
/// assert!(v.abs() <= fbm.bound());
/// # Ok::<(), natura_noise::NoiseError>(())
/// ```
Fbm, "Fbm", false,
"fBm of `basis` with `spectral` parameters (validated)."
}

fn fbm_rows<R: RowSet, B: Field>(
    basis: &B,
    simd: Simd,
    oct: &Octaves,
    rows: R,
    step: f64,
    out: &mut [f32],
    abs: bool,
) {
    rows.octave_rows(
        basis,
        simd,
        oct,
        step,
        out,
        #[inline(always)]
        |k, n, acc, _| {
            let w = oct.weight(k) as f32;
            if k == 0 {
                for (a, &v) in acc.iter_mut().zip(n) {
                    *a = w * if abs { v.abs() } else { v };
                }
            } else {
                for (a, &v) in acc.iter_mut().zip(n) {
                    *a += w * if abs { v.abs() } else { v };
                }
            }
        },
    );
}

monofractal! {
/// Turbulence: `Σ_k w_k·|N(f_k·p)|`, fBm of the absolute basis.
///
/// Called by the sources (`turbulence(PP, fw, octaves, λ, H)` in Musgrave 1998,
/// "Wind-Blown Waters") but not defined there; this is Perlin's definition
/// (Perlin 1985), with the crate's weights and fractional octaves. Its spectrum
/// is `1/f³` for amplitude `1/f`: the dissertation (Musgrave 1993, §2.3.2.1)
/// calls that steeper than "the expected `1/f²`", but `1/f³` is exactly what
/// amplitude `1/f` gives (`β = 2H + 1`); only the expectation was wrong. Values
/// in `[0, bound]`; the derivative jumps on the zero set of each octave
/// (creases).
Turbulence, "Turbulence", true,
"Turbulence of `basis` with `spectral` parameters (validated)."
}

/// Octaves evaluated per call of the basis's scaled evaluation (a small
/// stack buffer: no allocation, and no zeroing of [`MAX_OCTAVES`] slots per
/// point).
const OCTAVE_CHUNK: usize = 8;

/// `Σ_k w_k·n_k` (of `|n_k|` when `abs`) with the octave values `n_k` from
/// `eval(frequencies, out)`, summed one term at a time from the lowest octave
/// (the order of the plain loop, so the same bits).
#[inline(always)]
fn octave_sum(oct: &Octaves, abs: bool, eval: impl Fn(&[f64], &mut [f64])) -> f64 {
    let mut sum = -0.0;
    let mut n = [0.0; OCTAVE_CHUNK];
    for (f, w) in oct
        .frequencies()
        .chunks(OCTAVE_CHUNK)
        .zip(oct.weights().chunks(OCTAVE_CHUNK))
    {
        let n = &mut n[..f.len()];
        eval(f, n);
        for (w, &n) in w.iter().zip(n.iter()) {
            sum += w * if abs { n.abs() } else { n };
        }
    }
    sum
}

/// The sign used for one-sided derivatives of `|x|` (0 at 0).
#[inline]
pub(crate) fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}
