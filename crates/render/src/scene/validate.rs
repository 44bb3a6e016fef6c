//! The scene's value checks: every key against its range before any work
//! starts, naming the first bad key.

use natura_core::check::{finite, positive};

use super::{CameraKind, Diffuse, SceneDesc};
use crate::error::{RenderError, Result};

impl SceneDesc {
    /// Checks every value before any work starts, naming the first bad key.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`] naming the first scene key out of
    /// its range (the message gives the key, the value and the range).
    pub fn validate(&self) -> Result<()> {
        self.animation.validate()?;
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
        e.stream_power
            .validate()
            .map_err(|x| RenderError::in_section("erosion.stream_power", x))?;
        in_range(
            "erosion.droplets_per_sample",
            e.droplets_per_sample,
            0.0,
            1000.0,
        )?;
        e.droplets
            .validate()
            .map_err(|x| RenderError::in_section("erosion.droplets", x))?;
        in_range(
            "erosion.hydraulic_steps",
            f64::from(e.hydraulic_steps),
            0.0,
            100_000.0,
        )?;
        e.pipe
            .validate()
            .map_err(|x| RenderError::in_section("erosion.pipe", x))?;
        in_range(
            "erosion.thermal_steps",
            f64::from(e.thermal_steps),
            0.0,
            100_000.0,
        )?;
        e.thermal
            .validate()
            .map_err(|x| RenderError::in_section("erosion.thermal", x))?;

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
                name: "water.ocean_resolution".into(),
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

        let d = &self.detail;
        in_range("detail.amplitude_m", d.amplitude_m, 0.0, 1000.0)?;
        in_range("detail.h", d.h, 0.0, 2.0)?;
        in_range("detail.lacunarity", d.lacunarity, 1.5, 4.0)?;
        in_range("detail.octaves", f64::from(d.octaves), 0.0, 24.0)?;

        self.vegetation.validate()?;

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

        self.clouds.validate()?;
        self.textures.validate()?;
        self.terraces.validate(self.textures.strata.zscale)?;

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

/// Checks that `v` lies in `[lo, hi]`, saying so with the bounds in the message.
pub(super) fn in_range(name: &'static str, v: f64, lo: f64, hi: f64) -> Result<()> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(RenderError::Invalid {
            name: name.to_owned(),
            value: format!("{v}"),
            reason: format!("must lie in [{lo}, {hi}]"),
        })
    }
}
