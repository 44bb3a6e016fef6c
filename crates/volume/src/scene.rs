//! Ready-made scenes, each the one set-up its example, its tests and its
//! benchmarks share:
//!
//! - [`Cloudscape`]: kilometre-scale layer clouds over a plain at sunset,
//!   lit by the sun and sky of `natura-atmos` and seen through its aerial
//!   perspective (the `cloudscape` example);
//! - [`SteamCup`]: Ebert's steam rising from a teacup, lit from behind and
//!   the side (the `steam` example);
//! - [`SmokeAroundSphere`]: a fluid solver's warm smoke rising round a
//!   sphere over a floor, glowing by its temperature (the `smoke3d`
//!   example; the smoke itself comes from natura-fluid's `plume` preset).

use std::sync::Arc;

use glam::Vec3;
use natura_atmos::sky::{Atmosphere, AtmosphereParams, SkyView};
use natura_core::{NoProgress, Progress};

use crate::density::Density;
use crate::detail::{DetailParams, Detailed};
use crate::error::{Result, in_range, positive};
use crate::gas::{Steam, SteamParams};
use crate::grid::{GridDensity, SmokeVolume};
use crate::layer::{LayerClouds, LayerParams};
use crate::phase::CloudPhase;
use crate::transport::{
    CacheParams, Emission, FastSettings, GroundPlane, LookAtCamera, MediumParams, NearSunRays,
    Scattering, Scene, Shadows, SkyRadiance, Solid, SolidShape, Sun,
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
    /// `eye` and `pixel_angle` are replaced by the scene camera's, the
    /// angle widened to the march's parts where those are longer (see
    /// [`Cloudscape::fast_settings`]).
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
                let pixel = fov / p.height.max(1) as f32;
                let d = d.seen_by_march(eye, pixel, Self::STEP_GROWTH);
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

    /// The march's step at the eye (m).
    pub const STEP: f32 = 40.0;
    /// The growth of the march's step with the distance (m per m).
    pub const STEP_GROWTH: f32 = 0.01;
    /// Density samples per step with the detail (the grid alone takes one):
    /// [`DetailParams::MARCH_SUBSTEPS`].
    pub const DETAIL_SUBSTEPS: u32 = DetailParams::MARCH_SUBSTEPS;

    /// The fast mode's settings for this scene: steps of 40 m growing by 1 %
    /// of the distance (with the detail, three density samples per step, the
    /// light looked up once: [`FastSettings::substeps`]), shadow tables of 256 nodes across (direct shadow
    /// rays in 20 m steps for the eye rays within 3° of the sun, blended into
    /// the table out to 4.5°), the multiple-scattering cache (128 cells
    /// across, bands up to 3 with a zonal tail about the sun's beam up to
    /// band 23, two million events: the clouds are thick and their
    /// multiply scattered light broad, except toward the low sun, where the
    /// tail keeps its peak; the ground's light left to the ambient term;
    /// at 64 cells the thick cloud's light is smoothed over cells too wide
    /// and the frame's mean is 5.0 % short of the reference, at 128 4.4 %)
    /// with the forward peak truncated, the march stopped below a
    /// transmittance of 0.003.
    #[must_use]
    pub fn fast_settings(&self) -> FastSettings {
        FastSettings {
            step: Self::STEP,
            step_growth: Self::STEP_GROWTH,
            shadows: Shadows::Table(256),
            scattering: Scattering::Cache(CacheParams {
                cells: 128,
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
            substeps: if self.clouds.detail().is_some() {
                Self::DETAIL_SUBSTEPS
            } else {
                1
            },
        }
    }
}

/// Ebert's steam rising from a teacup at one moment (Ebert 2001, "Steam
/// rising from a teacup"): the basic gas shaped radially and vertically,
/// eroded by warped noise octaves down to a pixel's footprint, lit from
/// behind and the side, seen from 35 cm.
#[derive(Debug)]
pub struct SteamCup {
    steam: Steam,
    camera: LookAtCamera,
    step: f32,
}

impl SteamCup {
    /// The eye (m; the cup's rim is at the origin's height).
    pub const EYE: Vec3 = Vec3::new(0.0, -0.35, 0.07);
    /// The march's step (m).
    pub const STEP: f32 = 0.0008;

    /// The steam at `time` (s) from noise `seed`, for a `width × height`
    /// picture (its detail stops at that picture's pixel footprint, or at
    /// the march's step where that is longer: finer octaves would alias
    /// along the eye rays into streaks).
    ///
    /// # Errors
    ///
    /// As [`Steam::new`] (a bad time) and [`LookAtCamera::look_at`] (a bad
    /// picture size).
    pub fn new(time: f32, seed: u64, width: u32, height: u32) -> Result<Self> {
        let fov = 28f32.to_radians();
        let camera = LookAtCamera::look_at(
            Self::EYE,
            Vec3::new(0.0, 0.0, 0.045),
            Vec3::Z,
            fov,
            width,
            height,
        )?;
        let detail = DetailParams {
            feature_m: 0.015,
            octaves: 8,
            h: 0.8,
            amplitude: 0.12,
            warp: 0.35,
            ..DetailParams::default()
        }
        .seen_from(
            Self::EYE,
            (fov / height as f32).max(Self::STEP / Self::EYE.length()),
        );
        let steam = Steam::new(
            SteamParams {
                time,
                detail: Some(detail),
                ..SteamParams::default()
            },
            seed,
        )?;
        Ok(Self {
            steam,
            camera,
            step: Self::STEP,
        })
    }

    /// The cup and its tea: white porcelain, 9.6 cm across and 7 cm tall,
    /// its top 1 mm below the steam's mouth, and a disc of tea 1 mm thick on
    /// it, 4 mm short of its rim (closed cylinders: the cup's inside and
    /// its handle are not modelled).
    #[must_use]
    pub fn cup(&self) -> [Solid; 2] {
        let room = Vec3::new(0.3, 0.3, 0.36);
        [
            Solid {
                centre: Vec3::new(0.0, 0.0, -0.036),
                radius: 0.048,
                albedo: Vec3::new(0.85, 0.83, 0.8),
                sky_irradiance: room,
                shape: SolidShape::Cylinder { half_height: 0.035 },
            },
            Solid {
                centre: Vec3::new(0.0, 0.0, -0.0005),
                radius: 0.044,
                albedo: Vec3::new(0.09, 0.04, 0.015),
                sky_irradiance: room,
                shape: SolidShape::Cylinder {
                    half_height: 0.0005,
                },
            },
        ]
    }

    /// The scene: the steam (extinction 60 /m, albedo 0.95, Henyey–Greenstein
    /// g = 0.5) over its cup ([`SteamCup::cup`]) under a warm sun behind and
    /// beside it, a dim blue-grey room.
    #[must_use]
    pub fn scene(&self) -> Scene<'_> {
        Scene {
            sun: Some(Sun {
                direction: Vec3::new(-0.3, 0.8, 0.5).normalize(),
                irradiance: Vec3::new(2.4, 2.2, 2.0),
            }),
            solids: self.cup().to_vec(),
            ..Scene::new(
                &self.steam,
                MediumParams {
                    extinction: 60.0,
                    albedo: 0.95,
                    phase: CloudPhase::HenyeyGreenstein(0.5),
                },
                Vec3::new(0.03, 0.03, 0.04),
            )
        }
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> LookAtCamera {
        self.camera
    }

    /// The fast mode's settings: 0.8 mm steps, a shadow table of 96 nodes
    /// across, the multiple-scattering cache.
    #[must_use]
    pub fn fast_settings(&self) -> FastSettings {
        small_scene_settings(self.step)
    }
}

/// A fluid solver's warm smoke rising round a sphere over a floor (Fedkiw,
/// Stam & Jensen 2001, Fig. 5 in spirit): the smoke eroded by warped noise
/// octaves below the solver's cells, glowing by its temperature, the
/// sphere visible and casting its shadow on the smoke and the floor, the
/// sun high behind the camera's left.
#[derive(Debug)]
pub struct SmokeAroundSphere {
    density: Detailed<GridDensity>,
    temperature: GridDensity,
    ambient: f32,
    sphere: (Vec3, f32),
    camera: LookAtCamera,
    step: f32,
}

impl SmokeAroundSphere {
    /// The sky's radiance behind the smoke.
    pub const BACKGROUND: Vec3 = Vec3::new(0.05, 0.07, 0.12);

    /// The scene of `volume` (a solver's density and temperature) round the
    /// sphere of `centre` and `radius` (m), for a `width × height` picture
    /// seen from 3.4 box widths in front (the detail stops at the
    /// picture's pixel footprint or the march's step of half a cell,
    /// whichever is longer).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter)
    /// naming `radius` when it is not finite and positive; as
    /// [`LookAtCamera::look_at`] (a bad picture size) and [`Detailed::new`].
    pub fn new(volume: SmokeVolume, sphere: (Vec3, f32), width: u32, height: u32) -> Result<Self> {
        positive("radius", sphere.1)?;
        let b = volume.density.bounds();
        let centre = (b.min + b.max) * 0.5;
        let eye = centre + Vec3::new(0.6, -3.4, 0.1);
        let fov = 40f32.to_radians();
        let camera = LookAtCamera::look_at(eye, centre, Vec3::Z, fov, width, height)?;
        let step = 0.5 * volume.density.cell();
        let detail = DetailParams {
            feature_m: 2.0 * volume.density.cell(),
            octaves: 6,
            h: 0.8,
            amplitude: 0.4,
            warp: 0.3,
            ..DetailParams::default()
        }
        .seen_from(
            eye,
            (fov / height as f32).max(step / (eye - centre).length()),
        );
        let SmokeVolume {
            density,
            temperature,
            ambient,
        } = volume;
        Ok(Self {
            density: Detailed::new(density, &detail, 0x5e0c)?,
            temperature,
            ambient,
            sphere,
            camera,
            step,
        })
    }

    /// The scene: the smoke (extinction 40 /m, albedo 0.9, Henyey–Greenstein
    /// g = 0.3, glowing by its temperature above the ambient), a grey floor
    /// at height 0, the terracotta sphere, and the sun.
    #[must_use]
    pub fn scene(&self) -> Scene<'_> {
        let sky = Self::BACKGROUND * std::f32::consts::PI;
        Scene {
            sun: Some(Sun {
                direction: Vec3::new(-0.5, -0.3, 1.0).normalize(),
                irradiance: Vec3::new(2.6, 2.5, 2.3),
            }),
            ground: Some(GroundPlane {
                height: 0.0,
                albedo: Vec3::splat(0.35),
                sky_irradiance: sky,
            }),
            solids: vec![Solid {
                centre: self.sphere.0,
                radius: self.sphere.1,
                albedo: Vec3::new(0.7, 0.35, 0.25),
                sky_irradiance: sky,
                shape: SolidShape::Sphere,
            }],
            emission: Some(Emission {
                field: &self.temperature,
                offset: self.ambient,
                colour: Vec3::new(0.008, 0.003, 0.0008),
            }),
            ..Scene::new(
                &self.density,
                MediumParams {
                    extinction: 40.0,
                    albedo: 0.9,
                    phase: CloudPhase::HenyeyGreenstein(0.3),
                },
                Self::BACKGROUND,
            )
        }
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> LookAtCamera {
        self.camera
    }

    /// The fast mode's settings: steps of half a cell, a shadow table of 96
    /// nodes across, the multiple-scattering cache (with the light of the
    /// floor, the sphere and the glow).
    #[must_use]
    pub fn fast_settings(&self) -> FastSettings {
        small_scene_settings(self.step)
    }
}

/// The fast mode of the small presets: steps of `step`, a shadow table of
/// 96 nodes across, the multiple-scattering cache with its defaults.
fn small_scene_settings(step: f32) -> FastSettings {
    FastSettings {
        step,
        shadows: Shadows::Table(96),
        ..FastSettings::default()
    }
    .multiple_scattering()
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::Grid3;

    #[test]
    fn the_small_presets_build_their_scenes_and_refuse_bad_input() {
        let cup = SteamCup::new(1.0, 3, 16, 20).unwrap();
        let scene = cup.scene();
        assert!(scene.validate().is_ok());
        // The cup and its tea stand under the steam's mouth, the tea's top
        // level with it.
        assert_eq!(scene.solids.len(), 2);
        assert!(
            scene
                .solids
                .iter()
                .all(|s| !s.contains(Vec3::new(0.0, 0.0, 1e-4)))
        );
        assert!(scene.solids[1].contains(Vec3::new(0.0, 0.0, -1e-4)));
        assert_eq!(cup.camera().resolution().x, 16);
        assert!(SteamCup::new(1.0, 3, 0, 20).is_err());

        let n = 8;
        let mut rho = Grid3::new(n, n, 2 * n, 0.0f32).unwrap();
        rho[(4, 4, 4)] = 1.0;
        let t = Grid3::new(n, n, 2 * n, 300.0f32).unwrap();
        let vol = || SmokeVolume::from_solver(&rho, t.clone(), 0.125, 290.0).unwrap();
        let sphere = (Vec3::new(0.45, 0.5, 0.85), 0.15);
        let shot = SmokeAroundSphere::new(vol(), sphere, 10, 16).unwrap();
        let scene = shot.scene();
        assert!(scene.validate().is_ok());
        assert_eq!(scene.solids.len(), 1);
        assert!(scene.ground.is_some() && scene.emission.is_some());
        let e = SmokeAroundSphere::new(vol(), (sphere.0, f32::NAN), 10, 16).unwrap_err();
        assert!(e.to_string().contains("radius"), "{e}");
        assert!(SmokeAroundSphere::new(vol(), sphere, 10, 0).is_err());
    }
}
