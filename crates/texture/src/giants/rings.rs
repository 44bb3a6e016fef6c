//! Planetary rings: a one-dimensional fBm of radius as the density of a disk.

use glam::DVec3;
use natura_noise::{Fbm, Perlin};

use crate::error::{Result, colour, finite, in_range, positive};
use crate::footprint::{Footprint, fbm_at};
use crate::fractals::{fbm, spectral};
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// Parameters of [`Rings`], in units of the planet's radius. The source's C
/// function takes these arguments but prints no values (Figs. 15.17 and
/// 15.18); the defaults are natura's, a broad Saturn-like system.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct RingsParams {
    /// Seed of the noise.
    pub seed: u64,
    /// Inner edge of the rings (1.25 radii).
    pub inner_rad: f64,
    /// Outer edge of the rings (2.3 radii).
    pub outer_rad: f64,
    /// fBm `H` (`f_dim`, 0.4): smaller values give more, finer ringlets.
    pub f_dim: f64,
    /// fBm octaves (8).
    pub octaves: f64,
    /// Contrast of the density (0.9).
    pub density_scale: f64,
    /// Mean density (0.45).
    pub offset: f64,
    /// Width of the inner fade, as a fraction of the ring width (0.05).
    pub inner_rolloff: f64,
    /// Width of the outer fade, as a fraction of the ring width (0.08).
    pub outer_rolloff: f64,
    /// fBm cycles per unit radius (6).
    pub text_scale: f64,
    /// Offsets of the fBm's 1-D domain (x) and of the line it runs along (y, z).
    pub offset_point: DVec3,
    /// The ring particles' colour (0.82, 0.76, 0.64).
    pub colour: DVec3,
}

impl Default for RingsParams {
    fn default() -> Self {
        Self {
            seed: 0,
            inner_rad: 1.25,
            outer_rad: 2.3,
            f_dim: 0.4,
            octaves: 8.0,
            density_scale: 0.9,
            offset: 0.45,
            inner_rolloff: 0.05,
            outer_rolloff: 0.08,
            text_scale: 6.0,
            offset_point: DVec3::new(0.0, 0.37, 0.71),
            colour: DVec3::new(0.82, 0.76, 0.64),
        }
    }
}

impl RingsParams {
    /// Checks every parameter (`0 < inner_rad < outer_rad`, rolloffs in `[0, 1]`).
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        positive("inner_rad", self.inner_rad)?;
        if !(self.outer_rad.is_finite() && self.outer_rad > self.inner_rad) {
            return Err(crate::error::invalid(
                "outer_rad",
                self.outer_rad,
                "must be finite and > inner_rad",
            ));
        }
        finite("density_scale", self.density_scale)?;
        finite("offset", self.offset)?;
        in_range(
            "inner_rolloff",
            self.inner_rolloff,
            0.0,
            1.0,
            "must be in [0, 1]",
        )?;
        in_range(
            "outer_rolloff",
            self.outer_rolloff,
            0.0,
            1.0,
            "must be in [0, 1]",
        )?;
        positive("text_scale", self.text_scale)?;
        if !self.offset_point.is_finite() {
            return Err(crate::error::invalid(
                "offset_point",
                self.offset_point,
                "must be finite",
            ));
        }
        colour("colour", self.colour)?;
        spectral(self.f_dim, 2.0, self.octaves).validate()?;
        Ok(())
    }
}

/// Musgrave's planetary rings (Musgrave 1998, "Planetary Rings", `Rings`;
/// Musgrave 1993, §5.5): the density of a disk through the planet's
/// equator is a one-dimensional fBm of the radius,
///
/// ```text
/// density = density_scale·fBm((text_scale·r, 0, 0) + offset_point; f_dim, λ = 2, octaves) + offset
/// ```
///
/// rolled off to 0 at the inner and outer edges over fractions of the ring
/// width (`1 − (1 − t)²`, `t` the normalised distance from the edge), then
/// clamped to `[0, 1]`. "Any resemblance to Saturn's rings, or the gaps
/// therein, is entirely fictitious."
///
/// **Errata.** The listing calls `fBm(point, f_dim, 2.0, octaves)`, the C
/// code's `(point, H, λ, octaves)` order: `f_dim` is `H`. It stores the
/// result in an undeclared global `transparency = 1 − density`; the density
/// is returned instead. A zero rolloff width means no rolloff (the listing
/// would divide by zero).
#[derive(Clone, Debug)]
pub struct Rings {
    params: RingsParams,
    fbm: Fbm<Perlin>,
}

impl Rings {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`RingsParams::validate`].
    pub fn new(params: RingsParams) -> Result<Self> {
        params.validate()?;
        Ok(Self {
            fbm: fbm(
                params.seed,
                "rings",
                spectral(params.f_dim, 2.0, params.octaves),
            )?,
            params,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &RingsParams {
        &self.params
    }

    /// The rolloff factor at radius `r` (1 inside the band, 0 at its edges).
    #[must_use]
    pub fn rolloff(&self, r: f64) -> f64 {
        let q = &self.params;
        if r < q.inner_rad || r > q.outer_rad {
            return 0.0;
        }
        let band = q.outer_rad - q.inner_rad;
        let curve = |t: f64| {
            let s = 1.0 - t;
            1.0 - s * s
        };
        let inner = band * q.inner_rolloff;
        let outer = band * q.outer_rolloff;
        if inner > 0.0 && r < q.inner_rad + inner {
            curve((r - q.inner_rad) / inner)
        } else if outer > 0.0 && r > q.outer_rad - outer {
            curve((q.outer_rad - r) / outer)
        } else {
            1.0
        }
    }

    /// The density in `[0, 1]` at radius `r` for a footprint of `fp` radii.
    #[must_use]
    pub fn density_at(&self, r: f64, fp: Footprint) -> f64 {
        let q = &self.params;
        let roll = self.rolloff(r);
        if roll <= 0.0 {
            return 0.0;
        }
        let point = DVec3::new(q.text_scale * r, 0.0, 0.0) + q.offset_point;
        let d = q.density_scale * fbm_at(&self.fbm, point, fp.scaled(q.text_scale)) + q.offset;
        (d * roll).clamp(0.0, 1.0)
    }
}

impl SolidTexture for Rings {
    fn name(&self) -> &'static str {
        "rings"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Density
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::density(
            display_to_linear(self.params.colour),
            self.density_at(p.length(), fp),
        )
    }
}
