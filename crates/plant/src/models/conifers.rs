//! Coniferous trees competing for light, in tiers (after Takenaka 1994).
//!
//! Měch & Prusinkiewicz 1996, §8, Fig. 15: "the tree model is similar to
//! the original model by Takenaka and can be viewed as consisting of
//! approximately horizontal tiers produced in sequence by the apex of the
//! tree stem. The lower tiers are created first and therefore potentially
//! can spread more widely than the younger tiers higher up (the *phase
//! effect*)"; the competition for light keeps neighbouring crowns from
//! growing into each other, and the trees "retain branches that do not
//! receive enough light".
//!
//! The source prints no rules for this model, so they are ours, built from
//! the deciduous model's listing ([`crowns`](super::crowns)) and the text:
//!
//! - The stem apex `S` grows once a year (every `Del + 1` steps): a stem
//!   segment, then a whorl of `whorl` lateral branches pitched `tier_deg`
//!   from the stem, the next whorl turned by the divergence angle. The stem
//!   is not limited by light (the leader of a young conifer is, but the
//!   source does not say how).
//! - Each lateral carries the listing's leaf cluster `L` and apex `A`: the
//!   cluster reports its radius through `?E(r)` once a year, the
//!   environment ([`SkyLight`], nine sources of the overcast sky) answers
//!   with the light reaching it, and the listing's thresholds decide the
//!   cluster's survival (`r·LP ≥ LM`) and the apex's fate: fork (`> PB`),
//!   grow straight (`> PG`) or rest. A fork turns about the turtle's up
//!   vector, which a lateral pitched from the vertical stem keeps nearly
//!   vertical, so the tiers stay flat; each fork rolls the apex 180° so
//!   forks alternate sides.
//! - Nothing is shed: the listing's flow of photosynthates to the base and
//!   its cut `%` are left out, as the text says of this figure. A branch
//!   whose clusters all died stays bare.
//! - Branch widths are fixed at creation (the stem's from its yearly
//!   growth, the laterals' from their vigor), not the listing's pipe model,
//!   which needs the flow left out above; a tropism towards the ground
//!   bends the laterals' tips down as a conifer's do.
//!
//! Table 1 of the source gives Fig. 15 13 502 branch segments and 3 448
//! leaf clusters after 15 years in 194 steps; 194 steps in 15 years is
//! about 13 a year, `Del = 12` here. With the rules its counts depend on
//! unprinted, the table is not reproduced: the defaults here make one tree
//! of 12 251 segments and 6 526 living clusters after 15 years (pinned by a
//! test), and the figure's pair 2.5 m apart 19 577 segments and 9 795
//! living clusters.

use natura_core::check;

pub use super::crowns::{LeafCluster, living_clusters};
use super::crowns::{SkyLight, check_stand, light_defines, light_rules, stand_axiom};
use super::{Run, run_open};
use crate::error::Result;
use crate::lang::LSystem;
use crate::turtle::TurtleParams;

/// Parameters of the conifer model (the defaults are our own; the light
/// thresholds and leaf life are the deciduous listing's).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct ConiferParams {
    /// Lateral branches in a whorl.
    pub whorl: u32,
    /// Angle between a lateral and the stem, degrees (90 = horizontal).
    pub tier_deg: f64,
    /// Turn between consecutive whorls, degrees.
    pub divergence_deg: f64,
    /// The stem's growth in its first year, m.
    pub stem_growth: f64,
    /// Ratio of each year's stem growth to the year before's.
    pub stem_decrement: f64,
    /// A new lateral's first segment as a fraction of that year's stem growth.
    pub lateral_ratio: f64,
    /// Angle of a fork's new branch, degrees.
    pub fork_deg: f64,
    /// Deflection of the continuing axis at a fork or a straight growth, degrees.
    pub deflection_deg: f64,
    /// Apex vigor decrement VD.
    pub vigor_decrement: f64,
    /// Stem width per metre of its yearly growth.
    pub stem_width: f64,
    /// Lateral width per metre of vigor.
    pub lateral_width: f64,
    /// Bending of the laterals towards the ground (the turtle's elasticity).
    pub droop: f64,
    /// Delay Del (steps per year − 1).
    pub delay: u32,
    /// Years a leaf cluster stays, LS.
    pub leaf_years: u32,
    /// Full photosynthate production LP.
    pub production: f64,
    /// Leaf maintenance LM.
    pub leaf_maintenance: f64,
    /// Photosynthates needed for a fork PB.
    pub branching: f64,
    /// Photosynthates needed for growth PG.
    pub growth: f64,
    /// Transmittance τ of a leaf cluster.
    pub transmittance: f64,
    /// Years to grow.
    pub years: u32,
    /// Positions of the trees' bases along x (one tree per entry).
    pub trees_x: Vec<f64>,
}

impl Default for ConiferParams {
    fn default() -> Self {
        Self {
            whorl: 5,
            tier_deg: 75.0,
            divergence_deg: 36.0,
            stem_growth: 0.6,
            stem_decrement: 0.97,
            lateral_ratio: 0.55,
            fork_deg: 40.0,
            deflection_deg: 8.0,
            vigor_decrement: 0.9,
            stem_width: 0.12,
            lateral_width: 0.08,
            droop: 0.1,
            delay: 12,
            leaf_years: 5,
            production: 8.0,
            leaf_maintenance: 2.0,
            branching: 0.8,
            growth: 0.4,
            transmittance: 0.25,
            years: 15,
            trees_x: vec![0.0],
        }
    }
}

impl ConiferParams {
    /// Checks every value is finite and in range.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter)
    /// naming the field.
    pub fn validate(&self) -> Result<()> {
        check::count(
            "ConiferParams::whorl",
            self.whorl as usize,
            1,
            12,
            "1 to 12 branches",
        )?;
        for (n, v, lo, hi) in [
            ("ConiferParams::tier_deg", self.tier_deg, 0.0, 180.0),
            ("ConiferParams::fork_deg", self.fork_deg, 0.0, 180.0),
            (
                "ConiferParams::deflection_deg",
                self.deflection_deg,
                0.0,
                180.0,
            ),
            (
                "ConiferParams::divergence_deg",
                self.divergence_deg,
                -360.0,
                360.0,
            ),
        ] {
            check::in_range(n, v, lo, hi, "an angle in the range shown")?;
        }
        for (n, v) in [
            ("ConiferParams::stem_growth", self.stem_growth),
            ("ConiferParams::lateral_ratio", self.lateral_ratio),
            ("ConiferParams::production", self.production),
        ] {
            check::positive(n, v)?;
        }
        for (n, v) in [
            ("ConiferParams::stem_width", self.stem_width),
            ("ConiferParams::lateral_width", self.lateral_width),
            ("ConiferParams::leaf_maintenance", self.leaf_maintenance),
            ("ConiferParams::branching", self.branching),
            ("ConiferParams::growth", self.growth),
        ] {
            check::non_negative(n, v)?;
        }
        for (n, v) in [
            ("ConiferParams::stem_decrement", self.stem_decrement),
            ("ConiferParams::vigor_decrement", self.vigor_decrement),
        ] {
            check::in_range(n, v, 1e-6, 1.0, "a ratio in (0, 1]")?;
        }
        check::in_range("ConiferParams::droop", self.droop, 0.0, 1.0, "0 to 1")?;
        check::in_range(
            "ConiferParams::transmittance",
            self.transmittance,
            0.0,
            1.0,
            "a number in [0, 1]",
        )?;
        check_stand(
            [
                "ConiferParams::delay",
                "ConiferParams::leaf_years",
                "ConiferParams::years",
                "ConiferParams::trees_x",
            ],
            self.delay,
            self.leaf_years,
            self.years,
            &self.trees_x,
        )?;
        Ok(())
    }

    /// Derivation steps per year, `Del + 1`.
    #[must_use]
    pub fn steps_per_year(&self) -> u32 {
        self.delay + 1
    }

    /// The model's L-system text (see the module docs).
    #[must_use]
    pub fn lsystem_text(&self) -> String {
        let axiom = stand_axiom(&self.trees_x, "!(SW*V0)F(V0)S(V0,0)");
        let k = self.whorl;
        let turn = 360.0 / f64::from(k);
        let lateral = "[&(β)!(LW*LR*v)F(LR*v)L(LR*v,LP,0,0)A(LR*v,0)]";
        let mut whorl = String::new();
        for i in 0..k {
            whorl.push_str(lateral);
            if i + 1 < k {
                whorl.push_str(&format!("/({turn})"));
            }
        }
        let fork = "[+(α)!(LW*vig)F(vig)L(vig,LP,0,0)A(vig,0)]-(α0)!(LW*vig)F(vig)L(vig,LP,0,0)/(180)A(vig,0)";
        let grow = "-(α0)!(LW*vig)F(vig)L(vig,LP,0,0)/(180)A(vig,0)";
        format!(
            "#define β {}\n#define φ {}\n#define α {}\n#define α0 {}\n#define V0 {}\n#define SD {}\n\
             #define LR {}\n#define VD {}\n#define SW {}\n#define LW {}\n{}\
             tropism: 0, 0, -1, {}\n\
             Consider: ?E [ ] L\n\
             ω: {axiom}\n\
             S(vig,del) : del < Del -> S(vig,del+1)\n\
             S(vig,del) : del == Del {{ v = vig*SD; }} -> !(SW*v)F(v){whorl}/({turn}+φ)S(v,0)\n\
             {}",
            self.tier_deg,
            self.divergence_deg,
            self.fork_deg,
            self.deflection_deg,
            self.stem_growth,
            self.stem_decrement,
            self.lateral_ratio,
            self.vigor_decrement,
            self.stem_width,
            self.lateral_width,
            light_defines(
                self.delay,
                self.leaf_years,
                [
                    self.production,
                    self.leaf_maintenance,
                    self.branching,
                    self.growth
                ]
            ),
            self.droop,
            light_rules(fork, grow),
        )
    }
}

/// Grows the conifers for [`ConiferParams::years`] years in one shared light
/// environment (the overcast sky of the deciduous model).
///
/// # Errors
///
/// [`ConiferParams::validate`]'s errors; derivation, turtle and environment
/// errors.
pub fn conifers(p: &ConiferParams) -> Result<Run> {
    p.validate()?;
    let l = LSystem::parse(&p.lsystem_text())?;
    let t = TurtleParams::for_lsystem(&l);
    let mut env = SkyLight::overcast(p.transmittance);
    run_open(l, t, &mut env, p.years * p.steps_per_year(), 0)
}

#[cfg(test)]
mod tests;
