//! The scene's value checks: every key against its range before any work
//! starts, naming the first bad key, section by section; then the memory
//! the scene asks for against the budget (`budget.rs`).

use super::{
    AtmosphereDesc, CameraDesc, DetailDesc, Diffuse, ErosionDesc, MaterialDesc, RenderDesc,
    SceneDesc, SunDesc, TerrainDesc, WaterDesc, WaterWaves,
};
use crate::error::{RenderError, Result, fmt_f64};

pub(super) use crate::error::in_range;

/// Bound on compass azimuths, degrees: any direction, with room to spare
/// for a sequence that turns several times, while `to_radians` stays exact
/// enough in `f32`.
pub(super) const MAX_AZIMUTH_DEG: f64 = 1e4;

impl SceneDesc {
    /// Checks every value before any work starts, naming the first bad key;
    /// then that the scene fits the memory budget
    /// ([`MEMORY_BUDGET_BYTES`](super::MEMORY_BUDGET_BYTES)).
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`] naming the first scene key out of
    /// its range (the message gives the key, the value and the range), or
    /// the keys that make the scene too large for the memory budget.
    pub fn validate(&self) -> Result<()> {
        self.animation.validate()?;
        self.terrain.validate()?;
        self.validate_fractal()?;
        self.erosion.validate()?;
        self.water.validate()?;
        self.sun.validate()?;
        self.atmosphere.validate()?;
        self.detail.validate()?;
        self.vegetation.validate()?;
        self.materials.validate()?;
        self.camera.validate()?;
        self.clouds.validate()?;
        self.textures.validate()?;
        self.terraces
            .validate(self.textures.strata.zscale, self.textures.strata.txtscale)?;
        self.render.validate()?;
        self.validate_animation_keys()?;
        self.check_memory_budget()
    }
}

impl TerrainDesc {
    fn validate(&self) -> Result<()> {
        in_range("terrain.size", self.size, 64.0, 16_384.0)?;
        in_range("terrain.cell_size_m", self.cell_size_m, 1e-3, 1e5)?;
        in_range("terrain.feature_size_m", self.feature_size_m, 1e-3, 1e9)?;
        in_range("terrain.relief_m", self.relief_m, 0.0, 20_000.0)?;
        in_range("terrain.h", self.h, -1.0, 3.0)?;
        in_range("terrain.lacunarity", self.lacunarity, 1.01, 16.0)?;
        in_range("terrain.octaves", self.octaves, 1.0, 24.0)?;
        in_range("terrain.offset", self.offset, -1e3, 1e3)?;
        in_range("terrain.gain", self.gain, -1e3, 1e3)?;
        in_range("terrain.warp", self.warp, 0.0, 4.0)?;
        in_range("terrain.coast_fraction", self.coast_fraction, 0.0, 0.5)?;
        in_range("terrain.coast_depth_m", self.coast_depth_m, 0.0, 20_000.0)
    }
}

impl SceneDesc {
    /// The terrain's fractal from its keys: the noise's own checks (the
    /// octaves a lacunarity allows, a bounded fractal), named by the keys.
    fn validate_fractal(&self) -> Result<()> {
        crate::world::TerrainFunction::new(self, natura_core::Seed(self.seed)).map(|_| ())
    }
}

impl ErosionDesc {
    fn validate(&self) -> Result<()> {
        let steps = |name: &str, v: u32, hi: f64| in_range(name, v, 0.0, hi);
        steps("erosion.stream_power_steps", self.stream_power_steps, 1e4)?;
        self.stream_power
            .validate()
            .map_err(|x| RenderError::in_section("erosion.stream_power", x))?;
        in_range(
            "erosion.droplets_per_sample",
            self.droplets_per_sample,
            0.0,
            1000.0,
        )?;
        self.droplets
            .validate()
            .map_err(|x| RenderError::in_section("erosion.droplets", x))?;
        steps("erosion.hydraulic_steps", self.hydraulic_steps, 1e5)?;
        self.pipe
            .validate()
            .map_err(|x| RenderError::in_section("erosion.pipe", x))?;
        steps("erosion.thermal_steps", self.thermal_steps, 1e5)?;
        self.thermal
            .validate()
            .map_err(|x| RenderError::in_section("erosion.thermal", x))
    }
}

impl WaterDesc {
    fn validate(&self) -> Result<()> {
        if let Some(l) = self.level_m {
            in_range("water.level_m", l, -1e5, 1e5)?;
        }
        in_range("water.level_quantile", self.level_quantile, 0.0, 1.0)?;
        in_range("water.ripple_height_m", self.ripple_height_m, 0.0, 100.0)?;
        in_range("water.ripple_size_m", self.ripple_size_m, 1e-3, 1e6)?;
        // The weakest wind the wind sea and the ocean take, m/s (a calm is
        // 0 exactly, for the wind sea): Beaufort's calm reaches 0.5 m/s, and
        // far below it a spectrum's peak leaves f64 (a subnormal wind
        // validated and gave NaN waves).
        let breeze = 0.1;
        let u = self.wind_speed_m_s;
        if self.waves == WaterWaves::Ocean || u != 0.0 {
            in_range("water.wind_speed_m_s", u, breeze, 60.0).map_err(|e| match e {
                RenderError::Invalid {
                    name,
                    value,
                    reason,
                } if self.waves != WaterWaves::Ocean => RenderError::Invalid {
                    name,
                    value,
                    reason: format!(
                        "must be 0 (a calm) or {}",
                        reason.trim_start_matches("must ")
                    ),
                },
                e => e,
            })?;
        }
        if let Some(f) = self.fetch_m {
            in_range("water.fetch_m", f, 1.0, 1e7)?;
        }
        let az = MAX_AZIMUTH_DEG;
        in_range("water.wind_azimuth_deg", self.wind_azimuth_deg, -az, az)?;
        in_range("water.ocean_patch_m", self.ocean_patch_m, 1.0, 1e5)?;
        in_range("water.ocean_time_s", self.ocean_time_s, -1e6, 1e6)?;
        let n = self.ocean_resolution;
        if !n.is_power_of_two() || !(natura_ocean::MIN_SIZE..=natura_ocean::MAX_SIZE).contains(&n) {
            return Err(RenderError::Invalid {
                name: "water.ocean_resolution".into(),
                value: n.to_string(),
                reason: format!(
                    "must be a power of two in {}..={}",
                    natura_ocean::MIN_SIZE,
                    natura_ocean::MAX_SIZE
                ),
            });
        }
        for (i, v) in self.extinction_per_m.into_iter().enumerate() {
            in_range(&format!("water.extinction_per_m[{i}]"), v, 0.0, 1e3)?;
        }
        for (i, v) in self.scatter_albedo.into_iter().enumerate() {
            in_range(&format!("water.scatter_albedo[{i}]"), v, 0.0, 1.0)?;
        }
        Ok(())
    }
}

impl SunDesc {
    fn validate(&self) -> Result<()> {
        in_range("sun.elevation_deg", self.elevation_deg, -90.0, 90.0)?;
        let az = MAX_AZIMUTH_DEG;
        in_range("sun.azimuth_deg", self.azimuth_deg, -az, az)?;
        in_range(
            "sun.angular_diameter_deg",
            self.angular_diameter_deg,
            0.01,
            20.0,
        )?;
        self.check_above_horizon("sun.elevation_deg", self.elevation_deg)
    }

    /// Refuses an elevation below the horizon (the key's or an animation
    /// key's) unless twilight is allowed.
    pub(super) fn check_above_horizon(&self, name: &str, elevation_deg: f64) -> Result<()> {
        if !self.allow_below_horizon && elevation_deg < 0.0 {
            return Err(RenderError::invalid(
                name,
                fmt_f64(elevation_deg),
                "the sun is below the horizon; set sun.allow_below_horizon = true for twilight",
            ));
        }
        Ok(())
    }
}

impl AtmosphereDesc {
    fn validate(&self) -> Result<()> {
        in_range("atmosphere.haze", self.haze, 0.0, 100.0)?;
        in_range("atmosphere.mie_g", self.mie_g, 0.0, 0.99)?;
        in_range(
            "atmosphere.rain_extinction_per_m",
            self.rain_extinction_per_m,
            0.0,
            1.0,
        )?;
        in_range("atmosphere.rain_distance_m", self.rain_distance_m, 0.0, 1e6)
    }
}

impl DetailDesc {
    fn validate(&self) -> Result<()> {
        in_range("detail.amplitude_m", self.amplitude_m, 0.0, 1000.0)?;
        in_range("detail.h", self.h, 0.0, 2.0)?;
        in_range("detail.lacunarity", self.lacunarity, 1.5, 4.0)?;
        in_range("detail.octaves", self.octaves, 0.0, 24.0)
    }
}

impl MaterialDesc {
    fn validate(&self) -> Result<()> {
        in_range("materials.snow_line_m", self.snow_line_m, -1e6, 1e6)?;
        in_range(
            "materials.snow_line_noise_m",
            self.snow_line_noise_m,
            0.0,
            1e4,
        )?;
        in_range(
            "materials.snow_max_slope_deg",
            self.snow_max_slope_deg,
            0.0,
            90.0,
        )?;
        in_range(
            "materials.snow_slope_band_deg",
            self.snow_slope_band_deg,
            0.1,
            45.0,
        )?;
        in_range("materials.snow_sun_m", self.snow_sun_m, 0.0, 1e4)?;
        in_range("materials.snow_wind_m", self.snow_wind_m, 0.0, 1e4)?;
        in_range(
            "materials.snow_shelter_distance_m",
            self.snow_shelter_distance_m,
            0.0,
            1e4,
        )?;
        in_range("materials.snow_edge_m", self.snow_edge_m, 0.0, 1e4)?;
        in_range(
            "materials.snow_edge_size_m",
            self.snow_edge_size_m,
            0.1,
            1e5,
        )?;
        in_range("materials.rock_slope_deg", self.rock_slope_deg, 0.0, 90.0)?;
        in_range("materials.tree_line_m", self.tree_line_m, -1e6, 1e6)?;
        in_range("materials.sediment_min_m", self.sediment_min_m, 0.0, 1e4)?;
        in_range("materials.beach_height_m", self.beach_height_m, 0.0, 1e3)?;
        if let Diffuse::OrenNayar { sigma_deg } = self.diffuse {
            in_range("materials.diffuse.sigma_deg", sigma_deg, 0.0, 90.0)?;
        }
        for (name, c) in [
            ("materials.snow", self.snow),
            ("materials.rock", self.rock),
            ("materials.grass", self.grass),
            ("materials.forest", self.forest),
            ("materials.soil", self.soil),
            ("materials.sediment", self.sediment),
            ("materials.sand", self.sand),
        ] {
            for (i, v) in c.into_iter().enumerate() {
                in_range(&format!("{name}[{i}]"), v, 0.0, 1.0)?;
            }
        }
        in_range("materials.bump_size_m", self.bump_size_m, 0.0, 1e4)?;
        in_range("materials.bump_strength", self.bump_strength, 0.0, 10.0)
    }
}

impl CameraDesc {
    fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("camera.position_uv[0]", self.position_uv[0]),
            ("camera.position_uv[1]", self.position_uv[1]),
            ("camera.target_uv[0]", self.target_uv[0]),
            ("camera.target_uv[1]", self.target_uv[1]),
        ] {
            in_range(name, v, 0.0, 1.0)?;
        }
        if self.position_uv == self.target_uv {
            return Err(RenderError::invalid(
                "camera.target_uv",
                format!("{:?}", self.target_uv),
                "must differ from camera.position_uv",
            ));
        }
        in_range(
            "camera.height_above_ground_m",
            self.height_above_ground_m,
            0.01,
            1e6,
        )?;
        in_range("camera.pitch_deg", self.pitch_deg, -89.0, 89.0)?;
        in_range("camera.vfov_deg", self.vfov_deg, 0.1, 179.0)?;
        // Checked for every kind: a pinhole camera does not use it, but a
        // NaN or out-of-range value written there is still refused, not kept
        // (a scene that validates round-trips through its text unchanged).
        in_range("camera.hfov_deg", self.hfov_deg, 0.1, 720.0)
    }
}

impl RenderDesc {
    fn validate(&self) -> Result<()> {
        in_range("render.width", self.width, 1.0, 16_384.0)?;
        in_range("render.height", self.height, 1.0, 16_384.0)?;
        in_range("render.spp", self.spp, 1.0, 4096.0)?;
        in_range(
            "render.adaptive_samples",
            self.adaptive_samples,
            0.0,
            4096.0,
        )?;
        in_range("render.adaptive_contrast", self.adaptive_contrast, 0.0, 1.0)?;
        in_range("render.filter_sigma_px", self.filter_sigma_px, 0.0, 1.0)?;
        if let Some(ev) = self.exposure_ev {
            in_range("render.exposure_ev", ev, -64.0, 64.0)?;
        }
        Ok(())
    }
}
