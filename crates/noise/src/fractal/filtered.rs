//! Band-limited fBm: octaves fade out as they approach the filter width
//! (RenderMan `vfBm` loop with `filteredsnoise`, Musgrave 1998, "Distortion for
//! Cirrus Clouds and Global Circulation").

use glam::{DVec2, DVec3};

use crate::error::{NoiseError, Result};
use crate::field::Field;
use crate::fractal::Spectral;
use crate::fractal::fbm::Fbm;

/// `1 − smoothstep(0.2, 0.6, w)`: the fade of Musgrave 1998, "Distortion for
/// Cirrus Clouds and Global Circulation" that "crudely antialias\[es\] snoise
/// by fading to its average value at the Nyquist limit", for a filter width `w`
/// in lattice units. 1 for `w ≤ 0.2`, 0 for `w ≥ 0.6`, continuous and monotone
/// between.
#[must_use]
pub fn filter_fade(w: f64) -> f64 {
    let t = ((w - 0.2) / 0.4).clamp(0.0, 1.0);
    1.0 - t * t * (3.0 - 2.0 * t)
}

/// fBm that drops octaves finer than a filter width: octave `k` is scaled by
/// [`filter_fade`]`(width·f_k)`, and the loop stops once `width·f_k ≥ 1`
/// (where the fade is already 0, so the output is continuous in the width).
/// As the width → 0 it equals [`Fbm`]; octave `k` contributes nothing once
/// `width ≥ 0.6/f_k`.
///
/// As a [`Field`] it uses its stored [`width`](Self::width); call
/// [`eval2_width`](Self::eval2_width)/[`eval3_width`](Self::eval3_width) to
/// pass a per-point width (e.g. from a ray's footprint).
#[derive(Clone, Debug, PartialEq)]
pub struct FilteredFbm<B> {
    fbm: Fbm<B>,
    width: f64,
}

impl<B: Field> FilteredFbm<B> {
    /// Filtered fBm of `basis` with the default `width` (in world units, ≥ 0).
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] if `width` is NaN, infinite or negative;
    /// otherwise as [`Spectral::validate`](crate::Spectral::validate).
    pub fn new(basis: B, spectral: Spectral, width: f64) -> Result<Self> {
        if !(width.is_finite() && width >= 0.0) {
            return Err(NoiseError::InvalidParam {
                name: "width",
                value: width,
                expected: "must be finite and ≥ 0",
            });
        }
        Ok(Self {
            fbm: Fbm::new(basis, spectral)?,
            width,
        })
    }

    /// The stored filter width.
    #[must_use]
    pub fn width(&self) -> f64 {
        self.width
    }

    fn sum(&self, width: f64, eval: impl Fn(f64) -> f64) -> f64 {
        let o = self.fbm.octaves();
        let mut v = 0.0;
        for k in 0..o.count() {
            let w = width * o.frequency(k);
            if w >= 1.0 {
                break;
            }
            v += o.weight(k) * filter_fade(w) * eval(o.frequency(k));
        }
        v
    }

    /// The value at `p` for filter width `width` (world units).
    #[must_use]
    pub fn eval2_width(&self, p: DVec2, width: f64) -> f64 {
        self.sum(width, |f| self.fbm.basis().eval2(p * f))
    }

    /// The value at `p` for filter width `width` (world units).
    #[must_use]
    pub fn eval3_width(&self, p: DVec3, width: f64) -> f64 {
        self.sum(width, |f| self.fbm.basis().eval3(p * f))
    }
}

impl<B: Field> Field for FilteredFbm<B> {
    fn eval2(&self, p: DVec2) -> f64 {
        self.eval2_width(p, self.width)
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.eval3_width(p, self.width)
    }
    fn bound(&self) -> f64 {
        self.fbm.bound()
    }
    fn lipschitz2(&self) -> f64 {
        self.fbm.lipschitz2()
    }
    fn lipschitz3(&self) -> f64 {
        self.fbm.lipschitz3()
    }
}
