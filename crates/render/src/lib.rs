//! # natura-render
//!
//! Scenes that compose the natura crates into images: Musgrave's landscape
//! pipeline — fractal terrain ([`natura_noise`]), erosion
//! ([`natura_terrain`]), grid tracing ([`natura_trace`]), aerial perspective
//! and sky ([`natura_atmos`]) — as one library call.
//!
//! * [`SceneDesc`]: the whole scene as a `serde` struct, loadable from TOML,
//!   with a built-in default ([`DEFAULT_SCENE_TOML`]).
//! * [`World::build`]: synthesis, erosion, terraces along the rock strata
//!   (`[terraces]`: cliffs where hard beds stand, benches where soft ones
//!   wear back), maps and atmosphere.
//! * [`Renderer`]: the integrator (primary rays by maximum-mipmap grid
//!   tracing, sun shadows by any-hit rays, water reflection and refraction,
//!   aerial perspective per segment, sky for escaped rays, stratified
//!   samples with more where a pixel's samples disagree, rainbow in rain),
//!   tile-parallel and deterministic.
//! * [`clouds`]: a layer-cloud sky from natura-volume over the whole scene,
//!   lit by the sun and sky, marched once per direction of a grid, with a
//!   2-D map of its shadows on the terrain and water (`[clouds]`).
//! * [`surface_textures`]: natura-texture's rock strata on cliffs and a fine grain on
//!   snow, grass and scree, band-limited at the pixel's footprint
//!   (`[textures]`).
//! * [`vegetation::Forest`]: an ecosystem of natura-plant species (conifers,
//!   a broad-leaved tree, a shrub, a ground cover) grown on the terrain near
//!   the camera, instanced plant meshes traced through a two-level BVH, with
//!   shadows both ways and translucent leaves; beyond them a canopy layer
//!   grown from the same species carries the forest to the horizon.
//! * [`render_scene`]: all of it, with stage timings, returning a linear
//!   image and its exposure; [`Rendered::save`] writes EXR and PNG.
//!
//! The default scene ([`SceneDesc::default`]) is a 2048² terrain of 30 m
//! cells (61 km across) at 1920 × 1080. A quick look keeps the world's size
//! and coarsens it: 64 samples of 960 m cover the same 61 km, so the camera,
//! the sun and the haze keep the scene's proportions. (Shrinking
//! `terrain.size` alone shrinks the world but not the atmosphere: the view
//! is then hazy ground with no sky.)
//!
//! ```
//! use natura_render::{NoProgress, SceneDesc, render_scene};
//! let mut scene = SceneDesc::default();
//! scene.terrain.size = 64; // 64 × 960 m = 2048 × 30 m
//! scene.terrain.cell_size_m = 960.0;
//! scene.erosion.stream_power_steps = 3;
//! scene.erosion.thermal_steps = 3;
//! scene.clouds.enabled = false; // the layer clouds and the forest cost
//! scene.vegetation.enabled = false; // most; the default scene has both
//! scene.render.width = 96;
//! scene.render.height = 54;
//! scene.render.spp = 1;
//! let out = render_scene(&scene, &NoProgress)?;
//! assert_eq!((out.image.width(), out.image.height()), (96, 54));
//! assert!(out.image.first_non_finite().is_none() && out.exposure_ev.is_finite());
//! // The top-left pixel is sky: bluer than it is red.
//! let sky = out.image.get(0, 0).unwrap();
//! assert!(sky.z > sky.x);
//!
//! let dir = std::env::temp_dir().join(format!("natura-render-quickstart-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! out.save(dir.join("landscape.png"), dir.join("landscape.exr"))?;
//! assert!(dir.join("landscape.png").exists() && dir.join("landscape.exr").exists());
//! std::fs::remove_dir_all(&dir).unwrap();
//! # Ok::<(), natura_render::RenderError>(())
//! ```
#![forbid(unsafe_code)]

mod camera;
pub mod clouds;
mod error;
mod integrator;
pub mod material;
pub mod scene;
pub mod snow;
pub mod stray;
pub mod surface_textures;
pub mod vegetation;
pub mod water;
mod world;

use std::path::Path;

use natura_core::colour::luminance;
use natura_core::{Image, Progress};

pub use camera::SceneCamera;
pub use error::{RenderError, Result};
pub use integrator::{Renderer, WATER_IOR};
pub use scene::{
    AnimationDesc, AnimationKey, AtmosphereDesc, CameraDesc, CameraKind, CloudsDesc,
    DEFAULT_SCENE_TOML, DetailDesc, Diffuse, ErosionDesc, HydraulicModel, MaterialDesc,
    QUICK_TERRAIN_SIZE, RenderDesc, SceneDesc, SunDesc, TerrainDesc, TerrainGenerator,
    TexturesDesc, VegetationDesc, WaterDesc, WaterWaves,
};
pub use world::{
    ErodedTerrain, MIN_LAKE_DEPTH_M, MIN_LAKE_SAMPLES, StageTimes, TerrainFunction, World,
    sun_direction,
};

/// The vector types of the API, so users need no `glam` dependency of their own.
pub use glam;
/// The progress sink that reports nowhere, for [`render_scene`]'s last argument.
pub use natura_core::NoProgress;

/// The result of rendering a scene.
#[derive(Debug)]
pub struct Rendered {
    /// Linear scene-referred radiance (the EXR's content).
    pub image: Image,
    /// Exposure in stops applied before tone mapping (given or automatic).
    pub exposure_ev: f32,
    /// The scene's tone map.
    pub tone_map: natura_core::ToneMap,
    /// Time per stage.
    pub times: StageTimes,
    /// Figures of the forest, if the scene grew one.
    pub forest: Option<vegetation::ForestStats>,
}

impl Rendered {
    /// The display image: exposed and tone-mapped, values in `[0, 1]`.
    #[must_use]
    pub fn display(&self) -> Image {
        self.image.tone_mapped(self.exposure_ev, self.tone_map)
    }

    /// Writes the tone-mapped 8-bit sRGB PNG and the linear EXR as one
    /// [`OutputSet`](natura_core::io::OutputSet): both appear, or neither.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Core`] if either file cannot be written (a
    /// directory in the way, an unwritable folder, a failed encode).
    pub fn save(&self, png: impl AsRef<Path>, exr: impl AsRef<Path>) -> Result<()> {
        let (png, exr) = (png.as_ref(), exr.as_ref());
        let set = natura_core::io::OutputSet::new([png, exr])?;
        self.save_staged(&set, png, exr)?;
        Ok(set.commit()?)
    }

    /// Writes the PNG and EXR into a caller's [`OutputSet`](natura_core::io::OutputSet)
    /// that names both (the caller commits it with its other outputs).
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Core`] if either path is not in `set` or a file
    /// cannot be written.
    pub fn save_staged(
        &self,
        set: &natura_core::io::OutputSet,
        png: impl AsRef<Path>,
        exr: impl AsRef<Path>,
    ) -> Result<()> {
        self.image.save_exr(set.stage(exr)?)?;
        self.display().save_png(set.stage(png)?)?;
        Ok(())
    }
}

/// The exposure (stops) that maps the image's log-average luminance to 18 %
/// grey (Reinhard et al.'s key value), ignoring non-finite pixels.
#[must_use]
pub fn auto_exposure(image: &Image) -> f32 {
    let mut sum = 0.0f64;
    let mut n = 0usize;
    for c in image.pixels().as_slice() {
        let y = luminance(*c);
        if y.is_finite() && y >= 0.0 {
            sum += f64::from(1e-4 + y).ln();
            n += 1;
        }
    }
    if n == 0 {
        return 0.0;
    }
    let avg = (sum / n as f64).exp();
    (0.18 / avg).log2() as f32
}

/// Validates `scene`, builds its world, renders it, and picks the exposure.
///
/// Stages reported to `progress`: synthesis, stream power, pipe erosion,
/// thermal erosion, atmosphere tables, the forest's ecosystem,
/// acceleration, tracing.
///
/// # Errors
///
/// The errors of [`World::build`] and [`render_world`].
pub fn render_scene(scene: &SceneDesc, progress: &dyn Progress) -> Result<Rendered> {
    let world = World::build(scene, progress)?;
    render_world(&world, progress)
}

/// The renderer of `world` with everything its scene asks for — the
/// forest grown ([`vegetation::Forest::build`]) and added to
/// [`Renderer::new`]'s as [`Renderer::with_forest`] adds it, with one build
/// of its instance BVH — timing the stages `acceleration` and `forest` into
/// `times`. [`render_world`] renders with it; a caller rendering parts of a
/// frame ([`Renderer::render_region`]) builds the same one, so its pixels
/// equal the whole frame's.
///
/// # Errors
///
/// The errors of [`vegetation::Forest::build`] and [`Renderer::new`].
pub fn scene_renderer<'w>(
    world: &'w World,
    times: &mut StageTimes,
    progress: &dyn Progress,
) -> Result<Renderer<'w>> {
    let renderer = times.time("acceleration", || Renderer::new(world, progress))?;
    let forest = times.time("forest", || {
        vegetation::Forest::build_from(world, None, Some(&|p| renderer.tree_ground(p)), progress)
    })?;
    Ok(renderer.with_grounded_forest(forest))
}

/// What the tiles of one frame share, prepared once for all of them: the
/// clouds as the frame's renderer sees them and the population the forest's
/// ecosystem grows. A farm prepares it per frame and gives it to each
/// tile's [`scene_renderer_prepared`].
#[derive(Debug)]
pub struct FramePrep {
    /// [`clouds::CloudSky::for_world`] (`None` when the clouds are off).
    pub clouds: Option<clouds::CloudSky>,
    /// [`vegetation::Forest::grow`] (`None` when the forest is off).
    pub plants: Option<Vec<natura_plant::eco::Plant>>,
}

impl FramePrep {
    /// Prepares the frame of `world`.
    ///
    /// # Errors
    ///
    /// The errors of [`clouds::CloudSky::for_world`] and
    /// [`vegetation::Forest::grow`].
    pub fn new(world: &World, progress: &dyn Progress) -> Result<Self> {
        Ok(Self {
            clouds: clouds::CloudSky::for_world(world, progress)?,
            plants: vegetation::Forest::grow(world, progress)?,
        })
    }
}

/// As [`scene_renderer`], from the frame's [`FramePrep`] instead of growing
/// the forest and marching the clouds here (a prep without plants grows
/// them as [`scene_renderer`] does): the pixels equal
/// [`scene_renderer`]'s bit for bit when `prep` is [`FramePrep::new`]'s for
/// this world.
///
/// # Errors
///
/// The errors of [`vegetation::Forest::build_with_plants`] and
/// [`Renderer::with_clouds`].
pub fn scene_renderer_prepared<'w>(
    world: &'w World,
    prep: FramePrep,
    times: &mut StageTimes,
    progress: &dyn Progress,
) -> Result<Renderer<'w>> {
    let renderer = times.time("acceleration", || {
        Renderer::with_clouds(world, prep.clouds, progress)
    })?;
    // A prep without plants (nothing grows here, or nothing was prepared)
    // grows them as `scene_renderer` does.
    let forest = times.time("forest", || {
        vegetation::Forest::build_from(
            world,
            prep.plants,
            Some(&|p| renderer.tree_ground(p)),
            progress,
        )
    })?;
    Ok(renderer.with_grounded_forest(forest))
}

/// Renders an already built [`World`] (see [`render_scene`]); the stage
/// times include the world's.
///
/// # Errors
///
/// The errors of [`vegetation::Forest::build`], [`Renderer::new`] and
/// [`Renderer::render`].
pub fn render_world(world: &World, progress: &dyn Progress) -> Result<Rendered> {
    let scene = &world.scene;
    let mut times = world.times.clone();
    let renderer = scene_renderer(world, &mut times, progress)?;
    let forest_stats = renderer.forest().map(|f| f.stats().clone());
    let image = times.time("render", || renderer.render(progress))?;
    let exposure_ev = scene
        .render
        .exposure_ev
        .unwrap_or_else(|| auto_exposure(&image));
    Ok(Rendered {
        image,
        exposure_ev,
        tone_map: scene.render.tone_map,
        times,
        forest: forest_stats,
    })
}
