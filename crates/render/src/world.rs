//! Building the world a scene describes: fractal terrain, erosion, the maps
//! materials read (deposition, and the wetness the forest's ecosystem reads
//! too), the water level and the atmosphere.
//!
//! This is Musgrave's landscape pipeline (Musgrave 1993, ch. 2–4; Musgrave et al. 1989): noise
//! synthesis of a multifractal height field, erosion that carves drainage
//! into it, then rendering. Erosion runs in three passes, coarse to fine:
//! Braun–Willett stream power carves the valley network (the "fractal
//! drainage networks" the sources wished for), the virtual-pipe hydraulic
//! model adds gullies and sediment fans, and thermal weathering relaxes
//! slopes to the talus angle. Terraces then raise cliffs along the rock
//! strata on the hillsides (the layered hardness of Musgrave 1993, §2.4.4):
//! thermal weathering alone would leave no slope steeper than the talus
//! angle, so no cliff would show its strata.

use std::time::{Duration, Instant};

use glam::{DVec2, DVec3, Vec3};
use natura_atmos::Dir3;
use natura_atmos::sky::{Atmosphere, AtmosphereParams};
use natura_core::{Grid2, HeightField, Progress, Seed};
use natura_noise::{
    Displace, Field, HybridMultifractal, HybridParams, NoiseError, Perlin, RidgedMultifractal,
    RidgedParams, Spectral, VecNoise, VectorFbm, Warped,
};
use natura_terrain::analysis;
use natura_terrain::erosion::{DropletErosion, PipeModel, StreamPower, Thermal};
use natura_terrain::synth::{FieldMapping, TerraceParams, fill_field};
use natura_terrain::water::{CoastParams, LakeParams};

use crate::error::{RenderError, Result, fmt_f64};
use crate::scene::{HydraulicModel, SceneDesc, TerrainGenerator};

/// The warp of the terrain's domain: displacement by vector fBm of Perlin
/// noise (the general distortion `F(p + s·V(p))` of Musgrave 2001, "Domain Distortion").
type TerrainWarp = Displace<VectorFbm<VecNoise<Perlin>>>;

/// The fractal terrain function of a scene, before normalisation: a ridged,
/// hybrid or ridged-times-hybrid multifractal over Perlin noise, evaluated at
/// warped points. Evaluated in units of the first octave's wavelength.
#[derive(Debug)]
pub struct TerrainFunction {
    generator: TerrainGenerator,
    ridged: Warped<RidgedMultifractal<Perlin>, TerrainWarp>,
    hybrid: Warped<HybridMultifractal<Perlin>, TerrainWarp>,
}

impl TerrainFunction {
    /// Builds the function for `scene.terrain` with sub-seeds of `seed`.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`](crate::RenderError::Invalid) naming
    /// the `terrain` keys that make an invalid or unbounded fractal.
    pub fn new(scene: &SceneDesc, seed: Seed) -> Result<Self> {
        Self::build(scene, seed).map_err(terrain_noise_error)
    }

    fn build(scene: &SceneDesc, seed: Seed) -> std::result::Result<Self, NoiseError> {
        let t = &scene.terrain;
        let spectral = Spectral::default()
            .with_h(t.h)
            .with_lacunarity(t.lacunarity)
            .with_octaves(t.octaves)
            .with_frequency(1.0);
        let ridged = RidgedMultifractal::new(
            Perlin::new(seed.derive("ridged").0),
            RidgedParams {
                spectral,
                offset: t.offset,
                gain: t.gain,
            },
        )?;
        let hybrid = HybridMultifractal::new(
            Perlin::new(seed.derive("hybrid").0),
            HybridParams {
                spectral: spectral.with_h(0.25).with_octaves(t.octaves.min(8.0)),
                offset: 0.7,
            },
        )?;
        let warp = Displace::new(
            VectorFbm::new(
                VecNoise::new(Perlin::new(seed.derive("warp").0)),
                Spectral::default()
                    .with_h(0.5)
                    .with_octaves(4.0)
                    .with_frequency(1.0),
            )?,
            t.warp,
        )?;
        Ok(Self {
            generator: t.generator,
            ridged: Warped {
                field: ridged,
                warp: warp.clone(),
            },
            hybrid: Warped {
                field: hybrid,
                warp,
            },
        })
    }

    /// The (unnormalised) terrain value at `q`, in first-octave units.
    #[must_use]
    pub fn eval(&self, q: DVec2) -> f64 {
        match self.generator {
            TerrainGenerator::Ridged => self.ridged.eval2(q),
            TerrainGenerator::Hybrid => self.hybrid.eval2(q),
            TerrainGenerator::RidgedHybrid => {
                // The hybrid multifractal at half frequency decides where the
                // ranges are; the ridged multifractal supplies the ranges.
                let mask = (0.5 + 0.35 * self.hybrid.eval2(q * 0.5 + DVec2::new(17.0, -3.0)))
                    .clamp(0.0, 1.5);
                self.ridged.eval2(q) * mask + 0.25 * mask
            }
        }
    }
}

/// A noise error of the terrain's fractal, named by the scene's keys.
fn terrain_noise_error(e: NoiseError) -> RenderError {
    match e {
        NoiseError::InvalidParam {
            name,
            value,
            expected,
        } => {
            let key = match name {
                "frequency" => "terrain.feature_size_m".to_owned(),
                "h" | "lacunarity" | "octaves" | "offset" | "gain" => format!("terrain.{name}"),
                _ => format!("terrain.warp ({name})"),
            };
            RenderError::invalid(&key, fmt_f64(value), expected)
        }
        NoiseError::OctavesBeyondPrecision {
            octaves,
            lacunarity,
            max_octaves,
            ..
        } => RenderError::invalid(
            "terrain.octaves",
            fmt_f64(octaves),
            &format!(
                "at most {} octaves with terrain.lacunarity = {} (the finest octave's \
                 frequency stays within 2^32 times the first's)",
                fmt_f64(max_octaves),
                fmt_f64(lacunarity)
            ),
        ),
        NoiseError::Unbounded { bound, .. } => RenderError::invalid(
            "terrain.offset, terrain.gain, terrain.h",
            format_args!("a fractal bound of {bound:e}"),
            "the terrain's fractal must stay bounded: reduce the offset, the gain or raise h",
        ),
        other => RenderError::Noise(other),
    }
}

/// Wall-clock time of each stage, for reports and benchmarks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// `(stage, duration)` in the order run.
    pub stages: Vec<(String, Duration)>,
}

impl StageTimes {
    /// Runs `f`, recording its duration under `name`.
    pub fn time<T>(&mut self, name: &str, f: impl FnOnce() -> T) -> T {
        let t0 = Instant::now();
        let r = f();
        self.stages.push((name.to_owned(), t0.elapsed()));
        r
    }

    /// Total of all stages.
    #[must_use]
    pub fn total(&self) -> Duration {
        self.stages.iter().map(|(_, d)| *d).sum()
    }
}

/// The terrain after synthesis, erosion and the sunken coast, with the maps
/// erosion leaves: what [`World::build_eroded`] returns.
#[derive(Clone, Debug, PartialEq)]
pub struct ErodedTerrain {
    /// The eroded terrain, heights in metres above the datum.
    pub terrain: HeightField,
    /// Sediment deposited by erosion, metres (≥ 0).
    pub deposition: Grid2<f32>,
    /// Wetness in `[0, 1]` of the final terrain: natura-terrain's
    /// [`wetness`](natura_terrain::analysis::wetness).
    pub wetness: Grid2<f32>,
}

/// Everything built from a scene before rendering.
#[derive(Debug)]
pub struct World {
    /// The scene this world was built from (validated).
    pub scene: SceneDesc,
    /// The eroded terrain, heights in metres above the datum (sea level 0).
    pub terrain: HeightField,
    /// Sediment deposited by erosion, metres (≥ 0; erosion is not negative deposition here).
    pub deposition: Grid2<f32>,
    /// Wetness in `[0, 1]` of the terrain: natura-terrain's
    /// [`wetness`](natura_terrain::analysis::wetness), the one map the
    /// materials and the forest's ecosystem read.
    pub wetness: Grid2<f32>,
    /// The sea level, metres, if the scene has water.
    pub water_level: Option<f32>,
    /// The visible surface: the terrain with the sea and lakes on top (lakes
    /// fill every depression deeper than [`MIN_LAKE_DEPTH_M`] to its spill
    /// level). Equal to `terrain` where dry, and to `terrain` everywhere
    /// without water.
    pub surface: HeightField,
    /// Unit direction toward the sun (z up).
    pub sun: Vec3,
    /// The atmosphere with its precomputed tables.
    pub atmosphere: Atmosphere,
    /// How long each stage took.
    pub times: StageTimes,
}

impl World {
    /// Validates `scene` and builds its world, reporting each stage to `progress`.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`](crate::RenderError::Invalid) naming the first scene key out of
    /// its range, and the errors of synthesis, erosion ([`RenderError::Terrain`](crate::RenderError::Terrain))
    /// and the atmosphere ([`RenderError::Atmos`](crate::RenderError::Atmos)).
    pub fn build(scene: &SceneDesc, progress: &dyn Progress) -> Result<World> {
        scene.validate()?;
        let seed = Seed(scene.seed);
        let mut times = StageTimes::default();

        let mut terrain = times.time("synthesis", || synthesize(scene, seed, progress))?;
        let deposition = times.time("erosion", || erode(scene, &mut terrain, progress))?;
        times.time("terraces", || terrace(scene, seed, &mut terrain))?;
        times.time("coast", || sink_coast(scene, seed, &mut terrain))?;
        // The wetness (a flow analysis of the whole field, in good part
        // serial) and the water and the sky need only the finished terrain:
        // they run side by side, timed as one stage.
        let (wetness, water_sky) = times.time("wetness, lakes, atmosphere", || {
            join(
                || analysis::wetness(&terrain),
                || water_and_sky(scene, &terrain, progress),
            )
        });
        Ok(Self::assemble(
            scene, terrain, deposition, wetness?, water_sky?, times,
        ))
    }

    /// The terrain alone, exactly as [`World::build`] makes it (synthesis,
    /// erosion, the sunken coast), without maps or atmosphere: for sweeps,
    /// caches and exports.
    ///
    /// # Errors
    ///
    /// Returns the scene's validation errors and any error of synthesis or
    /// erosion.
    pub fn build_terrain(scene: &SceneDesc, progress: &dyn Progress) -> Result<HeightField> {
        scene.validate()?;
        let seed = Seed(scene.seed);
        let mut terrain = synthesize(scene, seed, progress)?;
        erode(scene, &mut terrain, progress)?;
        terrace(scene, seed, &mut terrain)?;
        sink_coast(scene, seed, &mut terrain)?;
        Ok(terrain)
    }

    /// The terrain and the maps erosion leaves, exactly as [`World::build`]
    /// makes them: the part of a world shared by every frame and tile of an
    /// animation (see [`World::from_eroded`]), worth caching.
    ///
    /// # Errors
    ///
    /// Returns the scene's validation errors and any error of synthesis or
    /// erosion.
    pub fn build_eroded(scene: &SceneDesc, progress: &dyn Progress) -> Result<ErodedTerrain> {
        scene.validate()?;
        let seed = Seed(scene.seed);
        let mut terrain = synthesize(scene, seed, progress)?;
        let deposition = erode(scene, &mut terrain, progress)?;
        terrace(scene, seed, &mut terrain)?;
        sink_coast(scene, seed, &mut terrain)?;
        let wetness = analysis::wetness(&terrain)?;
        Ok(ErodedTerrain {
            terrain,
            deposition,
            wetness,
        })
    }

    /// The world of `scene` over terrain built by [`World::build_eroded`]
    /// from a scene with the same seed, terrain and erosion sections: equal
    /// to [`World::build`]`(scene)` bit for bit (the water, sun and
    /// atmosphere come from `scene`).
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`](crate::RenderError::Invalid) naming the first scene key out of
    /// its range or a map whose size differs from the terrain's;
    /// [`RenderError::Core`](crate::RenderError::Core) if a height is not finite;
    /// the errors of the atmosphere.
    pub fn from_eroded(
        scene: &SceneDesc,
        eroded: ErodedTerrain,
        progress: &dyn Progress,
    ) -> Result<World> {
        scene.validate()?;
        let ErodedTerrain {
            terrain,
            deposition,
            wetness,
        } = eroded;
        terrain.check_finite()?;
        let (nx, ny) = (terrain.nx(), terrain.ny());
        for (name, map) in [("deposition", &deposition), ("wetness", &wetness)] {
            if (map.width(), map.height()) != (nx, ny) {
                return Err(crate::RenderError::invalid(
                    name,
                    format_args!("{} × {}", map.width(), map.height()),
                    &format!("the terrain's size, {nx} × {ny}"),
                ));
            }
        }
        Self::finish(
            scene,
            terrain,
            deposition,
            wetness,
            StageTimes::default(),
            progress,
        )
    }

    /// A world over a given height field (a DEM, or terrain made elsewhere):
    /// no synthesis or erosion; deposition is zero and wetness is
    /// natura-terrain's [`wetness`](natura_terrain::analysis::wetness) of
    /// the field. The scene's terrain and erosion sections are ignored.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`](crate::RenderError::Invalid) naming the first scene key out of
    /// its range; [`RenderError::Core`](crate::RenderError::Core) if the height field holds
    /// a NaN or infinite height; the errors of the flow analysis and the atmosphere.
    pub fn from_height_field(
        scene: &SceneDesc,
        terrain: HeightField,
        progress: &dyn Progress,
    ) -> Result<World> {
        scene.validate()?;
        terrain.check_finite()?;
        let mut times = StageTimes::default();
        let (nx, ny) = (terrain.nx(), terrain.ny());
        let deposition = Grid2::new(nx, ny, 0.0f32)?;
        let wetness = times.time("analysis", || analysis::wetness(&terrain))?;
        Self::finish(scene, terrain, deposition, wetness, times, progress)
    }

    /// The stages after the terrain and its maps, shared by [`World::build`]
    /// and [`World::from_height_field`]: the water level and surface, the
    /// sun, and the atmosphere's tables.
    fn finish(
        scene: &SceneDesc,
        terrain: HeightField,
        deposition: Grid2<f32>,
        wetness: Grid2<f32>,
        mut times: StageTimes,
        progress: &dyn Progress,
    ) -> Result<World> {
        let water_sky = times.time("lakes, atmosphere", || {
            water_and_sky(scene, &terrain, progress)
        })?;
        Ok(Self::assemble(
            scene, terrain, deposition, wetness, water_sky, times,
        ))
    }

    /// The world from its parts.
    fn assemble(
        scene: &SceneDesc,
        terrain: HeightField,
        deposition: Grid2<f32>,
        wetness: Grid2<f32>,
        (water_level, surface, atmosphere): WaterSky,
        times: StageTimes,
    ) -> World {
        World {
            scene: scene.clone(),
            terrain,
            deposition,
            wetness,
            water_level,
            surface,
            sun: sun_direction(scene.sun.elevation_deg, scene.sun.azimuth_deg),
            atmosphere,
            times,
        }
    }

    /// A shaded-relief map of the terrain (north up): terrain false colour,
    /// hill-shaded from the scene's sun, water in blue, deposition in light
    /// grey. For checking a scene's terrain before rendering it.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Core`](crate::RenderError::Core) if the image cannot be allocated.
    pub fn relief_map(&self) -> Result<natura_core::Image> {
        let hf = &self.terrain;
        let sun = Vec3::new(self.sun.x, self.sun.y, self.sun.z.max(0.35)).normalize();
        let shade = hf.hillshade(sun)?;
        let (lo, hi) = hf.min_max();
        let level = self.water_level.unwrap_or(f32::NEG_INFINITY);
        let (nx, ny) = (hf.nx(), hf.ny());
        Ok(natura_core::Image::from_fn(nx, ny, |i, r| {
            let j = ny - 1 - r;
            let h = hf.heights()[(i, j)];
            let s = 0.2 + 0.8 * shade[(i, j)];
            let w = self.surface.heights()[(i, j)];
            if w > h {
                let depth = ((w - h) / 200.0).clamp(0.0, 1.0);
                return Vec3::new(0.05, 0.15, 0.35).lerp(Vec3::new(0.01, 0.03, 0.12), depth);
            }
            // Land colours only: the terrain ramp from its green lowland up.
            let t = ((h - level.max(lo)) / (hi - level.max(lo)).max(1e-3)).clamp(0.0, 1.0);
            let base = natura_core::Ramp::Terrain.eval(0.27 + 0.73 * t);
            let dep = (self.deposition[(i, j)] / 2.0).clamp(0.0, 1.0);
            base.lerp(Vec3::splat(0.8), 0.5 * dep) * s
        })?)
    }

    /// The sun as an `atmos` direction.
    #[must_use]
    pub fn sun_dir(&self) -> Dir3 {
        // `sun` is a unit vector built from angles; Dir3::new only fails on zero/NaN.
        Dir3::new(self.sun.as_dvec3()).unwrap_or(Dir3::UP)
    }
}

/// The water level (if the scene has water), the water's surface and the
/// atmosphere's tables.
type WaterSky = (Option<f32>, HeightField, Atmosphere);

/// The stages after the terrain that need only it: the water level and
/// surface (the lakes) and the atmosphere's tables.
fn water_and_sky(
    scene: &SceneDesc,
    terrain: &HeightField,
    progress: &dyn Progress,
) -> Result<WaterSky> {
    let level = if scene.water.enabled {
        Some(water_level(scene, terrain)?)
    } else {
        None
    };
    let surface = water_surface(terrain, level)?;
    let atmosphere = Atmosphere::with_progress(atmosphere_params(scene, terrain), progress)?;
    Ok((level, surface, atmosphere))
}

/// `a` and `b`, side by side with the `parallel` feature (each result is
/// its closure's alone, so the world is the same bit for bit either way).
fn join<A: Send, B: Send>(a: impl FnOnce() -> A + Send, b: impl FnOnce() -> B + Send) -> (A, B) {
    #[cfg(feature = "parallel")]
    {
        rayon::join(a, b)
    }
    #[cfg(not(feature = "parallel"))]
    {
        (a(), b())
    }
}

/// Unit vector toward a sun at `elevation_deg` above the horizon and compass
/// `azimuth_deg` (clockwise from north = +y toward east = +x).
#[must_use]
pub fn sun_direction(elevation_deg: f64, azimuth_deg: f64) -> Vec3 {
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    DVec3::new(ce * sa, ce * ca, se).as_vec3().normalize()
}

/// Noise synthesis of the terrain, normalised to `[0, relief_m]`.
fn synthesize(scene: &SceneDesc, seed: Seed, progress: &dyn Progress) -> Result<HeightField> {
    let t = &scene.terrain;
    let f = TerrainFunction::new(scene, seed.derive("terrain"))?;
    let map = FieldMapping {
        origin: DVec2::ZERO,
        frequency: 1.0 / t.feature_size_m,
        height_m: 1.0,
        offset_m: 0.0,
    };
    progress.start("synthesis", 1);
    let mut hf = fill_field(t.size, t.size, t.cell_size_m, &map, &|x, y| {
        f.eval(DVec2::new(x, y))
    })?;
    let (lo, hi) = hf.min_max();
    let span = (hi - lo).max(f32::MIN_POSITIVE);
    let relief = t.relief_m as f32;
    for v in hf.heights_mut().as_mut_slice() {
        *v = relief * (*v - lo) / span;
    }
    progress.advance(1);
    progress.finish();
    hf.check_finite()?;
    Ok(hf)
}

/// Cliffs and benches where layered rock shows (natura-terrain's
/// [`terrace`](natura_terrain::synth::terrace)): the beds are the strata of
/// the scene's `[textures]`, `beds_per_cycle` to a cycle of their colour
/// map, bent by the strata's own fBm, so the cliffs follow the colour bands.
/// The bending is read from the strata's colour-map index modulo one cycle:
/// the terraces repeat every bed, and a bed divides the cycle.
fn terrace(scene: &SceneDesc, seed: Seed, hf: &mut HeightField) -> Result<()> {
    let t = &scene.terraces;
    if !t.enabled {
        return Ok(());
    }
    let s = &scene.textures.strata;
    let (cycle_m, bed_m) = t.cycle_and_bed_m(s.zscale, s.txtscale);
    let params = TerraceParams {
        bed_m,
        cliff_fraction: t.cliff_fraction,
        flatness: t.flatness,
        min_slope_deg: t.min_slope_deg,
        min_altitude_m: t.min_altitude_m,
    };
    let strata = crate::surface_textures::strata_of(&scene.textures, seed.derive("textures"))?;
    let cell = f64::from(hf.cell_size());
    let h = hf.heights();
    let fill = |i: usize, j: usize| {
        let z = h[(i, j)];
        let p = DVec3::new(i as f64 * cell, j as f64 * cell, f64::from(z));
        let index = strata.index(p, natura_texture::Footprint::POINT) as f32;
        // z + warp ≡ index · cycle (mod cycle).
        (index * cycle_m - z).rem_euclid(cycle_m)
    };
    #[cfg(feature = "parallel")]
    let warp = Grid2::par_from_fn(hf.nx(), hf.ny(), fill)?;
    #[cfg(not(feature = "parallel"))]
    let warp = Grid2::from_fn(hf.nx(), hf.ny(), fill)?;
    natura_terrain::synth::terrace(hf, &params, Some(&warp))?;
    hf.check_finite()?;
    Ok(())
}

/// Sinks the border of the field below the water
/// ([`sink_coast`](natura_terrain::water::sink_coast)) with the scene's
/// `terrain.coast_fraction` and `terrain.coast_depth_m`, the coastline's
/// wander from sub-seed `"coast"` of the scene's seed.
fn sink_coast(scene: &SceneDesc, seed: Seed, hf: &mut HeightField) -> Result<()> {
    let t = &scene.terrain;
    let params = CoastParams {
        fraction: t.coast_fraction as f32,
        depth_m: t.coast_depth_m as f32,
        ..CoastParams::default()
    };
    natura_terrain::water::sink_coast(hf, &params, seed)?;
    hf.check_finite()?;
    Ok(())
}

/// Stream power, then the pipe model, then thermal weathering. Returns the
/// deposition map (metres, ≥ 0).
fn erode(scene: &SceneDesc, hf: &mut HeightField, progress: &dyn Progress) -> Result<Grid2<f32>> {
    let e = &scene.erosion;
    let (nx, ny) = (hf.nx(), hf.ny());
    let mut deposition = Grid2::new(nx, ny, 0.0f32)?;

    if e.stream_power_steps > 0 {
        let mut sp = StreamPower::new(e.stream_power.clone(), hf)?;
        sp.run(hf, e.stream_power_steps, progress)?;
        let dep = sp.deposition()?;
        for (d, s) in deposition.as_mut_slice().iter_mut().zip(dep.as_slice()) {
            *d += s.max(0.0);
        }
    }
    let droplets = (e.droplets_per_sample * (hf.nx() * hf.ny()) as f64).round() as u64;
    if e.hydraulic_model == HydraulicModel::Droplets && droplets > 0 {
        let mut drops =
            DropletErosion::new(e.droplets.clone(), hf, Seed(scene.seed).derive("droplets"))?;
        drops.run(hf, droplets, progress)?;
        let dep = drops.deposition()?;
        for (d, s) in deposition.as_mut_slice().iter_mut().zip(dep.as_slice()) {
            *d += s.max(0.0);
        }
    }
    if e.hydraulic_model == HydraulicModel::Pipe && e.hydraulic_steps > 0 {
        let mut pipe = PipeModel::new(e.pipe.clone(), hf)?;
        pipe.run(hf, e.hydraulic_steps, progress)?;
        let dep = pipe.deposition()?;
        for (d, s) in deposition.as_mut_slice().iter_mut().zip(dep.as_slice()) {
            *d += s.max(0.0);
        }
    }
    if e.thermal_steps > 0 {
        let mut th = Thermal::new(e.thermal.clone(), hf)?;
        th.run(hf, e.thermal_steps, progress)?;
    }
    hf.check_finite()?;
    Ok(deposition)
}

/// Lakes shallower than this (metres) are left dry: puddles in the
/// triangulated surface, not lakes (natura-terrain's
/// [`LakeParams::min_depth_m`]).
pub const MIN_LAKE_DEPTH_M: f32 = 1.0;

/// Lakes of fewer samples than this are left dry (pits, not lakes;
/// natura-terrain's [`LakeParams::min_cells`]).
pub const MIN_LAKE_SAMPLES: usize = 48;

/// The terrain with its water on top (natura-terrain's
/// [`water_surface`](natura_terrain::water::water_surface) with
/// [`MIN_LAKE_DEPTH_M`] and [`MIN_LAKE_SAMPLES`]). Without water, the
/// terrain itself.
fn water_surface(terrain: &HeightField, sea: Option<f32>) -> Result<HeightField> {
    let Some(sea) = sea else {
        return Ok(terrain.clone());
    };
    let lakes = LakeParams {
        min_depth_m: MIN_LAKE_DEPTH_M,
        min_cells: MIN_LAKE_SAMPLES,
    };
    Ok(natura_terrain::water::water_surface(terrain, sea, &lakes)?)
}

/// The water level: the scene's `water.level_m`, or the `water.level_quantile`
/// of the heights inside the coastal border (natura-terrain's
/// [`water_level`](natura_terrain::water::water_level)), never below the
/// datum.
fn water_level(scene: &SceneDesc, hf: &HeightField) -> Result<f32> {
    if let Some(l) = scene.water.level_m {
        return Ok(l as f32);
    }
    let level = natura_terrain::water::water_level(
        hf,
        scene.terrain.coast_fraction,
        scene.water.level_quantile,
    )?;
    Ok(level.max(0.0))
}

/// Atmosphere parameters for the scene: Earth's, with the haze and options of
/// the scene and an aerial-perspective volume deep enough for the terrain.
fn atmosphere_params(scene: &SceneDesc, hf: &HeightField) -> AtmosphereParams {
    let a = &scene.atmosphere;
    let mut p = AtmosphereParams::default();
    p.mie.scattering *= a.haze;
    p.mie.absorption *= a.haze;
    p.mie.g = a.mie_g;
    p.ozone.enabled = a.ozone;
    p.multiple_scattering = a.multiple_scattering;
    p.sun_angular_radius = 0.5 * scene.sun.angular_diameter_deg.to_radians();
    let e = hf.extent();
    let diagonal = f64::from(e.x.hypot(e.y));
    p.lut.aerial_max_distance_m = p.lut.aerial_max_distance_m.max(1.05 * diagonal);
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sun_direction_compass() {
        let north = sun_direction(0.0, 0.0);
        assert!((north - Vec3::Y).length() < 1e-6);
        let east = sun_direction(0.0, 90.0);
        assert!((east - Vec3::X).length() < 1e-6);
        let up = sun_direction(90.0, 123.0);
        assert!((up - Vec3::Z).length() < 1e-6);
    }
}
