//! Puffy clouds: thresholded fBm over a blue sky.

use glam::DVec3;
use natura_noise::{Fbm, Perlin};

use crate::error::{Result, colour, in_range, positive};
use crate::footprint::{Footprint, fbm_at, smoothstep};
use crate::fractals::{fbm, spectral};
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// Parameters of [`PuffyClouds`]; `Default` is the `puffyclouds` shader's.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct PuffyCloudsParams {
    /// Seed of the noise.
    pub seed: u64,
    /// Texture frequency: larger values make smaller clouds (1).
    pub txtscale: f64,
    /// The sky between the clouds (0.15, 0.15, 0.6).
    pub skycolor: DVec3,
    /// The clouds' colour (white).
    pub cloudcolor: DVec3,
    /// fBm octaves (8); fewer give smoother, blobbier clouds.
    pub octaves: f64,
    /// fBm `H` (0.5): larger values give smoother cloud edges.
    pub h: f64,
    /// fBm lacunarity (2).
    pub lacunarity: f64,
    /// fBm value below which the sky is clear (0): raise it for fewer clouds.
    /// Must be below 1, where the clouds reach full cover.
    pub threshold: f64,
}

impl Default for PuffyCloudsParams {
    fn default() -> Self {
        Self {
            seed: 0,
            txtscale: 1.0,
            skycolor: DVec3::new(0.15, 0.15, 0.6),
            cloudcolor: DVec3::ONE,
            octaves: 8.0,
            h: 0.5,
            lacunarity: 2.0,
            threshold: 0.0,
        }
    }
}

impl PuffyCloudsParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        positive("txtscale", self.txtscale)?;
        colour("skycolor", self.skycolor)?;
        colour("cloudcolor", self.cloudcolor)?;
        in_range(
            "threshold",
            self.threshold,
            -1e6,
            1.0 - 1e-9,
            "must be finite and < 1",
        )?;
        spectral(self.h, self.lacunarity, self.octaves).validate()?;
        Ok(())
    }
}

/// Musgrave's puffy clouds (Musgrave 1998, "Clouds: Puffy Clouds"): fBm,
/// read as sky below `threshold` and blended to cloud above it,
///
/// ```text
/// value = fBm(txtscale·P);   Ct = mix(skycolor, cloudcolor, smoothstep(threshold, 1, value))
/// ```
///
/// The shader's fBm is assumed to lie in `[−1, 1]`, so "any value less than
/// zero represents blue sky". Unlit, as the shader (`Ci = Ct`).
#[derive(Clone, Debug)]
pub struct PuffyClouds {
    params: PuffyCloudsParams,
    fbm: Fbm<Perlin>,
}

impl PuffyClouds {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`PuffyCloudsParams::validate`].
    pub fn new(params: PuffyCloudsParams) -> Result<Self> {
        params.validate()?;
        let fbm = fbm(
            params.seed,
            "puffy",
            spectral(params.h, params.lacunarity, params.octaves),
        )?;
        Ok(Self { params, fbm })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &PuffyCloudsParams {
        &self.params
    }

    /// The cloud cover in `[0, 1]` at `p`: `smoothstep(threshold, 1, fBm)`.
    #[must_use]
    pub fn cover(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        let value = fbm_at(&self.fbm, p * q.txtscale, fp.scaled(q.txtscale));
        smoothstep(q.threshold, 1.0, value)
    }

    /// The colour at `p`.
    #[must_use]
    pub fn colour(&self, p: DVec3, fp: Footprint) -> DVec3 {
        let q = &self.params;
        display_to_linear(q.skycolor.lerp(q.cloudcolor, self.cover(p, fp)))
    }
}

impl SolidTexture for PuffyClouds {
    fn name(&self) -> &'static str {
        "puffy clouds"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Colour
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::colour(self.colour(p, fp))
    }
}
