//! Fire: flames from distorted fBm stretched by the upward acceleration of
//! hot gas, coloured like a black body.

use glam::DVec3;
use natura_noise::{DistNoise, Fbm, Perlin, Ridged};

use crate::error::{Result, finite, non_negative};
use crate::footprint::Footprint;
use crate::fractals::{perlin, spectral};
use crate::spline::ColourSpline;
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// The listing's colour map: black, through cherry red, orange and yellow,
/// to near white (Musgrave 1998, "Fire"), 8-bit.
pub const FLAME_KNOTS: [[u8; 3]; 18] = [
    [0, 0, 0],
    [0, 0, 0],
    [27, 0, 0],
    [54, 0, 0],
    [81, 0, 0],
    [109, 0, 0],
    [136, 0, 0],
    [166, 5, 0],
    [189, 30, 0],
    [211, 60, 0],
    [231, 91, 0],
    [238, 128, 0],
    [244, 162, 12],
    [248, 187, 58],
    [251, 209, 115],
    [254, 236, 210],
    [255, 241, 230],
    [255, 241, 230],
];

/// Where the flame's "ridges" come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum FlameBasis {
    /// `|fBm|`: the absolute value of the whole sum, as the listing computes
    /// it (dark sinews where the sum crosses zero). The default.
    #[default]
    AbsOfSum,
    /// fBm of the ridged basis `1 − |N|`, as the text and Fig. 15.6 credit,
    /// divided by its weight sum so it spans `[0, 1]` like `|fBm|`.
    Ridged,
}

/// Parameters of [`Flame`]; `Default` is the `flame` shader's.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct FlameParams {
    /// Seed of the noise.
    pub seed: u64,
    /// Distortion of the `DistfBm` basis (0): larger values give wispier flames.
    pub distortion: f64,
    /// Scale of the fBm ("chaos", 1).
    pub chaosscale: f64,
    /// Offset of the fBm (0).
    pub chaosoffset: f64,
    /// fBm octaves (7).
    pub octaves: f64,
    /// How fast the colour cools with height (1).
    pub flameheight: f64,
    /// The colour index at `z = 0` (0.5): brightness of the flame's base.
    pub flameamplitude: f64,
    /// Where the ridges come from.
    pub basis: FlameBasis,
}

impl Default for FlameParams {
    fn default() -> Self {
        Self {
            seed: 0,
            distortion: 0.0,
            chaosscale: 1.0,
            chaosoffset: 0.0,
            octaves: 7.0,
            flameheight: 1.0,
            flameamplitude: 0.5,
            basis: FlameBasis::AbsOfSum,
        }
    }
}

impl FlameParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        non_negative("distortion", self.distortion)?;
        finite("chaosscale", self.chaosscale)?;
        finite("chaosoffset", self.chaosoffset)?;
        finite("flameheight", self.flameheight)?;
        finite("flameamplitude", self.flameamplitude)?;
        spectral(0.5, 2.0, self.octaves).validate()?;
        Ok(())
    }
}

#[derive(Clone, Debug)]
enum Chaos {
    Sum(Fbm<DistNoise<Perlin>>),
    Ridged(Fbm<Ridged<DistNoise<Perlin>>>),
}

/// Musgrave's flame (Musgrave 1998, "Fire"): with `z` up,
///
/// ```text
/// PQ    = (x, y, z·e^(−z))                          the gas accelerates upwards
/// chaos = |chaosscale·DistfBm(PQ, octaves, λ = 2, H = ½, distortion) + chaosoffset|
/// cmap  = 0.85·chaos + 0.8·(flameamplitude − flameheight·z)
/// Ci    = spline(cmap, black … cherry red … orange … yellow … white)
/// ```
///
/// so for fixed noise the colour index falls linearly with height and the
/// flame cools upwards. Emissive (no lighting).
///
/// **Erratum.** The text calls the fBm "ridged" and Fig. 15.6 credits the
/// `1 − |noise|` basis for the flames' sinews, but the listing takes the
/// absolute value of the whole sum. The listing is the only complete
/// specification and its `[0, 1]`-ish range is what the colour map expects,
/// so it is the default; [`FlameBasis::Ridged`] uses the ridged basis the
/// text describes, normalised by the octave weights so that the colour map
/// still applies. The spline may overshoot its knots and the colour index is
/// unbounded; both are clamped.
#[derive(Clone, Debug)]
pub struct Flame {
    params: FlameParams,
    chaos: Chaos,
    colours: ColourSpline,
}

impl Flame {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`FlameParams::validate`].
    pub fn new(params: FlameParams) -> Result<Self> {
        params.validate()?;
        let s = spectral(0.5, 2.0, params.octaves);
        let basis = DistNoise::dist_noise(perlin(params.seed, "flame"), params.distortion)?;
        let chaos = match params.basis {
            FlameBasis::AbsOfSum => Chaos::Sum(Fbm::new(basis, s)?),
            FlameBasis::Ridged => Chaos::Ridged(Fbm::new(Ridged(basis), s)?),
        };
        Ok(Self {
            params,
            chaos,
            colours: ColourSpline::from_bytes(&FLAME_KNOTS)?,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &FlameParams {
        &self.params
    }

    /// The "chaos" value `|chaosscale·fBm(PQ) + chaosoffset|` at `p`.
    #[must_use]
    pub fn chaos(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        // e^−z overflows below z ≈ −709; far below the flame the stretch is
        // immaterial (the colour index is saturated there), so it is capped.
        let stretch = (-p.z).min(700.0).exp();
        let pq = DVec3::new(p.x, p.y, p.z * stretch);
        // PQ's z is compressed or stretched by d(z·e^−z)/dz = (1 − z)·e^−z.
        let fp = fp.scaled(((1.0 - p.z) * stretch).abs().max(1.0));
        let sum = match &self.chaos {
            Chaos::Sum(f) => f.eval3_band(pq, fp.visible(f.spectral())),
            Chaos::Ridged(f) => {
                let v = fp.visible(f.spectral());
                let w = f.octaves().band_weight_sum(v);
                if w > 0.0 {
                    f.eval3_band(pq, v) / w
                } else {
                    0.0
                }
            }
        };
        (q.chaosscale * sum + q.chaosoffset).abs()
    }

    /// The colour-map index at `p`.
    #[must_use]
    pub fn index(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        0.85 * self.chaos(p, fp) + 0.8 * (q.flameamplitude - q.flameheight * p.z)
    }

    /// The colour at `p`.
    #[must_use]
    pub fn colour(&self, p: DVec3, fp: Footprint) -> DVec3 {
        display_to_linear(self.colours.eval(self.index(p, fp)))
    }
}

impl SolidTexture for Flame {
    fn name(&self) -> &'static str {
        "flame"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Colour
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::colour(self.colour(p, fp))
    }
}
