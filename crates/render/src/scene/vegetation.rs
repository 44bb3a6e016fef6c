//! The scene's `[vegetation]` section: a forest grown by natura-plant's
//! ecosystem over the eroded terrain near the camera, drawn as instanced
//! plant meshes.

use serde::{Deserialize, Serialize};

use crate::error::{RenderError, Result, in_range as range};

/// The tree species the forest can grow, by scene name: natura-plant's
/// [`catalogue::NAMES`](natura_plant::eco::catalogue::NAMES).
pub const SPECIES_NAMES: [&str; 5] = natura_plant::eco::catalogue::NAMES;

/// A forest of instanced trees on the terrain around the camera.
///
/// Deussen et al.'s ecosystem (natura-plant's `eco`) grows the species over
/// the terrain within `radius_m` of the eye (seeding by altitude, slope,
/// wetness and light; growth; self-thinning), and every surviving plant is
/// drawn as an instance of one of a few prototype meshes per species. Trees
/// farther than `lod_distance_m` use a low-polygon crown; beyond `radius_m`
/// (fading in over its outer quarter) a canopy layer over the terrain
/// carries the forest to the horizon (`far_field`), as dense as the stand
/// wherever the same species would establish.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VegetationDesc {
    /// Whether to grow and draw the forest at all.
    pub enabled: bool,
    /// Species to grow, by name: the conifers `"spruce"` (cool upper
    /// slopes) and `"pine"` (dry, sunny ground), the broad-leaved `"beech"`
    /// (moist, low ground), the shrub `"juniper"` (dry, open ground up past
    /// the tree line) and the ground cover `"heather"` (open heath).
    pub species: Vec<String>,
    /// Seedlings per hectare per simulation step for each tree species where
    /// it may grow (0.1 to 500; the shrub and the ground cover seed more
    /// densely); the forest's density follows from seeding and
    /// self-thinning.
    pub density_per_ha: f64,
    /// Height of a mature tree, metres (1 to 120); younger trees are smaller.
    pub tree_height_m: f64,
    /// Altitude above which no tree establishes, metres; each species keeps
    /// to its own band between the water and this line.
    pub tree_line_m: f64,
    /// Trees grow within this horizontal distance of the camera, metres
    /// (10 to 20 000).
    pub radius_m: f64,
    /// Ecosystem simulation steps (1 to 200).
    pub steps: u32,
    /// Prototype meshes per species, by quantized size (1 to 16).
    pub prototypes_per_species: usize,
    /// Trees farther from the camera than this use the low-polygon crown,
    /// metres (0 = always; ≥ 0).
    pub lod_distance_m: f64,
    /// Fraction of the sunlight a leaf transmits to its shaded side (0 to 0.9).
    pub leaf_transmission: f64,
    /// Time of year of the leaves' colour (0 to 1): 0 the spring flush, 0.5
    /// high summer, 1 the height of autumn colour (the beech turns, the
    /// heather flowers, the conifers barely change).
    pub season: f64,
    /// Spread of each plant's leaf colour about its species' (0 to 0.5): its
    /// brightness and its shift toward yellow vary by up to this fraction.
    pub leaf_variation: f64,
    /// Whether the forest goes on beyond `radius_m` as a canopy layer over
    /// the terrain (else the trees end there).
    pub far_field: bool,
    /// Added to the scene's seed for the ecosystem (another forest over the
    /// same terrain).
    pub seed_offset: u64,
}

impl Default for VegetationDesc {
    fn default() -> Self {
        Self {
            enabled: true,
            species: vec![
                "spruce".into(),
                "pine".into(),
                "beech".into(),
                "juniper".into(),
                "heather".into(),
            ],
            density_per_ha: 8.0,
            tree_height_m: 22.0,
            tree_line_m: 1400.0,
            radius_m: 2500.0,
            steps: 14,
            prototypes_per_species: 8,
            lod_distance_m: 1000.0,
            leaf_transmission: 0.3,
            season: 0.5,
            leaf_variation: 0.2,
            far_field: true,
            seed_offset: 0,
        }
    }
}

impl VegetationDesc {
    /// Checks every value, naming the first bad key (`vegetation.…`).
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`] naming the key out of its range or
    /// the unknown species name.
    pub fn validate(&self) -> Result<()> {
        for (i, s) in self.species.iter().enumerate() {
            if !SPECIES_NAMES.contains(&s.as_str()) {
                return Err(RenderError::Invalid {
                    name: format!("vegetation.species[{i}]"),
                    value: format!("{s:?}"),
                    reason: format!("unknown species; known: {}", SPECIES_NAMES.join(", ")),
                });
            }
            if self.species[..i].contains(s) {
                return Err(RenderError::Invalid {
                    name: format!("vegetation.species[{i}]"),
                    value: format!("{s:?}"),
                    reason: "named twice".into(),
                });
            }
        }
        if self.enabled && self.species.is_empty() {
            return Err(RenderError::invalid(
                "vegetation.species",
                "[]",
                "name at least one species (or set vegetation.enabled = false)",
            ));
        }
        range("vegetation.density_per_ha", self.density_per_ha, 0.1, 500.0)?;
        range("vegetation.tree_height_m", self.tree_height_m, 1.0, 120.0)?;
        range("vegetation.tree_line_m", self.tree_line_m, -1e4, 1e5)?;
        range("vegetation.radius_m", self.radius_m, 10.0, 20_000.0)?;
        range("vegetation.steps", f64::from(self.steps), 1.0, 200.0)?;
        range(
            "vegetation.prototypes_per_species",
            self.prototypes_per_species as f64,
            1.0,
            16.0,
        )?;
        range("vegetation.lod_distance_m", self.lod_distance_m, 0.0, 1e6)?;
        range(
            "vegetation.leaf_transmission",
            self.leaf_transmission,
            0.0,
            0.9,
        )?;
        range("vegetation.season", self.season, 0.0, 1.0)?;
        range("vegetation.leaf_variation", self.leaf_variation, 0.0, 0.5)?;
        Ok(())
    }
}
