//! The species catalogue: ecosystem species at landscape scale (radii in
//! metres, altitude bands in metres above the water), each with the
//! L-system its prototypes grow from and the colours its bark and leaves are
//! shaded with through the seasons. The values are natura's own; the
//! species' parameters are those of Deussen et al. 1998, §4.3 (see
//! [`Species`]), and the beech's branching follows Prusinkiewicz &
//! Lindenmayer 1990, Fig. 2.8.
//!
//! The catalogue spans the layers of a temperate mountain forest: two
//! conifers (spruce, pine), a broad-leaved tree (beech), a shrub (juniper)
//! and a ground cover (heather). Every L-system is stochastic (Prusinkiewicz
//! & Lindenmayer 1990, §1.7): each derivation seed grows another plant of the
//! species, so a species' prototypes differ in form as well as in age.

use glam::Vec3;

use super::Species;

/// The names [`species`] knows, in catalogue order.
pub const NAMES: [&str; 5] = ["spruce", "pine", "beech", "juniper", "heather"];

/// The layer of the vegetation a species belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layer {
    /// A needle-leaved tree.
    Conifer,
    /// A broad-leaved tree.
    Broadleaf,
    /// A woody shrub, a few metres tall.
    Shrub,
    /// A low mat covering the ground (grass, heath).
    GroundCover,
}

impl Layer {
    /// Whether the layer forms the canopy a distant viewer sees (trees and
    /// shrubs; not the ground cover).
    #[must_use]
    pub fn is_canopy(self) -> bool {
        !matches!(self, Layer::GroundCover)
    }
}

/// How a species looks: what a renderer needs beyond the ecosystem (natura's
/// own values).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Look {
    /// The layer of the vegetation the species belongs to.
    pub layer: Layer,
    /// Height of a mature plant relative to a scene's tree height.
    pub height_factor: f32,
    /// Linear albedo of the leaves in high summer (reflectance).
    pub leaf: Vec3,
    /// Linear albedo of the leaves at the spring flush.
    pub leaf_spring: Vec3,
    /// Linear albedo of the leaves at the height of autumn colour.
    pub leaf_autumn: Vec3,
    /// Linear colour of the light a summer leaf transmits (times a scene's
    /// leaf transmission).
    pub leaf_transmit: Vec3,
    /// Linear albedo of the bark.
    pub bark: Vec3,
}

impl Look {
    /// The leaf albedo at `season` in `[0, 1]` (0 the spring flush, ½ high
    /// summer, 1 the height of autumn colour; clamped): linear between the
    /// three.
    #[must_use]
    pub fn leaf_at(&self, season: f32) -> Vec3 {
        let s = season.clamp(0.0, 1.0);
        if s <= 0.5 {
            self.leaf_spring.lerp(self.leaf, 2.0 * s)
        } else {
            self.leaf.lerp(self.leaf_autumn, 2.0 * s - 1.0)
        }
    }

    /// The transmitted leaf colour at `season`: the summer colour scaled as
    /// the albedo changes from its summer value, channel by channel.
    #[must_use]
    pub fn leaf_transmit_at(&self, season: f32) -> Vec3 {
        self.leaf_transmit * self.leaf_at(season) / self.leaf.max(Vec3::splat(1e-4))
    }
}

/// A monopodial conifer: whorls of four to six near-horizontal branches on
/// a straight leader, shorter toward the top (the lower whorls are older
/// and longer), needles as clusters along every branch.
const SPRUCE: &str = "angle: 30
ω: !(0.45)F(1.2)A(1)
A(l) -> F(l)[&(82)B(l)]/(72)[&(82)B(l)]/(72)[&(82)B(l)]/(72)[&(82)B(l)]/(72)[&(82)B(l)]/(41)A(l*0.93) : 0.5
A(l) -> F(l*1.1)[&(78)B(l)]/(90)[&(86)B(l*0.9)]/(90)[&(80)B(l)]/(90)[&(84)B(l*0.95)]/(45)A(l*0.91) : 0.3
A(l) -> F(l*0.9)[&(85)B(l*1.05)]/(60)[&(80)B(l)]/(60)[&(83)B(l*0.9)]/(60)[&(79)B(l)]/(60)[&(86)B(l)]/(60)[&(81)B(l*0.95)]/(33)A(l*0.94) : 0.2
B(l) -> !(0.06)F(l*0.42)[-(55)~L(1.1)][+(55)~L(1.1)][^(70)~L(1.0)]B(l*0.92) : 0.6
B(l) -> !(0.06)F(l*0.38)[-(64)~L(1.0)][+(47)~L(1.2)][^(75)~L(1.0)]B(l*0.9) : 0.4";

/// A pine: a tall clear stem and an open crown of ascending branches that
/// fork into needle-tufted twigs.
const PINE: &str = "angle: 30
ω: !(0.5)F(3)A(1)
A(l) -> F(l)[&(55)B(l*0.8)]/(120)[&(55)B(l*0.8)]/(120)[&(55)B(l*0.8)]/(137)A(l*0.86) : 0.6
A(l) -> F(l*1.15)[&(48)B(l*0.85)]/(150)[&(62)B(l*0.75)]/(137)A(l*0.84) : 0.4
B(l) -> !(0.08)F(l*0.55)[-(35)C(l*0.7)][+(35)C(l*0.7)]B(l*0.82) : 0.7
B(l) -> !(0.08)F(l*0.6)[-(45)C(l*0.8)]B(l*0.8) : 0.3
C(l) -> !(0.04)F(l*0.5)[^(40)~L(1.4)][&(40)~L(1.4)]~L(1.3)C(l*0.8)";

/// A broad-leaved tree: sympodial ternary branching (after Prusinkiewicz &
/// Lindenmayer 1990, Fig. 2.8), a leaf at every new shoot; now and then a
/// shoot forks in two only.
const BEECH: &str = "angle: 30
ω: !(0.55)F(2.5)/(45)A
A -> !F(1)[&(32)F(0.9)~L(1.5)A]/(125)[&(34)F(0.9)~L(1.5)A]/(110)[&(30)F(0.9)~L(1.5)A] : 0.7
A -> !F(1.1)[&(38)F(0.95)~L(1.6)A]/(160)[&(28)F(0.85)~L(1.5)A] : 0.3";

/// A juniper: several stems from the root, ascending and forking, scale
/// leaves in tufts along them.
const JUNIPER: &str = "angle: 30
ω: !(0.12)[&(18)S(1)]/(120)[&(26)S(1)]/(120)[&(14)S(1)]
S(l) -> !(0.08)F(l*0.6)[&(35)~L(0.9)S(l*0.75)]/(137)[^(30)~L(0.9)S(l*0.7)]~L(0.8) : 0.6
S(l) -> !(0.08)F(l*0.5)[&(45)~L(1.0)S(l*0.8)]/(100)~L(0.9)S(l*0.72) : 0.4";

/// Heather: a low mat of woody stems spreading from the root just above
/// the ground, tufted with short upright shoots.
const HEATHER: &str = "angle: 30
ω: !(0.03)[&(72)M(1)]/(72)[&(78)M(1)]/(72)[&(70)M(1)]/(72)[&(76)M(1)]/(72)[&(80)M(1)]
M(l) -> F(l*0.35)[^(60)~L(0.6)][+(40)^(50)~L(0.5)][-(40)^(50)~L(0.5)]M(l*0.85) : 0.7
M(l) -> F(l*0.3)[^(70)~L(0.7)][-(50)M(l*0.7)]M(l*0.8) : 0.3";

/// The ecosystem species of a catalogue entry at its site (altitude band
/// edges as fractions of the terrain's span, from `norm` and `above`) and
/// its look; `None` for an unknown name.
fn entry(
    name: &str,
    norm: &dyn Fn(f32) -> f64,
    above: &dyn Fn(f32) -> f64,
    water: f32,
    line: f32,
) -> Option<(Species, Look)> {
    let rgb = Vec3::new;
    Some(match name {
        "spruce" => (
            Species {
                max_radius: 3.2,
                growth: 0.3,
                survive_domination: 0.15,
                wet_optimum: 0.5,
                wet_tolerance: 0.4,
                light_optimum: 0.5,
                light_tolerance: 0.6,
                altitude_min: above(0.35 * (line - water)),
                altitude_max: norm(line),
                max_slope: 38f64.to_radians(),
                lsystem: SPRUCE.into(),
                max_steps: 12,
                ..Species::default()
            },
            Look {
                layer: Layer::Conifer,
                height_factor: 1.0,
                leaf: rgb(0.035, 0.075, 0.035),
                leaf_spring: rgb(0.05, 0.1, 0.04),
                leaf_autumn: rgb(0.035, 0.068, 0.035),
                leaf_transmit: rgb(0.05, 0.12, 0.03),
                bark: rgb(0.09, 0.06, 0.04),
            },
        ),
        "pine" => (
            Species {
                max_radius: 3.5,
                growth: 0.32,
                survive_domination: 0.05,
                wet_optimum: 0.2,
                wet_tolerance: 0.35,
                light_optimum: 0.85,
                light_tolerance: 0.45,
                altitude_min: above(2.0),
                altitude_max: norm(water + 0.85 * (line - water)),
                max_slope: 35f64.to_radians(),
                lsystem: PINE.into(),
                max_steps: 9,
                ..Species::default()
            },
            Look {
                layer: Layer::Conifer,
                height_factor: 0.9,
                leaf: rgb(0.05, 0.09, 0.035),
                leaf_spring: rgb(0.065, 0.11, 0.04),
                leaf_autumn: rgb(0.06, 0.085, 0.035),
                leaf_transmit: rgb(0.07, 0.13, 0.03),
                bark: rgb(0.16, 0.08, 0.05),
            },
        ),
        "beech" => (
            Species {
                max_radius: 4.5,
                growth: 0.4,
                survive_domination: 0.1,
                wet_optimum: 0.7,
                wet_tolerance: 0.35,
                light_optimum: 0.6,
                light_tolerance: 0.5,
                altitude_min: above(1.0),
                altitude_max: norm(water + 0.55 * (line - water)),
                max_slope: 32f64.to_radians(),
                lsystem: BEECH.into(),
                max_steps: 6,
                ..Species::default()
            },
            Look {
                layer: Layer::Broadleaf,
                height_factor: 1.0,
                leaf: rgb(0.07, 0.13, 0.035),
                leaf_spring: rgb(0.12, 0.22, 0.04),
                leaf_autumn: rgb(0.28, 0.11, 0.025),
                leaf_transmit: rgb(0.12, 0.2, 0.03),
                bark: rgb(0.2, 0.19, 0.17),
            },
        ),
        "juniper" => (
            Species {
                max_radius: 1.6,
                growth: 0.15,
                survive_domination: 0.3,
                wet_optimum: 0.25,
                wet_tolerance: 0.35,
                light_optimum: 0.8,
                light_tolerance: 0.5,
                altitude_min: above(20.0),
                altitude_max: norm(line + 150.0),
                max_slope: 40f64.to_radians(),
                lsystem: JUNIPER.into(),
                max_steps: 5,
                ..Species::default()
            },
            Look {
                layer: Layer::Shrub,
                height_factor: 0.14,
                leaf: rgb(0.04, 0.07, 0.045),
                leaf_spring: rgb(0.05, 0.085, 0.05),
                leaf_autumn: rgb(0.045, 0.065, 0.045),
                leaf_transmit: rgb(0.05, 0.1, 0.04),
                bark: rgb(0.12, 0.08, 0.06),
            },
        ),
        "heather" => (
            Species {
                max_radius: 1.2,
                growth: 0.12,
                survive_domination: 0.4,
                wet_optimum: 0.3,
                wet_tolerance: 0.4,
                light_optimum: 0.85,
                light_tolerance: 0.5,
                altitude_min: above(40.0),
                altitude_max: norm(line + 300.0),
                max_slope: 42f64.to_radians(),
                lsystem: HEATHER.into(),
                max_steps: 5,
                ..Species::default()
            },
            Look {
                layer: Layer::GroundCover,
                height_factor: 0.03,
                leaf: rgb(0.09, 0.1, 0.05),
                leaf_spring: rgb(0.08, 0.11, 0.045),
                leaf_autumn: rgb(0.16, 0.07, 0.12),
                leaf_transmit: rgb(0.08, 0.1, 0.04),
                bark: rgb(0.1, 0.07, 0.05),
            },
        ),
        _ => return None,
    })
}

/// Seedlings of a species per seedling of a tree, by layer: shrubs and the
/// ground cover seed more densely (natura's own values).
fn seeding(layer: Layer) -> f64 {
    match layer {
        Layer::Conifer | Layer::Broadleaf => 1.0,
        Layer::Shrub => 1.5,
        Layer::GroundCover => 3.0,
    }
}

/// The ecosystem species and look of the catalogue entry `name` (one of
/// [`NAMES`]), for a terrain whose
/// heights span `lo..hi` metres with the water at `water` metres and the
/// tree line at `tree_line` metres; tree seedlings per hectare per step
/// `density` (shrubs and ground cover seed more densely). `None` for an
/// unknown name.
#[must_use]
pub fn species(
    name: &str,
    density: f64,
    (lo, hi): (f32, f32),
    water: f32,
    tree_line: f32,
) -> Option<(Species, Look)> {
    // Absolute altitude bands as fractions of the terrain's span (the
    // ecosystem's altitudes are normalised over its terrain).
    let span = f64::from((hi - lo).max(1e-3));
    let norm = |m: f32| (f64::from(m - lo) / span).clamp(0.0, 1.0);
    let above = |m: f32| norm(water + m);
    let line = tree_line.max(water + 50.0);
    let (sp, look) = entry(name, &norm, &above, water, line)?;
    let r0 = 0.12 * sp.max_radius;
    let density = density * seeding(look.layer);
    Some((
        Species {
            name: name.into(),
            seeds_per_ha: density,
            initial_per_ha: 4.0 * density,
            r0_min: 0.5 * r0,
            r0_max: r0,
            vigor_spread: 0.5,
            ..sp
        },
        look,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_is_a_valid_species_and_no_other() {
        for name in NAMES {
            let (sp, look) = species(name, 50.0, (0.0, 1000.0), 100.0, 700.0).unwrap();
            assert_eq!(sp.name, name);
            assert!(sp.altitude_min < sp.altitude_max, "{name}");
            assert!((0.0..=1.0).contains(&sp.altitude_max), "{name}");
            assert!(look.height_factor > 0.0);
            let eco = crate::eco::EcoParams {
                species: vec![sp],
                ..crate::eco::EcoParams::default()
            };
            eco.validate().unwrap();
        }
        assert!(species("oak", 50.0, (0.0, 1000.0), 100.0, 700.0).is_none());
    }

    /// Each species' L-system parses, and two derivation seeds grow two
    /// different plants (the variants of its prototypes).
    #[test]
    fn every_species_grows_variants_by_seed() {
        for name in NAMES {
            let (sp, _) = species(name, 50.0, (0.0, 1000.0), 100.0, 700.0).unwrap();
            let lsys = crate::LSystem::parse(&sp.lsystem).unwrap();
            let grow = |seed: u64| {
                let mut d = crate::Derivation::new(&lsys, seed).unwrap();
                d.derive(sp.max_steps.min(6)).unwrap();
                format!("{:?}", d.string())
            };
            assert_ne!(grow(1), grow(2), "{name}");
            assert_eq!(grow(3), grow(3), "{name}");
        }
    }

    /// The layers the catalogue spans, and the seasons' colours: spring at
    /// 0, summer at ½, autumn at 1, linear between; the beech turns red-brown.
    #[test]
    fn the_catalogue_spans_the_layers_and_the_seasons() {
        let look = |n| species(n, 50.0, (0.0, 1000.0), 100.0, 700.0).unwrap().1;
        let layers: Vec<Layer> = NAMES.iter().map(|n| look(n).layer).collect();
        for l in [
            Layer::Conifer,
            Layer::Broadleaf,
            Layer::Shrub,
            Layer::GroundCover,
        ] {
            assert!(layers.contains(&l), "{l:?}");
        }
        let beech = look("beech");
        assert_eq!(beech.leaf_at(0.0), beech.leaf_spring);
        assert_eq!(beech.leaf_at(0.5), beech.leaf);
        assert_eq!(beech.leaf_at(1.0), beech.leaf_autumn);
        assert_eq!(beech.leaf_at(0.75), beech.leaf.lerp(beech.leaf_autumn, 0.5));
        assert!(beech.leaf_autumn.x > beech.leaf_autumn.y);
        assert!(beech.leaf.y > beech.leaf.x);
        assert_eq!(beech.leaf_transmit_at(0.5), beech.leaf_transmit);
        assert!(!look("heather").layer.is_canopy() && look("juniper").layer.is_canopy());
    }
}
