//! The forest: an ecosystem grown over the eroded terrain near the camera,
//! drawn as instanced plant meshes traced through a two-level BVH.
//!
//! 1. natura-plant's ecosystem (Deussen et al. 1998, §4) runs on the terrain
//!    within `radius_m` of the eye: species establish by altitude, slope,
//!    wetness and light (natura-plant's [`catalogue`]), grow, and thin
//!    themselves out. The
//!    wetness is the world's own map (cut to the same window), the one the
//!    materials read.
//! 2. Its approximate instancing (§5) quantizes each species' plant sizes
//!    into a few prototypes grown from the species' L-system; each is meshed
//!    ([`proto`]) in full and as a low-polygon crown.
//! 3. Every plant on dry land becomes an instance (position, yaw, scale to
//!    its height); trees farther than `lod_distance_m` from the eye use the
//!    crown, so distant forest costs a few dozen triangles a tree.
//! 4. Rays meet the trees through obvhs' wide BVHs ([`bvh`]): one over the
//!    instances, one per mesh; shading ([`shade`]) adds leaf translucency,
//!    on normals interpolated over each crown, and each plant's leaves take
//!    their own colour at the scene's season. Where a pixel covers many
//!    leaves, the sun reaching a leaf or the floor is the mean over them:
//!    the crowns as turbid media ([`turbid`]), instead of one shadow ray's
//!    fleck.
//! 5. Beyond the instanced trees the forest goes on to the horizon as a
//!    canopy layer over the terrain ([`canopy`]), its density learned from
//!    the stand and spread by the same species' establishment rules over
//!    the whole terrain, fading in as the trees thin out.

pub mod bvh;
pub mod canopy;
pub mod proto;
pub mod shade;
pub mod tri;
pub mod turbid;

use std::time::{Duration, Instant};

use glam::Vec3;
use natura_core::{Grid2, HeightField, Progress, Seed};
use natura_plant::eco::{EcoParams, Ecosystem, Instancing, Plant};

use crate::error::{RenderError, Result};
use crate::world::World;
use bvh::{Instanced, Mesh, Placement};
use canopy::{Canopy, CanopyInput, Ground, StandTree};
use natura_plant::eco::catalogue::{self, Look};
pub use shade::Light;
use turbid::CrownMedium;

/// The share of the forest drawn as instanced trees at horizontal distance
/// `dist` from the eye in a forest of radius `radius` (metres): 1 within
/// three quarters of the radius, falling linearly to 0 at the radius. The
/// trees thin out with it, and the canopy layer ([`canopy`]) takes the
/// rest.
#[must_use]
pub fn near_share(dist: f32, radius: f32) -> f32 {
    (4.0 * (1.0 - dist / radius)).clamp(0.0, 1.0)
}

/// The footprint, in leaf cards, under which the sun on a tree is one
/// shadow ray's ([`Forest::sun_visibility`]): a spray's flecks are about a
/// twentieth of its card (an own value).
const FLECK_OF_CARD: f32 = 0.05;

/// The footprint, in leaf cards, from which the sun on a tree is the mean
/// over the crowns as turbid media (an own value: from a quarter of a card
/// a pixel covers many flecks).
const MEAN_OF_CARD: f32 = 0.25;

/// Brightness of a low-polygon crown relative to a lit leaf: the mean
/// self-shadowing of a full crown seen from afar (own value, matched by eye
/// across the LOD distance in the default view).
pub const CROWN_HULL_SHADE: f32 = 0.6;

/// The closest tree surface along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeHit {
    /// Distance along the (unit) ray, metres.
    pub t: f32,
    /// The point hit, metres.
    pub point: Vec3,
    /// Unit geometric normal of the triangle hit (either side).
    pub normal: Vec3,
    /// Unit shading normal there: the mesh's corner normals interpolated
    /// (smooth across a crown).
    pub shading: Vec3,
    /// Whether the surface is leaf (else bark).
    pub leaf: bool,
    /// Index of the instance hit.
    pub instance: u32,
}

/// Figures of a built forest.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ForestStats {
    /// Plants alive at the end of the ecosystem simulation.
    pub plants: usize,
    /// Trees drawn (plants on dry land within the radius).
    pub instances: usize,
    /// Of them, drawn with the full mesh (nearer than the LOD distance).
    pub near: usize,
    /// Prototype meshes (full and crown, all species).
    pub meshes: usize,
    /// Triangles over all prototype meshes.
    pub triangles: usize,
    /// Time of the ecosystem simulation.
    pub ecosystem: Duration,
    /// Time of the prototypes' derivation, meshing and bottom-level BVHs.
    pub prototypes: Duration,
    /// Time of the top-level BVH over the instances.
    pub tlas: Duration,
    /// Time of the canopy layer beyond the trees (zero without it).
    pub canopy: Duration,
}

/// Instanced trees ready to trace and shade.
#[derive(Debug)]
pub struct Forest {
    scene: Instanced,
    /// Look per species index.
    looks: Vec<Look>,
    /// Species index per placement.
    species_of: Vec<u16>,
    /// Leaf albedo and transmitted colour per placement: the species' at the
    /// plant's own season, with the plant's own tint.
    leaf_of: Vec<(Vec3, Vec3)>,
    /// The forest beyond the trees, if the scene has it.
    canopy: Option<Canopy>,
    /// Each mesh's crown as a turbid medium (a crown mesh shares its full
    /// mesh's), for the sun's light where a pixel covers many leaves.
    media: Vec<Option<CrownMedium>>,
    /// The mean size of a leaf over the trees, metres.
    leaf_m: f32,
    transmission: f32,
    brute: bool,
    stats: ForestStats,
}

/// The part of `world`'s terrain within `radius` of `(x, y)`, clipped to the
/// field, with the same window of its wetness map: the cropped field, its
/// wetness and its origin in metres, or `None` if fewer than 3×3 samples
/// remain.
fn crop(
    terrain: &HeightField,
    wetness: &Grid2<f32>,
    x: f32,
    y: f32,
    radius: f32,
) -> Result<Option<(HeightField, Grid2<f32>, Vec3)>> {
    let c = terrain.cell_size();
    let (nx, ny) = (terrain.nx() as i64, terrain.ny() as i64);
    let lo = |v: f32| (((v - radius) / c).floor() as i64).clamp(0, nx.max(ny) - 1);
    let hi = |v: f32, n: i64| (((v + radius) / c).ceil() as i64).clamp(0, n - 1);
    let (i0, i1) = (lo(x).min(nx - 1), hi(x, nx));
    let (j0, j1) = (lo(y).min(ny - 1), hi(y, ny));
    if i1 - i0 < 2 || j1 - j0 < 2 {
        return Ok(None);
    }
    let h = terrain.heights();
    let (i0, j0) = (i0 as usize, j0 as usize);
    let (w, d) = ((i1 - i0 as i64 + 1) as usize, (j1 - j0 as i64 + 1) as usize);
    let hf = HeightField::from_fn(w, d, c, |i, j| h[(i0 + i, j0 + j)])?;
    let wet = Grid2::from_fn(w, d, |i, j| wetness[(i0 + i, j0 + j)])?;
    Ok(Some((
        hf,
        wet,
        Vec3::new(i0 as f32 * c, j0 as f32 * c, 0.0),
    )))
}

/// `placements` with each tree's foot moved to `ground(base)` (metres;
/// `None` leaves it) less 2 % of its height.
fn grounded(
    meshes: &[Mesh],
    placements: &[Placement],
    ground: &dyn Fn(Vec3) -> Option<f32>,
) -> Vec<Placement> {
    placements
        .iter()
        .map(|p| {
            let h = p.scale * meshes[p.mesh as usize].bounds.1.z;
            let mut q = *p;
            if let Some(z) = ground(p.position) {
                q.position.z = z - 0.02 * h;
            }
            q
        })
        .collect()
}

/// What the ecosystem of a world grows from: the terrain around the eye
/// (and its origin in the world), the species, their looks and the
/// simulation's parameters.
struct Stand {
    hf: HeightField,
    /// The world's wetness over `hf`.
    wetness: Grid2<f32>,
    origin: Vec3,
    looks: Vec<Look>,
    params: EcoParams,
    max_radius: Vec<f32>,
    water: f32,
}

impl Stand {
    fn of(world: &World) -> Result<Option<Self>> {
        let scene = &world.scene;
        let v = &scene.vegetation;
        if !v.enabled {
            return Ok(None);
        }
        let eye = world.eye();
        let Some((hf, wetness, origin)) = crop(
            &world.terrain,
            &world.wetness,
            eye.x,
            eye.y,
            v.radius_m as f32,
        )?
        else {
            return Ok(None);
        };
        let (lo, hi) = hf.min_max();
        let water = world.water_level.unwrap_or(lo);
        let mut species = Vec::new();
        let mut looks = Vec::new();
        for (i, name) in v.species.iter().enumerate() {
            let (s, l) = catalogue::species(
                name,
                v.density_per_ha,
                (lo, hi),
                water,
                v.tree_line_m as f32,
            )
            .ok_or_else(|| {
                RenderError::invalid(
                    &format!("vegetation.species[{i}]"),
                    format!("{name:?}"),
                    "unknown species",
                )
            })?;
            species.push(s);
            looks.push(l);
        }
        let params = EcoParams {
            species,
            steps: v.steps,
            seed: Seed(scene.seed.wrapping_add(v.seed_offset)).derive("vegetation"),
            sun: world.sun,
            max_plants: crate::scene::MAX_PLANTS,
        };
        let max_radius = params.species.iter().map(|s| s.max_radius as f32).collect();
        Ok(Some(Self {
            hf,
            wetness,
            origin,
            looks,
            params,
            max_radius,
            water,
        }))
    }
}

impl Forest {
    /// Grows and instances the forest of `world`'s `[vegetation]` section;
    /// `None` when it is disabled or no tree grows.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`] for an unknown species (the scene is
    /// validated before any work, so only for a hand-made world), and
    /// [`RenderError::Plant`] for errors of the ecosystem or the meshes.
    pub fn build(world: &World, progress: &dyn Progress) -> Result<Option<Self>> {
        Self::build_from(world, None, None, progress)
    }

    /// The population the ecosystem of `world`'s `[vegetation]` section
    /// grows ([`Ecosystem::plants`] after its last step), `None` when it is
    /// disabled: what [`Self::build_with_plants`] takes, so that renderers
    /// of the same frame in separate processes grow it once.
    ///
    /// # Errors
    ///
    /// As [`Self::build`].
    pub fn grow(world: &World, progress: &dyn Progress) -> Result<Option<Vec<Plant>>> {
        let Some(stand) = Stand::of(world)? else {
            return Ok(None);
        };
        let mut eco = Ecosystem::with_wetness(&stand.hf, stand.wetness, stand.params)?;
        eco.run(progress)?;
        Ok(Some(eco.plants().to_vec()))
    }

    /// As [`Self::build`], with the population [`Self::grow`] gave for this
    /// world instead of simulating it: the same forest, bit for bit.
    ///
    /// # Errors
    ///
    /// As [`Self::build`]; [`RenderError::Plant`] if `plants` cannot be the
    /// population of this world's ecosystem
    /// ([`Ecosystem::resume_with_wetness`]'s errors).
    pub fn build_with_plants(
        world: &World,
        plants: Vec<Plant>,
        progress: &dyn Progress,
    ) -> Result<Option<Self>> {
        Self::build_from(world, Some(plants), None, progress)
    }

    /// Grows (or, given `plants`, resumes) and instances the forest, each
    /// tree stood on `ground` as [`Self::set_ground`] does, with one build
    /// of the instance BVH.
    pub(crate) fn build_from(
        world: &World,
        plants: Option<Vec<Plant>>,
        ground: Option<&dyn Fn(Vec3) -> Option<f32>>,
        progress: &dyn Progress,
    ) -> Result<Option<Self>> {
        let scene = &world.scene;
        let v = &scene.vegetation;
        let Some(Stand {
            hf,
            wetness,
            origin,
            looks,
            params,
            max_radius,
            water,
        }) = Stand::of(world)?
        else {
            return Ok(None);
        };
        let eye = world.eye();
        let radius = v.radius_m as f32;
        let mut stats = ForestStats::default();

        let t0 = Instant::now();
        let eco = grow(&hf, wetness, params, plants, v.steps, progress)?;
        stats.plants = eco.plants().len();
        stats.ecosystem = t0.elapsed();

        let t1 = Instant::now();
        let inst = Instancing::new(&eco, v.prototypes_per_species)?;
        drop(eco);
        // Mesh 2k is prototype k in full, 2k + 1 its crown.
        let meshes = prototype_meshes(&inst)?;
        stats.meshes = meshes.len();
        stats.triangles = meshes.iter().map(Mesh::len).sum();
        stats.prototypes = t1.elapsed();

        let t2 = Instant::now();
        let mut placements = Vec::new();
        let mut species_of = Vec::new();
        let mut leaf_of = Vec::new();
        let mut trees = Vec::new();
        let tint = Seed(scene.seed.wrapping_add(v.seed_offset)).derive("vegetation.leaf");
        let (s, g) = (world.surface.heights(), world.terrain.heights());
        let cell = world.terrain.cell_size();
        let edge = Seed(scene.seed.wrapping_add(v.seed_offset)).derive("vegetation.edge");
        for pi in &inst.instances {
            let k = pi.prototype as usize;
            let full = &meshes[2 * k];
            let height = full.bounds.1.z;
            if full.is_empty() || height <= 0.0 {
                continue;
            }
            let p = pi.position + origin;
            let dist = (p.truncate() - eye.truncate()).length();
            let (gi, gj) = nearest_cell(p, cell, g);
            // The forest thins out over the outer quarter of the radius
            // instead of ending in a line.
            let keep = near_share(dist, radius);
            if keep < 1.0
                && edge.uniform(&[i64::from(p.x.to_bits()), i64::from(p.y.to_bits())]) as f32
                    >= keep
            {
                continue;
            }
            if s[(gi, gj)] > g[(gi, gj)] || p.z <= water {
                continue;
            }
            let si = pi.species as usize;
            let r = pi.scale * inst.prototypes[k].geometry_radius;
            let h =
                v.tree_height_m as f32 * looks[si].height_factor * (r / max_radius[si]).min(1.0);
            let scale = h / height;
            if looks[si].layer.is_canopy() {
                let (lo, hi) = full.bounds;
                trees.push(StandTree {
                    position: p,
                    crown_radius: 0.25 * scale * ((hi.x - lo.x) + (hi.y - lo.y)),
                    height: h,
                });
            }
            leaf_of.push(plant_leaf(&looks[si], v, tint, p));
            let near = f64::from(dist) <= v.lod_distance_m;
            stats.near += usize::from(near);
            placements.push(Placement {
                mesh: (2 * k + usize::from(!near)) as u32,
                // The trunk's foot a little into the ground.
                position: p - Vec3::Z * (0.02 * h),
                scale,
                cos_sin: (pi.rotation.cos(), pi.rotation.sin()),
            });
            species_of.push(pi.species);
        }
        if placements.is_empty() {
            return Ok(None);
        }
        stats.instances = placements.len();
        if let Some(ground) = ground {
            placements = grounded(&meshes, &placements, ground);
        }
        let elevation = world.sun.z.clamp(-1.0, 1.0).asin();
        let media: Vec<Option<CrownMedium>> = meshes
            .chunks_exact(2)
            .flat_map(|pair| {
                let m = CrownMedium::of(&pair[0], elevation);
                [m.clone(), m]
            })
            .collect();
        let leaf_m = placements
            .iter()
            .filter_map(|p| Some(media[p.mesh as usize].as_ref()?.leaf_size() * p.scale))
            .sum::<f32>()
            / placements.len() as f32;
        let scene_bvh = Instanced::new(meshes, placements);
        stats.tlas = t2.elapsed();
        let t3 = Instant::now();
        let canopy = if v.far_field {
            Some(Canopy::new(&canopy_input(world, trees, &scene_bvh))?)
        } else {
            None
        };
        stats.canopy = t3.elapsed();
        Ok(Some(Self {
            scene: scene_bvh,
            looks,
            species_of,
            leaf_of,
            canopy,
            media,
            leaf_m,
            transmission: v.leaf_transmission as f32,
            brute: false,
            stats,
        }))
    }

    /// Figures of the forest.
    #[must_use]
    pub fn stats(&self) -> &ForestStats {
        &self.stats
    }

    /// The meshes and placements (for tests and exports).
    #[must_use]
    pub fn instanced(&self) -> &Instanced {
        &self.scene
    }

    /// Stands every tree on the ground `ground(base)` gives (metres, `None`
    /// to leave a tree where it is), its foot 2 % of its height below it,
    /// and rebuilds the instance BVH: the renderer's traced surface carries
    /// procedural detail the ecosystem's terrain does not.
    pub fn set_ground(&mut self, ground: impl Fn(Vec3) -> Option<f32>) {
        let moved = grounded(&self.scene.meshes, &self.scene.placements, &ground);
        let t = Instant::now();
        self.scene = Instanced::new(std::mem::take(&mut self.scene.meshes), moved);
        self.stats.tlas += t.elapsed();
    }

    /// The canopy layer that carries the forest beyond the trees, if the
    /// scene has it (`vegetation.far_field`).
    #[must_use]
    pub fn canopy(&self) -> Option<&Canopy> {
        self.canopy.as_ref()
    }

    /// Radiance toward `-g.dir` of the ground `g` with the forest on it:
    /// the canopy layer's crowns and the floor under them
    /// ([`Canopy::ground_radiance`]); `g.radiance` without the layer.
    #[must_use]
    pub fn ground_radiance(&self, g: &Ground, light: &Light) -> Vec3 {
        self.canopy
            .as_ref()
            .map_or(g.radiance, |c| c.ground_radiance(g, light))
    }

    /// Traces by testing every triangle of every tree instead of the BVH
    /// (identical results, for checking; slow).
    pub fn set_brute_force(&mut self, brute: bool) {
        self.brute = brute;
    }

    /// The closest tree along the unit-direction ray `o + t·d`, `t < t_max`.
    #[must_use]
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<TreeHit> {
        let h = if self.brute {
            self.scene.closest_brute(o, d, 0.0, t_max)
        } else {
            self.scene.closest(o, d, 0.0, t_max)
        }?;
        let p = &self.scene.placements[h.instance as usize];
        let m = &self.scene.meshes[p.mesh as usize];
        let k = h.triangle as usize;
        let point = o + d * h.t;
        let w = tri::barycentric(p.local(point, true), &m.tris[k]);
        let [a, b, c] = m.shading[k];
        let shading = (a * w[0] + b * w[1] + c * w[2])
            .try_normalize()
            .unwrap_or(m.normals[k]);
        Some(TreeHit {
            t: h.t,
            point,
            normal: p.normal_to_world(m.normals[k]),
            shading: p.normal_to_world(shading),
            leaf: m.leaf[h.triangle as usize],
            instance: h.instance,
        })
    }

    /// Whether a tree lies along `o + t·d` for `t` in `(t_min, t_max)`.
    #[must_use]
    pub fn occluded(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> bool {
        if self.brute {
            self.scene.occluded_brute(o, d, t_min, t_max)
        } else {
            self.scene.occluded(o, d, t_min, t_max)
        }
    }

    /// The share of the sun's light along the unit direction `sun` that
    /// reaches `p` past the trees (beyond `t_min` metres), as a pixel whose
    /// footprint there is `footprint` metres wide sees it; `own` is the tree
    /// `p` lies on, if any.
    ///
    /// A prototype's leaf triangles are cards that stand for sprays of
    /// needles or leaves, through whose gaps the sun falls in flecks a
    /// fraction of the card across. Where the footprint is under a
    /// twentieth of a card (that tree's, or the forest's mean), a shadow
    /// ray through the trees' triangles: 1 or 0. Where it is a quarter of a
    /// card or more, the mean over the flecks: the crowns as turbid media
    /// ([`turbid`]), `exp(−Σ κ·s)`. Between, the two blended. So near leaves
    /// keep their sun-flecks and farther crowns are lit by their depth
    /// toward the sun, without one sample's fleck showing as a speck.
    #[must_use]
    pub fn sun_visibility(
        &self,
        p: Vec3,
        sun: Vec3,
        t_min: f32,
        footprint: f32,
        own: Option<u32>,
    ) -> f32 {
        let leaf = own
            .and_then(|i| {
                let pl = &self.scene.placements[i as usize];
                Some(self.media[pl.mesh as usize].as_ref()?.leaf_size() * pl.scale)
            })
            .unwrap_or(self.leaf_m);
        let mean = natura_core::smoothstep(FLECK_OF_CARD * leaf, MEAN_OF_CARD * leaf, footprint);
        let ray = if mean < 1.0 && !self.occluded(p, sun, t_min, f32::INFINITY) {
            1.0 - mean
        } else {
            0.0
        };
        if mean > 0.0 {
            ray + mean * self.scene.transmittance(p, sun, t_min, &self.media)
        } else {
            ray
        }
    }

    /// Radiance toward `-d` from a tree hit, lit by `light` (the sun's
    /// light times `sun_visible`, the share of it reaching the hit:
    /// [`Self::sun_visibility`]).
    #[must_use]
    pub fn shade(&self, hit: &TreeHit, d: Vec3, light: &Light, sun_visible: f32) -> Vec3 {
        let i = hit.instance as usize;
        let (leaf, leaf_transmit) = self.leaf_of[i];
        let look = Look {
            leaf,
            leaf_transmit,
            ..self.looks[self.species_of[i] as usize]
        };
        let l = shade::radiance(
            &look,
            hit.leaf,
            hit.shading,
            d,
            light,
            sun_visible,
            self.transmission,
        );
        // Odd meshes are the low-polygon crowns: an opaque hull stands for a
        // porous crown whose inner leaves are shaded by the outer ones.
        if self.scene.placements[hit.instance as usize].mesh % 2 == 1 {
            l * CROWN_HULL_SHADE
        } else {
            l
        }
    }
}

/// Largest shift of a plant's own season from the scene's (natura's own
/// value: neighbours leaf out and colour a few weeks apart).
const SEASON_SPREAD: f32 = 0.08;

/// The leaf albedo and transmitted colour of the plant of `look` at `p`:
/// the species' colours at the scene's season shifted by the plant's own,
/// times its own brightness and a shift between green and yellow, both
/// within `leaf_variation` (stateless hashes of the position under `tint`).
fn plant_leaf(look: &Look, v: &crate::scene::VegetationDesc, tint: Seed, p: Vec3) -> (Vec3, Vec3) {
    let key =
        |k: i64| tint.uniform(&[i64::from(p.x.to_bits()), i64::from(p.y.to_bits()), k]) as f32;
    let season = v.season as f32 + SEASON_SPREAD * (2.0 * key(0) - 1.0);
    let var = v.leaf_variation as f32;
    let bright = 1.0 + var * (2.0 * key(1) - 1.0);
    let yellow = var * (2.0 * key(2) - 1.0);
    let t = Vec3::new(
        bright * (1.0 + 0.8 * yellow),
        bright * (1.0 + 0.3 * yellow),
        bright * (1.0 - 0.5 * yellow),
    );
    (look.leaf_at(season) * t, look.leaf_transmit_at(season) * t)
}

/// What the canopy layer reads of `world`: the canopy species of its scene
/// over the whole terrain (altitudes normalised over it) and the stand's
/// `trees`.
fn canopy_input<'a>(
    world: &'a World,
    trees: Vec<StandTree>,
    stand: &'a Instanced,
) -> CanopyInput<'a> {
    let v = &world.scene.vegetation;
    let (lo, hi) = world.terrain.min_max();
    let water = world.water_level.unwrap_or(lo);
    let species = v
        .species
        .iter()
        .filter_map(|name| {
            catalogue::species(
                name,
                v.density_per_ha,
                (lo, hi),
                water,
                v.tree_line_m as f32,
            )
        })
        .filter(|(_, look)| look.layer.is_canopy())
        .collect();
    let eye = world.eye();
    CanopyInput {
        terrain: &world.terrain,
        surface: &world.surface,
        wetness: &world.wetness,
        sun: world.sun,
        water,
        species,
        season: v.season as f32,
        eye: eye.truncate(),
        radius: v.radius_m as f32,
        trees,
        stand,
        seed: Seed(world.scene.seed.wrapping_add(v.seed_offset)).derive("vegetation.canopy"),
    }
}

/// The ecosystem of the stand: `plants` resumed where given (a frame's
/// cached population), else grown from the start.
fn grow(
    hf: &HeightField,
    wetness: Grid2<f32>,
    params: EcoParams,
    plants: Option<Vec<Plant>>,
    steps: u32,
    progress: &dyn Progress,
) -> Result<Ecosystem> {
    Ok(match plants {
        Some(p) => Ecosystem::resume_with_wetness(hf, wetness, params, p, steps)?,
        None => {
            let mut eco = Ecosystem::with_wetness(hf, wetness, params)?;
            eco.run(progress)?;
            eco
        }
    })
}

/// The grid cell of `g` (spacing `cell`) nearest to `p`, clamped to the grid.
fn nearest_cell(p: Vec3, cell: f32, g: &Grid2<f32>) -> (usize, usize) {
    (
        ((p.x / cell).round() as usize).min(g.width() - 1),
        ((p.y / cell).round() as usize).min(g.height() - 1),
    )
}

/// The meshes of the instancing's prototypes: mesh 2k is prototype k in
/// full, 2k + 1 its crown hull (the low-polygon stand-in far away).
fn prototype_meshes(inst: &Instancing) -> Result<Vec<Mesh>> {
    let mut meshes = Vec::with_capacity(2 * inst.prototypes.len());
    for p in &inst.prototypes {
        let full = proto::full_mesh(&p.geometry)?;
        let crown = proto::crown_hull(&full, 0.8);
        meshes.push(full);
        meshes.push(crown);
    }
    Ok(meshes)
}

#[cfg(test)]
mod tests {
    use natura_core::NoProgress;

    use super::*;
    use crate::scene::SceneDesc;

    /// The forest's plants and the materials read one wetness map: the
    /// site the ecosystem grows on holds the world's wetness, element for
    /// element, over the ecosystem's window.
    #[test]
    fn the_ecosystem_reads_the_worlds_wetness() {
        let mut scene = SceneDesc::default();
        scene.water.enabled = false;
        scene.vegetation.tree_line_m = 80.0;
        scene.camera.position_uv = [0.5, 0.25];
        scene.vegetation.radius_m = 60.0;
        scene.vegetation.steps = 2;
        let hf = HeightField::from_fn(96, 96, 5.0, |i, j| {
            let (x, y) = (i as f32 * 0.11, j as f32 * 0.13);
            0.15 * j as f32 + 2.0 * x.sin() * y.cos()
        })
        .unwrap();
        let world = World::from_height_field(&scene, hf, &NoProgress).unwrap();
        let stand = Stand::of(&world).unwrap().expect("a stand around the eye");
        let c = world.terrain.cell_size();
        let (i0, j0) = (
            (stand.origin.x / c).round() as usize,
            (stand.origin.y / c).round() as usize,
        );
        let eco = Ecosystem::with_wetness(&stand.hf, stand.wetness, stand.params).unwrap();
        let site = eco.site().wetness.clone();
        // A window of the world, not the whole of it.
        assert!(site.width() >= 3 && site.width() < 96, "{}", site.width());
        for j in 0..site.height() {
            for i in 0..site.width() {
                assert_eq!(
                    site[(i, j)].to_bits(),
                    world.wetness[(i0 + i, j0 + j)].to_bits(),
                    "({i}, {j})"
                );
            }
        }
    }
}
