//! Ridged multifractal (Musgrave 1998b).

use crate::error::{Result, moderate};
use crate::field::Field;
use crate::fractal::Spectral;
use crate::fractal::batch_rows::{Pt, RowSet, multifractal};
use crate::fractal::fbm::sign;
use crate::lattice_math::Simd;

/// Parameters of [`RidgedMultifractal`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct RidgedParams {
    /// H, λ, octaves, frequency.
    pub spectral: Spectral,
    /// The ridge height: each octave's signal is `(offset − |N|)²`.
    pub offset: f64,
    /// How strongly a high (ridge) signal lets the next octave through:
    /// `weight = clamp(signal·gain, 0, 1)`. Larger gains give more detail on ridges.
    pub gain: f64,
}

impl Default for RidgedParams {
    /// `H = 1`, offset 1, gain 2: the published defaults ("Emil", Musgrave
    /// 2001, Figure 16).
    fn default() -> Self {
        Self {
            spectral: Spectral::default().with_h(1.0),
            offset: 1.0,
            gain: 2.0,
        }
    }
}

impl RidgedParams {
    /// Checks the spectral parameters and finite offset and gain.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`](crate::NoiseError::InvalidParam) naming the first parameter that is NaN, infinite or outside its domain, or [`NoiseError::OctavesBeyondPrecision`](crate::NoiseError::OctavesBeyondPrecision) if the octave count passes the precision limit for the lacunarity (the spectral parameters' own checks included).
    pub fn validate(&self) -> Result<()> {
        self.spectral.validate()?;
        moderate("offset", self.offset)?;
        moderate("gain", self.gain)
    }
}

multifractal! {
/// Ridged multifractal: octaves of the ridged basis `(offset − |N|)²`, each
/// weighted by the previous octave's signal, so ridges get sharp detail and
/// valleys stay smooth ("Emil", Musgrave 2001, Figure 16; the ridged basis of
/// Musgrave 1993, §2.3.2.5.3, and Musgrave 2001, "Perlin").
///
/// Follows Musgrave's `RidgedMultifractal()` listing (Musgrave 1998b):
/// ```text
/// signal = (offset − |N(p)|)²;  result = signal
/// for octave k ≥ 1: weight = clamp(signal·gain, 0, 1)
///                   signal = (offset − |N(λ^k p)|)²·weight
///                   result += signal·w_k              (× t for a partial octave)
/// ```
/// The printed code has no fractional octave; the partial octave here is
/// weighted by `t` (continuous in `octaves`). The derivative is discontinuous
/// on each octave's zero set (the ridges), so the field aliases unless band
/// limited (Musgrave 1993, §6.3.2.1).
RidgedMultifractal(RidgedParams),
"Ridged multifractal over `basis` (params validated)."
}

impl<B: Field> RidgedMultifractal<B> {
    fn value<P: Pt>(&self, p: P) -> f64 {
        let (off, gain) = (self.params.offset, self.params.gain);
        let o = &self.oct;
        let r = off - P::eval(&self.basis, p * o.frequency(0)).abs();
        let mut signal = r * r;
        let mut result = signal * o.partial(0);
        for k in 1..o.count() {
            let weight = (signal * gain).clamp(0.0, 1.0);
            let r = off - P::eval(&self.basis, p * o.frequency(k)).abs();
            signal = r * r * weight;
            result += signal * o.weight(k);
        }
        result
    }

    fn value_grad<P: Pt>(&self, p: P) -> (f64, P) {
        let (off, gain) = (self.params.offset, self.params.gain);
        let o = &self.oct;
        let (n, dn) = P::eval_grad(&self.basis, p * o.frequency(0));
        let r = off - n.abs();
        let mut signal = r * r;
        let mut dsignal = dn * (-2.0 * r * sign(n) * o.frequency(0));
        let mut result = signal * o.partial(0);
        let mut grad = dsignal * o.partial(0);
        for k in 1..o.count() {
            let x = signal * gain;
            let (weight, dweight) = if x <= 0.0 {
                (0.0, P::ZERO)
            } else if x >= 1.0 {
                (1.0, P::ZERO)
            } else {
                (x, dsignal * gain)
            };
            let (n, dn) = P::eval_grad(&self.basis, p * o.frequency(k));
            let r = off - n.abs();
            let dr2 = dn * (-2.0 * r * sign(n) * o.frequency(k));
            signal = r * r * weight;
            dsignal = dr2 * weight + dweight * (r * r);
            result += signal * o.weight(k);
            grad += dsignal * o.weight(k);
        }
        (result, grad)
    }

    fn max_r(&self) -> f64 {
        let off = self.params.offset;
        let b = self.basis.bound();
        // r = offset − |N| with |N| ∈ [0, b].
        off.abs().max((off - b).abs())
    }

    fn bound_impl(&self) -> f64 {
        let r = self.max_r();
        r * r * self.oct.weight_sum()
    }

    fn lipschitz_impl(&self, l: f64) -> f64 {
        let o = &self.oct;
        let r = self.max_r();
        let mut d = 2.0 * r * l * o.frequency(0);
        let mut total = d * o.partial(0);
        for k in 1..o.count() {
            d = 2.0 * r * l * o.frequency(k) + r * r * self.params.gain.abs() * d;
            total += d * o.weight(k);
        }
        total
    }

    fn rows<R: RowSet>(&self, simd: Simd, rows: R, step: f64, out: &mut [f32]) {
        let off = self.params.offset as f32;
        let gain = self.params.gain as f32;
        let o = &self.oct;
        rows.octave_rows(
            &self.basis,
            simd,
            o,
            step,
            out,
            #[inline(always)]
            |k, n, acc, signal| {
                let w = o.weight(k) as f32;
                if k == 0 {
                    for ((a, s), &v) in acc.iter_mut().zip(signal.iter_mut()).zip(n) {
                        let r = off - v.abs();
                        *s = r * r;
                        *a = *s * w;
                    }
                } else {
                    for ((a, s), &v) in acc.iter_mut().zip(signal.iter_mut()).zip(n) {
                        let weight = (*s * gain).clamp(0.0, 1.0);
                        let r = off - v.abs();
                        *s = r * r * weight;
                        *a += *s * w;
                    }
                }
            },
        );
    }
}
