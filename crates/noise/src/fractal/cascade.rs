//! The multiplicative cascade ("multifractal" in Mandelbrot's sense).

use crate::error::{Result, moderate};
use crate::field::Field;
use crate::fractal::Spectral;
use crate::fractal::batch_rows::{Pt, RowSet, multifractal};
use crate::lattice_math::Simd;

/// Where the octave amplitude enters each factor of the cascade.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum CascadeForm {
    /// Factor `(N + offset)·w_k` (Musgrave's `multifractal()` listing, Musgrave
    /// 1998b). The default.
    #[default]
    Weighted,
    /// Factor `offset + w_k·N`: `vMultifractalFunc` (Musgrave 1998, "The
    /// Multicolor Texture") with `offset` = `zero_offset` and the raw gain `H`
    /// ([`GainConvention::Raw`](crate::GainConvention::Raw)).
    Additive,
}

/// Parameters of [`Multifractal`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct MultifractalParams {
    /// H, λ, octaves, frequency.
    pub spectral: Spectral,
    /// Added to each octave's basis value before multiplying; near 1 the
    /// cascade stays near 1, smaller values make it more heterogeneous ("spiky").
    pub offset: f64,
    /// Where the amplitude enters the factor.
    pub form: CascadeForm,
}

impl Default for MultifractalParams {
    /// `H = 0.25`, 8 octaves, offset 1, weighted form.
    fn default() -> Self {
        Self {
            spectral: Spectral::default().with_h(0.25),
            offset: 1.0,
            form: CascadeForm::Weighted,
        }
    }
}

impl MultifractalParams {
    /// The `vMultifractalFunc` call of `multicolor` (Musgrave 1998, "The
    /// Multicolor Texture"): raw gain 0.7,
    /// λ 2, 8 octaves, zero offset 0.2, additive form.
    #[must_use]
    pub fn multicolor() -> Self {
        Self {
            spectral: Spectral {
                h: 0.7,
                lacunarity: 2.0,
                octaves: 8.0,
                frequency: 1.0,
                convention: crate::GainConvention::Raw,
            },
            offset: 0.2,
            form: CascadeForm::Additive,
        }
    }

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
/// A multiplicative cascade: `Π_k factor_k(N(λ^k p))` (Musgrave 1998, "The
/// Multicolor Texture", `vMultifractalFunc`), the "multifractal" in
/// Mandelbrot's sense; its values span orders of magnitude.
///
/// The partial octave contributes the factor `1 + t·(factor − 1)`, so the
/// product is continuous in `octaves` (the printed code adds `t·N·w` instead,
/// which jumps at integer octave counts).
Multifractal(MultifractalParams),
"Multiplicative cascade over `basis` (params validated)."
}

impl<B: Field> Multifractal<B> {
    /// Factor of octave `k` for basis value `n`, and its derivative in `n`.
    #[inline]
    fn factor(&self, k: usize, n: f64) -> (f64, f64) {
        let a = self.oct.amplitude(k);
        let (f, df) = match self.params.form {
            CascadeForm::Weighted => ((n + self.params.offset) * a, a),
            CascadeForm::Additive => (self.params.offset + a * n, a),
        };
        let t = self.oct.partial(k);
        (1.0 + t * (f - 1.0), t * df)
    }

    fn value<P: Pt>(&self, p: P) -> f64 {
        let o = &self.oct;
        let mut v = 1.0;
        for k in 0..o.count() {
            v *= self.factor(k, P::eval(&self.basis, p * o.frequency(k))).0;
        }
        v
    }

    fn value_grad<P: Pt>(&self, p: P) -> (f64, P) {
        let o = &self.oct;
        let mut v = 1.0;
        let mut g = P::ZERO;
        for k in 0..o.count() {
            let (n, dn) = P::eval_grad(&self.basis, p * o.frequency(k));
            let (f, df) = self.factor(k, n);
            g = g * f + dn * (v * df * o.frequency(k));
            v *= f;
        }
        (v, g)
    }

    /// `(sup|factor_k|, sup|∂factor_k/∂n|)` for every octave.
    fn factor_bounds(&self, k: usize) -> (f64, f64) {
        let b = self.basis.bound();
        let (lo, hi) = (self.factor(k, -b).0, self.factor(k, b).0);
        (lo.abs().max(hi.abs()), self.factor(k, 0.0).1.abs())
    }

    fn bound_impl(&self) -> f64 {
        (0..self.oct.count())
            .map(|k| self.factor_bounds(k).0)
            .product()
    }

    fn lipschitz_impl(&self, l: f64) -> f64 {
        let o = &self.oct;
        let mut v = 1.0;
        let mut d = 0.0;
        for k in 0..o.count() {
            let (f, df) = self.factor_bounds(k);
            d = d * f + v * df * l * o.frequency(k);
            v *= f;
        }
        d
    }

    fn rows<R: RowSet>(&self, simd: Simd, rows: R, step: f64, out: &mut [f32]) {
        let o = &self.oct;
        let off = self.params.offset as f32;
        let additive = self.params.form == CascadeForm::Additive;
        rows.octave_rows(
            &self.basis,
            simd,
            o,
            step,
            out,
            #[inline(always)]
            |k, n, acc, _| {
                let a = o.amplitude(k) as f32;
                let t = o.partial(k) as f32;
                let (c0, c1) = if additive { (off, a) } else { (off * a, a) };
                // factor = 1 + t·(c0 + c1·n − 1)
                if k == 0 {
                    for (r, &v) in acc.iter_mut().zip(n) {
                        *r = 1.0 + t * (c0 + c1 * v - 1.0);
                    }
                } else {
                    for (r, &v) in acc.iter_mut().zip(n) {
                        *r *= 1.0 + t * (c0 + c1 * v - 1.0);
                    }
                }
            },
        );
    }
}
