//! Band-limited evaluation: a fractal summed up to a real-valued number of
//! *visible* octaves.
//!
//! A renderer that knows how large a sample's footprint is drops the octaves
//! finer than it, so a texture seen from far away does not alias. This is the
//! dissertation's level-of-detail scheme (Musgrave 1993, §5.1.2): the number of
//! iterations of the fractal loop is a parameter, given the value the footprint
//! allows at each point, and the fractional remainder octave (§2.3.2.1, the `if
//! (i < 1) amplitude *= i` of the C code) makes the sum continuous in that
//! number, so the detail fades in smoothly as the footprint shrinks instead of
//! popping.
//!
//! With `visible ≥` the table's octave count every method here equals the
//! plain evaluation; with `visible = n + t` octave `k` keeps the factor
//! `clamp(visible − k, 0, 1)` (on top of the table's own partial-octave
//! factor), so octaves above `visible` contribute nothing and the one
//! straddling it contributes the fraction `t`.

use glam::{DVec2, DVec3};

use crate::field::Field;
use crate::fractal::Octaves;
use crate::fractal::cascade::{CascadeForm, Multifractal};
use crate::fractal::fbm::{Fbm, Turbulence, sign};
use crate::vector::{VectorFbm, VectorField};

impl Octaves {
    /// The real-valued octave count the table was built for (the
    /// `Spectral::octaves` it came from).
    #[must_use]
    pub fn total(&self) -> f64 {
        if self.fraction > 0.0 {
            (self.count - 1) as f64 + self.fraction
        } else {
            self.count as f64
        }
    }

    /// The factor octave `k` keeps when only `visible` octaves are summed:
    /// `clamp(min(visible, total) − k, 0, 1)` (NaN for a NaN `visible`).
    #[must_use]
    pub fn band_factor(&self, k: usize, visible: f64) -> f64 {
        if visible.is_nan() {
            return f64::NAN;
        }
        let v = if visible < self.total() {
            visible
        } else {
            self.total()
        };
        (v - k as f64).clamp(0.0, 1.0)
    }

    /// The weight of octave `k` in a sum of `visible` octaves: its amplitude
    /// times [`band_factor`](Self::band_factor). Equal to
    /// [`weight`](Self::weight) when `visible ≥` [`total`](Self::total).
    #[must_use]
    pub fn band_weight(&self, k: usize, visible: f64) -> f64 {
        self.amplitude(k) * self.band_factor(k, visible)
    }

    /// The number of octaves with a non-zero weight in a sum of `visible`
    /// octaves (all of them for a NaN `visible`, so NaN reaches the result).
    #[must_use]
    pub fn band_count(&self, visible: f64) -> usize {
        if visible.is_nan() || visible >= self.count as f64 {
            self.count
        } else if visible <= 0.0 {
            0
        } else {
            libm::ceil(visible) as usize
        }
    }

    /// `Σ_k band_weight(k)`: turns a basis bound into the band-limited sum's.
    #[must_use]
    pub fn band_weight_sum(&self, visible: f64) -> f64 {
        (0..self.band_count(visible))
            .map(|k| self.band_weight(k, visible))
            .sum()
    }

    /// `Σ_k band_weight(k)·frequency(k)`: turns a basis Lipschitz constant
    /// into the band-limited sum's.
    #[must_use]
    pub fn band_weighted_frequency_sum(&self, visible: f64) -> f64 {
        (0..self.band_count(visible))
            .map(|k| self.band_weight(k, visible) * self.frequency(k))
            .sum()
    }
}

impl<B: Field> Fbm<B> {
    /// The fBm at the 3-D point `p` summed over `visible` octaves: octave `k`
    /// keeps [`Octaves::band_factor`] `= clamp(visible − k, 0, 1)` of its
    /// weight, so the sum is continuous in `visible` and the detail finer than
    /// a pixel footprint can be dropped without popping (Musgrave 1993,
    /// §5.1.2). Equal to [`Field::eval3`] for `visible ≥` the octave count.
    #[must_use]
    pub fn eval3_band(&self, p: DVec3, visible: f64) -> f64 {
        let o = self.octaves();
        (0..o.band_count(visible))
            .map(|k| o.band_weight(k, visible) * self.basis().eval3(p * o.frequency(k)))
            .sum()
    }

    /// The fBm at the 2-D point `p` summed over `visible` octaves.
    #[must_use]
    pub fn eval2_band(&self, p: DVec2, visible: f64) -> f64 {
        let o = self.octaves();
        (0..o.band_count(visible))
            .map(|k| o.band_weight(k, visible) * self.basis().eval2(p * o.frequency(k)))
            .sum()
    }

    /// The weighted terms `band_weight(k)·N(f_k·p)` of the octaves `k` in
    /// `first..first + out.len()` of a sum over `visible` octaves, written to
    /// `out` in order (0 for octaves beyond the band). Summing them in order
    /// after the terms of the earlier octaves gives
    /// [`eval3_band`](Self::eval3_band) bit for bit, so a caller can sum a
    /// fractal incrementally and stop early.
    pub fn eval3_band_terms(&self, p: DVec3, visible: f64, first: usize, out: &mut [f64]) {
        let o = self.octaves();
        let n = o.band_count(visible);
        for (i, term) in out.iter_mut().enumerate() {
            let k = first + i;
            *term = if k < n {
                o.band_weight(k, visible) * self.basis().eval3(p * o.frequency(k))
            } else {
                0.0
            };
        }
    }

    /// The value and analytic gradient of [`eval3_band`](Self::eval3_band).
    #[must_use]
    pub fn eval_grad3_band(&self, p: DVec3, visible: f64) -> (f64, DVec3) {
        let o = self.octaves();
        let mut v = 0.0;
        let mut g = DVec3::ZERO;
        for k in 0..o.band_count(visible) {
            let w = o.band_weight(k, visible);
            let (n, dn) = self.basis().eval_grad3(p * o.frequency(k));
            v += w * n;
            g += dn * (w * o.frequency(k));
        }
        (v, g)
    }

    /// A bound on `|eval3_band(·, visible)|`.
    #[must_use]
    pub fn bound_band(&self, visible: f64) -> f64 {
        self.basis().bound() * self.octaves().band_weight_sum(visible)
    }

    /// A Lipschitz constant of `eval3_band(·, visible)`.
    #[must_use]
    pub fn lipschitz3_band(&self, visible: f64) -> f64 {
        self.basis().lipschitz3() * self.octaves().band_weighted_frequency_sum(visible)
    }
}

impl<B: Field> Turbulence<B> {
    /// Turbulence at the 3-D point `p` summed over `visible` octaves.
    #[must_use]
    pub fn eval3_band(&self, p: DVec3, visible: f64) -> f64 {
        let o = self.octaves();
        (0..o.band_count(visible))
            .map(|k| o.band_weight(k, visible) * self.basis().eval3(p * o.frequency(k)).abs())
            .sum()
    }

    /// The value and (one-sided on the creases) gradient of
    /// [`eval3_band`](Self::eval3_band).
    #[must_use]
    pub fn eval_grad3_band(&self, p: DVec3, visible: f64) -> (f64, DVec3) {
        let o = self.octaves();
        let mut v = 0.0;
        let mut g = DVec3::ZERO;
        for k in 0..o.band_count(visible) {
            let w = o.band_weight(k, visible);
            let (n, dn) = self.basis().eval_grad3(p * o.frequency(k));
            v += w * n.abs();
            g += dn * (w * o.frequency(k) * sign(n));
        }
        (v, g)
    }
}

impl<B: Field> Multifractal<B> {
    /// The cascade at the 3-D point `p` with only `visible` octaves'
    /// noise: a cascade is a product, so dropping a factor would change its
    /// magnitude; instead each octave's basis value is faded towards its
    /// mean 0 by [`Octaves::band_factor`] (the RenderMan `filteredsnoise`
    /// way), so an unresolved octave contributes its mean factor (`offset`
    /// in the additive form, `offset·w_k` in the weighted one). Equal to
    /// [`Field::eval3`] for `visible ≥` the octave count.
    #[must_use]
    pub fn eval3_band(&self, p: DVec3, visible: f64) -> f64 {
        if visible.is_nan() {
            return f64::NAN;
        }
        let o = self.octaves();
        let q = self.params();
        let mut v = 1.0;
        for k in 0..o.count() {
            let fade = (visible - k as f64).clamp(0.0, 1.0);
            let n = if fade > 0.0 {
                self.basis().eval3(p * o.frequency(k)) * fade
            } else {
                0.0
            };
            let a = o.amplitude(k);
            let f = match q.form {
                CascadeForm::Weighted => (n + q.offset) * a,
                CascadeForm::Additive => q.offset + a * n,
            };
            v *= 1.0 + o.partial(k) * (f - 1.0);
        }
        v
    }
}

impl<V: VectorField> VectorFbm<V> {
    /// The vector fBm at the 3-D point `p` summed over `visible` octaves.
    #[must_use]
    pub fn eval3_band(&self, p: DVec3, visible: f64) -> DVec3 {
        let o = self.octaves();
        (0..o.band_count(visible))
            .map(|k| self.field().eval3(p * o.frequency(k)) * o.band_weight(k, visible))
            .sum()
    }

    /// A bound on `|eval3_band(·, visible)|`.
    #[must_use]
    pub fn bound_band(&self, visible: f64) -> f64 {
        self.field().bound() * self.octaves().band_weight_sum(visible)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{GainConvention, Multifractal, Perlin, Spectral, VecNoise};

    fn fbm(octaves: f64) -> Fbm<Perlin> {
        Fbm::new(
            Perlin::new(3),
            Spectral::default()
                .with_octaves(octaves)
                .with_lacunarity(2.0)
                .with_h(0.6),
        )
        .unwrap()
    }

    #[test]
    fn full_band_equals_plain_evaluation() {
        for octaves in [1.0, 3.5, 8.0, 9.25] {
            let f = fbm(octaves);
            assert_eq!(f.octaves().total(), octaves);
            for i in 0..50 {
                let p = DVec3::new(0.37 * i as f64, -1.3 + 0.11 * i as f64, 2.9);
                let a = f.eval3(p);
                for v in [octaves, octaves + 0.5, 100.0, f64::INFINITY] {
                    let b = f.eval3_band(p, v);
                    assert!((a - b).abs() <= 1e-15 * a.abs().max(1.0), "{a} {b}");
                }
                let (gv, gg) = f.eval_grad3(p);
                let (bv, bg) = f.eval_grad3_band(p, octaves);
                assert!((gv - bv).abs() < 1e-14 && (gg - bg).length() < 1e-12);
            }
        }
    }

    #[test]
    fn fractional_band_is_a_partial_octave() {
        // fBm(p; k + t) = fBm(p; k) + t·w_k·N(λ^k p), as for the octave count itself.
        let f = fbm(8.0);
        let o = f.octaves().clone();
        let p = DVec3::new(0.3, 1.7, -2.2);
        for k in 0..7usize {
            for t in [0.0, 0.25, 0.5, 0.999] {
                let lhs = f.eval3_band(p, k as f64 + t);
                let rhs = f.eval3_band(p, k as f64)
                    + t * o.amplitude(k) * f.basis().eval3(p * o.frequency(k));
                assert!((lhs - rhs).abs() < 1e-14, "k={k} t={t}");
            }
        }
        assert_eq!(f.eval3_band(p, 0.0), 0.0);
        assert_eq!(f.eval3_band(p, -3.0), 0.0);
        assert!(f.eval3_band(p, f64::NAN).is_nan());
    }

    #[test]
    fn terms_sum_to_the_band_bit_for_bit() {
        let f = fbm(9.5);
        let p = DVec3::new(0.7, -2.3, 4.1);
        for v in [0.0, 2.5, 7.0, 9.5, 30.0] {
            let mut terms = [0.0; 12];
            f.eval3_band_terms(p, v, 0, &mut terms[..5]);
            f.eval3_band_terms(p, v, 5, &mut terms[5..]);
            let sum = terms.iter().fold(0.0, |a, t| a + t);
            assert_eq!(sum.to_bits(), (f.eval3_band(p, v) + 0.0).to_bits(), "v={v}");
        }
    }

    #[test]
    fn band_bounds_hold_and_shrink() {
        let f = fbm(8.0);
        let mut last = f64::INFINITY;
        for v in [8.0, 6.5, 4.0, 2.0, 1.0] {
            let l = f.lipschitz3_band(v);
            assert!(l <= last);
            last = l;
            for i in 0..200 {
                let p = DVec3::new(0.013 * i as f64, 0.7, -0.02 * i as f64);
                assert!(f.eval3_band(p, v).abs() <= f.bound_band(v));
            }
        }
    }

    #[test]
    fn cascade_band_fades_factors_to_their_mean() {
        let m = Multifractal::new(Perlin::new(5), crate::MultifractalParams::multicolor()).unwrap();
        let p = DVec3::new(0.3, -1.2, 2.2);
        assert_eq!(m.eval3_band(p, 8.0), m.eval3(p));
        assert_eq!(m.eval3_band(p, 100.0), m.eval3(p));
        // No octave resolved: every factor is its mean, the zero offset.
        let mean = libm::pow(0.2, 8.0);
        assert!((m.eval3_band(p, 0.0) - mean).abs() < 1e-18);
        assert!(m.eval3_band(p, f64::NAN).is_nan());
    }

    #[test]
    fn vector_and_turbulence_bands() {
        let s = Spectral::default()
            .with_h(0.5)
            .with_octaves(6.0)
            .with_convention(GainConvention::Raw);
        let v = VectorFbm::new(VecNoise::new(Perlin::new(1)), s).unwrap();
        let t = Turbulence::new(Perlin::new(1), s).unwrap();
        let p = DVec3::new(1.1, -0.4, 0.9);
        assert!((v.eval3(p) - v.eval3_band(p, 6.0)).length() < 1e-14);
        assert!((t.eval3(p) - t.eval3_band(p, 6.0)).abs() < 1e-14);
        let two = v.eval3_band(p, 2.0);
        let o = v.octaves();
        let manual = v.field().eval3(p) + v.field().eval3(p * o.frequency(1)) * o.amplitude(1);
        assert!((two - manual).length() < 1e-14);
        assert!(t.eval3_band(p, 3.0) >= 0.0);
        assert!(v.eval3_band(p, 3.5).length() <= v.bound_band(3.5));
    }
}
