//! Layer clouds over the landscape: natura-volume's layer-cloud sky
//! (Schneider 2015, "Modeling": weather coverage, height profile by cloud
//! type, Worley erosion), lit by
//! the sun and sky of the scene's atmosphere and seen through its aerial
//! perspective, marched once per direction of a grid, with a 2-D map of
//! their shadows.
//!
//! The layer lies above the terrain and the eye, so a ray that meets the
//! terrain never reaches it: clouds are seen only along rays that leave the
//! terrain (and their reflections in the water). What the eye sees along a
//! direction does not depend on the sample, so it is marched once per cell
//! of a grid of directions over the camera's view (azimuth and elevation,
//! cells of [`CloudsDesc::cache_pixels`] pixels) with natura-volume's fast
//! renderer (Ebert's low-albedo march with shadow tables, the multiple
//! scattering of [`CloudsDesc::scattering`](crate::scene::CloudsDesc::scattering)
//! — by default the sun's light traced once onto a grid — and the forward
//! peak truncated; see
//! [`natura_volume::transport::march`]), and looked up bilinearly: the clouds'
//! radiance in front of the sky and their transmittance, with the sky and
//! sun disc behind added at full resolution.
//!
//! Detail: the baked layer is soft below its voxels, so it is eroded by
//! natura-volume's detail ([`natura_volume::detail`]: noise octaves in
//! the manner of Schneider 2015's erosion, band-limited to a footprint)
//! down to the footprint of one cell of the grid of directions at each
//! point's distance from the eye: as fine as the marched directions can
//! show, and no finer, so the lookup does not alias it; and no finer than
//! the parts the march samples each step in (three a step, a third of
//! its growth with the distance), so it does not fold along the rays
//! ([`CloudsDesc::detail`](crate::scene::CloudsDesc::detail); an amplitude
//! of 0 is the baked layer alone). The shadow map below keeps the baked
//! layer: its cells are far coarser than the detail.
//!
//! The clouds' shadows: the sun's transmittance through the layer depends
//! only on where the sun's ray from a point enters the layer's base, so it
//! is a 2-D map over the base, covering the terrain's extent projected
//! along the sun ([`ShadowMap`]). It uses the δ-M extinction (Wiscombe
//! 1977: light scattered into the core of the phase function's forward
//! peak, within 20° of its direction, still arrives as sunlight).
//!
//! Approximations: a reflected ray sees the clouds the eye sees toward the
//! point where that ray crosses the middle of the layer (exact parallax at
//! mid-layer, the eye's aerial perspective); the sky light on the ground is
//! not dimmed under the clouds, and the clouds do not see the terrain's
//! light below them.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use natura_atmos::sky::SkyView;
use natura_core::{Grid2, Progress, Seed};
use natura_trace::Camera;
use natura_volume::detail::{DetailParams, Detailed};
use natura_volume::grid::GridDensity;
use natura_volume::layer::LayerClouds;
use natura_volume::transport::shadow::optical_depth_ray;
use natura_volume::transport::{
    FastRenderer, FastSettings, NearSunRays, Scene, Shadows, SkyRadiance, Sun,
};

use crate::error::{RenderError, Result};
use crate::scene::CloudsDesc;

use crate::world::World;

/// Most cells of the direction grid; a finer grid is coarsened to this.
const MAX_DIRECTIONS: usize = 1 << 22;

/// The clouds of a scene, ready to be looked up (see the module docs).
#[derive(Debug)]
pub struct CloudSky {
    eye: Vec3,
    /// Height of the middle of the layer (the reflections' parallax plane).
    mid: f32,
    dome: Dome,
    shadow: ShadowMap,
}

mod bytes;

/// What the clouds do to a ray that leaves the terrain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CloudView {
    /// The clouds' radiance (and the air's in front of them where they hide the sky).
    pub radiance: Vec3,
    /// Weight of the sky behind.
    pub transmittance: f32,
    /// Weight of the sun's disc behind.
    pub sun_transmittance: f32,
}

impl CloudSky {
    /// Builds the clouds of `world` for the camera at `eye` with pixel angle
    /// `pixel_angle` (radians), the sky `view`, or `None` when the scene's
    /// clouds are off ([`CloudsDesc::visible`]).
    ///
    /// # Errors
    ///
    /// [`RenderError::Invalid`] naming `clouds.layer.base_m` if the layer
    /// does not lie above the terrain and the eye; the errors of
    /// natura-volume's layer, baking and fast renderer.
    pub fn new(
        world: &World,
        camera: &dyn Camera,
        pixel_angle: f32,
        view: &SkyView,
        progress: &dyn Progress,
    ) -> Result<Option<Self>> {
        let desc = &world.scene.clouds;
        if !desc.visible() {
            return Ok(None);
        }
        let eye = world.eye();
        let (_, top) = world.surface.min_max();
        let l = &desc.layer;
        if l.base_m <= top.max(eye.z) {
            return Err(RenderError::invalid(
                "clouds.layer.base_m",
                l.base_m,
                &format!(
                    "must lie above the terrain and the camera (up to {:.0} m)",
                    top.max(eye.z)
                ),
            ));
        }
        progress.start("clouds", 3);
        let seed = Seed(world.scene.seed.wrapping_add(desc.seed_offset)).derive("clouds");
        let layer = LayerClouds::new(*l, seed.0)?;
        let grid = GridDensity::bake(&layer, desc.voxel_m)?;
        // The directions are marched a cell apart: the detail stops at the
        // cell's footprint or at the march's parts (see `seen_by_march`).
        let layout = Dome::layout(camera, pixel_angle * desc.cache_pixels);
        let detailed = desc.detail.amplitude > 0.0;
        let parts = if detailed {
            DetailParams::MARCH_SUBSTEPS
        } else {
            1
        };
        let clouds = if detailed {
            let d = desc
                .detail
                .seen_by_march(eye, layout.cell, desc.step_growth);
            Detailed::new(&grid, &d, seed.derive("cloud detail").0)
                .map_err(|e| crate::scene::clouds_in_section("clouds.detail", e))?
        } else {
            Detailed::without_detail(&grid)
        };
        progress.advance(1);

        let sky = Arc::new(view.clone());
        let sun = Sun {
            direction: world.sun,
            irradiance: view.sun_irradiance(),
        };
        let scene = Scene {
            density: &clouds,
            medium: desc.medium,
            sun: Some(sun),
            environment: SkyRadiance::Sky(sky.clone()),
            ground: None,
            emission: None,
            aerial: Some(sky),
            solids: Vec::new(),
        };
        let fast = FastRenderer::new(
            &scene,
            FastSettings {
                step: desc.step_m,
                step_growth: desc.step_growth,
                shadows: Shadows::Table(desc.shadow_table_nodes),
                scattering: desc.scattering,
                powder: 0.0,
                min_transmittance: 0.01,
                truncate_forward_peak: true,
                // Near the sun its forward peak needs each point's own
                // sunlight, not the table's interpolation.
                near_sun: Some(NearSunRays {
                    within_deg: 3.0,
                    step: 20.0,
                }),
                // With the detail, its density sampled in parts of each
                // step, the light once a step.
                substeps: parts,
            },
        )
        .map_err(|e| crate::scene::clouds_in_section("clouds", e))?;
        let dome = Dome::new(&fast, eye, &layout)?;
        progress.advance(1);
        let shadow = ShadowMap::new(world, &grid, desc)?;
        progress.advance(1);
        progress.finish();
        Ok(Some(Self {
            eye,
            mid: 0.5 * (l.base_m + l.top_m),
            dome,
            shadow,
        }))
    }

    /// The clouds of `world` as its renderer sees them — through the
    /// scene's camera, under the sky at the eye — or `None` when the
    /// scene's clouds are off: what [`crate::Renderer::new`] builds, for
    /// [`crate::Renderer::with_clouds`]. A farm prepares them once per frame
    /// and shares them between the frame's tiles
    /// ([`Self::to_bytes`], [`Self::from_bytes`]).
    ///
    /// # Errors
    ///
    /// The errors of [`Self::new`], of the scene's camera and of the sky
    /// view at the eye.
    pub fn for_world(world: &World, progress: &dyn Progress) -> Result<Option<Self>> {
        if !world.scene.clouds.visible() {
            return Ok(None);
        }
        let camera = crate::SceneCamera::of_world(world)?;
        let view = world
            .atmosphere
            .sky_view(world.eye().as_dvec3(), world.sun_dir())?;
        Self::new(
            world,
            camera.camera(),
            crate::camera::pixel_angle(world),
            &view,
            progress,
        )
    }

    /// The eye the clouds were marched from.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    /// What the clouds do to the ray from `o` along unit `d` that leaves
    /// the terrain: `None` if it never reaches the layer.
    #[must_use]
    pub fn view(&self, o: Vec3, d: Vec3) -> Option<CloudView> {
        if d.z <= 0.0 {
            return None;
        }
        if o == self.eye {
            let c = self.dome.lookup(d);
            return Some(CloudView {
                radiance: Vec3::new(c[0], c[1], c[2]),
                transmittance: c[3],
                sun_transmittance: c[4],
            });
        }
        // Another origin (a reflection): the eye's view toward where this
        // ray crosses the middle of the layer.
        let q = o + d * ((self.mid - o.z) / d.z);
        let e = (q - self.eye).try_normalize()?;
        let c = self.dome.lookup(e);
        Some(CloudView {
            radiance: Vec3::new(c[0], c[1], c[2]),
            transmittance: c[3],
            sun_transmittance: self.shadow.transmittance(o),
        })
    }

    /// The sun's transmittance through the clouds at `p` (below the layer).
    #[must_use]
    pub fn sun_transmittance(&self, p: Vec3) -> f32 {
        self.shadow.transmittance(p)
    }

    /// The 2-D shadow map.
    #[must_use]
    pub fn shadow_map(&self) -> &ShadowMap {
        &self.shadow
    }
}

/// Where the directions of a [`Dome`] lie: the first azimuth, whether the
/// grid wraps round, the cell (radians) and the grid's size.
#[derive(Clone, Copy, Debug)]
struct Layout {
    az0: f32,
    wrap: bool,
    cell: f32,
    nx: usize,
    ny: usize,
}

/// The clouds seen from the eye over a grid of directions: azimuth
/// (`atan2(x, y)`) by elevation, each cell the clouds' radiance (3), their
/// transmittance and the exact medium's (for the sun disc).
#[derive(Debug)]
struct Dome {
    az0: f32,
    el0: f32,
    inv_cell: f32,
    /// The grid spans the whole circle of azimuths.
    wrap: bool,
    cells: Grid2<[f32; 5]>,
}

fn azimuth(d: Vec3) -> f32 {
    d.x.atan2(d.y)
}

fn elevation(d: Vec3) -> f32 {
    d.z.clamp(-1.0, 1.0).asin()
}

fn dir(az: f32, el: f32) -> Vec3 {
    let (sa, ca) = az.sin_cos();
    let (se, ce) = el.sin_cos();
    Vec3::new(ce * sa, ce * ca, se)
}

impl Dome {
    /// The grid's layout over `camera`'s view, with cells of `cell`
    /// radians (coarsened so that there are at most [`MAX_DIRECTIONS`]).
    fn layout(camera: &dyn Camera, cell: f32) -> Layout {
        use std::f32::consts::{FRAC_PI_2, PI, TAU};
        // The camera's azimuths (about its centre's) and elevations, on a
        // lattice of rays over the image; reflections look up at minus the
        // elevation of a downward ray.
        let res = camera.resolution();
        let centre = azimuth(camera.ray_at(0.5 * res.x as f32, 0.5 * res.y as f32).dir);
        let (mut lo, mut hi, mut el_max) = (0.0f32, 0.0f32, 0.0f32);
        let n = 64;
        for j in 0..=n {
            for i in 0..=n {
                let d = camera
                    .ray_at(
                        res.x as f32 * i as f32 / n as f32,
                        res.y as f32 * j as f32 / n as f32,
                    )
                    .dir;
                let a = (azimuth(d) - centre + PI).rem_euclid(TAU) - PI;
                lo = lo.min(a);
                hi = hi.max(a);
                el_max = el_max.max(elevation(d).abs());
            }
        }
        let margin = 4f32.to_radians();
        let wrap = hi - lo + 2.0 * margin > 1.8 * PI;
        let (az0, span) = if wrap {
            (centre - PI, TAU)
        } else {
            (centre + lo - margin, hi - lo + 2.0 * margin)
        };
        let el_span = (el_max + margin).min(FRAC_PI_2);
        let mut cell = cell;
        let count = |c: f32| ((span / c).ceil() as usize + 2) * ((el_span / c).ceil() as usize + 2);
        while count(cell) > MAX_DIRECTIONS {
            cell *= 1.25;
        }
        Layout {
            az0,
            wrap,
            cell,
            nx: (span / cell).ceil() as usize + 2,
            ny: (el_span / cell).ceil() as usize + 2,
        }
    }

    fn new(fast: &FastRenderer<'_>, eye: Vec3, layout: &Layout) -> Result<Self> {
        let Layout {
            az0,
            wrap,
            cell,
            nx,
            ny,
        } = *layout;
        let el0 = 0.0;
        let f = |i: usize, j: usize| {
            let d = dir(az0 + i as f32 * cell, el0 + j as f32 * cell);
            let s = fast.seen(eye, d);
            [
                s.radiance.x,
                s.radiance.y,
                s.radiance.z,
                s.transmittance,
                s.direct_transmittance,
            ]
        };
        #[cfg(feature = "parallel")]
        let cells = Grid2::par_from_fn(nx, ny, f)?;
        #[cfg(not(feature = "parallel"))]
        let cells = Grid2::from_fn(nx, ny, f)?;
        Ok(Self {
            az0,
            el0,
            inv_cell: 1.0 / cell,
            wrap,
            cells,
        })
    }

    /// Bilinear lookup at the unit direction `d` (clamped to the grid).
    fn lookup(&self, d: Vec3) -> [f32; 5] {
        use std::f32::consts::TAU;
        let (nx, ny) = (self.cells.width(), self.cells.height());
        let mut a = (azimuth(d) - self.az0).rem_euclid(TAU);
        if !self.wrap && a > 0.5 * (TAU + (nx - 1) as f32 / self.inv_cell) {
            // Left of the grid rather than far right of it.
            a = 0.0;
        }
        let x = (a * self.inv_cell).clamp(0.0, (nx - 1) as f32);
        let y = ((elevation(d) - self.el0) * self.inv_cell).clamp(0.0, (ny - 1) as f32);
        let (x0, y0) = ((x as usize).min(nx - 2), (y as usize).min(ny - 2));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let c = &self.cells;
        let mut out = [0.0; 5];
        for (k, o) in out.iter_mut().enumerate() {
            let a = c[(x0, y0)][k] + (c[(x0 + 1, y0)][k] - c[(x0, y0)][k]) * fx;
            let b = c[(x0, y0 + 1)][k] + (c[(x0 + 1, y0 + 1)][k] - c[(x0, y0 + 1)][k]) * fx;
            *o = a + (b - a) * fy;
        }
        out
    }
}

/// The sun's transmittance through the cloud layer over its base: a point
/// `p` below the layer looks it up where the sun's ray from `p` meets the
/// base, `p_xy + (base − p_z)·s_xy/s_z`.
#[derive(Debug)]
pub struct ShadowMap {
    origin: Vec2,
    inv_cell: f32,
    base: f32,
    /// `s_xy / s_z` of the sun direction `s`.
    slope: Vec2,
    transmittance: Grid2<f32>,
}

impl ShadowMap {
    fn new(world: &World, grid: &GridDensity, desc: &CloudsDesc) -> Result<Self> {
        let sun = world.sun;
        let base = desc.layer.base_m;
        let slope = Vec2::new(sun.x, sun.y) / sun.z.max(0.02);
        let e = world.terrain.extent();
        let (lo, hi) = world.surface.min_max();
        let eye = world.eye();
        let (a, b) = (slope * (base - hi), slope * (base - lo.min(eye.z)));
        let min = Vec2::ZERO + a.min(b);
        let max = Vec2::new(e.x, e.y) + a.max(b);
        let cell = desc.shadow_cell_m;
        let (nx, ny) = (
            ((max.x - min.x) / cell).ceil() as usize + 1,
            ((max.y - min.y) / cell).ceil() as usize + 1,
        );
        let extinction = desc.medium.without_forward_peak().extinction;
        let step = desc.voxel_m;
        let f = |i: usize, j: usize| {
            let p = Vec3::new(min.x + i as f32 * cell, min.y + j as f32 * cell, base);
            (-optical_depth_ray(grid, extinction, p, sun, step)).exp()
        };
        #[cfg(feature = "parallel")]
        let transmittance = Grid2::par_from_fn(nx, ny, f)?;
        #[cfg(not(feature = "parallel"))]
        let transmittance = Grid2::from_fn(nx, ny, f)?;
        Ok(Self {
            origin: min,
            inv_cell: 1.0 / cell,
            base,
            slope,
            transmittance,
        })
    }

    /// The sun's transmittance through the layer at `p` (below the layer;
    /// bilinear in the map, clamped at its edges).
    #[must_use]
    pub fn transmittance(&self, p: Vec3) -> f32 {
        let q =
            (Vec2::new(p.x, p.y) + self.slope * (self.base - p.z) - self.origin) * self.inv_cell;
        self.transmittance
            .sample_bilinear(q.x, q.y, natura_core::Boundary::Clamp)
    }
}
