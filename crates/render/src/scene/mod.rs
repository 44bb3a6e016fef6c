//! The scene description: everything the landscape pipeline needs, as one
//! `serde` struct that loads from TOML.
//!
//! Every field has a default; the defaults together are the built-in scene
//! (also shipped as `scenes/default.toml`, embedded in the crate as
//! [`DEFAULT_SCENE_TOML`]). A scene file only needs the keys it changes.
//! Unknown keys are errors, so a typo never silently falls back to a default.
//!
//! Limits: a scene file is read only up to [`MAX_SCENE_FILE_BYTES`], and a
//! scene whose values each lie in their ranges must still fit, all
//! together, the memory budget [`MEMORY_BUDGET_BYTES`] (4 GiB): its
//! terrain (64 bytes a sample of `terrain.size`²), image (32 bytes a pixel),
//! clouds (voxels, shadow tables and the map of their shadows) and forest
//! (the ecosystem's seedlings over the square around the eye, at most
//! 20 000 000 plants) are estimated before any work, and a scene past the
//! budget is refused naming the keys that make it large.
//!
//! Conventions: z up, metres, degrees in the file (radians in code).
//! Compass azimuths are measured clockwise from north (+y) toward east (+x).
//!
//! This file holds the scene's types and defaults; `text.rs` reads and
//! writes it as TOML (errors name file, line, column and key) and
//! `validate.rs` checks every value before any work starts, and
//! `budget.rs` the memory the scene asks for against
//! [`MEMORY_BUDGET_BYTES`].

mod animation;
mod budget;
mod clouds;
mod quick;
mod terraces;
mod text;
mod textures;
mod validate;
mod vegetation;

pub use vegetation::{SPECIES_NAMES, VegetationDesc};

pub use animation::{AnimationDesc, AnimationKey, MAX_DURATION_S};
pub(crate) use budget::MAX_PLANTS;
pub use budget::{MAX_SCENE_FILE_BYTES, MEMORY_BUDGET_BYTES};
pub use quick::QUICK_TERRAIN_SIZE;

#[cfg(test)]
mod tests;

use natura_core::ToneMap;
use natura_terrain::erosion::{
    Depressions, DropletParams, PipeParams, StreamPowerParams, ThermalParams,
};
use serde::{Deserialize, Serialize};

pub(crate) use clouds::in_section as clouds_in_section;
pub use clouds::{CloudsDesc, MAX_CLOUD_VOXELS};
pub use terraces::TerracesDesc;
pub use textures::TexturesDesc;

/// The built-in scene as TOML: the defaults of every key, with comments.
pub const DEFAULT_SCENE_TOML: &str = include_str!("../../scenes/default.toml");

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
    /// Cliffs and benches where layered rock shows, after erosion.
    pub terraces: TerracesDesc,
    /// The lake or sea.
    pub water: WaterDesc,
    /// The sun.
    pub sun: SunDesc,
    /// Sky and aerial perspective.
    pub atmosphere: AtmosphereDesc,
    /// How the surface is coloured.
    pub materials: MaterialDesc,
    /// Procedural relief below the terrain's cell size, down to the pixel.
    pub detail: DetailDesc,
    /// Layer clouds over the scene, with their shadows.
    pub clouds: CloudsDesc,
    /// Solid textures on the surface (rock strata, grain) at the footprint.
    pub textures: TexturesDesc,
    /// The forest on the terrain near the camera.
    pub vegetation: VegetationDesc,
    /// Where the camera is and what it sees.
    pub camera: CameraDesc,
    /// Image size, sampling and output.
    pub render: RenderDesc,
    /// Frames, frame rate and camera path of an animated scene.
    pub animation: AnimationDesc,
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
///
/// Each model's parameters are natura-terrain's own parameter struct, as a
/// sub-table (`[erosion.stream_power]`, `[erosion.droplets]`, `[erosion.pipe]`,
/// `[erosion.thermal]`) in that struct's units (the talus angle in radians);
/// the models check their own ranges. Keys left out of a sub-table keep the
/// scene's defaults, not the model's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ErosionDesc {
    /// Braun–Willett stream-power steps (0 = off): carves the drainage network.
    pub stream_power_steps: u32,
    /// The stream-power model's parameters.
    pub stream_power: StreamPowerParams,
    /// The hydraulic model that adds gullies and sediment after stream power.
    pub hydraulic_model: HydraulicModel,
    /// Droplets per terrain sample for the droplet model (0 = off), so the
    /// erosion looks alike at every grid size: 0.25 is a million droplets on
    /// a 2048² terrain.
    pub droplets_per_sample: f64,
    /// The droplet model's parameters (it runs in cell units, so Beyer's
    /// constants hold at any resolution).
    pub droplets: DropletParams,
    /// Virtual-pipe hydraulic erosion steps for the pipe model (0 = off).
    pub hydraulic_steps: u32,
    /// The pipe model's parameters.
    pub pipe: PipeParams,
    /// Thermal weathering steps (0 = off): scree slopes at the talus angle.
    pub thermal_steps: u32,
    /// The thermal weathering model's parameters.
    pub thermal: ThermalParams,
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
    /// What shapes the surface's normals: the wind sea of the scene's wind
    /// over the water's fetch, fBm ripples, or a Tessendorf ocean patch
    /// (Phillips spectrum) from natura-ocean.
    pub waves: WaterWaves,
    /// Wave height scale of the ripples, metres (`waves = "ripples"`).
    pub ripple_height_m: f64,
    /// Wavelength of the largest ripples, metres.
    pub ripple_size_m: f64,
    /// Wind speed 10 m above the water, m/s: it drives the wind sea
    /// (`waves = "wind"`; 0 is a calm, the ripples alone, otherwise at
    /// least 0.1) and the ocean's Phillips spectrum (`waves = "ocean"`, at
    /// least 0.1).
    pub wind_speed_m_s: f64,
    /// Compass direction the wind blows toward, degrees clockwise from north
    /// (+y) toward east (+x): the waves', and the prevailing wind that
    /// drifted the snow.
    pub wind_azimuth_deg: f64,
    /// Distance the wind has blown over the water, metres (`waves =
    /// "wind"`); if absent, the square root of the water's area.
    pub fetch_m: Option<f64>,
    /// Side of the periodic wave patch, metres (`waves = "wind"` or `"ocean"`).
    pub ocean_patch_m: f64,
    /// FFT samples along each side of the wave patch, a power of two
    /// (`waves = "wind"` or `"ocean"`).
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
    /// The fetch-limited wind sea (JONSWAP) of `wind_speed_m_s` over
    /// `fetch_m`, filtered at the pixel's footprint, with the sun's
    /// glitter (see [`crate::water`]); in a calm, the ripples.
    #[default]
    Wind,
    /// Isotropic fBm ripples of `ripple_size_m` and `ripple_height_m`.
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
    /// Slope on which half the snow holds, degrees: snow sloughs off
    /// steeper ground (see `snow_slope_band_deg`).
    pub snow_max_slope_deg: f32,
    /// Half the width of the slopes over which the snow thins out, degrees:
    /// full cover below `snow_max_slope_deg` minus this, none above it plus this.
    pub snow_slope_band_deg: f32,
    /// How much higher the snow line lies on a steep slope facing the sun
    /// than on level ground, metres (shady slopes: as much lower).
    pub snow_sun_m: f32,
    /// How much lower the snow line lies in the lee of the prevailing wind
    /// (`water.wind_azimuth_deg`), and higher on crests it scours, metres.
    pub snow_wind_m: f32,
    /// How far upwind the terrain shelters the snow, metres.
    pub snow_shelter_distance_m: f32,
    /// Amplitude of the fine noise on the snow's edge, metres of altitude.
    pub snow_edge_m: f32,
    /// Largest wavelength of the noise on the snow's edge, metres.
    pub snow_edge_size_m: f32,
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

/// Procedural detail added to the terrain below its cell size, octave by
/// octave down to each pixel's footprint (Musgrave's procedural level of
/// detail): an fBm of Perlin noise in metres whose first octave has the
/// cell's wavelength. Lakes and the sea stay flat; where a pixel covers more
/// than half a cell the stored terrain is traced as it is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DetailDesc {
    /// Whether to add the detail at all.
    pub enabled: bool,
    /// Amplitude of the first (largest) octave, metres; the detail stays
    /// within `amplitude_m / (1 − lacunarity^(−h))` of the terrain.
    pub amplitude_m: f64,
    /// Musgrave's H of the detail's fBm (0 to 2); larger is smoother.
    pub h: f64,
    /// Wavelength ratio between octaves (1.5 to 4).
    pub lacunarity: f64,
    /// Most octaves, however close the surface (0 to 24).
    pub octaves: u32,
    /// Added to the scene's seed for the detail's noise (a different
    /// detail over the same terrain).
    pub seed_offset: u64,
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
    /// Samples per pixel (stratified): every pixel takes these.
    pub spp: u32,
    /// Samples a pixel takes in all where its `spp` samples disagree
    /// (their luminance contrast exceeds `adaptive_contrast`): a silhouette
    /// against a far brighter sky, lit needles among shade. With `spp = k²`
    /// and `adaptive_samples = spp·m²` all of them fill a `km × km` grid.
    /// At most `spp` (0 included), or with one sample a pixel: no pixel
    /// takes more, and every pixel is as without refinement.
    pub adaptive_samples: u32,
    /// The contrast `(max − min) / (max + min)` of a pixel's sample
    /// luminances above which it takes `adaptive_samples`, in `[0, 1]`:
    /// lower refines more pixels (smoother edges, a slower render), 1
    /// none. Differences near black and above white (at the scene's
    /// sunlit white surface) do not count. The default, 0.7, is below the
    /// 0.86 at which one bright sample in four makes a pixel four times
    /// brighter than its neighbours (0.77 where the tone map's toe
    /// steepens dark contrasts); in the default landscape it refines about
    /// 2.4 % of the pixels, mostly in the forest's crowns, whose lit and
    /// shaded needles disagree at every threshold (0.25 refines 12 %).
    pub adaptive_contrast: f32,
    /// The camera's blur: the standard deviation, in pixels, of the
    /// Gaussian pixel filter (truncated at 3σ) that weighs the samples of
    /// a pixel and of its neighbours into its value, in `[0, 1]`; 0 is the
    /// box, each pixel the mean of its own samples. A real camera's lens,
    /// low-pass filter and demosaicing spread a point of light over a few
    /// pixels, so a lit needle or a glint narrower than a pixel shows as a
    /// soft dot, not as one lone bright pixel; the default, 0.5, is the
    /// filter of Pharr, Jakob & Humphreys (2023, §8.8.4). Each pixel's
    /// samples count by their mean, so a pixel that took
    /// `adaptive_samples` weighs no more than its neighbours. In the
    /// default landscape at 1920 × 1080 it leaves 637 of the box's 2949
    /// stray pixels (the specks a lit crown tip or a sunlit spot makes
    /// among shade) for 6–9 % more render time (its tiles also trace the
    /// ring of pixels around them).
    pub filter_sigma_px: f32,
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
            terraces: TerracesDesc::default(),
            water: WaterDesc::default(),
            sun: SunDesc::default(),
            atmosphere: AtmosphereDesc::default(),
            materials: MaterialDesc::default(),
            detail: DetailDesc::default(),
            clouds: CloudsDesc::default(),
            textures: TexturesDesc::default(),
            vegetation: VegetationDesc::default(),
            camera: CameraDesc::default(),
            render: RenderDesc::default(),
            animation: AnimationDesc::default(),
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

impl TerrainDesc {
    /// Sets the samples per side to `size` and scales the cells so that the
    /// terrain keeps its extent in metres: the same world, finer or
    /// coarser. [`SceneDesc::validate`] checks the new size and cell size.
    ///
    /// ```
    /// use natura_render::TerrainDesc;
    ///
    /// let mut t = TerrainDesc::default(); // 2048 samples of 30 m
    /// t.resample(512);
    /// assert_eq!((t.size, t.cell_size_m), (512, 120.0));
    /// ```
    pub fn resample(&mut self, size: usize) {
        self.cell_size_m *= self.size as f32 / size as f32;
        self.size = size;
    }
}

impl Default for ErosionDesc {
    fn default() -> Self {
        Self {
            stream_power_steps: 15,
            stream_power: StreamPowerParams {
                k: 2e-6,
                m: 0.5,
                n: 1.0,
                uplift_m_per_yr: 0.0,
                dt_yr: 2000.0,
                // Route flow through depressions without filling them: they
                // become lakes, not sediment flats.
                depressions: Depressions::Route,
            },
            hydraulic_model: HydraulicModel::Droplets,
            droplets_per_sample: 0.25,
            droplets: DropletParams {
                radius: 3,
                capacity: 1.0,
                erode: 0.1,
                deposit: 0.1,
                evaporate: 0.02,
                // Rounds of droplets in row bands: both cores at work, every
                // droplet still on the live terrain.
                batch: 1 << 16,
                ..DropletParams::default()
            },
            hydraulic_steps: 120,
            pipe: PipeParams::default(),
            thermal_steps: 20,
            thermal: ThermalParams {
                talus_angle: 38f64.to_radians(),
                talus_rate: 0.1,
                ..ThermalParams::default()
            },
        }
    }
}

impl Default for WaterDesc {
    fn default() -> Self {
        Self {
            enabled: true,
            level_m: None,
            level_quantile: 0.12,
            waves: WaterWaves::Wind,
            ripple_height_m: 0.12,
            ripple_size_m: 40.0,
            wind_speed_m_s: 4.0,
            wind_azimuth_deg: 200.0,
            fetch_m: None,
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
            snow_max_slope_deg: 45.0,
            snow_slope_band_deg: 15.0,
            snow_sun_m: 150.0,
            snow_wind_m: 150.0,
            snow_shelter_distance_m: 300.0,
            snow_edge_m: 60.0,
            snow_edge_size_m: 150.0,
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

impl Default for DetailDesc {
    fn default() -> Self {
        Self {
            enabled: true,
            amplitude_m: 2.5,
            h: 0.8,
            lacunarity: 2.0,
            octaves: 9,
            seed_offset: 0,
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
            adaptive_samples: 16,
            adaptive_contrast: 0.7,
            filter_sigma_px: 0.5,
            exposure_ev: None,
            tone_map: ToneMap::AcesFilmic,
        }
    }
}
