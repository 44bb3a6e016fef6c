//! Musgrave's vector-valued multifractal `MVfBm`: the continents of Gaea.

use glam::{DVec2, DVec3};

use crate::error::{NoiseError, Result, finite};
use crate::field::Field;
use crate::fractal::{GainConvention, Octaves, Spectral};
use crate::vector::{Smooth, VectorField};
use crate::warp::VlNoise;

/// Parameters of [`VectorMultifractal`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct VectorMultifractalParams {
    /// Gain ω (under [`GainConvention::Raw`], the source's form), λ, octaves
    /// and base frequency. The gain both sets the cascade factor `ω^k` of
    /// octave `k` and caps each octave's weight at `ω`.
    pub spectral: Spectral,
    /// `N_OFFSET`: added to the basis before it multiplies the running weight
    /// (0.7); smaller values damp the cascade faster, so fewer regions stay rough.
    pub offset: f64,
    /// The point scale of the first octave's `VLNoise` weight (1.5): larger
    /// values make the initial roughness map finer.
    pub first_scale: f64,
}

impl Default for VectorMultifractalParams {
    /// The values of the dissertation's Gaea (Musgrave 1993, §5.8, the `PLANET`
    /// texture's argument vector): lacunarity 2, 10 octaves, gain `ω = λ^(−½ −
    /// H)` with `H = −0.48`, i.e. `2^−0.02 ≈ 0.986`, `N_OFFSET = 0.7`,
    /// first-octave `VLNoise` scale 1.5.
    fn default() -> Self {
        Self {
            spectral: Spectral {
                h: libm::pow(2.0, -0.5 + 0.48),
                lacunarity: 2.0,
                octaves: 10.0,
                frequency: 1.0,
                convention: GainConvention::Raw,
            },
            offset: 0.7,
            first_scale: 1.5,
        }
    }
}

impl VectorMultifractalParams {
    /// Checks the spectral parameters, a finite offset and a finite, non-zero first scale.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] naming the first bad parameter (or the
    /// spectral parameters' own errors).
    pub fn validate(&self) -> Result<()> {
        self.spectral.validate()?;
        finite("offset", self.offset)?;
        finite("first_scale", self.first_scale)?;
        if self.first_scale == 0.0 {
            return Err(NoiseError::InvalidParam {
                name: "first_scale",
                value: self.first_scale,
                expected: "must be non-zero",
            });
        }
        Ok(())
    }
}

/// The vector multifractal `MVfBm` of Musgrave 1993, §5.8: a sum of basis
/// gradients (`DNoise`) whose weights cascade, so that some regions of the
/// planet get rough, wiggly coastlines and others stay smooth (heterogeneous
/// fractal dimension; Musgrave 2001, "Building Planets").
///
/// ```text
/// weight = |VLNoise(p, first_scale)|;   result = weight·∇N(p)
/// octave k ≥ 1:  weight = min(1, |weight·ω^k·(offset + N(λ^k p))|)
///                result += min(weight, ω)·∇N(λ^k p)
/// ```
///
/// The octave amplitude is capped at `ω`, not `ω^k`: the decay comes only
/// from the cascading weight, whose factors compound `ω^k` on top of the
/// product of the shifted basis values. A partial last octave contributes its
/// fraction (the listing rounds the octave count up), and the listing's
/// `VERY_SMALL` early exit, which makes the sum jump, is not applied. The
/// listing reads the basis value and its gradient at the same point; here one
/// [`Field::eval_grad3`] call gives both.
#[derive(Clone, Debug, PartialEq)]
pub struct VectorMultifractal<B> {
    basis: B,
    first: VlNoise<B>,
    params: VectorMultifractalParams,
    oct: Octaves,
    omega: f64,
}

impl<B: Smooth + Clone> VectorMultifractal<B> {
    /// The vector multifractal over `basis` (params validated).
    ///
    /// # Errors
    /// As [`VectorMultifractalParams::validate`].
    pub fn new(basis: B, params: VectorMultifractalParams) -> Result<Self> {
        params.validate()?;
        let oct = params.spectral.octaves_table()?;
        let first = VlNoise::vl_noise(basis.clone(), params.first_scale)?;
        Ok(Self {
            basis,
            first,
            omega: params.spectral.gain(),
            params,
            oct,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &VectorMultifractalParams {
        &self.params
    }

    /// The precomputed octave table.
    pub fn octaves(&self) -> &Octaves {
        &self.oct
    }

    /// The weights `min(weight_k, ω)` (octave 0: `weight_0`) of every octave
    /// with a non-zero band factor, for inspection and tests.
    pub fn weights3(&self, p: DVec3, visible: f64, out: &mut [f64]) -> usize {
        let mut n = 0;
        self.walk3(p, visible, |k, w, _| {
            if let Some(slot) = out.get_mut(k) {
                *slot = w;
                n = k + 1;
            }
        });
        n
    }

    /// The value at `p` summed over `visible` octaves (see
    /// [`Fbm::eval3_band`](crate::Fbm::eval3_band)).
    #[must_use]
    pub fn eval3_band(&self, p: DVec3, visible: f64) -> DVec3 {
        let mut r = DVec3::ZERO;
        self.walk3(p, visible, |_, w, g| r += g * w);
        r
    }

    /// Calls `f(k, weight·band factor, ∇N)` for each octave in turn.
    fn walk3(&self, p: DVec3, visible: f64, mut f: impl FnMut(usize, f64, DVec3)) {
        let o = &self.oct;
        let n = o.band_count(visible);
        if n == 0 {
            return;
        }
        let tp = p * o.frequency(0);
        let mut weight = self.first.eval3(tp).abs();
        let (_, g) = self.basis.eval_grad3(tp);
        f(0, weight * o.band_factor(0, visible), g);
        for k in 1..n {
            let (v, g) = self.basis.eval_grad3(p * o.frequency(k));
            weight = (weight * o.amplitude(k) * (self.params.offset + v))
                .abs()
                .min(1.0);
            f(k, weight.min(self.omega) * o.band_factor(k, visible), g);
        }
    }

    /// A bound on `|eval3_band(·, visible)|`.
    #[must_use]
    pub fn bound_band(&self, visible: f64) -> f64 {
        let o = &self.oct;
        let cap = self.omega.min(1.0);
        let l = self.basis.lipschitz3();
        (0..o.band_count(visible))
            .map(|k| {
                let w = if k == 0 { self.basis.bound() } else { cap };
                w * l * o.band_factor(k, visible)
            })
            .sum()
    }

    /// A Lipschitz constant of `eval3_band(·, visible)`: the weights'
    /// Lipschitz constants cascade as the weights do, each term adding
    /// `|∇weight_k|·|∇N| + weight_k·|Hessian N|·f_k`.
    #[must_use]
    pub fn lipschitz3_band(&self, visible: f64) -> f64 {
        let o = &self.oct;
        let (b, l, h) = (
            self.basis.bound(),
            self.basis.lipschitz3(),
            self.basis.hessian_bound(),
        );
        let off = self.params.offset.abs();
        let cap = self.omega.min(1.0);
        let mut lw = self.first.lipschitz3() * o.frequency(0);
        let mut wmax = b;
        let mut total = o.band_factor(0, visible) * (lw * l + wmax * h * o.frequency(0));
        for k in 1..o.band_count(visible) {
            let a = o.amplitude(k);
            lw = a * (off + b) * lw + wmax * a * l * o.frequency(k);
            wmax = (wmax * a * (off + b)).min(1.0);
            total += o.band_factor(k, visible) * (lw * l + wmax.min(cap) * h * o.frequency(k));
        }
        total
    }
}

impl<B: Smooth + Clone> VectorField for VectorMultifractal<B> {
    fn eval3(&self, p: DVec3) -> DVec3 {
        self.eval3_band(p, f64::INFINITY)
    }

    fn eval2(&self, p: DVec2) -> DVec2 {
        let o = &self.oct;
        let tp = p * o.frequency(0);
        let mut weight = self.first.eval2(tp).abs();
        let mut r = self.basis.eval_grad2(tp).1 * (weight * o.partial(0));
        for k in 1..o.count() {
            let (v, g) = self.basis.eval_grad2(p * o.frequency(k));
            weight = (weight * o.amplitude(k) * (self.params.offset + v))
                .abs()
                .min(1.0);
            r += g * (weight.min(self.omega) * o.partial(k));
        }
        r
    }

    fn bound(&self) -> f64 {
        self.bound_band(f64::INFINITY)
    }

    fn lipschitz(&self) -> f64 {
        self.lipschitz3_band(f64::INFINITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Perlin;

    fn mf() -> VectorMultifractal<Perlin> {
        VectorMultifractal::new(Perlin::new(11), VectorMultifractalParams::default()).unwrap()
    }

    #[test]
    fn weights_stay_in_unit_interval_and_under_the_cap() {
        let m = mf();
        let omega = m.params().spectral.gain();
        let mut w = [0.0; 16];
        for i in 0..400 {
            let p = DVec3::new(
                0.173 * i as f64,
                1.0 - 0.031 * i as f64,
                0.5 * (i % 7) as f64,
            );
            let n = m.weights3(p, f64::INFINITY, &mut w);
            assert_eq!(n, 10);
            assert!(w[0] >= 0.0 && w[0] <= 1.0);
            for &x in &w[1..n] {
                assert!((0.0..=omega).contains(&x), "{x}");
            }
        }
    }

    #[test]
    fn matches_the_listing_loop() {
        // The C listing, written out with the basis' own calls.
        let m = mf();
        let b = Perlin::new(11);
        let vl = VlNoise::vl_noise(b, 1.5).unwrap();
        let omega = libm::pow(2.0, -0.02);
        for i in 0..50 {
            let p = DVec3::new(0.41 * i as f64, -0.2 * i as f64, 0.77);
            let mut tp = p;
            let mut weight = vl.eval3(tp).abs();
            let mut result = b.eval_grad3(tp).1 * weight;
            let mut o = omega;
            for _ in 1..10 {
                tp *= 2.0;
                weight *= o * (0.7 + b.eval3(tp));
                weight = weight.abs().min(1.0);
                result += b.eval_grad3(tp).1 * weight.min(omega);
                o *= omega;
            }
            let got = m.eval3(p);
            assert!((got - result).length() < 1e-9, "{got} {result}");
            assert!(got.length() <= m.bound());
        }
    }

    #[test]
    fn lipschitz_bound_holds_on_close_pairs() {
        let m = mf();
        for v in [3.0, 6.5, 10.0] {
            let l = m.lipschitz3_band(v);
            for i in 0..300 {
                let p = DVec3::new(0.0137 * i as f64, 0.3, -0.011 * i as f64);
                let q = p + DVec3::new(1e-4, -2e-4, 1.5e-4);
                let d = (m.eval3_band(p, v) - m.eval3_band(q, v)).length();
                assert!(d <= l * (p - q).length() * (1.0 + 1e-9), "v={v}");
            }
        }
    }

    #[test]
    fn refuses_bad_params() {
        let p = VectorMultifractalParams {
            offset: f64::NAN,
            ..Default::default()
        };
        assert!(VectorMultifractal::new(Perlin::new(0), p).is_err());
        let mut p = VectorMultifractalParams::default();
        p.spectral.octaves = 0.0;
        assert!(VectorMultifractal::new(Perlin::new(0), p).is_err());
        let p = VectorMultifractalParams {
            first_scale: 0.0,
            ..Default::default()
        };
        assert!(VectorMultifractal::new(Perlin::new(0), p).is_err());
    }
}
