//! The memory a scene asks for, estimated from its keys before anything is
//! allocated, against a stated budget: a scene whose values each lie in
//! their ranges may still ask, all together, for more memory than a machine
//! has (a forest of a billion seedlings, a terrain of 16 384² samples at
//! full resolution), and is then refused by the keys that make it large.

use super::SceneDesc;
use crate::error::{RenderError, Result, fmt_f64};

/// Most memory a scene may ask for, bytes (4 GiB): the sum of the estimates
/// of its terrain, image, clouds and forest (with its far canopy layer).
pub const MEMORY_BUDGET_BYTES: u64 = 4 << 30;

/// Largest scene file read, bytes (16 MiB): far more than any scene needs
/// (the built-in one is 13 kB); a larger file is refused before it is read.
pub const MAX_SCENE_FILE_BYTES: u64 = 16 << 20;

/// Bytes per terrain sample over the pipeline: the height field, the
/// erosion models' state, the deposition and wetness maps, the water
/// surface and its analysis, and the tracer's max-mipmaps.
const TERRAIN_BYTES_PER_SAMPLE: f64 = 64.0;

/// Bytes per image pixel: the linear image, the tone-mapped one and the
/// encoders' buffers.
const IMAGE_BYTES_PER_PIXEL: f64 = 32.0;

/// Bytes per terrain sample of the far forest's canopy layer while it is
/// built: the ecosystem's five site maps over the whole terrain (altitude,
/// slope, wetness, light, heights), the suitability, the stand's crown area
/// and the layer's far and near indices, each an `f32`.
const CANOPY_BYTES_PER_SAMPLE: f64 = 9.0 * 4.0;
/// Most plants the forest's ecosystem may hold at once (its `max_plants`).
pub(crate) const MAX_PLANTS: usize = 20_000_000;

/// Bytes per plant of the forest: the ecosystem's plant, its instance and
/// placement, and its share of the instance BVH.
const BYTES_PER_PLANT: f64 = std::mem::size_of::<natura_plant::eco::Plant>() as f64 + 96.0;

/// One part of a scene's memory: the keys that size it and its bytes.
struct Part {
    keys: &'static str,
    values: String,
    bytes: f64,
}

impl SceneDesc {
    /// The estimated memory of each large allocation the scene makes
    /// (bytes), by the keys that size it.
    fn memory_parts(&self) -> Result<Vec<Part>> {
        let mut parts = Vec::new();
        let t = &self.terrain;
        let n = t.size as f64;
        parts.push(Part {
            keys: "terrain.size",
            values: t.size.to_string(),
            bytes: n * n * TERRAIN_BYTES_PER_SAMPLE,
        });
        let r = &self.render;
        parts.push(Part {
            keys: "render.width, render.height",
            values: format!("{}, {}", r.width, r.height),
            bytes: f64::from(r.width) * f64::from(r.height) * IMAGE_BYTES_PER_PIXEL,
        });
        if self.clouds.visible() {
            self.cloud_parts(&mut parts);
        }
        if self.vegetation.enabled {
            parts.push(self.forest_part()?);
            if self.vegetation.far_field {
                parts.push(Part {
                    keys: "vegetation.far_field, terrain.size",
                    values: format!("true, {}", t.size),
                    bytes: n * n * CANOPY_BYTES_PER_SAMPLE,
                });
            }
        }
        Ok(parts)
    }

    /// The clouds' voxels, their two shadow tables and the map of their
    /// shadows on the ground.
    fn cloud_parts(&self, parts: &mut Vec<Part>) {
        let c = &self.clouds;
        let l = &c.layer;
        let size = [
            f64::from(l.region_max[0] - l.region_min[0]),
            f64::from(l.region_max[1] - l.region_min[1]),
            f64::from(l.top_m - l.base_m),
        ];
        let voxel = f64::from(c.voxel_m);
        parts.push(Part {
            keys: "clouds.voxel_m",
            values: fmt_f64(voxel),
            bytes: size
                .iter()
                .map(|s| (s / voxel).ceil().max(1.0))
                .product::<f64>()
                * 4.0,
        });
        // natura-volume's table: `nodes` along the longest side, the others
        // in proportion.
        let nodes = c.shadow_table_nodes as f64;
        let h = size.iter().copied().fold(0.0, f64::max) / (nodes - 1.0).max(1.0);
        let table: f64 = size
            .iter()
            .map(|s| ((s / h).ceil() + 1.0).clamp(2.0, nodes.max(2.0)))
            .product();
        parts.push(Part {
            keys: "clouds.shadow_table_nodes",
            values: c.shadow_table_nodes.to_string(),
            bytes: 2.0 * table * 4.0,
        });
        // The shadow map covers the terrain and its shadow's reach: the
        // sun's horizontal slope (at its lowest, over the sequence) times the
        // height from the sea floor to the cloud base.
        let lowest = self
            .animation
            .keys
            .iter()
            .filter_map(|k| k.sun_elevation_deg)
            .fold(self.sun.elevation_deg, f64::min);
        let (s, co) = lowest.to_radians().sin_cos();
        let slope = co.abs() / s.max(0.02);
        let reach = slope * (f64::from(l.base_m) + self.terrain.coast_depth_m);
        let extent = self.terrain.size as f64 * f64::from(self.terrain.cell_size_m);
        let side = (extent + reach) / f64::from(c.shadow_cell_m) + 2.0;
        parts.push(Part {
            keys: "clouds.shadow_cell_m",
            values: fmt_f64(f64::from(c.shadow_cell_m)),
            bytes: side * side * 4.0,
        });
    }

    /// The forest: the seedlings its ecosystem sows over the square around
    /// the eye, `4 × density_per_ha` per hectare and species at the start and
    /// `density_per_ha` at each step, and the population they grow into.
    fn forest_part(&self) -> Result<Part> {
        let v = &self.vegetation;
        let extent = self.terrain.size as f64 * f64::from(self.terrain.cell_size_m);
        let side = (2.0 * v.radius_m + 2.0 * f64::from(self.terrain.cell_size_m)).min(extent);
        let hectares = side * side / 1e4;
        let per_step = v.density_per_ha * hectares * v.species.len() as f64;
        let initial = 4.0 * per_step;
        let keys = "vegetation.density_per_ha, vegetation.radius_m";
        let values = format!("{}, {}", fmt_f64(v.density_per_ha), fmt_f64(v.radius_m));
        if initial + per_step > MAX_PLANTS as f64 {
            return Err(RenderError::Invalid {
                name: keys.to_owned(),
                value: values,
                reason: format!(
                    "the forest would sow {} seedlings over {} ha of {} species at the start, \
                     more than the {} plants the memory budget allows its ecosystem; \
                     lower the density or the radius",
                    fmt_f64(initial.round()),
                    fmt_f64(hectares.round()),
                    v.species.len(),
                    MAX_PLANTS
                ),
            });
        }
        let population = (initial + f64::from(v.steps) * per_step).min(MAX_PLANTS as f64);
        Ok(Part {
            keys,
            values,
            bytes: (population + per_step) * BYTES_PER_PLANT,
        })
    }

    /// Refuses a scene whose estimated memory passes
    /// [`MEMORY_BUDGET_BYTES`], naming the keys of its largest part.
    pub(super) fn check_memory_budget(&self) -> Result<()> {
        let parts = self.memory_parts()?;
        let total: f64 = parts.iter().map(|p| p.bytes).sum();
        if total <= MEMORY_BUDGET_BYTES as f64 {
            return Ok(());
        }
        let Some(largest) = parts.iter().max_by(|a, b| a.bytes.total_cmp(&b.bytes)) else {
            return Ok(());
        };
        let gib = |b: f64| b / f64::from(1u32 << 30);
        Err(RenderError::Invalid {
            name: largest.keys.to_owned(),
            value: largest.values.clone(),
            reason: format!(
                "the scene would need about {:.1} GiB ({:.1} GiB of it for these keys), \
                 more than the memory budget of {} GiB",
                gib(total),
                gib(largest.bytes),
                MEMORY_BUDGET_BYTES >> 30
            ),
        })
    }
}
