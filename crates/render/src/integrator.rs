//! The integrator: radiance along camera rays through the world.
//!
//! Primary rays are grid-traced against the terrain (maximum mipmaps), sun
//! shadows come from any-hit rays, the water plane reflects (traced terrain
//! or sky) and refracts (the lake bed seen through absorbing water) with
//! exact Fresnel weights, aerial perspective is applied to every segment
//! that reaches the camera, escaped rays see the sky with its sun disc, and
//! rain shows a rainbow opposite the sun. This is the shading pipeline of
//! Musgrave's landscapes (Musgrave 1993, ch. 3–4) with physical sky and haze.

use glam::{DVec2, Vec2, Vec3};
use natura_atmos::Dir3;
use natura_atmos::optics::fresnel;
use natura_atmos::rainbow::{Rainbow, RainbowParams};
use natura_atmos::sky::SkyView;
use natura_core::{Boundary, Image, Progress, Seed, mix64, unit_f64};
use natura_noise::{FilteredFbm, Perlin, Spectral};
use natura_ocean::{Ocean, OceanParams, Phillips, Surface, WaterSurface};
use natura_trace::{
    Camera, Detail, DetailParams, DetailSurface, DetailTracer, Hit, MipmapTracer, PanoramicCamera,
    PinholeCamera, Projection, Ray, RayCone, Tracer,
};

use crate::clouds::CloudSky;
use crate::error::Result;
use crate::material::{Materials, SurfaceSample};
use crate::scene::{CameraKind, WaterWaves};
use crate::strata::SurfaceTextures;
use crate::vegetation::{Forest, Light, TreeHit};
use crate::world::World;

/// Refractive index of water used for the lake surface.
pub const WATER_IOR: f64 = 1.333;

/// The camera of a scene.
#[derive(Clone, Copy, Debug)]
pub enum SceneCamera {
    /// A pinhole camera.
    Pinhole(PinholeCamera),
    /// A cylindrical or spherical panorama.
    Panoramic(PanoramicCamera),
}

impl SceneCamera {
    /// The camera as a natura-trace [`Camera`] (primary rays per pixel).
    #[must_use]
    pub fn camera(&self) -> &dyn Camera {
        match self {
            SceneCamera::Pinhole(c) => c,
            SceneCamera::Panoramic(c) => c,
        }
    }
}

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
        let scene = &world.scene;
        let r = &scene.render;
        progress.start("acceleration", 2);
        let pixel_angle = (scene.camera.vfov_deg as f32).to_radians() / r.height as f32;
        let tracer = DetailTracer::new(detail_surface(world)?, RayCone::cone(pixel_angle))?;
        progress.advance(1);
        let ground = MipmapTracer::new(&world.terrain)?;
        progress.advance(1);
        progress.finish();

        let eye = world.eye();
        let dir = world.view_direction();
        let c = &scene.camera;
        let camera = match c.kind {
            CameraKind::Pinhole => SceneCamera::Pinhole(PinholeCamera::look_at(
                eye,
                eye + dir,
                Vec3::Z,
                (c.vfov_deg as f32).to_radians(),
                r.width,
                r.height,
            )?),
            CameraKind::Cylindrical | CameraKind::Spherical => {
                SceneCamera::Panoramic(PanoramicCamera::new(
                    eye,
                    dir,
                    Vec3::Z,
                    (c.hfov_deg as f32).to_radians(),
                    (c.vfov_deg as f32).to_radians(),
                    if c.kind == CameraKind::Cylindrical {
                        Projection::Cylindrical
                    } else {
                        Projection::Spherical
                    },
                    r.width,
                    r.height,
                )?)
            }
        };

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
        let ripples = FilteredFbm::new(
            Perlin::new(seed.derive("ripples").0),
            Spectral::default()
                .with_h(0.5)
                .with_octaves(8.0)
                .with_frequency(1.0 / w.ripple_size_m),
            0.0,
        )?;
        let ocean = match w.waves {
            WaterWaves::Ripples => None,
            WaterWaves::Ocean => {
                progress.start("ocean", 1);
                let (n, l) = (w.ocean_resolution, w.ocean_patch_m);
                let params = OceanParams {
                    nx: n,
                    ny: n,
                    lx: l,
                    ly: l,
                    choppiness: 1.0,
                    ..OceanParams::default()
                };
                let spectrum = Phillips {
                    wind_speed: w.wind_speed_m_s,
                    // Compass azimuth (clockwise from +y) to the angle from +x.
                    wind_direction: (90.0 - w.wind_azimuth_deg).to_radians(),
                    small_wave_length: l / n as f64,
                    ..Phillips::default()
                };
                let ocean = Ocean::new(&params, &spectrum, seed.derive("ocean"))?;
                let surface = Surface::new(&ocean.evaluate(w.ocean_time_s)?, None)?;
                progress.advance(1);
                progress.finish();
                Some(surface)
            }
        };
        let rainbow = if scene.atmosphere.rain_extinction_per_m > 0.0 {
            progress.start("rainbow table", 1);
            let params = RainbowParams {
                rays_per_wavelength: 20_000,
                ..RainbowParams::default()
            };
            let rb = Rainbow::new(&params)?;
            progress.advance(1);
            progress.finish();
            Some(rb)
        } else {
            None
        };
        let clouds = CloudSky::new(world, camera.camera(), pixel_angle, &view, progress)?;
        Ok(Self {
            world,
            tracer,
            ground,
            view,
            camera,
            materials,
            ripples,
            ocean,
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
            seed: seed.derive("pixels"),
        })
    }

    /// Adds trees: primary rays meet them before the terrain and water,
    /// they shadow the terrain and each other, and the terrain shadows them.
    /// Each tree stands on the traced surface (with its detail, as seen at
    /// the tree's distance).
    #[must_use]
    pub fn with_forest(mut self, mut forest: Option<Forest>) -> Self {
        if let Some(f) = &mut forest {
            let s = self.tracer.surface();
            f.set_ground(|p| {
                let w = f64::from((p - self.eye).length() * self.pixel_angle);
                s.height(p.x, p.y, w).map(|h| h as f32)
            });
        }
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

    /// Renders the linear (scene-referred) image in parallel tiles.
    ///
    /// Each pixel averages `spp` stratified samples whose positions are
    /// random numbers indexed by pixel and sample, so the image is
    /// bit-identical for any thread count. The primary rays of a tile (all
    /// their samples) are traced together with [`Tracer::trace_many`], the
    /// mipmap tracer's lock-step lanes; every pixel equals [`Self::pixel`]
    /// bit for bit.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Core`](crate::RenderError::Core) if the image cannot be allocated, and the
    /// errors of sky and aerial-perspective lookups.
    pub fn render(&self, progress: &dyn Progress) -> Result<Image> {
        self.render_region(0, 0, self.width, self.height, progress)
    }

    /// Renders the `width × height` pixel rectangle of the image whose
    /// top-left pixel is `(x0, y0)`, in parallel tiles: a shard of a frame.
    ///
    /// Every pixel is a function of its position, sample index and seed only
    /// (see [`Self::render`]), so the region equals the same rectangle of the
    /// full image bit for bit, whatever the region and thread count.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`](crate::RenderError::Invalid) if the
    /// rectangle is empty or reaches outside the image, and the errors of
    /// [`Self::render`].
    pub fn render_region(
        &self,
        x0: u32,
        y0: u32,
        width: u32,
        height: u32,
        progress: &dyn Progress,
    ) -> Result<Image> {
        let inside =
            |o: u32, n: u32, side: u32| n > 0 && o.checked_add(n).is_some_and(|e| e <= side);
        if !inside(x0, width, self.width) || !inside(y0, height, self.height) {
            return Err(crate::RenderError::invalid(
                "region",
                format_args!("{width} × {height} at ({x0}, {y0})"),
                &format!(
                    "a non-empty rectangle inside the {} × {} image",
                    self.width, self.height
                ),
            ));
        }
        let n = self.spp as usize;
        let grid = natura_trace::render_tiles(
            width,
            height,
            natura_trace::DEFAULT_TILE,
            progress,
            |bx, by, w, h, out| {
                let (bx, by) = (x0 + bx, y0 + by);
                let mut rays = Vec::with_capacity((w * h) as usize * n);
                for y in by..by + h {
                    for x in bx..bx + w {
                        rays.extend((0..self.spp).map(|s| self.primary_ray(x, y, s)));
                    }
                }
                let hits = self.tracer.trace_many(&rays, 0.0, f32::INFINITY);
                for (r, h) in rays.chunks_exact(n).zip(hits.chunks_exact(n)) {
                    let mut sum = Vec3::ZERO;
                    for (ray, hit) in r.iter().zip(h) {
                        sum += self.radiance_traced(ray, hit.as_ref());
                    }
                    out.push(sum / self.spp as f32);
                }
            },
        )?;
        Ok(Image::from_grid(grid))
    }

    /// The average radiance of pixel `(x, y)` over its stratified samples.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for s in 0..self.spp {
            let ray = self.primary_ray(x, y, s);
            let hit = self.tracer.trace(&ray, 0.0, f32::INFINITY);
            sum += self.radiance_traced(&ray, hit.as_ref());
        }
        sum / self.spp as f32
    }

    /// Sample `s` of pixel `(x, y)`: the camera ray through its jittered
    /// position in a stratified `⌈√spp⌉²` grid, with a unit direction.
    fn primary_ray(&self, x: u32, y: u32, s: u32) -> Ray {
        let n = self.spp;
        let side = (n as f32).sqrt().ceil() as u32;
        let h = self.seed.hash(&[i64::from(x), i64::from(y), i64::from(s)]);
        let (jx, jy) = (
            unit_f64(h) as f32,
            unit_f64(mix64(h ^ 0x9E37_79B9_7F4A_7C15)) as f32,
        );
        let jitter = if n == 1 {
            glam::Vec2::splat(0.5)
        } else {
            // Stratum (s mod side, s / side) of a side × side grid, jittered inside.
            let (sx, sy) = ((s % side) as f32, (s / side) as f32);
            glam::Vec2::new(
                (sx + jx) / side as f32,
                ((sy + jy) / side as f32).min(1.0 - f32::EPSILON),
            )
        };
        let ray = self.camera.camera().ray(x, y, jitter);
        Ray::new(ray.origin, ray.dir.normalize())
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
        let t_surface = match &surface {
            Some(SurfaceHit::Water { t, .. }) => *t,
            Some(SurfaceHit::Terrain(h)) => h.t,
            None => f32::INFINITY,
        };
        let tree = self
            .forest
            .as_ref()
            .and_then(|f| Some((f, f.intersect(ray.origin, d, t_surface)?)));
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
        if h.point.z - level <= 1e-3 * (1.0 + level.abs()) {
            return Some(SurfaceHit::Water {
                t: h.t,
                point: h.point,
            });
        }
        let t0 = (h.t - 1e-3 * h.t.max(1.0)).max(0.0);
        if ray.dir.z >= 0.0 {
            // A rising ray above the water level never meets the plane: what
            // it hit on the shore triangle is the bare bank (or nothing).
            return self
                .ground
                .trace(ray, t0, f32::INFINITY)
                .map(SurfaceHit::Terrain);
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

    /// Whether a tree stands between `p` and the sun (beyond `t_min` metres).
    fn trees_occlude(&self, p: Vec3, t_min: f32) -> bool {
        self.forest
            .as_ref()
            .is_some_and(|f| f.occluded(p, self.sun, t_min, f32::INFINITY))
    }

    /// Radiance leaving a tree toward `-d`: the sun unless the terrain or a
    /// tree (its own crown included) is in the way, and skylight.
    fn shade_tree(&self, f: &Forest, h: &TreeHit, d: Vec3) -> Vec3 {
        // Past the surface hit by a few centimetres, so the shadow ray of a
        // leaf lit from behind passes through it (its transmitted light).
        let eps = 0.03 + 1e-6 * h.point.abs().max_element();
        let fp = RayCone {
            at_origin_m: h.t * self.pixel_angle,
            per_metre: self.pixel_angle,
        };
        let visible = self.sun.z > 0.0
            && !self.trees_occlude(h.point, eps)
            && !self.tracer.occluded_footprint(
                &Ray::new(h.point, self.sun),
                eps,
                f32::INFINITY,
                fp,
            );
        let light = Light {
            sun: self.sun,
            // The clouds' shadow dims the sun on trees as on the ground.
            sun_irradiance: self.sun_irradiance * self.cloud_shadow(h.point),
            sky_irradiance: self.sky_irradiance,
        };
        f.shade(h, d, &light, visible)
    }

    /// The water level of the cell `(i, j)` of the surface: its lowest corner.
    fn cell_level(&self, cell: glam::UVec2) -> f32 {
        let s = self.world.surface.heights();
        let (i, j) = (cell.x as usize, cell.y as usize);
        let (i1, j1) = ((i + 1).min(s.width() - 1), (j + 1).min(s.height() - 1));
        s[(i, j)].min(s[(i1, j)]).min(s[(i, j1)]).min(s[(i1, j1)])
    }

    /// Height of the traced surface (terrain, lakes and sea) below `p`.
    fn surface_height(&self, p: Vec3) -> f32 {
        let inv = 1.0 / self.world.terrain.cell_size();
        self.world
            .surface
            .heights()
            .sample_bilinear(p.x * inv, p.y * inv, Boundary::Clamp)
    }

    /// Depth of water at a surface point, if it is wet (lake or sea).
    fn water_depth(&self, p: Vec3) -> Option<f32> {
        self.world.water_level?;
        let w = self.world;
        let inv = 1.0 / w.terrain.cell_size();
        let s = w
            .surface
            .heights()
            .sample_bilinear(p.x * inv, p.y * inv, Boundary::Clamp);
        let g = w
            .terrain
            .heights()
            .sample_bilinear(p.x * inv, p.y * inv, Boundary::Clamp);
        let depth = s - g;
        (depth > 0.02).then_some(depth)
    }

    /// Distance to the sea plane along `d` from `o`, if the ray goes down onto it.
    fn sea_t(&self, o: Vec3, d: Vec3) -> Option<f32> {
        let level = self.world.water_level?;
        (o.z > level && d.z < 0.0)
            .then(|| (level - o.z) / d.z)
            .filter(|t| t.is_finite() && *t > 0.0)
    }

    /// The sky seen from `o` along unit `d` (a ray that left the terrain),
    /// with the sun's disc and the clouds in front of both.
    fn sky(&self, o: Vec3, d: Vec3) -> Vec3 {
        let sky = self.view.radiance_f32(d);
        let disc = Dir3::from_f32(d).map_or(Vec3::ZERO, |dir| self.view.sun_disc(dir));
        match self.clouds.as_ref().and_then(|c| c.view(o, d)) {
            Some(c) => c.radiance + sky * c.transmittance + disc * c.sun_transmittance,
            None => sky + disc,
        }
    }

    /// The fraction of the sun's light the clouds let through to `p`.
    fn cloud_shadow(&self, p: Vec3) -> f32 {
        self.clouds.as_ref().map_or(1.0, |c| c.sun_transmittance(p))
    }

    fn terrain_point(&self, h: &Hit) -> TerrainPoint {
        TerrainPoint {
            point: h.point,
            geo: h.geometric_normal,
            smooth: h.smooth_normal,
        }
    }

    /// Radiance leaving a terrain point toward `-d`, at distance `t` from the viewer.
    fn shade_terrain(&self, tp: &TerrainPoint, d: Vec3, t: f32) -> Vec3 {
        let w = self.world;
        let cell = w.terrain.cell_size();
        let (gx, gy) = (tp.point.x / cell, tp.point.y / cell);
        let sample = SurfaceSample {
            point: tp.point,
            normal: tp.smooth,
            deposition_m: w.deposition.sample_bilinear(gx, gy, Boundary::Clamp),
            wetness: w.wetness.sample_bilinear(gx, gy, Boundary::Clamp),
        };
        let footprint = t * self.pixel_angle;
        let albedo = self.materials.albedo_at(&sample, footprint);
        let n = self.materials.bumped_normal(tp.point, tp.smooth, footprint);
        let v = -d;
        let mut l = Vec3::ZERO;

        // Direct sun, with a shadow ray from just above the surface.
        let cos_i = n.dot(self.sun);
        if cos_i > 0.0 && tp.geo.dot(self.sun) > -0.05 {
            let eps = 1e-2 * cell + 1e-5 * tp.point.abs().max_element();
            let shadow = Ray::new(tp.point + tp.geo * eps, self.sun);
            let fp = RayCone {
                at_origin_m: footprint,
                per_metre: self.pixel_angle,
            };
            if !self
                .tracer
                .occluded_footprint(&shadow, eps, f32::INFINITY, fp)
                && !self.trees_occlude(shadow.origin, eps)
            {
                let f = self.materials.diffuse_factor(n, self.sun, v) * self.cloud_shadow(tp.point);
                l += albedo / std::f32::consts::PI * self.sun_irradiance * cos_i * f;
            }
        }
        // Sky light over the visible hemisphere, plus light bounced off the
        // surroundings for normals that face down-slope.
        let up = 0.5 * (1.0 + n.z);
        let bounce = 0.5
            * (1.0 - n.z)
            * 0.25
            * (self.sun_irradiance * self.sun.z.max(0.0) + self.sky_irradiance);
        l += albedo / std::f32::consts::PI * (self.sky_irradiance * up + bounce);
        l
    }

    /// The normal of the fBm ripples at `p`, band-limited to a pixel of the
    /// given footprint (metres): octaves finer than the footprint fade out
    /// (the RenderMan `vfBm` filter of natura-noise's [`FilteredFbm`]), so
    /// distant water tends to its mean plane instead of aliasing into glitter.
    fn ripple_normal(&self, p: Vec3, footprint: f32) -> Vec3 {
        let wdesc = &self.world.scene.water;
        if wdesc.ripple_height_m <= 0.0 {
            return Vec3::Z;
        }
        let width = f64::from(footprint);
        let q = DVec2::new(f64::from(p.x), f64::from(p.y));
        // Central differences at a tenth of the finest wavelength kept.
        let h = (0.1 * width).max(0.01 * wdesc.ripple_size_m / 128.0);
        let fx = self.ripples.eval2_width(q + DVec2::X * h, width)
            - self.ripples.eval2_width(q - DVec2::X * h, width);
        let fy = self.ripples.eval2_width(q + DVec2::Y * h, width)
            - self.ripples.eval2_width(q - DVec2::Y * h, width);
        let g = DVec2::new(fx, fy) * (wdesc.ripple_height_m / (2.0 * h));
        Vec3::new(-g.x as f32, -g.y as f32, 1.0).normalize()
    }

    /// Radiance leaving the water surface at `p` toward `-d` (`reflect_terrain`:
    /// whether reflection rays may hit the terrain, off for secondary bounces).
    fn shade_water(&self, p: Vec3, d: Vec3, t: f32, reflect_terrain: bool) -> Vec3 {
        let wdesc = &self.world.scene.water;
        // A pixel's footprint on the water: t·α across the view, stretched by
        // 1/|d_z| along it at grazing angles; their geometric mean is the
        // isotropic filter width.
        let footprint = t * self.pixel_angle / d.z.abs().max(1e-3).sqrt();
        let n = if let Some(ocean) = &self.ocean {
            // Normals of the wind sea, flattened where a pixel covers many
            // wavelengths (the mean normal of a rough patch is its plane).
            let patch = wdesc.ocean_patch_m as f32;
            let fade = 1.0 - crate::material::smoothstep(0.01 * patch, 0.2 * patch, footprint);
            let n = ocean.normal_at(Vec2::new(p.x, p.y));
            (Vec3::Z + (n - Vec3::Z) * fade).normalize()
        } else {
            self.ripple_normal(p, footprint)
        };
        let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
        let fr = fresnel(1.0, WATER_IOR, f64::from(cos_i)).unpolarized() as f32;

        // Reflection: the terrain (mountains mirrored in the lake) or the sky and sun.
        let mut r = d - 2.0 * d.dot(n) * n;
        if r.z < 1e-4 {
            r.z = r.z.abs().max(1e-4);
            r = r.normalize();
        }
        let reflected = if reflect_terrain {
            let rray = Ray::new(p + Vec3::Z * 1e-2, r);
            // At a shoreline the exact water plane lies below the interpolated
            // surface of its cell; a ray leaving it starts under the traced
            // surface, so it sees only the bare terrain (the rising shore).
            let under = self.surface_height(rray.origin) > rray.origin.z;
            let hit = if under {
                self.ground
                    .trace(&rray, 0.0, f32::INFINITY)
                    .map(SurfaceHit::Terrain)
            } else {
                let fp = RayCone {
                    at_origin_m: t * self.pixel_angle,
                    per_metre: self.pixel_angle,
                };
                let first = self.tracer.trace_footprint(&rray, 0.0, f32::INFINITY, fp);
                self.intersect(&rray, first.as_ref())
            };
            let (lt, tr) = match hit {
                Some(SurfaceHit::Water { t: tr, point }) => {
                    (self.shade_water(point, r, t + tr, false), tr)
                }
                Some(SurfaceHit::Terrain(h)) => {
                    (self.shade_terrain(&self.terrain_point(&h), r, t + h.t), h.t)
                }
                None => (self.sky(p, r), f32::INFINITY),
            };
            if tr.is_finite() {
                let ap = self.view.aerial_perspective_f32(r, tr);
                lt * ap.transmittance + ap.in_scatter
            } else {
                lt
            }
        } else {
            self.sky(p, r)
        };

        // Transmission: the bed seen through absorbing, scattering water.
        let sigma = Vec3::from(wdesc.extinction_per_m);
        let albedo = Vec3::from(wdesc.scatter_albedo);
        let ambient = self.sun_irradiance * (self.sun.z.max(0.0) * self.cloud_shadow(p))
            + self.sky_irradiance;
        let body = albedo * ambient / std::f32::consts::PI;
        let eta = (1.0 / WATER_IOR) as f32;
        let cos_t2 = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
        let transmitted = if cos_t2 > 0.0 {
            let tdir = (eta * d + (eta * cos_i - cos_t2.sqrt()) * n).normalize();
            let tray = Ray::new(p - Vec3::Z * 1e-2, tdir);
            match self.ground.trace(&tray, 0.0, 2_000.0) {
                Some(h) => {
                    let tp = self.terrain_point(&h);
                    let water_depth = (p.z - h.point.z).max(0.0);
                    let sun_path = water_depth / self.sun.z.max(0.05);
                    let bed = self.shade_terrain(&tp, tdir, t + h.t) * exp3(-sigma * sun_path);
                    let att = exp3(-sigma * h.t);
                    bed * att + body * (Vec3::ONE - att)
                }
                None => body,
            }
        } else {
            Vec3::ZERO
        };
        fr * reflected + (1.0 - fr) * transmitted
    }

    /// Rain between `rain_distance_m` and the hit: extinction of what is behind
    /// and the rainbow's single scattering (Musgrave 1993, §4.2.4.3.2).
    fn rain(&self, rb: &Rainbow, d: Vec3, dist: f32, behind: Vec3) -> Vec3 {
        let a = &self.world.scene.atmosphere;
        let start = a.rain_distance_m as f32;
        let end = dist.min(start + 6_000.0);
        if end <= start {
            return behind;
        }
        let len = f64::from(end - start);
        let beta = a.rain_extinction_per_m;
        let (Ok(view), sun) = (Dir3::from_f32(d), self.world.sun_dir()) else {
            return behind;
        };
        let bow = rb
            .radiance(view, sun, self.sun_irradiance.as_dvec3(), beta, len)
            .map(|v| v.as_vec3())
            .unwrap_or(Vec3::ZERO);
        let ap = self.view.aerial_perspective_f32(d, start);
        behind * (-(beta * len) as f32).exp() + bow * ap.transmittance
    }
}

/// The traced surface of a world: its water surface plus the scene's
/// procedural detail (the first octave at the cell's wavelength), kept off
/// the lakes and the sea by a mask that is 0 on every wet sample and its
/// neighbours and 1 elsewhere. Without detail (disabled, or amplitude or
/// octaves 0) the surface is the height field alone and is traced exactly as
/// before.
fn detail_surface(world: &World) -> Result<DetailSurface<'_>> {
    let d = &world.scene.detail;
    let on = d.enabled && d.amplitude_m > 0.0 && d.octaves > 0;
    let detail = Detail::new(&DetailParams {
        amplitude_m: if on { d.amplitude_m as f32 } else { 0.0 },
        h: d.h as f32,
        lacunarity: d.lacunarity as f32,
        octaves: if on { d.octaves } else { 0 },
        wavelength_m: world.terrain.cell_size(),
        seed: Seed(world.scene.seed.wrapping_add(d.seed_offset))
            .derive("detail")
            .0,
    })?;
    let mask = if on && world.water_level.is_some() {
        let (s, g) = (world.surface.heights(), world.terrain.heights());
        let (nx, ny) = (s.width(), s.height());
        let wet = |i: usize, j: usize| s[(i, j)] > g[(i, j)];
        Some(natura_core::Grid2::from_fn(nx, ny, |i, j| {
            let near_water = (i.saturating_sub(1)..=(i + 1).min(nx - 1))
                .any(|a| (j.saturating_sub(1)..=(j + 1).min(ny - 1)).any(|b| wet(a, b)));
            if near_water { 0.0f32 } else { 1.0 }
        })?)
    } else {
        None
    };
    Ok(DetailSurface::new(&world.surface, detail, mask)?)
}

#[inline]
fn exp3(v: Vec3) -> Vec3 {
    Vec3::new(v.x.exp(), v.y.exp(), v.z.exp())
}
