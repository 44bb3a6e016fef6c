//! The scene's `[clouds]` section: a layer-cloud sky over the landscape
//! (natura-volume's layer model and cloud medium, embedded as their own
//! parameter structs), with the settings of its fast rendering, and their
//! checks.

use natura_volume::VolumeError;
use natura_volume::detail::DetailParams;
use natura_volume::layer::LayerParams;
use natura_volume::phase::CloudPhase;
use natura_volume::transport::{CacheParams, MediumParams, Scattering};
use serde::{Deserialize, Serialize};

use super::validate::in_range;
use crate::error::{RenderError, Result};

/// Layer clouds over the whole scene, lit by the sun and sky, casting
/// shadows on the terrain and water, seen through the aerial perspective.
///
/// The layer must lie above the terrain and the camera (checked when the
/// world is rendered): the clouds are then seen only by rays that leave the
/// terrain, so they are marched once per direction on a grid of directions
/// (not per sample), and their shadows come from a 2-D map of the sun's
/// transmittance through the layer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CloudsDesc {
    /// Whether there are clouds at all (a coverage or density scale of 0
    /// is a clear sky too).
    pub enabled: bool,
    /// The cloud layer: natura-volume's [`LayerParams`] in world metres
    /// (the terrain spans `[0, size·cell_size_m]` in x and y).
    pub layer: LayerParams,
    /// The cloud medium: natura-volume's [`MediumParams`] (extinction per
    /// metre at density 1, albedo, phase function).
    pub medium: MediumParams,
    /// Edge of the voxels the layer is baked into, metres.
    pub voxel_m: f32,
    /// Step of the march through the layer near the eye, metres.
    pub step_m: f32,
    /// Growth of the march's step with distance (metres per metre).
    pub step_growth: f32,
    /// Nodes of the clouds' own sun-shadow table along the region's longest side.
    pub shadow_table_nodes: usize,
    /// Angular size of a cell of the grid of marched directions, in pixels
    /// (1: one march per pixel; larger is faster and softer).
    pub cache_pixels: f32,
    /// Cell of the 2-D map of the sun's transmittance through the layer
    /// (the clouds' shadows on the ground and water), metres.
    pub shadow_cell_m: f32,
    /// Added to the scene's seed for the clouds' noise.
    pub seed_offset: u64,
    /// The wind that carries the clouds over an animation, metres per
    /// second toward +x (east) and +y (north): frame `f` adds
    /// `wind_m_s · f / fps` to `layer.wind_offset`.
    pub wind_m_s: [f64; 2],
    /// Detail down to the footprint of the marched directions:
    /// natura-volume's [`DetailParams`] (the baked layer eroded by noise
    /// octaves that stop where a cell of [`CloudsDesc::cache_pixels`] pixels
    /// can no longer show them, or at a third of the march's step where
    /// that is longer: the march samples the density in three parts a
    /// step when the detail is on; Schneider 2015's erosion). Its `eye` and
    /// `pixel_angle` are replaced by the camera's; `amplitude = 0` turns the
    /// detail off (the baked layer alone, as before it existed).
    pub detail: DetailParams,
    /// How the clouds' light scattered more than once is counted:
    /// natura-volume's [`Scattering`]. The default is its cache
    /// ([`CacheParams`]: the sun's light traced once per scene onto a grid
    /// over the layer, with spherical-harmonic bands up to 3); `"single"`
    /// counts single scattering only, and `{ octaves = { … } }` the octave
    /// approximation of Wrenninge et al. 2013, which needs no set-up.
    pub scattering: Scattering,
}

impl Default for CloudsDesc {
    fn default() -> Self {
        Self {
            enabled: true,
            layer: LayerParams {
                region_min: [-25_000.0, -15_000.0],
                region_max: [75_000.0, 85_000.0],
                base_m: 3200.0,
                top_m: 4800.0,
                coverage: 0.42,
                cloud_type: 0.75,
                weather_scale_m: 9000.0,
                shape_scale_m: 2500.0,
                detail_scale_m: 450.0,
                detail_erosion: 0.35,
                density_scale: 1.0,
                wind_offset: [0.0, 0.0],
                detail: None,
            },
            medium: MediumParams {
                extinction: 0.03,
                albedo: 0.99,
                phase: CloudPhase::Cloud { diameter_um: 20.0 },
            },
            voxel_m: 125.0,
            step_m: 60.0,
            step_growth: 0.01,
            shadow_table_nodes: 400,
            cache_pixels: 2.0,
            shadow_cell_m: 100.0,
            seed_offset: 0,
            wind_m_s: [6.0, 2.0],
            // No warp: the curl noise that stirs the detail (nine lookups a
            // sample) adds about a quarter to a detailed frame (the
            // cloudscape at 1080 rows: 5.2 s against 4.1 s).
            detail: DetailParams {
                feature_m: 250.0,
                warp: 0.0,
                ..DetailParams::default()
            },
            scattering: Scattering::Cache(CacheParams {
                cells: 96,
                events: 4_000_000,
                order: 3,
                zonal: 0,
                // The terrain is drawn apart from the clouds' scene, which
                // has no ground or solids to light them.
                local: 0,
                seed: 0x5ca7,
            }),
        }
    }
}

/// Most voxels the baked layer may hold.
pub const MAX_CLOUD_VOXELS: f64 = 64.0 * 1024.0 * 1024.0;

impl CloudsDesc {
    /// Whether the clouds are drawn: enabled, with coverage and density.
    #[must_use]
    pub fn visible(&self) -> bool {
        self.enabled && self.layer.coverage > 0.0 && self.layer.density_scale > 0.0
    }

    /// Checks every key of the section (whether or not it is enabled).
    pub(crate) fn validate(&self) -> Result<()> {
        in_range("clouds.wind_m_s[0]", self.wind_m_s[0], -100.0, 100.0)?;
        in_range("clouds.wind_m_s[1]", self.wind_m_s[1], -100.0, 100.0)?;
        let l = &self.layer;
        for (name, v) in [
            ("clouds.layer.region_min[0]", l.region_min[0]),
            ("clouds.layer.region_min[1]", l.region_min[1]),
            ("clouds.layer.region_max[0]", l.region_max[0]),
            ("clouds.layer.region_max[1]", l.region_max[1]),
        ] {
            in_range(name, f64::from(v), -1e7, 1e7)?;
        }
        for k in 0..2 {
            if l.region_max[k] <= l.region_min[k] {
                return Err(RenderError::invalid(
                    "clouds.layer.region_max",
                    format!("{:?}", l.region_max),
                    "must exceed clouds.layer.region_min on each axis",
                ));
            }
        }
        in_range("clouds.layer.base_m", f64::from(l.base_m), 0.0, 1e5)?;
        in_range("clouds.layer.top_m", f64::from(l.top_m), 0.0, 1e5)?;
        if l.top_m <= l.base_m {
            return Err(RenderError::invalid(
                "clouds.layer.top_m",
                l.top_m,
                "must lie above clouds.layer.base_m",
            ));
        }
        in_range(
            "clouds.layer.density_scale",
            f64::from(l.density_scale),
            0.0,
            100.0,
        )?;
        if l.detail.is_some() {
            // Baked into voxels, the footprint's octaves would be lost.
            return Err(RenderError::invalid(
                "clouds.layer.detail",
                "a table",
                "the layer is baked into voxels: give its detail as clouds.detail",
            ));
        }
        l.validate().map_err(|e| in_section("clouds.layer", e))?;
        in_range(
            "clouds.medium.extinction",
            f64::from(self.medium.extinction),
            0.0,
            1.0,
        )?;
        self.medium
            .validate()
            .map_err(|e| in_section("clouds.medium", e))?;
        in_range("clouds.voxel_m", f64::from(self.voxel_m), 10.0, 10_000.0)?;
        let voxels = f64::from((l.region_max[0] - l.region_min[0]) / self.voxel_m).ceil()
            * f64::from((l.region_max[1] - l.region_min[1]) / self.voxel_m).ceil()
            * f64::from((l.top_m - l.base_m) / self.voxel_m).ceil();
        if voxels > MAX_CLOUD_VOXELS {
            return Err(RenderError::invalid(
                "clouds.voxel_m",
                self.voxel_m,
                "too small for the layer's region: more than 2^26 voxels",
            ));
        }
        in_range("clouds.step_m", f64::from(self.step_m), 1.0, 10_000.0)?;
        in_range("clouds.step_growth", f64::from(self.step_growth), 0.0, 1.0)?;
        in_range(
            "clouds.shadow_table_nodes",
            self.shadow_table_nodes as f64,
            2.0,
            1024.0,
        )?;
        in_range(
            "clouds.cache_pixels",
            f64::from(self.cache_pixels),
            0.25,
            64.0,
        )?;
        in_range(
            "clouds.shadow_cell_m",
            f64::from(self.shadow_cell_m),
            1.0,
            10_000.0,
        )?;
        self.detail
            .validate()
            .map_err(|e| in_section("clouds.detail", e))?;
        // Its keys are named `cache.…` and `octaves.…` already.
        self.scattering
            .validate()
            .map_err(|e| in_section("clouds.scattering", e))?;
        Ok(())
    }
}

/// A natura-volume parameter error re-named by the scene key of its
/// sub-table (`coverage` in `clouds.layer` becomes `clouds.layer.coverage`).
pub(crate) fn in_section(section: &str, e: VolumeError) -> RenderError {
    match e {
        VolumeError::InvalidParameter {
            name,
            value,
            expected,
        } => RenderError::Invalid {
            name: format!("{section}.{name}"),
            value: crate::error::short(&value),
            reason: expected.to_owned(),
        },
        VolumeError::InvalidBounds { min, max, .. } => RenderError::Invalid {
            name: format!("{section}.region_min"),
            value: format!("{min:?} to {max:?}"),
            reason: "the layer's box must be finite and not empty".to_owned(),
        },
        other => RenderError::Volume(other),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn invalid_name(e: RenderError) -> String {
        match e {
            RenderError::Invalid { name, .. } => name,
            other => panic!("expected Invalid, got {other:?}"),
        }
    }

    /// The detail's keys are checked by their scene names; a layer's own
    /// detail (which baking would lose) is refused.
    #[test]
    fn bad_detail_keys_are_named() {
        let mut d = CloudsDesc::default();
        d.validate().unwrap();
        d.detail.amplitude = 1.5;
        assert_eq!(
            invalid_name(d.validate().unwrap_err()),
            "clouds.detail.amplitude"
        );
        let mut d = CloudsDesc::default();
        d.detail.feature_m = f32::NAN;
        assert_eq!(
            invalid_name(d.validate().unwrap_err()),
            "clouds.detail.feature_m"
        );
        let mut d = CloudsDesc::default();
        d.layer.detail = Some(DetailParams::default());
        assert_eq!(
            invalid_name(d.validate().unwrap_err()),
            "clouds.layer.detail"
        );
    }

    /// The multiple scattering's keys are checked by their scene names, and
    /// each choice survives a round trip through TOML.
    #[test]
    fn scattering_keys_are_named_and_round_trip() {
        use natura_volume::transport::ScatterOctaves;
        let mut d = CloudsDesc::default();
        if let Scattering::Cache(c) = &mut d.scattering {
            c.cells = 2;
        }
        assert_eq!(
            invalid_name(d.validate().unwrap_err()),
            "clouds.scattering.cache.cells"
        );
        d.scattering = Scattering::Octaves(ScatterOctaves {
            a: f32::NAN,
            ..ScatterOctaves::default()
        });
        assert_eq!(
            invalid_name(d.validate().unwrap_err()),
            "clouds.scattering.octaves.a"
        );
        for choice in [
            Scattering::Single,
            Scattering::Octaves(ScatterOctaves::default()),
            CloudsDesc::default().scattering,
        ] {
            let mut scene = crate::SceneDesc::default();
            scene.clouds.scattering = choice;
            let text = scene.to_toml_string().unwrap();
            let back = crate::SceneDesc::from_toml_str(&text, "round.toml").unwrap();
            assert_eq!(back.clouds.scattering, choice, "{text}");
        }
    }
}
