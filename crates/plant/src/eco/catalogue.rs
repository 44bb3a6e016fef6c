//! The species catalogue: ecosystem species at landscape scale (radii in
//! metres, altitude bands in metres above the water), each with the
//! L-system its prototypes grow from and the colours its bark and leaves are
//! shaded with. The values are natura's own; the species' parameters are
//! those of Deussen et al. 1998, §4.3 (see [`Species`]), and the beech's
//! branching follows Prusinkiewicz & Lindenmayer 1990, Fig. 2.8.

use glam::Vec3;

use super::Species;

/// The names [`species`] knows, in catalogue order.
pub const NAMES: [&str; 3] = ["spruce", "pine", "beech"];

/// How a species looks: what a renderer needs beyond the ecosystem (natura's
/// own values).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Look {
    /// Height of a mature tree relative to a scene's tree height.
    pub height_factor: f32,
    /// Linear albedo of the leaves (reflectance).
    pub leaf: Vec3,
    /// Linear colour of the light a leaf transmits (times a scene's leaf
    /// transmission).
    pub leaf_transmit: Vec3,
    /// Linear albedo of the bark.
    pub bark: Vec3,
}

/// A monopodial conifer: whorls of five near-horizontal branches on a
/// straight leader, shorter toward the top (the lower whorls are older and
/// longer), needles as clusters along every branch.
const SPRUCE: &str = "angle: 30
ω: !(0.45)F(1.2)A(1)
A(l) -> F(l)[&(82)B(l)]/(72)[&(82)B(l)]/(72)[&(82)B(l)]/(72)[&(82)B(l)]/(72)[&(82)B(l)]/(41)A(l*0.93)
B(l) -> !(0.06)F(l*0.42)[-(55)~L(1.1)][+(55)~L(1.1)][^(70)~L(1.0)]B(l*0.92)";

/// A pine: a tall clear stem and an open crown of ascending branches that
/// fork into needle-tufted twigs.
const PINE: &str = "angle: 30
ω: !(0.5)F(3)A(1)
A(l) -> F(l)[&(55)B(l*0.8)]/(120)[&(55)B(l*0.8)]/(120)[&(55)B(l*0.8)]/(137)A(l*0.86)
B(l) -> !(0.08)F(l*0.55)[-(35)C(l*0.7)][+(35)C(l*0.7)]B(l*0.82)
C(l) -> !(0.04)F(l*0.5)[^(40)~L(1.4)][&(40)~L(1.4)]~L(1.3)C(l*0.8)";

/// A broad-leaved tree: sympodial ternary branching (after Prusinkiewicz &
/// Lindenmayer 1990, Fig. 2.8), a leaf at every new shoot.
const BEECH: &str = "angle: 30
ω: !(0.55)F(2.5)/(45)A
A -> !F(1)[&(32)F(0.9)~L(1.5)A]/(125)[&(34)F(0.9)~L(1.5)A]/(110)[&(30)F(0.9)~L(1.5)A]";

/// The ecosystem species and look of the catalogue entry `name` (one of
/// [`NAMES`]), for a terrain whose
/// heights span `lo..hi` metres with the water at `water` metres and the
/// tree line at `tree_line` metres; seedlings per hectare per step
/// `density`. `None` for an unknown name.
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
    let (sp, look) = match name {
        "spruce" => (
            Species {
                name: name.into(),
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
                height_factor: 1.0,
                leaf: Vec3::new(0.035, 0.075, 0.035),
                leaf_transmit: Vec3::new(0.05, 0.12, 0.03),
                bark: Vec3::new(0.09, 0.06, 0.04),
            },
        ),
        "pine" => (
            Species {
                name: name.into(),
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
                height_factor: 0.9,
                leaf: Vec3::new(0.05, 0.09, 0.035),
                leaf_transmit: Vec3::new(0.07, 0.13, 0.03),
                bark: Vec3::new(0.16, 0.08, 0.05),
            },
        ),
        "beech" => (
            Species {
                name: name.into(),
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
                height_factor: 1.0,
                leaf: Vec3::new(0.07, 0.13, 0.035),
                leaf_transmit: Vec3::new(0.12, 0.2, 0.03),
                bark: Vec3::new(0.2, 0.19, 0.17),
            },
        ),
        _ => return None,
    };
    let r0 = 0.12 * sp.max_radius;
    Some((
        Species {
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
}
