//! Planet clouds: fBm in a domain stretched by a large-scale distortion, the
//! first approximation to global circulation.

use glam::DVec3;
use natura_noise::{Fbm, Perlin, Spectral, VecNoise, VectorFbm, VectorField, VlNoise};

use crate::error::{Result, finite, in_range, non_negative, positive};
use crate::footprint::{Footprint, fbm_at, vfbm_at};
use crate::fractals::{fbm, perlin, spectral, vfbm, vl_fbm};
use crate::texture::{Sample, SolidTexture, TextureKind};

/// The basis of the cloud fBm.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum CloudBasis {
    /// Perlin noise (the RenderMan `planetclouds` shader). The default.
    #[default]
    Perlin,
    /// The dissertation's `VLNoise`, "variable lacunarity noise" (Musgrave
    /// 1993, §5.2): its fBm has a "stringy, wispy character, somewhat more
    /// cloud-like"; each octave evaluates the noise twice, once with its
    /// gradient (`DNoise`), where Perlin noise evaluates it once.
    VariableLacunarity,
}

/// The vector field that distorts the cloud domain.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum CloudDistortion {
    /// One octave of vector noise: smooth, large-scale streaming (the default).
    #[default]
    Noise,
    /// Vector fBm with the clouds' spectral parameters: Musgrave 1998,
    /// Fig. 15.3, which "looks more like cotton than turbulence".
    Fbm,
}

/// Parameters of [`PlanetClouds`]; `Default` is the RenderMan `planetclouds`
/// shader's (Musgrave 1998, "Distortion for Cirrus Clouds and Global Circulation").
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct PlanetCloudsParams {
    /// Seed of the noises.
    pub seed: u64,
    /// Magnitude of the domain distortion (1): larger values stretch the
    /// clouds into longer streams.
    pub distortion: f64,
    /// What distorts the domain.
    pub distortion_field: CloudDistortion,
    /// Texture frequency of the clouds after distortion (1; the
    /// dissertation's `rescale`): larger values give smaller cloud systems.
    pub rescale: f64,
    /// The fBm basis.
    pub basis: CloudBasis,
    /// fBm `H` (0.7): larger values give smoother clouds.
    pub h: f64,
    /// fBm lacunarity (2).
    pub lacunarity: f64,
    /// fBm octaves (9).
    pub octaves: f64,
    /// Added to the fBm before clamping (0): raise it for more cover; must
    /// exceed −1.
    pub offset: f64,
}

impl Default for PlanetCloudsParams {
    fn default() -> Self {
        Self {
            seed: 0,
            distortion: 1.0,
            distortion_field: CloudDistortion::Noise,
            rescale: 1.0,
            basis: CloudBasis::Perlin,
            h: 0.7,
            lacunarity: 2.0,
            octaves: 9.0,
            offset: 0.0,
        }
    }
}

impl PlanetCloudsParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        non_negative("distortion", self.distortion)?;
        positive("rescale", self.rescale)?;
        finite("offset", self.offset)?;
        in_range("offset", self.offset, -1.0 + 1e-6, f64::MAX, "must be > −1")?;
        self.spectral().validate()?;
        Ok(())
    }

    /// The cloud fBm's spectral parameters (`H` in the C-code sense).
    #[must_use]
    pub fn spectral(&self) -> Spectral {
        spectral(self.h, self.lacunarity, self.octaves)
    }
}

#[derive(Clone, Debug)]
enum Clouds {
    Perlin(Fbm<Perlin>),
    Vl(Fbm<VlNoise<Perlin>>),
}

#[derive(Clone, Debug)]
enum Distortion {
    Noise(VecNoise<Perlin>),
    Fbm(Box<VectorFbm<VecNoise<Perlin>>>),
}

/// Musgrave's planetary cloud texture (Musgrave 1993, §5.2; Musgrave 1998,
/// "Distortion for Cirrus Clouds and Global Circulation"): the density of a
/// cloud layer wrapped round a planet,
///
/// ```text
/// PP = rescale·(P + distortion·V(P))          V: vector noise or vector fBm
/// density = clamp(fBm(PP) + offset, 0, 1) / (1 + offset)
/// ```
///
/// **Errata corrected.** The dissertation's C `Planet_Clouds` computes the
/// distortion vector but never adds it to the point (its "insert
/// distortion" comment has no code), so its clouds are undistorted; here the
/// distortion is applied, as in the RenderMan shader and as the text
/// describes. Its return `result / 1.0+ offset` divides by 1 and then adds
/// the offset (a precedence slip for `/(1 + offset)`), which lets the density
/// exceed 1; here it is `clamp(·, 0, 1)/(1 + offset)`. It passes `H` into
/// `VLfBm`'s raw-gain slot, so octave `k` gets `H^k` instead of `λ^(−kH)`;
/// here `H` is the spectral exponent of every other fBm. Its pseudo-code's
/// `cutoff` (unused in the C) is the offset with the sign flipped
/// (`(result − cutoff)/(1 − cutoff)`), so one `offset` (which may be
/// negative, above −1) covers both; the density is then also capped at 1.
/// The argument vector printed for Plate 4.3 has 6 values for 7 parameters
/// and is not reproduced. The fBm-distorted variant of Fig. 15.3 passes `H`
/// into `VfBm`'s gain slot; here it is `H`.
#[derive(Clone, Debug)]
pub struct PlanetClouds {
    params: PlanetCloudsParams,
    clouds: Clouds,
    distort: Distortion,
}

impl PlanetClouds {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`PlanetCloudsParams::validate`].
    pub fn new(params: PlanetCloudsParams) -> Result<Self> {
        params.validate()?;
        let s = params.spectral();
        let clouds = match params.basis {
            CloudBasis::Perlin => Clouds::Perlin(fbm(params.seed, "clouds", s)?),
            CloudBasis::VariableLacunarity => Clouds::Vl(vl_fbm(params.seed, "clouds", s)?),
        };
        let distort = match params.distortion_field {
            CloudDistortion::Noise => {
                Distortion::Noise(VecNoise::new(perlin(params.seed, "circulation")))
            }
            CloudDistortion::Fbm => Distortion::Fbm(Box::new(vfbm(params.seed, "circulation", s)?)),
        };
        Ok(Self {
            params,
            clouds,
            distort,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &PlanetCloudsParams {
        &self.params
    }

    /// The distorted, rescaled point `PP` where the cloud fBm is evaluated.
    #[must_use]
    pub fn distorted(&self, p: DVec3, fp: Footprint) -> DVec3 {
        let q = &self.params;
        let v = match &self.distort {
            Distortion::Noise(n) => n.eval3(p) * fp.fade(1.0),
            Distortion::Fbm(f) => vfbm_at(f, &q.spectral(), p, fp),
        };
        (p + v * q.distortion) * q.rescale
    }

    /// The raw cloud fBm at `p` (before offset and clamping).
    #[must_use]
    pub fn value(&self, p: DVec3, fp: Footprint) -> f64 {
        let pp = self.distorted(p, fp);
        let fp = fp.scaled(self.params.rescale);
        match &self.clouds {
            Clouds::Perlin(f) => fbm_at(f, pp, fp),
            Clouds::Vl(f) => fbm_at(f, pp, fp),
        }
    }

    /// The cloud density in `[0, 1]` at `p`.
    #[must_use]
    pub fn density(&self, p: DVec3, fp: Footprint) -> f64 {
        let o = self.params.offset;
        ((self.value(p, fp) + o).clamp(0.0, 1.0) / (1.0 + o)).min(1.0)
    }
}

impl SolidTexture for PlanetClouds {
    fn name(&self) -> &'static str {
        "planet clouds"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Density
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::density(DVec3::ONE, self.density(p, fp))
    }
}
