//! The planet's colours by altitude, latitude and moisture: Musgrave's
//! climate colouring of Gaea with a moisture field beside it.
//!
//! Musgrave colours Gaea by a climate index — latitude, perturbed by
//! altitude — looked up in a colour map taken from a photograph of the
//! Earth: polar white, grey, green, buff desert (Musgrave 1998, "Gaea:
//! Building an Entire Planet", build-up steps (b)–(d); Musgrave 1993,
//! §5.6). One index cannot say that a desert and a rain forest lie on the
//! same parallel, so here the index is split into the two quantities a
//! biome depends on: a temperature (latitude and altitude, the index's two
//! terms) and a moisture (a band-limited fBm over the planet's circulation
//! belts), read off a chart of temperature against moisture (natura's
//! thresholds) whose colours are the terran
//! texture's own palette ([`LAND_KNOTS`](crate::earth::terran::LAND_KNOTS):
//! browns, greens, buff, white; the ocean colour (0.12, 0.3, 0.6) darkened
//! with depth as the terran shader darkens it).

use glam::DVec3;
use natura_noise::{Fbm, Perlin};

use crate::error::{Result, finite, in_range, positive};
use crate::footprint::{Footprint, fbm_at, smoothstep};
use crate::fractals::{fbm, spectral};
use crate::texture::display_to_linear;

/// The biome chart's colours, display values: the terran palette's knots
/// (Musgrave 1998, the `terran` spline) and its ocean colour.
mod palette {
    use glam::DVec3;
    /// Buff desert (the spline's seventh knot).
    pub const DESERT: DVec3 = DVec3::new(0.6, 0.5, 0.23);
    /// Dry grass and savanna, between the olive knot and the desert.
    pub const SAVANNA: DVec3 = DVec3::new(0.42, 0.4, 0.16);
    /// Steppe and meadow (the olive knot).
    pub const GRASS: DVec3 = DVec3::new(0.2, 0.3, 0.0);
    /// Temperate forest (the fifth knot).
    pub const FOREST: DVec3 = DVec3::new(0.085, 0.2, 0.04);
    /// Rain forest (the sixth knot).
    pub const JUNGLE: DVec3 = DVec3::new(0.065, 0.22, 0.04);
    /// Boreal forest: the temperate green, darker.
    pub const TAIGA: DVec3 = DVec3::new(0.06, 0.14, 0.05);
    /// Tundra: the grey-brown the spline passes through before the snow.
    pub const TUNDRA: DVec3 = DVec3::new(0.42, 0.4, 0.3);
    /// Bare rock on steep slopes (the spline's brown, greyed).
    pub const ROCK: DVec3 = DVec3::new(0.44, 0.39, 0.33);
    /// Beach sand.
    pub const SAND: DVec3 = DVec3::new(0.76, 0.7, 0.5);
    /// Snow and ice (the spline's white; green and blue equal, as in every
    /// colour here, so no blend of them turns lilac).
    pub const SNOW: DVec3 = DVec3::new(0.94, 0.95, 0.95);
    /// Shallow water over a shelf: the terran ocean colour, lighter.
    pub const SHALLOW: DVec3 = DVec3::new(0.14, 0.38, 0.62);
    /// Deep ocean: the terran ocean colour at its largest darkening (× 0.25).
    pub const DEEP: DVec3 = DVec3::new(0.03, 0.075, 0.15);
}

/// Parameters of the biome colouring ([`Biomes`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct BiomeParams {
    /// Mean annual temperature at sea level on the equator, °C (27).
    pub equator_c: f64,
    /// …and at the poles, °C (−25); it falls with the square of latitude.
    pub pole_c: f64,
    /// Temperature lapse rate, °C per km of altitude (6.5).
    pub lapse_c_per_km: f64,
    /// Mean annual temperature below which snow and sea ice lie, °C (−8).
    pub snow_c: f64,
    /// Frequency of the moisture fBm, cycles per planet radius (3).
    pub moisture_frequency: f64,
    /// Octaves of the moisture fBm (24: from continents down to a few
    /// centimetres on Earth; fewer are summed where the footprint is wider).
    pub moisture_octaves: f64,
    /// Strength of the circulation belts in the moisture: wet at the
    /// equator and at 60°, dry at 30° and at the poles (0.25).
    pub belts: f64,
    /// Height of the beaches above sea level, metres (12).
    pub beach_m: f64,
    /// Depth at which the ocean reaches its deep colour, metres (2500).
    pub deep_m: f64,
    /// Slope (rise over run) at which bare rock starts to show (0.7; all
    /// rock at twice it).
    pub rock_slope: f64,
}

impl Default for BiomeParams {
    fn default() -> Self {
        Self {
            equator_c: 27.0,
            pole_c: -25.0,
            lapse_c_per_km: 6.5,
            snow_c: -8.0,
            moisture_frequency: 3.0,
            moisture_octaves: 24.0,
            belts: 0.25,
            beach_m: 12.0,
            deep_m: 2500.0,
            rock_slope: 0.7,
        }
    }
}

impl BiomeParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        in_range(
            "equator_c",
            self.equator_c,
            -100.0,
            100.0,
            "must be in [−100, 100] °C",
        )?;
        in_range(
            "pole_c",
            self.pole_c,
            -100.0,
            100.0,
            "must be in [−100, 100] °C",
        )?;
        in_range(
            "lapse_c_per_km",
            self.lapse_c_per_km,
            0.0,
            50.0,
            "must be in [0, 50] °C per km",
        )?;
        finite("snow_c", self.snow_c)?;
        positive("moisture_frequency", self.moisture_frequency)?;
        in_range(
            "moisture_octaves",
            self.moisture_octaves,
            1.0,
            32.0,
            "must be in [1, 32]",
        )?;
        in_range("belts", self.belts, 0.0, 1.0, "must be in [0, 1]")?;
        positive("beach_m", self.beach_m)?;
        positive("deep_m", self.deep_m)?;
        positive("rock_slope", self.rock_slope)?;
        Ok(())
    }
}

/// The biome colouring of a terrain planet: temperature from latitude and
/// altitude, moisture from a band-limited fBm over circulation belts, and
/// the colour of the biome they select, blended smoothly between biomes
/// (every boundary is a smoothstep of a continuous field, so none aliases).
#[derive(Debug)]
pub struct Biomes {
    params: BiomeParams,
    moisture: Fbm<Perlin>,
}

impl Biomes {
    /// The colouring for `params`, its moisture seeded by `seed`.
    ///
    /// # Errors
    /// As [`BiomeParams::validate`].
    pub fn new(params: BiomeParams, seed: u64) -> Result<Self> {
        params.validate()?;
        let mut s = spectral(0.3, 2.0, params.moisture_octaves);
        s.frequency = params.moisture_frequency;
        Ok(Self {
            params,
            moisture: fbm(seed, "moisture", s)?,
        })
    }

    /// The spread of temperature (°C) over a footprint whose height has
    /// standard deviation `height_sd_m`: the lapse rate times it.
    #[must_use]
    pub fn spread(&self, height_sd_m: f64) -> f64 {
        self.params.lapse_c_per_km * height_sd_m / 1e3
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &BiomeParams {
        &self.params
    }

    /// Mean annual temperature, °C, at sine of latitude `sin_lat` and
    /// `height_m` above sea level: `T_eq − (T_eq − T_pole)·(φ/90°)² −
    /// lapse·h` (the climate index's latitude and altitude terms).
    #[must_use]
    pub fn temperature(&self, sin_lat: f64, height_m: f64) -> f64 {
        let q = &self.params;
        let f = sin_lat.clamp(-1.0, 1.0).asin().abs() / std::f64::consts::FRAC_PI_2;
        q.equator_c - (q.equator_c - q.pole_c) * f * f - q.lapse_c_per_km * height_m.max(0.0) / 1e3
    }

    /// Moisture in `[0, 1]` at the unit direction `dir` for a footprint
    /// `fp` (units of the planet radius): `½ + belts·cos 6φ + ½·fBm`, the
    /// cosine wet at the equator and 60°, dry at 30° and the poles.
    #[must_use]
    pub fn moisture(&self, dir: DVec3, fp: Footprint) -> f64 {
        let lat = dir.z.clamp(-1.0, 1.0).asin();
        let m = 0.5 + self.params.belts * (6.0 * lat).cos() + 0.6 * fbm_at(&self.moisture, dir, fp);
        m.clamp(0.0, 1.0)
    }

    /// The land's colour (linear RGB) at temperature `temp_c`, moisture
    /// `moisture`, `height_m` above sea level and slope `slope` (rise over
    /// run): desert, savanna, grass, forest and jungle by warmth and
    /// moisture; tundra where cold; bare rock on steep slopes; sand on the
    /// beach; snow below `snow_c`. `spread_c` is how much the temperature
    /// varies over the footprint (its altitude's spread times the lapse
    /// rate): the snow line is blended over that much more, so a peak
    /// narrower than a pixel shows the share of snow on it rather than a
    /// white speck.
    #[must_use]
    pub fn land(
        &self,
        temp_c: f64,
        moisture: f64,
        height_m: f64,
        slope: f64,
        spread_c: f64,
    ) -> DVec3 {
        use palette::*;
        let q = &self.params;
        let snow = 2.0f64.hypot(2.0 * spread_c.max(0.0));
        let warm = smoothstep(4.0, 20.0, temp_c);
        let dry = TUNDRA.lerp(DESERT, warm);
        let middling = GRASS.lerp(SAVANNA, smoothstep(12.0, 24.0, temp_c));
        let wood = TAIGA
            .lerp(FOREST, smoothstep(0.0, 10.0, temp_c))
            .lerp(JUNGLE, smoothstep(18.0, 25.0, temp_c));
        let mut c = dry
            .lerp(middling, smoothstep(0.2, 0.42, moisture))
            .lerp(wood, smoothstep(0.45, 0.7, moisture));
        c = TUNDRA.lerp(c, smoothstep(-2.0, 4.0, temp_c));
        c = c.lerp(ROCK, smoothstep(q.rock_slope, 2.0 * q.rock_slope, slope));
        let sand =
            smoothstep(-2.0, 4.0, temp_c) * (1.0 - smoothstep(0.3, 1.0, height_m / q.beach_m));
        c = c.lerp(SAND, sand);
        c = c.lerp(
            SNOW,
            1.0 - smoothstep(q.snow_c - snow, q.snow_c + snow, temp_c),
        );
        display_to_linear(c)
    }

    /// The sea's colour (linear RGB) at `depth_m` below sea level and
    /// surface temperature `temp_c`: shallow to deep blue, ice where cold.
    #[must_use]
    pub fn sea(&self, temp_c: f64, depth_m: f64) -> DVec3 {
        use palette::*;
        let q = &self.params;
        let c = SHALLOW.lerp(DEEP, smoothstep(0.0, q.deep_m, depth_m.max(0.0)).sqrt());
        let ice = 1.0 - smoothstep(q.snow_c - 6.0, q.snow_c - 2.0, temp_c);
        display_to_linear(c.lerp(SNOW, ice))
    }
}
