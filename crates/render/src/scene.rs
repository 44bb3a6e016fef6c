//! The scene description: everything the landscape pipeline needs, as one
//! `serde` struct that loads from TOML.
//!
//! Every field has a default; the defaults together are the built-in scene
//! (also shipped as `scenes/default.toml`, embedded in the crate as
//! [`DEFAULT_SCENE_TOML`]). A scene file only needs the keys it changes.
//! Unknown keys are errors, so a typo never silently falls back to a default.
//!
//! Conventions: z up, metres, degrees in the file (radians in code).
//! Compass azimuths are measured clockwise from north (+y) toward east (+x).

use std::path::Path;

use natura_core::ToneMap;
use serde::{Deserialize, Serialize};

use crate::error::{RenderError, Result};

/// The built-in scene as TOML: the defaults of every key, with comments.
pub const DEFAULT_SCENE_TOML: &str = include_str!("../scenes/default.toml");

/// A complete landscape scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SceneDesc {
    /// Master seed; every stage derives its own sub-seed from it.
    pub seed: u64,
    /// The fractal terrain.
    pub terrain: TerrainDesc,
    /// Erosion applied to the terrain, in order: stream power, hydraulic, thermal.
    pub erosion: ErosionDesc,
    /// The lake or sea.
    pub water: WaterDesc,
    /// The sun.
    pub sun: SunDesc,
    /// Sky and aerial perspective.
    pub atmosphere: AtmosphereDesc,
    /// How the surface is coloured.
    pub materials: MaterialDesc,
    /// Where the camera is and what it sees.
    pub camera: CameraDesc,
    /// Image size, sampling and output.
    pub render: RenderDesc,
}

/// Which multifractal shapes the terrain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TerrainGenerator {
    /// Musgrave's ridged multifractal: sharp alpine ridges, smooth valleys.
    Ridged,
    /// Musgrave's hybrid multifractal: smooth lowlands, rough peaks.
    Hybrid,
    /// Ridged mountains whose amplitude is modulated by a hybrid multifractal:
    /// ranges separated by rolling lowland basins.
    RidgedHybrid,
}

/// The fractal terrain, before erosion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TerrainDesc {
    /// Samples per side of the square height field (≥ 64).
    pub size: usize,
    /// Metres between samples.
    pub cell_size_m: f32,
    /// The multifractal.
    pub generator: TerrainGenerator,
    /// Wavelength of the first (largest) octave, metres.
    pub feature_size_m: f64,
    /// Height scale, metres: the multifractal's value times this.
    pub relief_m: f64,
    /// Musgrave's H (fractal increment); larger is smoother.
    pub h: f64,
    /// Frequency ratio between octaves (> 1).
    pub lacunarity: f64,
    /// Number of octaves (may be fractional).
    pub octaves: f64,
    /// Multifractal offset (ridge height for ridged; signal offset for hybrid).
    pub offset: f64,
    /// Ridged multifractal gain.
    pub gain: f64,
    /// Domain distortion, in units of the first octave's wavelength (0 = none).
    pub warp: f64,
    /// Width of the border over which the land sinks into the sea, as a
    /// fraction of the field's side (0 = no border; the field's edges show).
    pub coast_fraction: f64,
    /// Depth below the water level the border sinks to, metres.
    pub coast_depth_m: f64,
}

/// Erosion of the synthesised terrain.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ErosionDesc {
    /// Braun–Willett stream-power steps (0 = off): carves the drainage network.
    pub stream_power_steps: u32,
    /// Stream-power erodibility K (m^(1−2m)/yr).
    pub stream_power_k: f64,
    /// Stream-power area exponent m.
    pub stream_power_m: f64,
    /// Uplift rate, metres per year.
    pub uplift_m_per_yr: f64,
    /// Stream-power time step, years.
    pub stream_power_dt_yr: f64,
    /// The hydraulic model that adds gullies and sediment after stream power.
    pub hydraulic_model: HydraulicModel,
    /// Droplets per terrain sample for the droplet model (0 = off), so the
    /// erosion looks alike at every grid size: 0.25 is a million droplets on
    /// a 2048² terrain.
    pub droplets_per_sample: f64,
    /// Erosion brush radius of the droplets, cells.
    pub droplet_radius: u32,
    /// Virtual-pipe hydraulic erosion steps for the pipe model (0 = off).
    pub hydraulic_steps: u32,
    /// Rain for the pipe model, metres of water per second.
    pub rain_m_per_s: f64,
    /// Sediment capacity constant of the pipe model.
    pub sediment_capacity: f64,
    /// Thermal weathering steps (0 = off): scree slopes at the talus angle.
    pub thermal_steps: u32,
    /// Talus angle, degrees.
    pub talus_deg: f64,
}

/// Which hydraulic erosion model adds the fine detail.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HydraulicModel {
    /// Particle (droplet) erosion: cheap, carves gullies on every slope.
    Droplets,
    /// Mei–Decaudin–Hu virtual-pipe shallow water: physically fuller, needs
    /// many steps to show at landscape scale.
    Pipe,
}

/// The water body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WaterDesc {
    /// Whether there is water at all.
    pub enabled: bool,
    /// Water level in metres; if absent, `level_quantile` decides.
    pub level_m: Option<f64>,
    /// Water level as the fraction of land cells it floods (0–1).
    pub level_quantile: f64,
    /// What shapes the surface's normals: fBm ripples (lakes) or a
    /// Tessendorf ocean patch from natura-ocean (seas).
    pub waves: WaterWaves,
    /// Wave height scale of the ripples, metres (`waves = "ripples"`).
    pub ripple_height_m: f64,
    /// Wavelength of the largest ripples, metres.
    pub ripple_size_m: f64,
    /// Wind speed 10 m above the sea driving the ocean's Phillips spectrum,
    /// m/s (`waves = "ocean"`).
    pub wind_speed_m_s: f64,
    /// Compass direction the wind blows toward, degrees clockwise from north
    /// (+y) toward east (+x) (`waves = "ocean"`).
    pub wind_azimuth_deg: f64,
    /// Side of the periodic ocean patch, metres (`waves = "ocean"`).
    pub ocean_patch_m: f64,
    /// FFT samples along each side of the ocean patch, a power of two
    /// (`waves = "ocean"`).
    pub ocean_resolution: usize,
    /// Time of the ocean snapshot, seconds (`waves = "ocean"`).
    pub ocean_time_s: f64,
    /// Extinction of light in the water per metre, linear RGB (red goes first).
    pub extinction_per_m: [f32; 3],
    /// Colour scattered back up by the water body (linear RGB albedo).
    pub scatter_albedo: [f32; 3],
}

/// The normals of the water surface (its height stays at the water level:
/// the surface is traced flat and shaded with these normals).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WaterWaves {
    /// Isotropic fBm ripples of `ripple_size_m` and `ripple_height_m`.
    #[default]
    Ripples,
    /// A wind-driven Tessendorf FFT ocean patch (Phillips spectrum), tiled
    /// over the water (natura-ocean's [`Surface`](natura_ocean::Surface)).
    Ocean,
}

/// The sun.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SunDesc {
    /// Elevation above the horizon, degrees.
    pub elevation_deg: f64,
    /// Compass azimuth, degrees clockwise from north (+y).
    pub azimuth_deg: f64,
    /// Apparent diameter, degrees.
    pub angular_diameter_deg: f64,
    /// Whether a sun below the horizon is allowed (twilight); otherwise it is an error.
    pub allow_below_horizon: bool,
}

/// Sky and aerial perspective.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AtmosphereDesc {
    /// Multiplier on the aerosol (Mie) density: 1 is a clear day, 3 hazy.
    pub haze: f64,
    /// Mie asymmetry g (forward scattering of haze, 0–1).
    pub mie_g: f64,
    /// Whether the ozone layer absorbs (it keeps twilight skies blue).
    pub ozone: bool,
    /// Whether multiple scattering is included (Hillaire 2020); off = single scattering.
    pub multiple_scattering: bool,
    /// Rain (extinction per metre) between the camera and the far terrain,
    /// which shows a rainbow when the sun is behind the camera (0 = dry).
    pub rain_extinction_per_m: f64,
    /// Distance to the rain curtain, metres.
    pub rain_distance_m: f64,
}

/// The surface's diffuse reflection model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Diffuse {
    /// Lambert's law.
    Lambert,
    /// Oren–Nayar rough diffuse (qualitative model) with facet slope σ in degrees.
    OrenNayar {
        /// Standard deviation of facet angles, degrees.
        sigma_deg: f32,
    },
}

/// How the surface is coloured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MaterialDesc {
    /// Altitude of the snow line, metres.
    pub snow_line_m: f32,
    /// Amplitude of the fractal perturbation of the snow line, metres.
    pub snow_line_noise_m: f32,
    /// Snow does not hold on slopes steeper than this, degrees.
    pub snow_max_slope_deg: f32,
    /// Slopes steeper than this are bare rock, degrees.
    pub rock_slope_deg: f32,
    /// Vegetation thins out above this altitude, metres.
    pub tree_line_m: f32,
    /// Deposited sediment thicker than this shows as gravel, metres.
    pub sediment_min_m: f32,
    /// Beach band above the water level, metres.
    pub beach_height_m: f32,
    /// Diffuse model.
    pub diffuse: Diffuse,
    /// Albedo of snow (sRGB-encoded components in 0–1).
    pub snow: [f32; 3],
    /// Albedo of rock.
    pub rock: [f32; 3],
    /// Albedo of grass and low vegetation.
    pub grass: [f32; 3],
    /// Albedo of forest (dense vegetation in wet valleys).
    pub forest: [f32; 3],
    /// Albedo of soil and scree.
    pub soil: [f32; 3],
    /// Albedo of river gravel and sediment.
    pub sediment: [f32; 3],
    /// Albedo of beach sand.
    pub sand: [f32; 3],
    /// Scale of the procedural bump detail, metres (0 = off).
    pub bump_size_m: f32,
    /// Strength of the bump detail (slope units).
    pub bump_strength: f32,
}

/// The camera's projection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CameraKind {
    /// A pinhole camera with `vfov_deg`.
    Pinhole,
    /// Musgrave's cylindrical virtual screen with `hfov_deg` (may exceed 180).
    Cylindrical,
    /// An equirectangular (spherical) panorama with `hfov_deg`.
    Spherical,
}

/// Where the camera is and what it sees. Positions are given in field
/// coordinates (`[0, 1]²` across the terrain) so a scene works at any size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraDesc {
    /// Projection.
    pub kind: CameraKind,
    /// Camera position across the terrain, `[u, v]` in `[0, 1]`.
    pub position_uv: [f64; 2],
    /// Height of the eye above the ground (or water) below it, metres.
    pub height_above_ground_m: f64,
    /// Point the camera looks toward, `[u, v]` in `[0, 1]`.
    pub target_uv: [f64; 2],
    /// Pitch of the view above the horizontal, degrees (negative looks down).
    pub pitch_deg: f64,
    /// Vertical field of view (pinhole and panoramas), degrees.
    pub vfov_deg: f64,
    /// Horizontal field of view of the panoramas, degrees.
    pub hfov_deg: f64,
}

/// Image size, sampling and output.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RenderDesc {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Samples per pixel (stratified).
    pub spp: u32,
    /// Exposure in stops; absent = automatic (log-average luminance to mid grey).
    pub exposure_ev: Option<f32>,
    /// Tone map for the PNG.
    pub tone_map: ToneMap,
}

impl Default for SceneDesc {
    fn default() -> Self {
        Self {
            seed: 2,
            terrain: TerrainDesc::default(),
            erosion: ErosionDesc::default(),
            water: WaterDesc::default(),
            sun: SunDesc::default(),
            atmosphere: AtmosphereDesc::default(),
            materials: MaterialDesc::default(),
            camera: CameraDesc::default(),
            render: RenderDesc::default(),
        }
    }
}

impl Default for TerrainDesc {
    fn default() -> Self {
        Self {
            size: 2048,
            cell_size_m: 30.0,
            generator: TerrainGenerator::RidgedHybrid,
            feature_size_m: 24_000.0,
            relief_m: 2400.0,
            h: 0.9,
            lacunarity: 2.1,
            octaves: 11.0,
            offset: 1.0,
            gain: 2.0,
            warp: 0.05,
            coast_fraction: 0.1,
            coast_depth_m: 300.0,
        }
    }
}

impl Default for ErosionDesc {
    fn default() -> Self {
        Self {
            stream_power_steps: 15,
            stream_power_k: 2e-6,
            stream_power_m: 0.5,
            uplift_m_per_yr: 0.0,
            stream_power_dt_yr: 2000.0,
            hydraulic_model: HydraulicModel::Droplets,
            droplets_per_sample: 0.25,
            droplet_radius: 3,
            hydraulic_steps: 120,
            rain_m_per_s: 0.01,
            sediment_capacity: 0.05,
            thermal_steps: 20,
            talus_deg: 38.0,
        }
    }
}

impl Default for WaterDesc {
    fn default() -> Self {
        Self {
            enabled: true,
            level_m: None,
            level_quantile: 0.12,
            waves: WaterWaves::Ripples,
            ripple_height_m: 0.12,
            ripple_size_m: 40.0,
            wind_speed_m_s: 8.0,
            wind_azimuth_deg: 200.0,
            ocean_patch_m: 256.0,
            ocean_resolution: 256,
            ocean_time_s: 0.0,
            extinction_per_m: [0.45, 0.09, 0.06],
            scatter_albedo: [0.02, 0.08, 0.10],
        }
    }
}

impl Default for SunDesc {
    fn default() -> Self {
        Self {
            elevation_deg: 9.0,
            azimuth_deg: 235.0,
            angular_diameter_deg: 0.53,
            allow_below_horizon: false,
        }
    }
}

impl Default for AtmosphereDesc {
    fn default() -> Self {
        Self {
            haze: 1.6,
            mie_g: 0.8,
            ozone: true,
            multiple_scattering: true,
            rain_extinction_per_m: 0.0,
            rain_distance_m: 4000.0,
        }
    }
}

impl Default for MaterialDesc {
    fn default() -> Self {
        Self {
            snow_line_m: 1450.0,
            snow_line_noise_m: 220.0,
            snow_max_slope_deg: 42.0,
            rock_slope_deg: 40.0,
            tree_line_m: 950.0,
            sediment_min_m: 0.5,
            beach_height_m: 1.5,
            diffuse: Diffuse::OrenNayar { sigma_deg: 20.0 },
            snow: [0.92, 0.94, 0.97],
            rock: [0.42, 0.39, 0.36],
            grass: [0.33, 0.40, 0.18],
            forest: [0.13, 0.20, 0.10],
            soil: [0.45, 0.38, 0.29],
            sediment: [0.36, 0.33, 0.28],
            sand: [0.50, 0.45, 0.35],
            bump_size_m: 6.0,
            bump_strength: 0.12,
        }
    }
}

impl Default for CameraDesc {
    fn default() -> Self {
        Self {
            kind: CameraKind::Pinhole,
            position_uv: [0.78, 0.47],
            height_above_ground_m: 40.0,
            target_uv: [0.3, 0.75],
            pitch_deg: -3.0,
            vfov_deg: 36.0,
            hfov_deg: 220.0,
        }
    }
}

impl Default for RenderDesc {
    fn default() -> Self {
        Self {
            width: 1920,
            height: 1080,
            spp: 4,
            exposure_ev: None,
            tone_map: ToneMap::AcesFilmic,
        }
    }
}

impl SceneDesc {
    /// Parses a scene from TOML text. `name` labels errors (e.g. the file name).
    ///
    /// Errors name the line, column and dotted key, e.g.
    /// `scene.toml:12:1: key 'sun.elevation': unknown field ...`.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Scene`] naming `name` with the line and column
    /// of malformed TOML, an unknown key or a value of the wrong type.
    pub fn from_toml_str(text: &str, name: &str) -> Result<Self> {
        let scene: SceneDesc = toml::from_str(text).map_err(|e| toml_error(text, name, &e))?;
        Ok(scene)
    }

    /// Reads and parses a scene file. A missing or unreadable file is an error naming it.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Scene`] naming the file if it cannot be read, the
    /// errors of [`SceneDesc::from_toml_str`], and those of
    /// [`SceneDesc::validate`].
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| {
            RenderError::Scene(format!("{}: cannot read scene file: {e}", path.display()))
        })?;
        let scene = Self::from_toml_str(&text, &path.display().to_string())?;
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as TOML text (every key written out).
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Scene`] if a value cannot be written as TOML
    /// (a NaN or infinite number).
    pub fn to_toml_string(&self) -> Result<String> {
        toml::to_string_pretty(self)
            .map_err(|e| RenderError::Scene(format!("cannot write scene as TOML: {e}")))
    }

    /// Checks every value before any work starts, naming the first bad key.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`] naming the first scene key out of
    /// its range (the message gives the key, the value and the range).
    pub fn validate(&self) -> Result<()> {
        let t = &self.terrain;
        in_range("terrain.size", t.size as f64, 64.0, 16_384.0)?;
        in_range("terrain.cell_size_m", f64::from(t.cell_size_m), 1e-3, 1e5)?;
        positive("terrain.feature_size_m", t.feature_size_m)?;
        in_range("terrain.relief_m", t.relief_m, 0.0, 20_000.0)?;
        finite("terrain.h", t.h)?;
        in_range("terrain.lacunarity", t.lacunarity, 1.01, 16.0)?;
        in_range("terrain.octaves", t.octaves, 1.0, 24.0)?;
        finite("terrain.offset", t.offset)?;
        finite("terrain.gain", t.gain)?;
        in_range("terrain.warp", t.warp, 0.0, 4.0)?;
        in_range("terrain.coast_fraction", t.coast_fraction, 0.0, 0.5)?;
        in_range("terrain.coast_depth_m", t.coast_depth_m, 0.0, 20_000.0)?;

        let e = &self.erosion;
        in_range(
            "erosion.stream_power_steps",
            f64::from(e.stream_power_steps),
            0.0,
            10_000.0,
        )?;
        in_range("erosion.stream_power_k", e.stream_power_k, 0.0, 1.0)?;
        in_range("erosion.stream_power_m", e.stream_power_m, 0.0, 2.0)?;
        in_range("erosion.uplift_m_per_yr", e.uplift_m_per_yr, 0.0, 1.0)?;
        in_range(
            "erosion.stream_power_dt_yr",
            e.stream_power_dt_yr,
            1e-6,
            1e7,
        )?;
        in_range(
            "erosion.droplets_per_sample",
            e.droplets_per_sample,
            0.0,
            1000.0,
        )?;
        in_range(
            "erosion.droplet_radius",
            f64::from(e.droplet_radius),
            1.0,
            16.0,
        )?;
        in_range(
            "erosion.hydraulic_steps",
            f64::from(e.hydraulic_steps),
            0.0,
            100_000.0,
        )?;
        in_range("erosion.rain_m_per_s", e.rain_m_per_s, 0.0, 1.0)?;
        in_range("erosion.sediment_capacity", e.sediment_capacity, 0.0, 100.0)?;
        in_range(
            "erosion.thermal_steps",
            f64::from(e.thermal_steps),
            0.0,
            100_000.0,
        )?;
        in_range("erosion.talus_deg", e.talus_deg, 1.0, 89.0)?;

        let w = &self.water;
        if let Some(l) = w.level_m {
            finite("water.level_m", l)?;
        }
        in_range("water.level_quantile", w.level_quantile, 0.0, 1.0)?;
        in_range("water.ripple_height_m", w.ripple_height_m, 0.0, 100.0)?;
        positive("water.ripple_size_m", w.ripple_size_m)?;
        in_range("water.wind_speed_m_s", w.wind_speed_m_s, 0.1, 60.0)?;
        finite("water.wind_azimuth_deg", w.wind_azimuth_deg)?;
        in_range("water.ocean_patch_m", w.ocean_patch_m, 1.0, 1e5)?;
        in_range("water.ocean_time_s", w.ocean_time_s, -1e6, 1e6)?;
        let n = w.ocean_resolution;
        if !n.is_power_of_two() || !(natura_ocean::MIN_SIZE..=natura_ocean::MAX_SIZE).contains(&n) {
            return Err(RenderError::Invalid {
                name: "water.ocean_resolution",
                value: n.to_string(),
                reason: format!(
                    "must be a power of two in {}..={}",
                    natura_ocean::MIN_SIZE,
                    natura_ocean::MAX_SIZE
                ),
            });
        }
        for (i, v) in w.extinction_per_m.iter().enumerate() {
            in_range(
                [
                    "water.extinction_per_m[0]",
                    "water.extinction_per_m[1]",
                    "water.extinction_per_m[2]",
                ][i],
                f64::from(*v),
                0.0,
                1e3,
            )?;
        }
        for (i, v) in w.scatter_albedo.iter().enumerate() {
            in_range(
                [
                    "water.scatter_albedo[0]",
                    "water.scatter_albedo[1]",
                    "water.scatter_albedo[2]",
                ][i],
                f64::from(*v),
                0.0,
                1.0,
            )?;
        }

        let s = &self.sun;
        in_range("sun.elevation_deg", s.elevation_deg, -90.0, 90.0)?;
        finite("sun.azimuth_deg", s.azimuth_deg)?;
        in_range(
            "sun.angular_diameter_deg",
            s.angular_diameter_deg,
            0.01,
            20.0,
        )?;
        if !s.allow_below_horizon && s.elevation_deg < 0.0 {
            return Err(RenderError::invalid(
                "sun.elevation_deg",
                s.elevation_deg,
                "the sun is below the horizon; set sun.allow_below_horizon = true for twilight",
            ));
        }

        let a = &self.atmosphere;
        in_range("atmosphere.haze", a.haze, 0.0, 100.0)?;
        in_range("atmosphere.mie_g", a.mie_g, 0.0, 0.99)?;
        in_range(
            "atmosphere.rain_extinction_per_m",
            a.rain_extinction_per_m,
            0.0,
            1.0,
        )?;
        in_range("atmosphere.rain_distance_m", a.rain_distance_m, 0.0, 1e6)?;

        let m = &self.materials;
        finite("materials.snow_line_m", f64::from(m.snow_line_m))?;
        in_range(
            "materials.snow_line_noise_m",
            f64::from(m.snow_line_noise_m),
            0.0,
            1e4,
        )?;
        in_range(
            "materials.snow_max_slope_deg",
            f64::from(m.snow_max_slope_deg),
            0.0,
            90.0,
        )?;
        in_range(
            "materials.rock_slope_deg",
            f64::from(m.rock_slope_deg),
            0.0,
            90.0,
        )?;
        finite("materials.tree_line_m", f64::from(m.tree_line_m))?;
        in_range(
            "materials.sediment_min_m",
            f64::from(m.sediment_min_m),
            0.0,
            1e4,
        )?;
        in_range(
            "materials.beach_height_m",
            f64::from(m.beach_height_m),
            0.0,
            1e3,
        )?;
        if let Diffuse::OrenNayar { sigma_deg } = m.diffuse {
            in_range(
                "materials.diffuse.sigma_deg",
                f64::from(sigma_deg),
                0.0,
                90.0,
            )?;
        }
        for (name, c) in [
            ("materials.snow", m.snow),
            ("materials.rock", m.rock),
            ("materials.grass", m.grass),
            ("materials.forest", m.forest),
            ("materials.soil", m.soil),
            ("materials.sediment", m.sediment),
            ("materials.sand", m.sand),
        ] {
            for v in c {
                in_range(name, f64::from(v), 0.0, 1.0)?;
            }
        }
        in_range("materials.bump_size_m", f64::from(m.bump_size_m), 0.0, 1e4)?;
        in_range(
            "materials.bump_strength",
            f64::from(m.bump_strength),
            0.0,
            10.0,
        )?;

        let c = &self.camera;
        for (name, v) in [
            ("camera.position_uv[0]", c.position_uv[0]),
            ("camera.position_uv[1]", c.position_uv[1]),
            ("camera.target_uv[0]", c.target_uv[0]),
            ("camera.target_uv[1]", c.target_uv[1]),
        ] {
            in_range(name, v, 0.0, 1.0)?;
        }
        if c.position_uv == c.target_uv {
            return Err(RenderError::invalid(
                "camera.target_uv",
                format!("{:?}", c.target_uv),
                "must differ from camera.position_uv",
            ));
        }
        in_range(
            "camera.height_above_ground_m",
            c.height_above_ground_m,
            0.01,
            1e6,
        )?;
        in_range("camera.pitch_deg", c.pitch_deg, -89.0, 89.0)?;
        match c.kind {
            CameraKind::Pinhole => in_range("camera.vfov_deg", c.vfov_deg, 0.1, 179.0)?,
            CameraKind::Cylindrical | CameraKind::Spherical => {
                in_range("camera.vfov_deg", c.vfov_deg, 0.1, 179.0)?;
                in_range("camera.hfov_deg", c.hfov_deg, 0.1, 720.0)?;
            }
        }

        let r = &self.render;
        in_range("render.width", f64::from(r.width), 1.0, 16_384.0)?;
        in_range("render.height", f64::from(r.height), 1.0, 16_384.0)?;
        in_range("render.spp", f64::from(r.spp), 1.0, 4096.0)?;
        if let Some(ev) = r.exposure_ev {
            in_range("render.exposure_ev", f64::from(ev), -64.0, 64.0)?;
        }
        Ok(())
    }
}

fn finite(name: &'static str, v: f64) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(RenderError::invalid(name, v, "must be finite"))
    }
}

fn positive(name: &'static str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(RenderError::invalid(name, v, "must be finite and > 0"))
    }
}

fn in_range(name: &'static str, v: f64, lo: f64, hi: f64) -> Result<()> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(RenderError::Invalid {
            name,
            value: format!("{v}"),
            reason: format!("must lie in [{lo}, {hi}]"),
        })
    }
}

/// Turns a TOML error into one that names the file, line, column and dotted key.
fn toml_error(text: &str, name: &str, e: &toml::de::Error) -> RenderError {
    let message = e.message().trim().to_owned();
    let Some(span) = e.span() else {
        return RenderError::Scene(format!("{name}: {message}"));
    };
    let start = span.start.min(text.len());
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    let key = dotted_key(text, start);
    match key {
        Some(k) => RenderError::Scene(format!("{name}:{line}:{col}: key '{k}': {message}")),
        None => RenderError::Scene(format!("{name}:{line}:{col}: {message}")),
    }
}

/// The dotted key at byte `pos`: the `key = …` on that line, prefixed by the
/// last `[table]` header above it.
fn dotted_key(text: &str, pos: usize) -> Option<String> {
    let line_start = text[..pos].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[pos..].find('\n').map_or(text.len(), |i| pos + i);
    let line = text[line_start..line_end].trim();
    let header = |l: &str| -> Option<String> {
        let l = l.trim();
        (l.starts_with('[') && !l.starts_with("[[")).then(|| {
            l.trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .to_owned()
        })
    };
    if let Some(h) = header(line) {
        return Some(h);
    }
    let key = line.split('=').next()?.trim().trim_matches('"').to_owned();
    if key.is_empty() || line.starts_with('#') {
        return None;
    }
    let table = text[..line_start].lines().rev().find_map(header);
    Some(match table {
        Some(t) if !t.is_empty() => format!("{t}.{key}"),
        _ => key,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_default_scene_equals_the_defaults() {
        let parsed = SceneDesc::from_toml_str(DEFAULT_SCENE_TOML, "default.toml").unwrap();
        assert_eq!(parsed, SceneDesc::default());
        parsed.validate().unwrap();
    }

    #[test]
    fn round_trips_through_toml() {
        let mut s = SceneDesc {
            seed: 99,
            ..SceneDesc::default()
        };
        s.water.level_m = Some(12.5);
        s.render.exposure_ev = Some(-3.5);
        s.materials.diffuse = Diffuse::Lambert;
        s.camera.kind = CameraKind::Cylindrical;
        let text = s.to_toml_string().unwrap();
        assert_eq!(SceneDesc::from_toml_str(&text, "x").unwrap(), s);
    }

    #[test]
    fn empty_file_is_the_default_scene() {
        assert_eq!(
            SceneDesc::from_toml_str("", "empty").unwrap(),
            SceneDesc::default()
        );
    }

    #[test]
    fn unknown_key_names_line_and_key() {
        let text = "seed = 3\n\n[sun]\nelevation_deg = 10.0\nelevaton = 5\n";
        let err = SceneDesc::from_toml_str(text, "scene.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("scene.toml:5:"), "{err}");
        assert!(err.contains("sun.elevaton"), "{err}");
    }

    #[test]
    fn wrong_type_names_line_and_key() {
        let text = "[camera]\nvfov_deg = 30.0\n\n[render]\nwidth = \"wide\"\n";
        let err = SceneDesc::from_toml_str(text, "s.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("s.toml:5:"), "{err}");
        assert!(err.contains("render.width"), "{err}");
    }

    #[test]
    fn syntax_error_names_line() {
        let text = "seed = 3\n[terrain\nsize = 4\n";
        let err = SceneDesc::from_toml_str(text, "bad.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("bad.toml:2:"), "{err}");
    }

    #[test]
    fn impossible_values_are_refused_by_name() {
        type Mutation = Box<dyn Fn(&mut SceneDesc)>;
        let cases: Vec<(&str, Mutation)> = vec![
            ("render.spp", Box::new(|s| s.render.spp = 0)),
            ("render.width", Box::new(|s| s.render.width = 0)),
            ("terrain.size", Box::new(|s| s.terrain.size = 3)),
            (
                "terrain.cell_size_m",
                Box::new(|s| s.terrain.cell_size_m = -1.0),
            ),
            ("terrain.h", Box::new(|s| s.terrain.h = f64::NAN)),
            (
                "sun.elevation_deg",
                Box::new(|s| s.sun.elevation_deg = -5.0),
            ),
            (
                "erosion.talus_deg",
                Box::new(|s| s.erosion.talus_deg = 90.0),
            ),
            (
                "camera.target_uv",
                Box::new(|s| s.camera.target_uv = s.camera.position_uv),
            ),
            (
                "water.ocean_resolution",
                Box::new(|s| s.water.ocean_resolution = 300),
            ),
            (
                "water.wind_speed_m_s",
                Box::new(|s| s.water.wind_speed_m_s = 0.0),
            ),
        ];
        for (key, mutate) in cases {
            let mut s = SceneDesc::default();
            mutate(&mut s);
            let err = s.validate().unwrap_err().to_string();
            assert!(err.contains(key), "{key}: {err}");
        }
        let mut twilight = SceneDesc::default();
        twilight.sun.elevation_deg = -4.0;
        twilight.sun.allow_below_horizon = true;
        twilight.validate().unwrap();
    }

    #[test]
    fn missing_file_is_named() {
        let err = SceneDesc::load("/no/such/scene.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("/no/such/scene.toml"), "{err}");
    }
}
