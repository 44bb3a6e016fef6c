//! Noise ripples: a two-octave fBm displacement for a mirror-like lake.

use glam::DVec3;
use natura_noise::{Fbm, Perlin};

use crate::error::{Result, finite, positive};
use crate::footprint::{Footprint, fbm_at, fbm_grad_at};
use crate::fractals::{fbm, spectral};
use crate::texture::{Sample, SolidTexture, TextureKind};

/// Parameters of [`Ripples`]; `Default` is the `ripples` shader's.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct RipplesParams {
    /// Seed of the noise.
    pub seed: u64,
    /// Displacement amplitude `Km` (1).
    pub km: f64,
    /// fBm octaves (2: "degenerate", fewer than a fractal needs, but it works).
    pub octaves: f64,
    /// fBm `H` (3.0: each octave 1/8 of the one before, very smooth).
    pub h: f64,
    /// fBm lacunarity (2).
    pub lacunarity: f64,
    /// Per-axis frequency of the ripples (1, 1, 1): stretch one lateral axis
    /// ("scaling it up in one of the lateral directions") to suggest waves.
    pub scale: DVec3,
}

impl Default for RipplesParams {
    fn default() -> Self {
        Self {
            seed: 0,
            km: 1.0,
            octaves: 2.0,
            h: 3.0,
            lacunarity: 2.0,
            scale: DVec3::ONE,
        }
    }
}

impl RipplesParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        finite("km", self.km)?;
        positive("scale.x", self.scale.x)?;
        positive("scale.y", self.scale.y)?;
        positive("scale.z", self.scale.z)?;
        spectral(self.h, self.lacunarity, self.octaves).validate()?;
        Ok(())
    }
}

/// Musgrave's water (Musgrave 1998, "Noise Ripples"): the displacement
/// `Km·fBm(P)` along the normal of "a reflective silver plane" — "the
/// cheapest and easiest trick I ever did with procedural textures". As a
/// bump map its normal comes from the analytic gradient of the fBm
/// ([`SolidTexture::height_gradient`]).
///
/// **Erratum.** The listing calls `fBm(PP, 3.0, 2.0, octaves)`, the older
/// `(point, H, lacunarity, octaves)` argument order of the C code, not the
/// RenderMan `(point, filterwidth, octaves, lacunarity, H)` of the other
/// shaders; read in that order it asks for `H = 3`, `λ = 2`, which is what
/// the defaults are.
#[derive(Clone, Debug)]
pub struct Ripples {
    params: RipplesParams,
    fbm: Fbm<Perlin>,
}

impl Ripples {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`RipplesParams::validate`].
    pub fn new(params: RipplesParams) -> Result<Self> {
        params.validate()?;
        let fbm = fbm(
            params.seed,
            "ripples",
            spectral(params.h, params.lacunarity, params.octaves),
        )?;
        Ok(Self { params, fbm })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &RipplesParams {
        &self.params
    }

    fn footprint(&self, fp: Footprint) -> Footprint {
        fp.scaled(self.params.scale.max_element())
    }

    /// The displacement at `p`.
    #[must_use]
    pub fn height(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        q.km * fbm_at(&self.fbm, p * q.scale, self.footprint(fp))
    }
}

impl SolidTexture for Ripples {
    fn name(&self) -> &'static str {
        "ripples"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Height
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::height(self.height(p, fp))
    }
    fn height_gradient(&self, p: DVec3, fp: Footprint) -> DVec3 {
        let q = &self.params;
        let (_, g) = fbm_grad_at(&self.fbm, p * q.scale, self.footprint(fp));
        g * q.scale * q.km
    }
}
