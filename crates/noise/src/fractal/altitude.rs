//! Fractal statistics by altitude: Musgrave's heterogeneous fBm `hfBm`
//! (Musgrave 1993, §2.3.2.3; Musgrave et al. 1989, §3.3).

use crate::error::{NoiseError, Result, finite};
use crate::field::Field;
use crate::fractal::Spectral;
use crate::fractal::batch_rows::{Pt, RowSet, multifractal};
use crate::lattice_math::Simd;
use glam::{DVec2, DVec3};

/// Parameters of [`StatsByAltitude`] (the `c_t`, `c_s`, `c_0` of Musgrave 1993,
/// §2.3.2.3.1).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct StatsByAltitudeParams {
    /// H, λ, octaves, frequency. Musgrave 1993, §2.3.2.3.1 writes the
    /// amplitude as `ϖ = λ^(−β/2)`: use
    /// [`GainConvention::HalfBeta`](crate::GainConvention::HalfBeta) to
    /// reproduce it.
    pub spectral: Spectral,
    /// `c_t`: shifts the basis so `N + c_t` is (nearly) always positive
    /// (0.7 in the C code).
    pub shift: f64,
    /// `c_s`: scales the shifted basis; larger values roughen high ground faster.
    pub scale: f64,
    /// `c_0`: "sea level", added to the first octave.
    pub sea_level: f64,
}

impl Default for StatsByAltitudeParams {
    /// The C code's constants (`c_t = 0.7`, `c_s = 1`, `c_0 = 0`) with `H = 0.8`.
    fn default() -> Self {
        Self {
            spectral: Spectral::default().with_h(0.8),
            shift: 0.7,
            scale: 1.0,
            sea_level: 0.0,
        }
    }
}

impl StatsByAltitudeParams {
    /// Checks the spectral parameters and finite shift, scale and sea level.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] naming the first parameter that is NaN, infinite or outside its domain, or [`NoiseError::OctavesBeyondPrecision`] if the octave count passes the precision limit for the lacunarity (the spectral parameters' own checks included).
    pub fn validate(&self) -> Result<()> {
        self.spectral.validate()?;
        finite("shift", self.shift)?;
        finite("scale", self.scale)?;
        finite("sea_level", self.sea_level)
    }
}

multifractal! {
/// Fractal statistics by altitude: the power of each octave is proportional
/// to the altitude so far, so high ground is rough and low ground smooth
/// ("crossover scale modulated by altitude", Musgrave et al. 1989, §3.3).
///
/// The canonical equation form (Musgrave 1993, §2.3.2.3.1; Musgrave et al.
/// 1989, §3.3):
/// ```text
/// A_0 = (N(p) + c_t)·c_s + c_0
/// A_k = A_{k−1} + A_{k−1}·(N(λ^k p) + c_t)·c_s·w_k       (× t for a partial octave)
/// ```
/// The dissertation's three statements of this model disagree: its
/// pseudo-code (`result + min(1,result) + …`), its C code (which multiplies
/// by the previous *increment*) and this equation are three different
/// algorithms, and the C code's `SMALL` is never defined; the equation is implemented here and
/// the C
/// code as [`StatsByAltitudeLegacy`]. The form is multiplicative: `A_0 = 0`
/// gives 0 everywhere, and with `(N + c_t)·c_s ≥ 0` and `A_0 > 0` the
/// altitude never decreases with octaves.
StatsByAltitude(StatsByAltitudeParams),
"Statistics-by-altitude fBm over `basis` (params validated)."
}

impl<B: Field> StatsByAltitude<B> {
    fn value<P: Pt>(&self, p: P) -> f64 {
        let q = &self.params;
        let o = &self.oct;
        let mut a = (P::eval(&self.basis, p * o.frequency(0)) + q.shift) * q.scale + q.sea_level;
        for k in 1..o.count() {
            a += a * (P::eval(&self.basis, p * o.frequency(k)) + q.shift) * q.scale * o.weight(k);
        }
        a
    }

    fn value_grad<P: Pt>(&self, p: P) -> (f64, P) {
        let q = &self.params;
        let o = &self.oct;
        let (n, dn) = P::eval_grad(&self.basis, p * o.frequency(0));
        let mut a = (n + q.shift) * q.scale + q.sea_level;
        let mut g = dn * (q.scale * o.frequency(0));
        for k in 1..o.count() {
            let (n, dn) = P::eval_grad(&self.basis, p * o.frequency(k));
            let c = q.scale * o.weight(k);
            let f = 1.0 + (n + q.shift) * c;
            g = g * f + dn * (a * c * o.frequency(k));
            a *= f;
        }
        (a, g)
    }

    fn bound_impl(&self) -> f64 {
        let q = &self.params;
        let b = self.basis.bound();
        let mut a = (b + q.shift.abs()) * q.scale.abs() + q.sea_level.abs();
        for k in 1..self.oct.count() {
            a *= 1.0 + (b + q.shift.abs()) * q.scale.abs() * self.oct.weight(k);
        }
        a
    }

    fn lipschitz_impl(&self, l: f64) -> f64 {
        let q = &self.params;
        let o = &self.oct;
        let b = self.basis.bound();
        let mut a = (b + q.shift.abs()) * q.scale.abs() + q.sea_level.abs();
        let mut d = l * q.scale.abs() * o.frequency(0);
        for k in 1..o.count() {
            let c = q.scale.abs() * o.weight(k);
            let f = 1.0 + (b + q.shift.abs()) * c;
            d = d * f + a * c * l * o.frequency(k);
            a *= f;
        }
        d
    }

    fn rows<R: RowSet>(&self, simd: Simd, rows: R, step: f64, out: &mut [f32]) {
        let q = &self.params;
        let (shift, scale, sea) = (q.shift as f32, q.scale as f32, q.sea_level as f32);
        let o = &self.oct;
        rows.octave_rows(
            &self.basis,
            simd,
            o,
            step,
            out,
            #[inline(always)]
            |k, n, acc, _| {
                if k == 0 {
                    for (a, &v) in acc.iter_mut().zip(n) {
                        *a = (v + shift) * scale + sea;
                    }
                } else {
                    let c = scale * o.weight(k) as f32;
                    for (a, &v) in acc.iter_mut().zip(n) {
                        *a += *a * (v + shift) * c;
                    }
                }
            },
        );
    }
}

/// The dissertation's C `hfBm(point, omega, octaves)` (Musgrave 1993,
/// §2.3.2.3.1), reproduced as printed, for its pictures (Plates 2.4-2.5, 4.2):
/// ```text
/// a = prev = 0.7 + N(p);  o = ω
/// for i = 1; i < octaves: p *= 2; prev = prev·o·(0.7 + N(p)); a += prev
///                         if prev < SMALL: break;  o *= ω
/// return 0.15/ω · a
/// ```
/// Quirks kept: λ is hard-wired to 2; each term multiplies the previous
/// *increment* (so octave k carries `ω^(k(k+1)/2)`, a super-geometric decay);
/// the octave count rounds up; and a negative increment ends the loop. `SMALL`
/// is undefined in the source: [`small`](Self::small) defaults to `VERY_SMALL =
/// 1e-4` (Musgrave 1998, "Gaea: Building an Entire Planet").
#[derive(Clone, Debug, PartialEq)]
pub struct StatsByAltitudeLegacy<B> {
    basis: B,
    omega: f64,
    octaves: f64,
    small: f64,
}

impl<B: Field> StatsByAltitudeLegacy<B> {
    /// The C `hfBm` over `basis` with gain `omega` (in `(0, ∞)`) and `octaves` (in `(0, 64]`).
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] if `omega` or `octaves` is NaN, infinite or outside its domain.
    pub fn new(basis: B, omega: f64, octaves: f64) -> Result<Self> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(NoiseError::InvalidParam {
                name: "omega",
                value: omega,
                expected: "must be finite and > 0",
            });
        }
        crate::error::in_range(
            "octaves",
            octaves,
            f64::MIN_POSITIVE,
            64.0,
            "must be in (0, 64]",
        )?;
        Ok(Self {
            basis,
            omega,
            octaves,
            small: 1e-4,
        })
    }

    /// The early-exit threshold `SMALL`.
    #[must_use]
    pub fn small(&self) -> f64 {
        self.small
    }

    fn value<P: Pt>(&self, p: P) -> f64 {
        let mut tp = p;
        let mut prev = 0.7 + P::eval(&self.basis, p);
        let mut a = prev;
        let mut o = self.omega;
        let mut i = 1.0;
        while i < self.octaves {
            tp = tp * 2.0;
            prev = prev * o * (0.7 + P::eval(&self.basis, tp));
            a += prev;
            if prev < self.small {
                break;
            }
            o *= self.omega;
            i += 1.0;
        }
        0.15 / self.omega * a
    }
}

impl<B: Field> Field for StatsByAltitudeLegacy<B> {
    fn eval2(&self, p: DVec2) -> f64 {
        self.value(p)
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.value(p)
    }
    fn bound(&self) -> f64 {
        let b = 0.7 + self.basis.bound();
        let (mut prev, mut a, mut o) = (b, b, self.omega);
        let mut i = 1.0;
        while i < self.octaves {
            prev *= o * b;
            a += prev;
            o *= self.omega;
            i += 1.0;
        }
        0.15 / self.omega * a
    }
    /// Infinite: the early exit makes the field discontinuous.
    fn lipschitz2(&self) -> f64 {
        f64::INFINITY
    }
    fn lipschitz3(&self) -> f64 {
        f64::INFINITY
    }
}
