//! Crossover scales: a different basis at large and small scales (MojoWorld,
//! Musgrave 2001, "Crossover Scales", described only in words there; the blend
//! is ours).

use glam::{DVec2, DVec3};

use crate::error::{NoiseError, Result};
use crate::field::Field;
use crate::fractal::{Octaves, Spectral};

/// fBm whose basis crosses over from `A` (large features) to `B` (small
/// features) between two feature sizes: octave `k`, of feature size `1/f_k`
/// (world units), uses `(1 − t_k)·A + t_k·B` with `t_k = smoothstep(ln begin,
/// ln end, ln(1/f_k))` for `begin > end`. This is one crossover between two
/// bases; MojoWorld allows up to three bases with begin/end scales in metres
/// (Musgrave 2001, "Crossover Scales") (a third would be a second blend of the
/// same form).
#[derive(Clone, Debug, PartialEq)]
pub struct CrossoverFbm<A, B> {
    large: A,
    small: B,
    oct: Octaves,
    t: [f64; crate::fractal::MAX_OCTAVES],
}

impl<A: Field, B: Field> CrossoverFbm<A, B> {
    /// Crossover fBm: `large` for features bigger than `begin`, `small` below
    /// `end` (world units, `begin > end > 0`).
    ///
    /// # Errors
    /// As [`Spectral::validate`](crate::Spectral::validate), and [`NoiseError::InvalidParam`] if `begin` or `end` is invalid.
    pub fn new(large: A, small: B, spectral: Spectral, begin: f64, end: f64) -> Result<Self> {
        let oct = spectral.octaves_table()?;
        if !(end.is_finite() && end > 0.0) {
            return Err(NoiseError::InvalidParam {
                name: "end",
                value: end,
                expected: "must be finite and > 0",
            });
        }
        if !(begin.is_finite() && begin > end) {
            return Err(NoiseError::InvalidParam {
                name: "begin",
                value: begin,
                expected: "must be finite and > end",
            });
        }
        let mut t = [0.0; crate::fractal::MAX_OCTAVES];
        let (lb, le) = (libm::log(begin), libm::log(end));
        for (k, tk) in t.iter_mut().enumerate().take(oct.count()) {
            let s = ((lb - libm::log(1.0 / oct.frequency(k))) / (lb - le)).clamp(0.0, 1.0);
            *tk = s * s * (3.0 - 2.0 * s);
        }
        Ok(Self {
            large,
            small,
            oct,
            t,
        })
    }

    /// The blend weight of the small-scale basis in octave `k`.
    #[must_use]
    pub fn blend(&self, k: usize) -> f64 {
        self.t[k]
    }

    fn sum(&self, eval: impl Fn(usize, f64) -> (f64, f64)) -> f64 {
        let o = &self.oct;
        (0..o.count())
            .map(|k| {
                let t = self.t[k];
                let (a, b) = eval(k, o.frequency(k));
                o.weight(k) * ((1.0 - t) * a + t * b)
            })
            .sum()
    }
}

impl<A: Field, B: Field> Field for CrossoverFbm<A, B> {
    fn eval2(&self, p: DVec2) -> f64 {
        self.sum(|k, f| {
            let t = self.t[k];
            let a = if t < 1.0 {
                self.large.eval2(p * f)
            } else {
                0.0
            };
            let b = if t > 0.0 {
                self.small.eval2(p * f)
            } else {
                0.0
            };
            (a, b)
        })
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.sum(|k, f| {
            let t = self.t[k];
            let a = if t < 1.0 {
                self.large.eval3(p * f)
            } else {
                0.0
            };
            let b = if t > 0.0 {
                self.small.eval3(p * f)
            } else {
                0.0
            };
            (a, b)
        })
    }
    fn bound(&self) -> f64 {
        self.large.bound().max(self.small.bound()) * self.oct.weight_sum()
    }
    fn lipschitz2(&self) -> f64 {
        self.large.lipschitz2().max(self.small.lipschitz2()) * self.oct.weighted_frequency_sum()
    }
    fn lipschitz3(&self) -> f64 {
        self.large.lipschitz3().max(self.small.lipschitz3()) * self.oct.weighted_frequency_sum()
    }
}
