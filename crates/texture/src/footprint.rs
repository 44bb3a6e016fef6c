//! The pixel footprint and level of detail: the one place where the size of
//! what a sample covers becomes the octaves a texture may show.
//!
//! Musgrave's procedural textures are fractals with potentially unlimited
//! high frequencies, which "play merry hell with the point sampling schemes
//! of computer graphics" (Musgrave 1993, §5.1.2). His remedy is to make the
//! number of iterations of the fractal loop a parameter and give it, at each
//! point, the value the screen resolution allows, with the fractional
//! remainder octave (§2.3.2.1) making the result continuous in that number.
//! natura does exactly that: a [`Footprint`] holds the width of the area a
//! sample covers in texture space, [`Footprint::visible`] turns it into a
//! real-valued octave count, and the textures sum their fractals through
//! natura-noise's band-limited evaluation (`Fbm::eval3_band`), so octaves
//! finer than the footprint fade out smoothly and a planet seen from far
//! away does not shimmer.
//!
//! The rule itself is natura-noise's [`visible_octaves`]: octave `k` of
//! lattice frequency `f_k` is kept whole while `width·f_k ≤ ½/λ`, fades out
//! linearly in `log f` over the octave below the Nyquist limit, and is gone
//! from `width·f_k = ½` on (samples `width` apart represent frequencies up to
//! `1/(2·width)`; see that function for why). The rule this module used to
//! state, `1 + log_λ(½ / (width·f₀))`, faded each octave over the octave
//! above the limit instead and so let every footprint alias a partial
//! octave; it is corrected here by one octave. Single noise evaluations (a
//! distortion vector, a crater ray) fade by the same rule with `λ = 2`
//! ([`Footprint::fade`]); the shaders of Musgrave 1998 fade them with
//! `filteredsnoise`, `1 − smoothstep(0.2, 0.6, width·f)` (natura-noise's
//! `filter_fade`), whose ramp straddles the limit, so the octave rule keeps
//! every noise consistent instead.

use glam::DVec3;
use natura_noise::{Fbm, Field, Spectral, Turbulence, VectorFbm, VectorField, visible_octaves};

use crate::error::{Result, invalid};

/// `width × lattice frequency` at which an octave is gone: the Nyquist limit
/// of natura-noise's rule ([`natura_noise::fractal::lod::NYQUIST`]). An
/// octave is kept whole up to `FULL_DETAIL / λ`, a single noise evaluation
/// ([`Footprint::fade`]) up to `FULL_DETAIL / 2`.
#[deprecated(note = "the octave rule lives in natura_noise::visible_octaves; \
                     an octave is gone, not whole, at width·f = FULL_DETAIL")]
pub const FULL_DETAIL: f64 = natura_noise::fractal::lod::NYQUIST;

/// The width of the area one sample covers, in the texture's own space
/// (texture units, not pixels). Zero is a point sample: every octave is summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct Footprint {
    width: f64,
}

impl Footprint {
    /// A point sample: all octaves.
    pub const POINT: Footprint = Footprint { width: 0.0 };

    /// A footprint of `width` texture units.
    ///
    /// # Errors
    /// [`TextureError::InvalidParameter`](crate::TextureError::InvalidParameter)
    /// unless `width` is finite and `≥ 0`.
    pub fn new(width: f64) -> Result<Self> {
        if width.is_finite() && width >= 0.0 {
            Ok(Self { width })
        } else {
            Err(invalid("width", width, "must be finite and ≥ 0"))
        }
    }

    /// The footprint of one pixel of angular size `pixel_angle` (radians)
    /// seen at `distance`, in world units: `distance·pixel_angle`.
    ///
    /// # Errors
    /// [`TextureError::InvalidParameter`](crate::TextureError::InvalidParameter)
    /// unless both are finite and `≥ 0`.
    pub fn of_pixel(distance: f64, pixel_angle: f64) -> Result<Self> {
        crate::error::non_negative("distance", distance)?;
        crate::error::non_negative("pixel_angle", pixel_angle)?;
        Self::new(distance * pixel_angle)
    }

    /// The width, texture units.
    #[must_use]
    pub fn width(self) -> f64 {
        self.width
    }

    /// The same footprint in a space scaled by `factor` (a texture that
    /// evaluates at `factor·p` sees a footprint `|factor|` times wider).
    #[must_use]
    pub fn scaled(self, factor: f64) -> Self {
        let w = self.width * factor.abs();
        Self {
            width: if w.is_finite() { w } else { f64::MAX },
        }
    }

    /// The real-valued number of octaves of a fractal with base frequency
    /// `frequency` and lacunarity `lacunarity` that this footprint shows:
    /// natura-noise's [`visible_octaves`], `log_λ(½ / (width·f₀))`, at least
    /// 0, unbounded for a point sample.
    #[must_use]
    pub fn visible_octaves(self, frequency: f64, lacunarity: f64) -> f64 {
        visible_octaves(self.width, frequency, lacunarity)
    }

    /// [`visible_octaves`](Self::visible_octaves) for a fractal's spectral parameters.
    #[must_use]
    pub fn visible(self, spectral: &Spectral) -> f64 {
        self.visible_octaves(spectral.frequency, spectral.lacunarity)
    }

    /// The weight of one noise evaluation at lattice frequency `frequency`:
    /// the octave rule with `λ = 2` — 1 while the footprint covers at most a
    /// quarter of a cell, falling linearly in `log f` to 0 at half a cell
    /// (the Nyquist limit).
    #[must_use]
    pub fn fade(self, frequency: f64) -> f64 {
        self.visible_octaves(frequency, 2.0).min(1.0)
    }
}

/// A band-limited fBm at `p` for footprint `fp`.
pub(crate) fn fbm_at<B: Field>(f: &Fbm<B>, p: DVec3, fp: Footprint) -> f64 {
    f.eval3_band(p, fp.visible(f.spectral()))
}

/// Value and gradient of [`fbm_at`].
pub(crate) fn fbm_grad_at<B: Field>(f: &Fbm<B>, p: DVec3, fp: Footprint) -> (f64, DVec3) {
    f.eval_grad3_band(p, fp.visible(f.spectral()))
}

/// A band-limited turbulence at `p` for footprint `fp`.
pub(crate) fn turbulence_at<B: Field>(f: &Turbulence<B>, p: DVec3, fp: Footprint) -> f64 {
    f.eval3_band(p, fp.visible(f.spectral()))
}

/// A band-limited vector fBm (built with `spectral`) at `p` for footprint `fp`.
pub(crate) fn vfbm_at<V: VectorField>(
    f: &VectorFbm<V>,
    spectral: &Spectral,
    p: DVec3,
    fp: Footprint,
) -> DVec3 {
    f.eval3_band(p, fp.visible(spectral))
}

/// `smoothstep(e0, e1, x)` as RenderMan defines it (0 below `e0`, 1 above `e1`).
#[must_use]
pub(crate) fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    if x <= e0 {
        0.0
    } else if x >= e1 {
        1.0
    } else {
        let t = (x - e0) / (e1 - e0);
        t * t * (3.0 - 2.0 * t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn visible_octaves_step_by_the_lacunarity() {
        // No octave at the Nyquist limit of the base frequency, one a
        // factor λ below it.
        let fp = Footprint::new(0.5).unwrap();
        assert_eq!(fp.visible_octaves(1.0, 2.0), 0.0);
        assert_eq!(fp.fade(1.0), 0.0);
        assert_eq!(Footprint::new(0.25).unwrap().fade(1.0), 1.0);
        // Each halving of the footprint shows one more octave at λ = 2.
        for k in 1..20 {
            let fp = Footprint::new(0.5 / f64::from(1u32 << k)).unwrap();
            assert!((fp.visible_octaves(1.0, 2.0) - f64::from(k)).abs() < 1e-9);
        }
        assert_eq!(Footprint::POINT.visible_octaves(1.0, 2.0), f64::INFINITY);
        assert_eq!(Footprint::new(1e9).unwrap().visible_octaves(1.0, 2.0), 0.0);
        assert!(Footprint::new(-1.0).is_err());
        assert!(Footprint::new(f64::NAN).is_err());
        assert!(Footprint::of_pixel(10.0, 1e-3).unwrap().width() - 0.01 < 1e-15);
    }

    #[test]
    fn smoothstep_is_renderman_s() {
        assert_eq!(smoothstep(0.0, 1.0, -1.0), 0.0);
        assert_eq!(smoothstep(0.0, 1.0, 2.0), 1.0);
        assert_eq!(smoothstep(0.0, 1.0, 0.5), 0.5);
    }
}
