//! The parameters of a planet.

use glam::DVec3;

use crate::air::{PlanetCloudsParams, VenusParams};
use crate::earth::{LunaParams, TerranParams};
use crate::error::{Result, colour, direction, in_range, invalid, non_negative, positive};
use crate::fractals::spectral;
use crate::giants::{GasGiantParams, RingsParams};
use crate::planet::biome::BiomeParams;

/// Earth's mean radius, metres.
pub const EARTH_RADIUS_M: f64 = 6.371e6;

/// The brightest sun channel [`LightParams::sun_colour`] accepts: 10⁶ times
/// the reference sun, far within `f32` range after every factor of shading.
pub const MAX_SUN_COLOUR: f64 = 1e6;

/// The range of [`TerrainParams::texture_scale`], texture units per radius.
pub const TEXTURE_SCALE_RANGE: (f64, f64) = (1e-6, 1e6);

/// Detail finer than the continents: the lower crossover, below which the
/// relief turns smooth (Musgrave 1993, §2.2.1.4: "the smaller scale at which
/// the surface becomes smooth and non-fractal").
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct PlanetDetailParams {
    /// Spectral exponent of the detail octaves (1: smoother than the
    /// continents; every octave adds about the same slope, so the ground
    /// stays rough at every scale a footprint shows, where well above 1 the
    /// slopes shrink and near ground turns to a blur).
    pub h: f64,
    /// Lattice cell of the finest octave, metres (0.01: 1 cm).
    pub finest_m: f64,
}

impl Default for PlanetDetailParams {
    fn default() -> Self {
        Self {
            h: 1.0,
            finest_m: 0.01,
        }
    }
}

impl PlanetDetailParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        crate::error::finite("h", self.h)?;
        positive("finest_m", self.finest_m)?;
        Ok(())
    }
}

/// The displaced terrain of a planet: a [`Terran`](crate::earth::Terran)
/// whose continents' chaos becomes height.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TerrainParams {
    /// The continents, climate colouring, mottle and ocean (the `terran`
    /// texture).
    pub terran: TerranParams,
    /// Metres of height per unit of chaos above sea level (before the
    /// texture's `mtn_scale`): the height of the mountains.
    pub relief_m: f64,
    /// Units of the texture sphere per planet radius (1: the texture's unit
    /// sphere is the planet).
    pub texture_scale: f64,
    /// Octaves finer than the continents', continuing their fBm with another
    /// `H` (fBm continents with a whole number of octaves only).
    pub detail: Option<PlanetDetailParams>,
    /// Colour by biome — altitude, latitude and moisture ([`Biomes`](crate::planet::Biomes)) —
    /// instead of the terran texture's climate index (`None`).
    #[cfg_attr(feature = "serde", serde(default))]
    pub biomes: Option<BiomeParams>,
}

impl TerrainParams {
    /// The octave count at lacunarity `lacunarity` whose finest octave has a
    /// lattice cell of `finest_m` metres on a planet of radius `radius_m`
    /// with `texture_scale` texture units per radius (base frequency 1).
    #[must_use]
    pub fn octaves_for(radius_m: f64, texture_scale: f64, lacunarity: f64, finest_m: f64) -> f64 {
        1.0 + (radius_m / (texture_scale * finest_m)).ln() / lacunarity.ln()
    }

    /// Earth-scale terrain: fBm continents of `H = 0.5` (the terran
    /// shader's `spectral_exp`), `λ = 2` and 16 octaves (down to ~100 m
    /// cells at Earth's radius: rough enough for mountains at every scale
    /// from continents to hills, a few hundred metres of relief across a
    /// few kilometres) and 8 km of relief per unit of chaos, then
    /// detail (`H = 1`) down to 1 cm, coloured by biome
    /// ([`BiomeParams`]). Without biomes the terran climate index colours
    /// it; that index is squared ("driving back the glaciers", `map_exp` 2;
    /// natura's choice for an Earth-scale relief, whose chaos spans more
    /// than the texture's bump) so temperate green reaches further from
    /// the equator.
    #[must_use]
    pub fn earth() -> Self {
        let terran = TerranParams {
            spectral: spectral(0.5, 2.0, 16.0),
            map_exp: 2.0,
            ..TerranParams::default()
        };
        Self {
            terran,
            relief_m: 8000.0,
            texture_scale: 1.0,
            detail: Some(PlanetDetailParams::default()),
            biomes: Some(BiomeParams::default()),
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        self.terran.validate()?;
        non_negative("relief_m", self.relief_m)?;
        in_range(
            "texture_scale",
            self.texture_scale,
            TEXTURE_SCALE_RANGE.0,
            TEXTURE_SCALE_RANGE.1,
            "must be in [10⁻⁶, 10⁶] texture units per radius",
        )?;
        if let Some(b) = &self.biomes {
            b.validate()?;
        }
        if let Some(d) = &self.detail {
            d.validate()?;
            let o = self.terran.spectral.octaves;
            if self.terran.continents != crate::earth::Continents::Fbm || o.fract() != 0.0 {
                return Err(invalid(
                    "detail",
                    o,
                    "detail continues fBm continents with a whole number of octaves",
                ));
            }
        }
        Ok(())
    }
}

/// The octave count, from the continents' first, of the detail's finest
/// octave (lattice cell `d.finest_m`) on a planet of radius `radius_m` with
/// `texture_scale` texture units per radius, under the continents'
/// spectral parameters `cs`, checked against natura-noise's limits for the
/// detail's own fBm (the octaves from the continents' last whole one down):
/// at most 64 octaves spanning at most 2³² in frequency.
///
/// # Errors
/// [`TextureError`](crate::TextureError) naming `detail.finest_m` (with the
/// radius, scale and octave counts) if the detail's octaves are infinite or
/// beyond those limits.
pub(crate) fn detail_finest_octave(
    radius_m: f64,
    texture_scale: f64,
    cs: &natura_noise::Spectral,
    d: &PlanetDetailParams,
) -> Result<f64> {
    let finest =
        1.0 + (radius_m / (texture_scale * cs.frequency * d.finest_m)).ln() / cs.lacunarity.ln();
    let k = cs.octaves as usize;
    let octaves = finest - k as f64;
    if octaves > 0.0 || octaves.is_nan() {
        let span = cs.lacunarity.powf(octaves.ceil() - 1.0);
        if !(octaves <= 64.0 && span <= 2f64.powi(32)) {
            return Err(crate::TextureError::InvalidParameter {
                name: "detail.finest_m",
                value: format!(
                    "{:e} ({octaves} octaves of detail below the continents' {k}, on a radius of \
                     {radius_m} m at texture_scale {texture_scale})",
                    d.finest_m
                ),
                reason: "radius_m / (texture_scale × finest_m) must leave at most 64 octaves of \
                         detail, spanning at most 2³² in frequency (natura-noise's limits)",
            });
        }
    }
    Ok(finest)
}

/// What covers the planet.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
// Plain `Copy` parameters: boxing the terrain to shrink the enum would cost
// the `Copy` every caller relies on for a few hundred bytes.
#[allow(clippy::large_enum_variant)]
pub enum SurfaceParams {
    /// Displaced terrain with oceans (Gaea).
    Terrain(TerrainParams),
    /// A smooth sphere of Coriolis-twisted clouds.
    Venus(VenusParams),
    /// A smooth banded gas giant.
    GasGiant(GasGiantParams),
    /// A smooth, bump-mapped moon with a rayed crater.
    Luna(LunaParams),
}

/// The radial atmosphere (natura-atmos's `RadialAtmosphere`, Musgrave
/// 1993 §4.1.6, its errata corrected there) and its umbra.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct PlanetAtmosphereParams {
    /// Scale height, metres (8000, Earth's).
    pub scale_height_m: f64,
    /// Extinction per metre at sea level, per channel (Earth's Rayleigh
    /// coefficients at 680, 550 and 440 nm, Bruneton & Neyret 2008).
    pub extinction: DVec3,
    /// The day side's fog colour `I_a`: what an infinitely thick atmosphere
    /// looks like in full sun. The fog's colour comes from `extinction`
    /// (in-scattering `I_a·(1 − e^{−τ})` grows with each channel's `τ`); a
    /// blue `I_a` counts the air's blue twice. Earth's is grey: a thick
    /// layer of non-absorbing air scatters every wavelength alike.
    pub day_colour: DVec3,
    /// The night side's fog colour (inside the planet's shadow cylinder).
    pub night_colour: DVec3,
    /// How much wider than the planet the shadow cylinder is, metres
    /// (must exceed any ray offset; Musgrave 1993 §4.1.6).
    pub umbra_margin_m: f64,
    /// Whether the day side's haze is also dimmed by the sun's cosine and
    /// lit by the sunlight that reaches it through the air, reddening
    /// towards the terminator (Musgrave 1993 §4.1.6.5's second remedy,
    /// Plate 4.6; true). Without it the haze keeps its colour and ends in a
    /// hard edge where it enters the umbra (Plate 4.5).
    pub lambert_haze: bool,
}

impl Default for PlanetAtmosphereParams {
    fn default() -> Self {
        Self {
            scale_height_m: 8000.0,
            extinction: DVec3::new(5.8e-6, 13.5e-6, 33.1e-6),
            day_colour: DVec3::splat(0.3),
            night_colour: DVec3::new(0.002, 0.003, 0.006),
            umbra_margin_m: 1000.0,
            lambert_haze: true,
        }
    }
}

impl PlanetAtmosphereParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        positive("scale_height_m", self.scale_height_m)?;
        for c in self.extinction.to_array() {
            non_negative("extinction", c)?;
        }
        colour("day_colour", self.day_colour)?;
        colour("night_colour", self.night_colour)?;
        positive("umbra_margin_m", self.umbra_margin_m)?;
        Ok(())
    }
}

/// The cloud shell: a sphere concentric with the planet, transparency
/// mapped by [`PlanetClouds`](crate::air::PlanetClouds).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct CloudLayerParams {
    /// The cloud texture, evaluated on the unit sphere of directions.
    pub clouds: PlanetCloudsParams,
    /// Height of the shell above sea level, metres (10 000).
    pub altitude_m: f64,
    /// The clouds' albedo (linear).
    pub albedo: DVec3,
    /// Whether the clouds shadow the ground (true).
    pub shadows: bool,
    /// How much the cover rises in the wet circulation belts and falls under
    /// the subtropical highs (`belts·cos 6φ`, 0.2).
    pub belts: f64,
    /// Width of the clouds' soft edge, in units of the cloud fBm (0.6: most
    /// of a cloud is thinner than opaque, so its billows show).
    pub softness: f64,
    /// Number of storms wound into the shell (8).
    pub storms: u32,
    /// A storm's angular radius, radians (0.25; each storm is 0.6 to 1.4
    /// times it).
    pub storm_radius: f64,
    /// A storm's rotation at its centre, radians (5).
    pub storm_twist: f64,
    /// How much a storm adds to the cover at its centre (0.35).
    pub storm_cover: f64,
}

impl Default for CloudLayerParams {
    /// The RenderMan `planetclouds` defaults with 13 octaves (fine enough
    /// to stay detailed from a mountain top), cloud systems half the
    /// shader's size (`rescale` 2, so a storm winds several of them into
    /// its arms), a gentle distortion (0.3: the shader's 1 folds the domain
    /// into streaks, see [`CloudShell`](crate::planet::CloudShell)) and
    /// eight storms.
    fn default() -> Self {
        Self {
            clouds: PlanetCloudsParams {
                octaves: 13.0,
                offset: -0.1,
                distortion: 0.3,
                rescale: 2.0,
                ..PlanetCloudsParams::default()
            },
            altitude_m: 10_000.0,
            albedo: DVec3::splat(0.95),
            shadows: true,
            belts: 0.2,
            softness: 0.6,
            storms: 8,
            storm_radius: 0.25,
            storm_twist: 5.0,
            storm_cover: 0.35,
        }
    }
}

impl CloudLayerParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        self.clouds.validate()?;
        positive("altitude_m", self.altitude_m)?;
        colour("albedo", self.albedo)?;
        in_range("belts", self.belts, 0.0, 1.0, "must be in [0, 1]")?;
        in_range(
            "softness",
            self.softness,
            1e-6,
            10.0,
            "must be in [10⁻⁶, 10]",
        )?;
        if self.storms > 64 {
            return Err(invalid("storms", self.storms, "must be at most 64"));
        }
        in_range(
            "storm_radius",
            self.storm_radius,
            0.0,
            1.0,
            "must be in [0, 1] radians",
        )?;
        in_range(
            "storm_twist",
            self.storm_twist,
            -50.0,
            50.0,
            "must be in [−50, 50] radians",
        )?;
        in_range(
            "storm_cover",
            self.storm_cover,
            0.0,
            2.0,
            "must be in [0, 2]",
        )?;
        Ok(())
    }
}

/// The sun and the light that does not come from it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct LightParams {
    /// Direction towards the sun (normalised when the planet is built).
    pub sun: DVec3,
    /// The sun's colour and intensity (linear, each channel in `[0, 10⁶]`:
    /// [`MAX_SUN_COLOUR`]).
    pub sun_colour: DVec3,
    /// Light reaching every surface from elsewhere (fraction of the sun).
    pub ambient: f64,
    /// Whether the terrain casts shadows (true).
    pub terrain_shadows: bool,
    /// The sun's angular radius, radians (0.00465, as seen from the Earth).
    pub sun_radius: f64,
}

impl Default for LightParams {
    fn default() -> Self {
        Self {
            sun: DVec3::new(1.0, -0.45, 0.35),
            sun_colour: DVec3::ONE,
            ambient: 0.02,
            terrain_shadows: true,
            sun_radius: 0.00465,
        }
    }
}

impl LightParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        direction("sun", self.sun)?;
        for c in self.sun_colour.to_array() {
            in_range(
                "sun_colour",
                c,
                0.0,
                MAX_SUN_COLOUR,
                "each channel must be in [0, 10⁶]",
            )?;
        }
        in_range("ambient", self.ambient, 0.0, 1.0, "must be in [0, 1]")?;
        in_range(
            "sun_radius",
            self.sun_radius,
            0.0,
            0.5,
            "must be in [0, 0.5] radians",
        )?;
        Ok(())
    }
}

/// Everything that makes a planet.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
// Every key is required in files: the optional layers default to present,
// and a format that omits `None` (TOML) could not say "no clouds" if a
// missing key meant the default.
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct PlanetParams {
    /// Radius of the sea-level sphere, metres (Earth's, 6 371 km).
    pub radius_m: f64,
    /// What covers it.
    pub surface: SurfaceParams,
    /// Its atmosphere, if any.
    pub atmosphere: Option<PlanetAtmosphereParams>,
    /// Its cloud shell, if any.
    pub clouds: Option<CloudLayerParams>,
    /// Its rings (in the equatorial plane, radii in planet radii), if any.
    pub rings: Option<RingsParams>,
    /// The sun.
    pub light: LightParams,
}

impl Default for PlanetParams {
    /// Gaea: [`PlanetParams::gaea`].
    fn default() -> Self {
        Self::gaea()
    }
}

impl PlanetParams {
    /// An Earth-like planet of Earth's radius: terrain, a radial atmosphere
    /// with its umbra, and a cloud shell.
    #[must_use]
    pub fn gaea() -> Self {
        Self {
            radius_m: EARTH_RADIUS_M,
            surface: SurfaceParams::Terrain(TerrainParams::earth()),
            atmosphere: Some(PlanetAtmosphereParams::default()),
            clouds: Some(CloudLayerParams::default()),
            rings: None,
            light: LightParams::default(),
        }
    }

    /// Venus (radius 6 052 km) under a thick, yellowish haze.
    #[must_use]
    pub fn venus() -> Self {
        Self {
            radius_m: 6.052e6,
            surface: SurfaceParams::Venus(VenusParams::default()),
            atmosphere: Some(PlanetAtmosphereParams {
                scale_height_m: 15_000.0,
                extinction: DVec3::new(6e-6, 8e-6, 12e-6),
                day_colour: DVec3::new(0.95, 0.9, 0.72),
                ..PlanetAtmosphereParams::default()
            }),
            clouds: None,
            rings: None,
            light: LightParams::default(),
        }
    }

    /// A Jupiter-sized banded giant (radius 69 911 km) with Saturn-like
    /// rings and a hazy atmosphere.
    #[must_use]
    pub fn jupiter() -> Self {
        Self {
            radius_m: 6.9911e7,
            surface: SurfaceParams::GasGiant(GasGiantParams::default()),
            atmosphere: Some(PlanetAtmosphereParams {
                scale_height_m: 60_000.0,
                extinction: DVec3::new(1.5e-6, 1.8e-6, 2.4e-6),
                day_colour: DVec3::new(0.9, 0.86, 0.78),
                ..PlanetAtmosphereParams::default()
            }),
            clouds: None,
            rings: Some(RingsParams::default()),
            light: LightParams::default(),
        }
    }

    /// Selene, a Moon-sized airless moon (radius 1 737.4 km).
    #[must_use]
    pub fn selene() -> Self {
        Self {
            radius_m: 1.7374e6,
            surface: SurfaceParams::Luna(LunaParams::default()),
            atmosphere: None,
            clouds: None,
            rings: None,
            light: LightParams {
                ambient: 0.01,
                ..LightParams::default()
            },
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        if !(self.radius_m.is_finite() && self.radius_m > 0.0) {
            return Err(invalid("radius_m", self.radius_m, "must be finite and > 0"));
        }
        in_range(
            "radius_m",
            self.radius_m,
            1.0,
            1e12,
            "must be between 1 m and 10¹² m",
        )?;
        match &self.surface {
            SurfaceParams::Terrain(t) => {
                t.validate()?;
                if t.relief_m > self.radius_m {
                    return Err(invalid(
                        "relief_m",
                        t.relief_m,
                        "must be in [0, radius_m]: mountains no higher than the planet is wide",
                    ));
                }
                if let Some(d) = &t.detail {
                    detail_finest_octave(self.radius_m, t.texture_scale, &t.terran.spectral, d)?;
                }
            }
            SurfaceParams::Venus(v) => v.validate()?,
            SurfaceParams::GasGiant(g) => g.validate()?,
            SurfaceParams::Luna(l) => l.validate()?,
        }
        if let Some(a) = &self.atmosphere {
            a.validate()?;
        }
        if let Some(c) = &self.clouds {
            c.validate()?;
        }
        if let Some(r) = &self.rings {
            r.validate()?;
        }
        self.light.validate()
    }
}
