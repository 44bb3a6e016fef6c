//! The integrator: radiance along camera rays through the world.
//!
//! Primary rays are grid-traced against the terrain (maximum mipmaps), sun
//! shadows come from any-hit rays, the water plane reflects (traced terrain
//! or sky) and refracts (the lake bed seen through absorbing water) with
//! exact Fresnel weights, aerial perspective is applied to every segment
//! that reaches the camera, escaped rays see the sky with its sun disc, and
//! rain shows a rainbow opposite the sun. This is the shading pipeline of
//! Musgrave's landscapes (Musgrave 1993, ch. 3–4) with physical sky and haze.
//!
//! This module traces (pixels, samples, the first surface a ray meets);
//! the light leaving each surface is in `shade`, and the water levels, sea
//! plane and detail mask of the traced surface in `surface`.

use glam::{DVec2, Vec2, Vec3};
use natura_atmos::Dir3;
use natura_atmos::optics::fresnel;
use natura_atmos::rainbow::{Rainbow, RainbowParams};
use natura_atmos::sky::SkyView;
use natura_core::colour::luminance;
use natura_core::{Boundary, Image, Progress, Seed, mix64, unit_f64};
use natura_noise::{FilteredFbm, Perlin, Spectral};
use natura_ocean::{Phillips, Surface, WaterSurface};
use natura_trace::{
    Detail, DetailParams, DetailSurface, DetailTracer, Hit, MipmapTracer, Ray, RayCone, Tracer,
};

use crate::camera::{SceneCamera, pixel_angle};
use crate::clouds::CloudSky;
use crate::error::Result;
use crate::material::{Materials, SurfaceSample};
use crate::scene::{SceneDesc, WaterDesc, WaterWaves};
use crate::snow::Shelter;
use crate::surface_textures::SurfaceTextures;
use crate::vegetation::canopy::Ground;
use crate::vegetation::{Forest, Light, TreeHit};
use crate::water::{WindSea, glitter};
use crate::world::World;

mod pixels;
mod sampling;
mod shade;
mod surface;

use natura_core::filter::PixelFilter;
use sampling::{Adaptive, refined_position};
use surface::detail_surface;

/// Refractive index of water used for the lake surface.
pub const WATER_IOR: f64 = 1.333;

/// Everything needed per sample, built once per render from a [`World`].
pub struct Renderer<'w> {
    world: &'w World,
    /// The terrain with lakes and sea on top, with the scene's procedural
    /// detail on dry land: primary, shadow and reflection rays.
    tracer: DetailTracer<'w>,
    /// The bare terrain: rays refracted into the water.
    ground: MipmapTracer<'w>,
    view: SkyView,
    camera: SceneCamera,
    materials: Materials,
    ripples: FilteredFbm<Perlin>,
    /// The ocean patch whose normals shade the water (`waves = "ocean"`).
    ocean: Option<Surface>,
    /// The wind sea whose filtered slopes shade the water (`waves = "wind"`
    /// in a wind).
    wind_sea: Option<WindSea>,
    rainbow: Option<Rainbow>,
    /// The scene's layer clouds and their shadows, if any.
    clouds: Option<CloudSky>,
    /// The trees, if the scene has any ([`Renderer::with_forest`]).
    forest: Option<Forest>,
    sun: Vec3,
    sun_irradiance: Vec3,
    sky_irradiance: Vec3,
    eye: Vec3,
    pixel_angle: f32,
    width: u32,
    height: u32,
    spp: u32,
    /// When a pixel takes more than its `spp` samples.
    adaptive: Adaptive,
    /// How a pixel's samples spread over the image plane.
    filter: PixelFilter,
    seed: Seed,
}

impl std::fmt::Debug for Renderer<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("eye", &self.eye)
            .field("sun", &self.sun)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("spp", &self.spp)
            .field("adaptive_samples", &self.adaptive.total())
            .field("filter", &self.filter)
            .finish_non_exhaustive()
    }
}

/// What a ray meets first.
enum SurfaceHit {
    /// Dry terrain.
    Terrain(Hit),
    /// A lake or the sea, at ray parameter `t`.
    Water {
        /// Ray parameter.
        t: f32,
        /// The point on the water surface.
        point: Vec3,
    },
}

impl SurfaceHit {
    /// The ray parameter of the hit.
    fn t(&self) -> f32 {
        match self {
            SurfaceHit::Terrain(h) => h.t,
            SurfaceHit::Water { t, .. } => *t,
        }
    }
}

/// Surface point of a terrain hit, in the form shading needs.
struct TerrainPoint {
    point: Vec3,
    geo: Vec3,
    smooth: Vec3,
}

impl<'w> Renderer<'w> {
    /// Builds the acceleration structure, the sky view at the eye, the camera,
    /// materials and (with rain) the rainbow table.
    ///
    /// # Errors
    ///
    /// Returns the errors of building the acceleration structure, the sky view,
    /// the camera ([`RenderError::Trace`](crate::RenderError::Trace), [`RenderError::Atmos`](crate::RenderError::Atmos)),
    /// the materials and the rainbow table.
    pub fn new(world: &'w World, progress: &dyn Progress) -> Result<Self> {
        Self::build(world, None, progress)
    }

    /// As [`Self::new`], with the scene's clouds prepared beforehand
    /// ([`CloudSky::for_world`], perhaps read back with
    /// [`CloudSky::from_bytes`]) instead of built here: a renderer of part
    /// of a frame then skips the clouds' cost, and its pixels equal those
    /// of [`Self::new`]'s bit for bit when `clouds` is what
    /// [`CloudSky::for_world`] gives for this world.
    ///
    /// # Errors
    ///
    /// [`RenderError::Invalid`](crate::RenderError::Invalid) naming `clouds`
    /// if `clouds` is given for a scene whose clouds are off, is missing for
    /// one whose clouds are on, or was prepared for another eye; and the
    /// errors of [`Self::new`].
    pub fn with_clouds(
        world: &'w World,
        clouds: Option<CloudSky>,
        progress: &dyn Progress,
    ) -> Result<Self> {
        let on = world.scene.clouds.visible();
        match &clouds {
            Some(_) if !on => Err(crate::RenderError::invalid(
                "clouds",
                "prepared",
                "the scene's clouds are off",
            )),
            None if on => Err(crate::RenderError::invalid(
                "clouds",
                "none",
                "the scene's clouds are on: prepare them with CloudSky::for_world",
            )),
            Some(c) if c.eye() != world.eye() => Err(crate::RenderError::invalid(
                "clouds",
                format!("prepared at {}", c.eye()),
                &format!("prepared for another eye (this scene's is {})", world.eye()),
            )),
            _ => Self::build(world, Some(clouds), progress),
        }
    }

    fn build(
        world: &'w World,
        prepared: Option<Option<CloudSky>>,
        progress: &dyn Progress,
    ) -> Result<Self> {
        let scene = &world.scene;
        let r = &scene.render;
        progress.start("acceleration", 2);
        let pixel_angle = pixel_angle(world);
        let tracer = DetailTracer::new(detail_surface(world)?, RayCone::cone(pixel_angle))?;
        progress.advance(1);
        let ground = MipmapTracer::new(&world.terrain)?;
        progress.advance(1);
        progress.finish();

        let eye = world.eye();
        let camera = SceneCamera::of_world(world)?;

        let sun_dir = world.sun_dir();
        let view = world.atmosphere.sky_view(eye.as_dvec3(), sun_dir)?;
        let sun_irradiance = view.sun_irradiance();
        let sky_irradiance = view.sky_irradiance();
        let seed = Seed(scene.seed);
        let materials = Materials::new(
            &scene.materials,
            world.water_level,
            seed.derive("materials"),
        )?
        .with_textures(SurfaceTextures::new(
            &scene.textures,
            seed.derive("textures"),
        )?);
        let w = &scene.water;
        let materials = materials.with_snow_exposure(
            world.sun,
            Some(world.terrain.clone()),
            snow_shelter(world)?,
        );
        let ripples = FilteredFbm::new(
            Perlin::new(seed.derive("ripples").0),
            Spectral::default()
                .with_h(0.5)
                .with_octaves(8.0)
                .with_frequency(1.0 / w.ripple_size_m),
            0.0,
        )?;
        let ocean = ocean_surface(w, seed, progress)?;
        let wind_sea = match w.waves {
            WaterWaves::Wind if world.water_level.is_some() => {
                WindSea::new(w, fetch_m(world), seed, progress)?
            }
            _ => None,
        };
        let rainbow = rainbow_table(scene, progress)?;
        let clouds = match prepared {
            Some(c) => c,
            None => CloudSky::new(world, camera.camera(), pixel_angle, &view, progress)?,
        };
        Ok(Self {
            world,
            tracer,
            ground,
            view,
            camera,
            materials,
            ripples,
            ocean,
            wind_sea,
            rainbow,
            clouds,
            forest: None,
            sun: world.sun,
            sun_irradiance,
            sky_irradiance,
            eye,
            pixel_angle,
            width: r.width,
            height: r.height,
            spp: r.spp,
            adaptive: Adaptive::new(
                r.spp,
                r.adaptive_samples,
                r.adaptive_contrast,
                // A white Lambertian surface in the sun and the sky.
                luminance(sun_irradiance * world.sun.z.max(0.0) + sky_irradiance)
                    / std::f32::consts::PI,
            ),
            filter: PixelFilter::gaussian(r.filter_sigma_px),
            seed: seed.derive("pixels"),
        })
    }

    /// Adds trees: primary rays meet them before the terrain and water,
    /// the water mirrors them, they shadow the terrain and each other, and
    /// the terrain shadows them.
    /// Each tree stands on the traced surface (with its detail, as seen at
    /// the tree's distance).
    #[must_use]
    pub fn with_forest(mut self, mut forest: Option<Forest>) -> Self {
        if let Some(f) = &mut forest {
            f.set_ground(|p| self.tree_ground(p));
        }
        self.forest = forest;
        self
    }

    /// The traced surface's height under a tree's base `p` (with its
    /// detail, as seen at the tree's distance): where [`Self::with_forest`]
    /// stands each tree.
    pub(crate) fn tree_ground(&self, p: Vec3) -> Option<f32> {
        let w = f64::from((p - self.eye).length() * self.pixel_angle);
        self.tracer.surface().height(p.x, p.y, w).map(|h| h as f32)
    }

    /// Adds a forest already stood on [`Self::tree_ground`].
    pub(crate) fn with_grounded_forest(mut self, forest: Option<Forest>) -> Self {
        self.forest = forest;
        self
    }

    /// The trees, if any.
    #[must_use]
    pub fn forest(&self) -> Option<&Forest> {
        self.forest.as_ref()
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &SceneCamera {
        &self.camera
    }

    /// Bytes of the acceleration structure.
    #[must_use]
    pub fn acceleration_bytes(&self) -> usize {
        self.tracer.memory_bytes() + self.ground.memory_bytes()
    }

    /// Radiance arriving at the camera along a primary `ray`.
    #[must_use]
    pub fn radiance(&self, ray: &Ray) -> Vec3 {
        let ray = Ray::new(ray.origin, ray.dir.normalize());
        let hit = self.tracer.trace(&ray, 0.0, f32::INFINITY);
        self.radiance_traced(&ray, hit.as_ref())
    }

    /// [`Self::radiance`] along a unit-direction `ray` whose first hit on the
    /// traced surface over `[0, ∞)` is `hit`.
    fn radiance_traced(&self, ray: &Ray, hit: Option<&Hit>) -> Vec3 {
        let d = ray.dir;
        let surface = self.intersect(ray, hit);
        let tree = self.tree_before(ray, surface.as_ref());
        let (mut l, dist) = match (tree, surface) {
            (Some((f, h)), _) => (self.shade_tree(f, &h, d), h.t),
            (None, Some(SurfaceHit::Water { t, point })) => {
                (self.shade_water(point, d, t, true), t)
            }
            (None, Some(SurfaceHit::Terrain(h))) => {
                (self.shade_terrain(&self.terrain_point(&h), d, h.t), h.t)
            }
            (None, None) => (self.sky(ray.origin, d), f32::INFINITY),
        };
        if dist.is_finite() {
            let ap = self.view.aerial_perspective_f32(d, dist);
            l = l * ap.transmittance + ap.in_scatter;
        }
        if let Some(rb) = &self.rainbow {
            l = self.rain(rb, d, dist, l);
        }
        l
    }

    /// The tree `ray` (unit direction) meets before `surface` (the ray's
    /// first terrain or water hit, or none), if the scene has a forest.
    fn tree_before(&self, ray: &Ray, surface: Option<&SurfaceHit>) -> Option<(&Forest, TreeHit)> {
        let f = self.forest.as_ref()?;
        let t_max = surface.map_or(f32::INFINITY, SurfaceHit::t);
        Some((f, f.intersect(ray.origin, ray.dir, t_max)?))
    }

    /// The first thing `ray` (unit direction) meets: dry terrain or a water
    /// surface, or nothing.
    ///
    /// The `surface` field holds the lakes and sea on top of the terrain, so
    /// it finds where a ray reaches water; but its triangles along a shore
    /// slope from the water level up to the bank. A hit there is resolved
    /// exactly: the water is the plane at the lake's level `L` (the lowest
    /// surface sample of the hit cell), and the ray either meets the bare
    /// terrain before that plane (the bank) or the plane itself.
    /// `hit` is the ray's first hit on the traced surface over `[0, ∞)`.
    fn intersect(&self, ray: &Ray, hit: Option<&Hit>) -> Option<SurfaceHit> {
        let Some(&h) = hit else {
            // Beyond the terrain the sea plane goes on to the horizon.
            return self.sea_t(ray.origin, ray.dir).map(|t| SurfaceHit::Water {
                t,
                point: ray.at(t),
            });
        };
        if self.water_depth(h.point).is_none() {
            return Some(SurfaceHit::Terrain(h));
        }
        let level = self.cell_level(h.cell);
        let t0 = (h.t - 1e-3 * h.t.max(1.0)).max(0.0);
        if ray.dir.z >= 0.0 {
            // A rising ray never meets the plane from above: what it hit on
            // the shore triangle is the bare bank (or nothing). This holds
            // however close to the level the hit is: a ray reflected off the
            // water leaves a hair above the level and meets the shore
            // triangle within centimetres of it, and taken for water there
            // it mirrors the bright sky at the horizon (lone bright pixels
            // along far shores).
            return self
                .ground
                .trace(ray, t0, f32::INFINITY)
                .map(SurfaceHit::Terrain);
        }
        // On the level to the hit point's rounding (a few ulps of the
        // heights and distances involved): the lake's flat triangles. Any
        // higher, the hit is on a shore triangle and is resolved exactly.
        if h.point.z - level <= 1e-5 * (1.0 + level.abs() + h.t) {
            return Some(SurfaceHit::Water {
                t: h.t,
                point: h.point,
            });
        }
        let t_plane = (level - ray.origin.z) / ray.dir.z;
        match self.ground.trace(ray, t0, t_plane) {
            Some(g) => Some(SurfaceHit::Terrain(g)),
            None => Some(SurfaceHit::Water {
                t: t_plane,
                point: ray.at(t_plane),
            }),
        }
    }
}

/// The ocean patch whose normals shade the water (`waves = "ocean"`): a
/// Phillips spectrum in the scene's wind, evaluated at the scene's time.
fn ocean_surface(w: &WaterDesc, seed: Seed, progress: &dyn Progress) -> Result<Option<Surface>> {
    match w.waves {
        WaterWaves::Ripples | WaterWaves::Wind => Ok(None),
        WaterWaves::Ocean => {
            progress.start("ocean", 1);
            let (n, l) = (w.ocean_resolution, w.ocean_patch_m);
            let spectrum = Phillips {
                wind_speed: w.wind_speed_m_s,
                wind_direction: crate::water::wind_angle_rad(w),
                small_wave_length: l / n as f64,
                ..Phillips::default()
            };
            let surface = crate::water::wave_patch(w, &spectrum, seed.derive("ocean"))?;
            progress.advance(1);
            progress.finish();
            Ok(Some(surface))
        }
    }
}

/// The fetch of the scene's wind over its water, metres: `water.fetch_m`,
/// or the square root of the water's area (at least one cell).
fn fetch_m(world: &World) -> f64 {
    if let Some(f) = world.scene.water.fetch_m {
        return f;
    }
    let (s, g) = (world.surface.heights(), world.terrain.heights());
    let wet = s
        .as_slice()
        .iter()
        .zip(g.as_slice())
        .filter(|(s, g)| s > g)
        .count()
        .max(1);
    f64::from(world.terrain.cell_size()) * (wet as f64).sqrt()
}

/// The prevailing wind's shelter of the snow with `snow_wind_m`, or `None`
/// where the wind moves no snow (`snow_wind_m` 0).
fn snow_shelter(world: &World) -> Result<Option<(Shelter, f32)>> {
    let (m, w) = (&world.scene.materials, &world.scene.water);
    if m.snow_wind_m <= 0.0 {
        return Ok(None);
    }
    let shelter = Shelter::new(
        &world.terrain,
        w.wind_azimuth_deg,
        m.snow_shelter_distance_m,
    )?;
    Ok(Some((shelter, m.snow_wind_m)))
}

/// The rainbow's table when the scene has rain, else `None`.
fn rainbow_table(scene: &SceneDesc, progress: &dyn Progress) -> Result<Option<Rainbow>> {
    if scene.atmosphere.rain_extinction_per_m > 0.0 {
        progress.start("rainbow table", 1);
        let params = RainbowParams {
            rays_per_wavelength: 20_000,
            ..RainbowParams::default()
        };
        let rb = Rainbow::new(&params)?;
        progress.advance(1);
        progress.finish();
        Ok(Some(rb))
    } else {
        Ok(None)
    }
}
