//! Venus: cloud streaks sheared by the Coriolis effect.

use glam::DVec3;
use natura_noise::{DistNoise, Fbm, Perlin, Twist, TwistLaw};

use crate::error::{Result, colour, finite, non_negative};
use crate::footprint::{Footprint, fbm_at};
use crate::fractals::{dist_fbm, spectral};
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// Parameters of [`Venus`]; `Default` is the RenderMan `venus` shader's
/// (Musgrave 1998, "The Coriolis Effect").
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct VenusParams {
    /// Seed of the noise.
    pub seed: u64,
    /// Mean brightness of the clouds (1).
    pub offset: f64,
    /// Contrast of the cloud streaks (0.6).
    pub scale: f64,
    /// Coriolis twist (0.22): turns per unit squared distance from the pole
    /// axis; larger values shear the streaks more.
    pub twist: f64,
    /// fBm `H` (0.65).
    pub h: f64,
    /// fBm octaves (8).
    pub octaves: f64,
    /// fBm lacunarity (2).
    pub lacunarity: f64,
    /// Distortion of the `DistNoise` basis (1; 0 gives plain fBm).
    pub distortion: f64,
    /// The sphere's colour: "a pale yellow sphere" (the shade is natura's;
    /// the source gives none).
    pub colour: DVec3,
}

impl Default for VenusParams {
    fn default() -> Self {
        Self {
            seed: 0,
            offset: 1.0,
            scale: 0.6,
            twist: 0.22,
            h: 0.65,
            octaves: 8.0,
            lacunarity: 2.0,
            distortion: 1.0,
            colour: DVec3::new(0.93, 0.86, 0.62),
        }
    }
}

impl VenusParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        finite("offset", self.offset)?;
        finite("scale", self.scale)?;
        finite("twist", self.twist)?;
        non_negative("distortion", self.distortion)?;
        colour("colour", self.colour)?;
        spectral(self.h, self.lacunarity, self.octaves).validate()?;
        Ok(())
    }
}

/// Musgrave's Venus (Musgrave 1993, §5.4, `Coriolis`; Musgrave 1998, "The
/// Coriolis Effect", `venus`): the texture point is rotated about the z axis
/// by `θ = 2π·twist·r²`, `r` the distance of the point's direction from the
/// axis ("a twist of the clouds as the square of the radius from the axis of
/// rotation"), and the sphere's colour is scaled by
///
/// ```text
/// value = |offset + scale·fBm(rotated P)|
/// ```
///
/// with the "modified fBm" both sources' text describes (`DistfBm`, the
/// dissertation's code uses the similar `VLfBm`).
///
/// **Errata corrected.** The RenderMan listing's call
/// `fBm(PP, filtwidth/octaves, 2, H)` has one argument too few (the octave
/// count is folded into the filter width); it is read as
/// `fBm(PP, filtwidth, octaves, 2, H)`. The C code passes `omega` as a raw
/// gain and uses the unnormalised hit point; natura follows the shader
/// (`H` a spectral exponent, `r` from the unit direction). The colour is
/// clamped to `[0, 1]`.
#[derive(Clone, Debug)]
pub struct Venus {
    params: VenusParams,
    twist: Twist,
    fbm: Fbm<DistNoise<Perlin>>,
}

impl Venus {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`VenusParams::validate`].
    pub fn new(params: VenusParams) -> Result<Self> {
        params.validate()?;
        let twist = Twist::new(TwistLaw::Quadratic {
            twist: params.twist,
        })?;
        let fbm = dist_fbm(
            params.seed,
            "venus",
            spectral(params.h, params.lacunarity, params.octaves),
            params.distortion,
        )?;
        Ok(Self { params, twist, fbm })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &VenusParams {
        &self.params
    }

    /// The Coriolis-twisted texture point.
    #[must_use]
    pub fn twisted(&self, p: DVec3) -> DVec3 {
        let n = p.normalize_or_zero();
        let (s, c) = self.twist.angle(n.x.hypot(n.y)).sin_cos();
        DVec3::new(c * p.x - s * p.y, s * p.x + c * p.y, p.z)
    }

    /// The cloud brightness `|offset + scale·fBm|` at `p`.
    #[must_use]
    pub fn value(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        (q.offset + q.scale * fbm_at(&self.fbm, self.twisted(p), fp)).abs()
    }

    /// The colour at `p`.
    #[must_use]
    pub fn colour(&self, p: DVec3, fp: Footprint) -> DVec3 {
        display_to_linear(self.params.colour * self.value(p, fp))
    }
}

impl SolidTexture for Venus {
    fn name(&self) -> &'static str {
        "venus"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Colour
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::colour(self.colour(p, fp))
    }
}
