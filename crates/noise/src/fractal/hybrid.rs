//! Hybrid multifractal (Musgrave 1998b).

use crate::error::{Result, moderate};
use crate::field::Field;
use crate::fractal::Spectral;
use crate::fractal::batch_rows::{Pt, RowSet, multifractal};
use crate::lattice_math::Simd;

/// Parameters of [`HybridMultifractal`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct HybridParams {
    /// H, λ, octaves, frequency.
    pub spectral: Spectral,
    /// Added to the basis in every octave: `signal = (N + offset)·w_k`.
    /// Larger offsets make the terrain rougher overall and shift it up.
    pub offset: f64,
}

impl Default for HybridParams {
    /// `H = 0.25`, offset 0.7, 8 octaves: the published defaults of the hybrid
    /// multifractal (Musgrave 1998b).
    fn default() -> Self {
        Self {
            spectral: Spectral::default().with_h(0.25),
            offset: 0.7,
        }
    }
}

impl HybridParams {
    /// Checks the spectral parameters and a finite offset.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`](crate::NoiseError::InvalidParam) naming the first parameter that is NaN, infinite or outside its domain, or [`NoiseError::OctavesBeyondPrecision`](crate::NoiseError::OctavesBeyondPrecision) if the octave count passes the precision limit for the lacunarity (the spectral parameters' own checks included).
    pub fn validate(&self) -> Result<()> {
        self.spectral.validate()?;
        moderate("offset", self.offset)
    }
}

multifractal! {
/// Hybrid multifractal: "additive/multiplicative" — each octave is added,
/// weighted by the running product of earlier signals (capped at 1), so low
/// areas are smooth and high areas rough. MojoWorld's "multifractal" (formerly
/// "hybrid multifractal"), its "first choice for terrains on a planetary scale"
/// (Musgrave 2001, "The Heterofractal Function" and "The Multifractal
/// Function").
///
/// It follows Musgrave's `HybridMultifractal()` listing (Musgrave 1998b):
/// ```text
/// result = (N(p) + offset)·w_0;  weight = result
/// for octave k ≥ 1: weight = min(weight, 1)
///                   signal = (N(λ^k p) + offset)·w_k
///                   result += weight·signal;  weight *= signal
/// ```
/// Correction: the printed remainder `result += t·N·w_k` drops the weight and
/// offset, so the output jumps as `octaves` crosses an integer; here the
/// partial octave adds `t·weight·signal`, continuous in `octaves`.
HybridMultifractal(HybridParams),
"Hybrid multifractal over `basis` (params validated)."
}

impl<B: Field> HybridMultifractal<B> {
    fn value<P: Pt>(&self, p: P) -> f64 {
        let off = self.params.offset;
        let o = &self.oct;
        let mut result = (P::eval(&self.basis, p * o.frequency(0)) + off) * o.amplitude(0);
        let mut weight = result;
        result *= o.partial(0);
        for k in 1..o.count() {
            weight = weight.min(1.0);
            let signal = (P::eval(&self.basis, p * o.frequency(k)) + off) * o.amplitude(k);
            result += weight * signal * o.partial(k);
            weight *= signal;
        }
        result
    }

    fn value_grad<P: Pt>(&self, p: P) -> (f64, P) {
        let off = self.params.offset;
        let o = &self.oct;
        let (n, dn) = P::eval_grad(&self.basis, p * o.frequency(0));
        let a0 = o.amplitude(0);
        let mut weight = (n + off) * a0;
        let mut dweight = dn * (a0 * o.frequency(0));
        let mut result = weight * o.partial(0);
        let mut grad = dweight * o.partial(0);
        for k in 1..o.count() {
            if weight > 1.0 {
                weight = 1.0;
                dweight = P::ZERO;
            }
            let (n, dn) = P::eval_grad(&self.basis, p * o.frequency(k));
            let signal = (n + off) * o.amplitude(k);
            let dsignal = dn * (o.amplitude(k) * o.frequency(k));
            let t = o.partial(k);
            result += weight * signal * t;
            grad += (dweight * signal + dsignal * weight) * t;
            dweight = dweight * signal + dsignal * weight;
            weight *= signal;
        }
        (result, grad)
    }

    /// Bounds `(|weight|, |∇weight|)` recursion shared by bound and Lipschitz.
    fn recursion(&self, l: f64) -> (f64, f64) {
        let o = &self.oct;
        let b = self.basis.bound() + self.params.offset.abs();
        // With offset ≥ bound every signal is ≥ 0 and the cap bounds the weight by 1.
        let nonneg = self.params.offset >= self.basis.bound();
        let mut w = b * o.amplitude(0);
        let mut dw = l * o.amplitude(0) * o.frequency(0);
        let mut total = w * o.partial(0);
        let mut dtotal = dw * o.partial(0);
        for k in 1..o.count() {
            // The cap only bounds the positive side: weight ∈ [−w, min(w, 1)].
            let wc = if nonneg { w.min(1.0) } else { w };
            let s = b * o.amplitude(k);
            let ds = l * o.amplitude(k) * o.frequency(k);
            let t = o.partial(k);
            total += wc * s * t;
            dtotal += (dw * s + ds * wc) * t;
            dw = dw * s + ds * wc;
            w = wc * s;
        }
        (total, dtotal)
    }

    fn bound_impl(&self) -> f64 {
        self.recursion(0.0).0
    }

    fn lipschitz_impl(&self, l: f64) -> f64 {
        self.recursion(l).1
    }

    fn rows<R: RowSet>(&self, simd: Simd, rows: R, step: f64, out: &mut [f32]) {
        let off = self.params.offset as f32;
        let o = &self.oct;
        rows.octave_rows(
            &self.basis,
            simd,
            o,
            step,
            out,
            #[inline(always)]
            |k, n, acc, weight| {
                let a = o.amplitude(k) as f32;
                let t = o.partial(k) as f32;
                if k == 0 {
                    for ((r, w), &v) in acc.iter_mut().zip(weight.iter_mut()).zip(n) {
                        *w = (v + off) * a;
                        *r = *w * t;
                    }
                } else {
                    for ((r, w), &v) in acc.iter_mut().zip(weight.iter_mut()).zip(n) {
                        let wc = if *w > 1.0 { 1.0 } else { *w };
                        let signal = (v + off) * a;
                        *r += wc * signal * t;
                        *w = wc * signal;
                    }
                }
            },
        );
    }
}
