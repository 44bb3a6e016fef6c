//! Heterogeneous terrain: Musgrave's `Terrain()` (Musgrave 1993, §2.3.2.5).

use crate::error::{NoiseError, Result, moderate};
use crate::field::Field;
use crate::fractal::Spectral;
use crate::fractal::batch_rows::{Pt, RowSet, multifractal};
use crate::lattice_math::Simd;

/// Parameters of [`HeteroTerrain`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct HeteroTerrainParams {
    /// H, λ, octaves, frequency.
    pub spectral: Spectral,
    /// Shifts the basis before weighting: each octave's signal is
    /// `0.5·(offset + N)`. Larger offsets make more of the terrain rough
    /// (at `offset ≥ 1 + 2·threshold` it is plain fBm, scaled).
    pub offset: f64,
    /// `c_c` of Musgrave 1993, §2.3.2.5.1: the signal level at and above
    /// which higher frequencies get full weight; below it they fade linearly to
    /// 0 at signal 0. Smaller thresholds give rougher valleys. Must be > 0.
    pub threshold: f64,
}

impl Default for HeteroTerrainParams {
    /// `H = 0.8` (terrain-like, Musgrave 1993, §2.2.1.4), offset 1, threshold
    /// 0.5 (the sources give no values for Plates 2.8-2.9; these give smooth
    /// valleys and rough peaks).
    fn default() -> Self {
        Self {
            spectral: Spectral::default().with_h(0.8),
            offset: 1.0,
            threshold: 0.5,
        }
    }
}

impl HeteroTerrainParams {
    /// Checks the spectral parameters, a finite offset and a positive finite threshold.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] naming the first parameter that is NaN, infinite or outside its domain, or [`NoiseError::OctavesBeyondPrecision`] if the octave count passes the precision limit for the lacunarity (the spectral parameters' own checks included).
    pub fn validate(&self) -> Result<()> {
        self.spectral.validate()?;
        moderate("offset", self.offset)?;
        if !(self.threshold.is_finite() && self.threshold > 0.0) {
            return Err(NoiseError::InvalidParam {
                name: "threshold",
                value: self.threshold,
                expected: "must be finite and > 0",
            });
        }
        Ok(())
    }
}

multifractal! {
/// Musgrave's large-scale heterogeneous terrain `Terrain()`: each octave is
/// weighted by the (displaced) value of the octave below, so valleys stay
/// smooth at all scales (Musgrave 1993, §2.3.2.5).
///
/// Follows the C code (Musgrave 1993, §2.3.2.5.1), with signed noise:
/// ```text
/// signal = result = 0.5·(offset + N(p))
/// for octave k ≥ 1: weight = clamp(signal/threshold, 0, 1)
///                   signal = weight·0.5·(offset + N(λ^k p))
///                   result += λ^(−kH)·signal          (× t for a partial octave)
/// ```
/// The dissertation's printed equation has the two cases of `F(v)` inverted
/// relative to its code and its stated intent, and it writes `f^β` for the
/// code's `f^−H`; the code is followed. The weights cascade (signal contains
/// the previous weight), so once a signal is ≤ 0 every later octave is 0 ("once
/// the terrain has become smooth locally, it will never get any rougher",
/// Musgrave 1993, §6.2.1.1). The `VERY_SMALL` early exit is not applied. With
/// the ridged basis ([`Ridged`](crate::Ridged)) it gives "Hell" (Musgrave 1993,
/// Plate 2.9).
HeteroTerrain(HeteroTerrainParams),
"Heterogeneous terrain over `basis` (params validated)."
}

impl<B: Field> HeteroTerrain<B> {
    fn value<P: Pt>(&self, p: P) -> f64 {
        let (off, thr) = (self.params.offset, self.params.threshold);
        let o = &self.oct;
        let mut signal = 0.5 * (off + P::eval(&self.basis, p * o.frequency(0)));
        let mut result = signal * o.partial(0);
        for k in 1..o.count() {
            let weight = (signal / thr).clamp(0.0, 1.0);
            signal = weight * 0.5 * (off + P::eval(&self.basis, p * o.frequency(k)));
            result += o.weight(k) * signal;
        }
        result
    }

    fn value_grad<P: Pt>(&self, p: P) -> (f64, P) {
        let (off, thr) = (self.params.offset, self.params.threshold);
        let o = &self.oct;
        let (n, dn) = P::eval_grad(&self.basis, p * o.frequency(0));
        let mut signal = 0.5 * (off + n);
        let mut dsignal = dn * (0.5 * o.frequency(0));
        let mut result = signal * o.partial(0);
        let mut grad = dsignal * o.partial(0);
        for k in 1..o.count() {
            let r = signal / thr;
            let (weight, dweight) = if r <= 0.0 {
                (0.0, P::ZERO)
            } else if r >= 1.0 {
                (1.0, P::ZERO)
            } else {
                (r, dsignal * (1.0 / thr))
            };
            let (n, dn) = P::eval_grad(&self.basis, p * o.frequency(k));
            let base = 0.5 * (off + n);
            signal = weight * base;
            dsignal = dweight * base + dn * (weight * 0.5 * o.frequency(k));
            result += o.weight(k) * signal;
            grad += dsignal * o.weight(k);
        }
        (result, grad)
    }

    fn bound_impl(&self) -> f64 {
        let s = 0.5 * (self.params.offset.abs() + self.basis.bound());
        s * self.oct.weight_sum()
    }

    fn lipschitz_impl(&self, l: f64) -> f64 {
        let o = &self.oct;
        let s = 0.5 * (self.params.offset.abs() + self.basis.bound());
        // |∇signal_k| ≤ |∇weight|·s + ½·L·f_k with |∇weight| ≤ |∇signal_{k−1}|/threshold.
        let mut d = 0.5 * l * o.frequency(0);
        let mut total = d * o.partial(0);
        for k in 1..o.count() {
            d = d / self.params.threshold * s + 0.5 * l * o.frequency(k);
            total += o.weight(k) * d;
        }
        total
    }

    fn rows<R: RowSet>(&self, simd: Simd, rows: R, step: f64, out: &mut [f32]) {
        let off = self.params.offset as f32;
        let inv_thr = (1.0 / self.params.threshold) as f32;
        let o = &self.oct;
        rows.octave_rows(
            &self.basis,
            simd,
            o,
            step,
            out,
            #[inline(always)]
            |k, n, acc, signal| {
                if k == 0 {
                    let t = o.partial(0) as f32;
                    for ((a, s), &v) in acc.iter_mut().zip(signal.iter_mut()).zip(n) {
                        *s = 0.5 * (off + v);
                        *a = *s * t;
                    }
                } else {
                    let w = o.weight(k) as f32;
                    for ((a, s), &v) in acc.iter_mut().zip(signal.iter_mut()).zip(n) {
                        let weight = (*s * inv_thr).clamp(0.0, 1.0);
                        *s = weight * (0.5 * (off + v));
                        *a += w * *s;
                    }
                }
            },
        );
    }
}
