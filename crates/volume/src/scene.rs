//! A ready-made kilometre-scale scene: layer clouds over a plain at sunset,
//! lit by the sun and sky of `natura-atmos` and seen through its aerial
//! perspective. The `cloudscape` example and the benchmarks render it.

use std::sync::Arc;

use glam::Vec3;
use natura_atmos::sky::{Atmosphere, AtmosphereParams, SkyView};
use natura_core::{NoProgress, Progress};

use crate::detail::{DetailParams, Detailed};
use crate::error::{Result, in_range, positive};
use crate::grid::GridDensity;
use crate::layer::{LayerClouds, LayerParams};
use crate::phase::CloudPhase;
use crate::transport::{
    CacheParams, FastSettings, GroundPlane, LookAtCamera, MediumParams, NearSunRays, Scattering,
    Scene, Shadows, SkyRadiance, Sun,
};

/// Parameters of [`Cloudscape`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CloudscapeParams {
    /// The cloud layer.
    pub layer: LayerParams,
    /// Sun elevation (degrees above the horizon, in `[−5, 90]`).
    pub sun_elevation_deg: f32,
    /// Voxel size of the baked layer (m).
    pub cell_m: f32,
    /// Extinction at cloud density 1 (1/m).
    pub extinction: f32,
    /// Eye height above the plain (m).
    pub eye_height_m: f32,
    /// Camera pitch above the horizon (degrees).
    pub pitch_deg: f32,
    /// Image size.
    pub width: usize,
    /// Image size.
    pub height: usize,
    /// Detail down to the pixel footprint around the baked grid
    /// ([`crate::detail`]), or `None` (the grid alone, bit for bit). Its
    /// `eye` and `pixel_angle` are replaced by the scene camera's.
    pub detail: Option<DetailParams>,
}

impl Default for CloudscapeParams {
    /// Broken cumulus between 1.2 and 2.6 km, the sun 6° up ahead, 1920 × 1080.
    fn default() -> Self {
        Self {
            layer: LayerParams {
                region_min: [-2_000.0, -18_000.0],
                region_max: [34_000.0, 18_000.0],
                base_m: 1200.0,
                top_m: 2600.0,
                coverage: 0.45,
                cloud_type: 0.75,
                ..LayerParams::default()
            },
            sun_elevation_deg: 6.0,
            cell_m: 100.0,
            extinction: 0.03,
            eye_height_m: 30.0,
            pitch_deg: 9.0,
            width: 1920,
            height: 1080,
            detail: None,
        }
    }
}

/// The scene of [`CloudscapeParams`]: the layer baked to a grid, the sky view
/// at the eye, the sun, the plain and the camera.
#[derive(Clone, Debug)]
pub struct Cloudscape {
    clouds: Detailed<GridDensity>,
    sky: Arc<SkyView>,
    sun: Sun,
    ground: GroundPlane,
    medium: MediumParams,
    camera: LookAtCamera,
}

impl Cloudscape {
    /// Builds the scene (bakes the clouds, builds the sky's tables).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter) for a bad
    /// field; [`VolumeError::Core`](crate::VolumeError::Core) for a bad image size (the
    /// camera's checks); as [`LayerClouds::new`], [`GridDensity::bake`],
    /// [`DetailParams::validate`] and the sky of `natura-atmos`.
    pub fn new(p: &CloudscapeParams, seed: u64) -> Result<Self> {
        Self::new_with_progress(p, seed, &NoProgress)
    }

    /// [`Cloudscape::new`], reporting the bake of the clouds to `progress`
    /// (as [`GridDensity::bake_with_progress`]: the stage `"bake"`, one unit
    /// per z slice).
    ///
    /// # Errors
    ///
    /// As [`Cloudscape::new`].
    pub fn new_with_progress(
        p: &CloudscapeParams,
        seed: u64,
        progress: &dyn Progress,
    ) -> Result<Self> {
        in_range(
            "sun_elevation_deg",
            p.sun_elevation_deg,
            -5.0,
            90.0,
            "must lie in [−5, 90]",
        )?;
        positive("cell_m", p.cell_m)?;
        positive("extinction", p.extinction)?;
        positive("eye_height_m", p.eye_height_m)?;
        in_range(
            "pitch_deg",
            p.pitch_deg,
            -80.0,
            80.0,
            "must lie in [−80, 80]",
        )?;
        let layer = LayerClouds::new(p.layer, seed)?;
        let clouds = GridDensity::bake_with_progress(&layer, p.cell_m, progress)?;
        let atm = Atmosphere::new(AtmosphereParams::default())?;
        let sun_dir = Atmosphere::sun_at_elevation_deg(f64::from(p.sun_elevation_deg))?;
        let eye = Vec3::new(0.0, 0.0, p.eye_height_m);
        let sky = Arc::new(atm.sky_view(eye.as_dvec3(), sun_dir)?);
        let sun = Sun::from_sky(&sky);
        let ground = GroundPlane {
            height: 0.0,
            albedo: Vec3::new(0.10, 0.12, 0.06),
            sky_irradiance: sky.sky_irradiance(),
        };
        let pitch = p.pitch_deg.to_radians();
        // A side beyond `u32` is refused by the camera's own size check.
        let side = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
        let fov = 50f32.to_radians();
        let camera = LookAtCamera::look_at(
            eye,
            eye + Vec3::new(pitch.cos(), 0.0, pitch.sin()) * 1000.0,
            Vec3::Z,
            fov,
            side(p.width),
            side(p.height),
        )?;
        let clouds = match &p.detail {
            Some(d) => {
                let d = d.seen_from(eye, fov / p.height.max(1) as f32);
                Detailed::new(clouds, &d, seed.wrapping_add(7))?
            }
            None => Detailed::without_detail(clouds),
        };
        Ok(Self {
            clouds,
            sky,
            sun,
            ground,
            medium: MediumParams {
                extinction: p.extinction,
                albedo: 0.99,
                phase: CloudPhase::default(),
            },
            camera,
        })
    }

    /// The scene to render.
    #[must_use]
    pub fn scene(&self) -> Scene<'_> {
        Scene {
            density: &self.clouds,
            medium: self.medium,
            sun: Some(self.sun),
            environment: SkyRadiance::Sky(self.sky.clone()),
            ground: Some(self.ground),
            emission: None,
            aerial: Some(self.sky.clone()),
            solids: Vec::new(),
        }
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> LookAtCamera {
        self.camera
    }

    /// The baked clouds (without the detail).
    #[must_use]
    pub fn clouds(&self) -> &GridDensity {
        self.clouds.base()
    }

    /// The clouds the scene renders: the baked grid with its detail, if any.
    #[must_use]
    pub fn density(&self) -> &Detailed<GridDensity> {
        &self.clouds
    }

    /// The fast mode's settings for this scene: steps of 40 m growing by 1 %
    /// of the distance, shadow tables of 256 nodes across (direct shadow
    /// rays in 20 m steps for the eye rays within 3° of the sun, blended into
    /// the table out to 4.5°), the multiple-scattering cache (64 cells
    /// across, bands up to 3 with a zonal tail about the sun's beam up to
    /// band 23, two million events: the clouds are thick and their
    /// multiply scattered light broad, except toward the low sun, where the
    /// tail keeps its peak; the ground's light left to the ambient term)
    /// with the forward peak truncated, the march stopped below a
    /// transmittance of 0.003.
    #[must_use]
    pub fn fast_settings(&self) -> FastSettings {
        FastSettings {
            step: 40.0,
            step_growth: 0.01,
            shadows: Shadows::Table(256),
            scattering: Scattering::Cache(CacheParams {
                cells: 64,
                events: 2_000_000,
                order: 3,
                zonal: 23,
                // The ground's light by the environment's ambient term: traced
                // (shadowed by the clouds), it moves the clouds' mean by
                // 0.2 % and costs 0.4 s.
                local: 0,
                ..CacheParams::default()
            }),
            powder: 0.0,
            min_transmittance: 0.003,
            truncate_forward_peak: true,
            near_sun: Some(NearSunRays {
                within_deg: 3.0,
                step: 20.0,
            }),
        }
    }
}
