//! Gas giants: horizontal cloud bands perturbed by distorted fBm, "much like
//! Perlin's marble".

use glam::DVec3;
use natura_noise::{DistNoise, Fbm, Perlin};

use crate::error::{Result, finite, non_negative};
use crate::footprint::{Footprint, fbm_at};
use crate::fractals::{dist_fbm, spectral};
use crate::spline::ColourSpline;
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// Jupiter-like band colours (natura's, chosen from Voyager-era photographs;
/// the source gives no colours). The spline wraps: its ends match.
pub const JUPITER_KNOTS: [[u8; 3]; 12] = [
    [222, 205, 180],
    [236, 222, 196],
    [201, 165, 128],
    [139, 100, 72],
    [232, 219, 196],
    [190, 128, 84],
    [246, 239, 222],
    [170, 126, 92],
    [214, 190, 160],
    [122, 88, 66],
    [236, 222, 196],
    [201, 165, 128],
];

/// Saturn-like band colours (pale golds; natura's).
pub const SATURN_KNOTS: [[u8; 3]; 10] = [
    [214, 196, 150],
    [230, 214, 170],
    [204, 180, 128],
    [238, 226, 190],
    [190, 164, 116],
    [226, 206, 160],
    [176, 150, 108],
    [222, 204, 158],
    [230, 214, 170],
    [204, 180, 128],
];

/// The band colours of a [`GasGiant`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Bands {
    /// Creams, tans and browns ([`JUPITER_KNOTS`]). The default.
    #[default]
    Jupiter,
    /// Pale golds ([`SATURN_KNOTS`]).
    Saturn,
}

/// Parameters of [`GasGiant`]. The source gives neither code nor values
/// (Musgrave 1993, §5.5); these are natura's, tuned to resemble Plate 5.6.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct GasGiantParams {
    /// Seed of the noise.
    pub seed: u64,
    /// Band cycles from the south pole to the north pole (3).
    pub bands: f64,
    /// How far the fBm pushes the bands (0.12): larger values give more
    /// turbulent belts.
    pub turbulence: f64,
    /// Frequency of the perturbing fBm (4 per radius).
    pub frequency: f64,
    /// fBm `H` (0.6).
    pub h: f64,
    /// fBm octaves (7).
    pub octaves: f64,
    /// Distortion of the `DistfBm` basis (0.8): stretched, streaming eddies.
    pub distortion: f64,
    /// How much faster the fBm's domain is stretched along longitude than
    /// latitude (3): zonal winds shear the eddies into streaks.
    pub zonal_stretch: f64,
    /// The band colours.
    pub colours: Bands,
}

impl Default for GasGiantParams {
    fn default() -> Self {
        Self {
            seed: 0,
            bands: 3.0,
            turbulence: 0.12,
            frequency: 4.0,
            h: 0.6,
            octaves: 7.0,
            distortion: 0.8,
            zonal_stretch: 3.0,
            colours: Bands::Jupiter,
        }
    }
}

impl GasGiantParams {
    /// Saturn: fewer, paler bands and calmer belts.
    #[must_use]
    pub fn saturn() -> Self {
        Self {
            bands: 2.5,
            turbulence: 0.05,
            colours: Bands::Saturn,
            ..Self::default()
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        finite("bands", self.bands)?;
        finite("turbulence", self.turbulence)?;
        crate::error::positive("frequency", self.frequency)?;
        non_negative("distortion", self.distortion)?;
        crate::error::positive("zonal_stretch", self.zonal_stretch)?;
        spectral(self.h, 2.0, self.octaves).validate()?;
        Ok(())
    }
}

/// A gas giant like Jupiter or Saturn (Musgrave 1993, §5.5): horizontal
/// strata of band colours whose index is perturbed by fBm, as in Perlin's
/// marble,
///
/// ```text
/// index = bands·(z + 1)/2 + turbulence·DistfBm(frequency·(x, y, z/zonal_stretch))    (mod 1)
/// ```
///
/// with `z` of the unit direction. "Enclosing a sphere so textured in a
/// fairly dense, hazy atmosphere can give a good approximation" (the planet
/// renderer's atmosphere does that). The source notes that "the eddy
/// structure that characterizes turbulent flow on all scales is
/// conspicuously missing"; the domain squashed in latitude shears the
/// perturbation into zonal streaks, a first step natura adds.
#[derive(Clone, Debug)]
pub struct GasGiant {
    params: GasGiantParams,
    fbm: Fbm<DistNoise<Perlin>>,
    colours: ColourSpline,
}

impl GasGiant {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`GasGiantParams::validate`].
    pub fn new(params: GasGiantParams) -> Result<Self> {
        params.validate()?;
        let colours = match params.colours {
            Bands::Jupiter => ColourSpline::from_bytes(&JUPITER_KNOTS)?,
            Bands::Saturn => ColourSpline::from_bytes(&SATURN_KNOTS)?,
        };
        Ok(Self {
            fbm: dist_fbm(
                params.seed,
                "bands",
                spectral(params.h, 2.0, params.octaves),
                params.distortion,
            )?,
            colours,
            params,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &GasGiantParams {
        &self.params
    }

    /// The band index in `[0, 1)` at `p`.
    #[must_use]
    pub fn index(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        let n = p.normalize_or_zero();
        let d = DVec3::new(p.x, p.y, p.z / q.zonal_stretch) * q.frequency;
        let turb = fbm_at(&self.fbm, d, fp.scaled(q.frequency));
        let i = q.bands * 0.5 * (n.z + 1.0) + q.turbulence * turb;
        let f = i - i.floor();
        if f < 1.0 { f } else { 0.0 }
    }

    /// The colour at `p`.
    #[must_use]
    pub fn colour(&self, p: DVec3, fp: Footprint) -> DVec3 {
        display_to_linear(self.colours.eval(self.index(p, fp)))
    }
}

impl SolidTexture for GasGiant {
    fn name(&self) -> &'static str {
        "gas giant"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Colour
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::colour(self.colour(p, fp))
    }
}
