//! Branch tiers of *Terminalia catappa* (Honda's model) competing for space.
//!
//! Měch & Prusinkiewicz 1996, §5, Fig. 5: a tier is a horizontal whorl of
//! five branches that bifurcate every step; competition for light is reduced
//! to collisions between apices and circular leaf clusters. Each apex sends
//! `?E(x)` with its vigor `x`; the environment answers 1 (may branch) if the
//! apex lies in no existing cluster, or only in clusters of smaller vigor, and
//! 0 (stops) otherwise; then a cluster of radius ρ is added at the apex.
//!
//! Errata: the printed listing shows one symbol for both contraction ratios
//! (here `r1` = 0.94, `r2` = 0.87, as the text's values say); the text says
//! two of the axiom's branches hold a `/` that rolls the apex 180° so
//! branching alternates sides, but the listing lost it — here it is placed
//! before the apex in the second and fourth branch, as `/(180)` (a bare `/`
//! would roll by the listing's default angle and lift those branches out of
//! the tier's plane). The source does not say in which order the apices of
//! one step are checked: here every apex of a step is checked against the
//! clusters of earlier steps, then the step's clusters are added, so the
//! result does not depend on order.
//!
//! The environment holds "each apex or non-terminal node" as a cluster, but
//! the listing reports only apices. The whorl's own node, where a tier's
//! five branches start, is a non-terminal node too: here each tier's axiom
//! reports it with a `?E(1)` before the whorl (no production reads the
//! reply). Its cluster lies a branch's length from the tier's first apices
//! and, at the defaults, out of the other tier's reach, so it changes no
//! growth there (a test checks); it makes the clusters two more than the
//! segments, as in the source's Table 1.
//!
//! **Table 1, Fig. 5: 138 branch segments and 140 leaf clusters after 5
//! steps**, which the defaults reproduce. The source prints neither
//! parameter the counts depend on, the cluster radius ρ nor the distance
//! between the two tiers' centres, so both are derived from the counts.
//! Without competition the two tiers make 630 segments. A tier's own
//! clusters stop an apex whose segment is shorter than ρ and whose mother's
//! vigor is not smaller than its own, so ρ sets how many contractions a
//! branch survives: 138 needs ρ between 0.87·0.94² = 0.769 (a lateral
//! segment followed by two straight ones) and 0.94⁴ = 0.781 (four straight
//! ones), and, inside that interval, tiers between 2.99 and 3.08 apart,
//! where the tiers meet (farther apart they make more, 140 from 3.09 and
//! 174 once they no longer meet; nearer, 136). The
//! defaults take the middle of both, ρ = 0.775 and a spacing of 3.04; a test
//! checks the count over that whole range and its change outside it.
use glam::DVec3;
use natura_core::check;

use super::{Run, run_open};
use crate::error::Result;
use crate::lang::LSystem;
use crate::open::{Environment, Message, Reply};
use crate::turtle::{TurtleFrame, TurtleParams};

/// Parameters of the tier model.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct TiersParams {
    /// Contraction ratio and vigor of the straight daughter (`r1`).
    pub r1: f64,
    /// Contraction ratio and vigor of the lateral daughter (`r2`).
    pub r2: f64,
    /// Branching angle of the straight daughter, degrees (`α1`).
    pub alpha1_deg: f64,
    /// Branching angle of the lateral daughter, degrees (`α2`).
    pub alpha2_deg: f64,
    /// Divergence angle of the whorl, degrees (`φ`; 138.5, not 137.5, in the source).
    pub divergence_deg: f64,
    /// Radius ρ of every leaf cluster (not printed in the source; the
    /// default reproduces its Table 1, see the module docs).
    pub cluster_radius: f64,
    /// Derivation steps (5 in the source's Table 1).
    pub steps: u32,
    /// Number of tiers side by side (Fig. 5 shows two).
    pub tiers: u32,
    /// Distance between the centres of neighbouring tiers (not printed in
    /// the source; the default reproduces its Table 1).
    pub spacing: f64,
}

impl Default for TiersParams {
    fn default() -> Self {
        Self {
            r1: 0.94,
            r2: 0.87,
            alpha1_deg: 24.4,
            alpha2_deg: 36.9,
            divergence_deg: 138.5,
            cluster_radius: 0.775,
            steps: 5,
            tiers: 2,
            spacing: 3.04,
        }
    }
}

impl TiersParams {
    /// Checks the ratios lie in (0, 1], angles are finite, radius and spacing positive.
    ///
    /// # Errors
    ///
    /// [`crate::PlantError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        check::in_range("TiersParams::r1", self.r1, 1e-6, 1.0, "a ratio in (0, 1]")?;
        check::in_range("TiersParams::r2", self.r2, 1e-6, 1.0, "a ratio in (0, 1]")?;
        check::finite("TiersParams::alpha1_deg", self.alpha1_deg)?;
        check::finite("TiersParams::alpha2_deg", self.alpha2_deg)?;
        check::finite("TiersParams::divergence_deg", self.divergence_deg)?;
        check::positive("TiersParams::cluster_radius", self.cluster_radius)?;
        check::non_negative("TiersParams::spacing", self.spacing)?;
        check::count(
            "TiersParams::steps",
            self.steps as usize,
            0,
            20,
            "at most 20 steps",
        )?;
        check::count(
            "TiersParams::tiers",
            self.tiers as usize,
            1,
            16,
            "1 to 16 tiers",
        )?;
        Ok(())
    }

    /// The model's L-system text (the source's listing with the errata above
    /// applied, and each whorl's node reported to the environment).
    #[must_use]
    pub fn lsystem_text(&self) -> String {
        let whorl = "-(90)[F(1)?E(1)A(1)]+(φ)[F(1)/(180)?E(1)A(1)]+(φ)[F(1)?E(1)A(1)]+(φ)[F(1)/(180)?E(1)A(1)]+(φ)[F(1)?E(1)A(1)]";
        let mut axiom = String::new();
        // Tiers side by side along x: turn to +x, move, turn back; the
        // whorl's node reports itself as a cluster (see the module docs).
        for k in 0..self.tiers {
            let x = (f64::from(k) - f64::from(self.tiers - 1) / 2.0) * self.spacing;
            axiom.push_str(&format!("[-(90)f({x})+(90)?E(1){whorl}]"));
        }
        format!(
            "#define r1 {}\n#define r2 {}\n#define α1 {}\n#define α2 {}\n#define φ {}\n\
             ω: {axiom}\n\
             p1: ?E(x) < A(v) : x == 1 -> [+(α2)F(v*r2)?E(r2)A(v*r2)]-(α1)F(v*r1)?E(r1)A(v*r1)\n\
             p2: ?E(x) -> ε\n",
            self.r1, self.r2, self.alpha1_deg, self.alpha2_deg, self.divergence_deg
        )
    }
}

/// The environment: leaf clusters of radius ρ around every apex that reported.
#[derive(Clone, Debug, Default)]
pub struct ClusterField {
    /// Cluster radius ρ.
    pub radius: f64,
    /// Centres and vigors of the clusters so far.
    pub clusters: Vec<(DVec3, f64)>,
}

impl Environment for ClusterField {
    fn respond(&mut self, _step: u32, m: &[Message], r: &mut Vec<Reply>) -> Result<()> {
        let rr = self.radius * self.radius;
        let mut new = Vec::with_capacity(m.len());
        for msg in m {
            let p = msg.state.frame.p;
            let v = msg.values.first().copied().unwrap_or(0.0);
            let free = self
                .clusters
                .iter()
                .all(|&(c, cv)| c.distance_squared(p) > rr || cv < v);
            r.push(Reply {
                address: msg.address,
                values: vec![if free { 1.0 } else { 0.0 }],
            });
            new.push((p, v));
        }
        self.clusters.extend(new);
        Ok(())
    }
}

/// Grows the tiers; returns the run and the leaf clusters.
///
/// # Errors
///
/// [`TiersParams::validate`]'s errors; derivation and turtle errors.
pub fn tiers(p: &TiersParams) -> Result<(Run, ClusterField)> {
    p.validate()?;
    grow(&p.lsystem_text(), p.cluster_radius, p.steps)
}

/// Grows the tier model's text `text` for `steps` steps among clusters of
/// `radius`.
fn grow(text: &str, radius: f64, steps: u32) -> Result<(Run, ClusterField)> {
    let l = LSystem::parse(text)?;
    // The tier is horizontal: the turtle heads along +x with up +z, so it draws in the ground plane.
    let t = TurtleParams {
        start: TurtleFrame::new(DVec3::ZERO, DVec3::X, DVec3::Y),
        ..TurtleParams::for_lsystem(&l)
    };
    let mut env = ClusterField {
        radius,
        clusters: Vec::new(),
    };
    let run = run_open(l, t, &mut env, steps, 0)?;
    Ok((run, env))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::testenv::Recorder;
    use crate::{Derivation, Turtle};

    #[test]
    fn environment_sees_every_apex_and_competition_prunes() {
        let p = TiersParams::default();
        let l = LSystem::parse(&p.lsystem_text()).unwrap();
        let t = Turtle::new(&l, TurtleParams::for_lsystem(&l)).unwrap();
        let mut inner = ClusterField {
            radius: p.cluster_radius,
            ..ClusterField::default()
        };
        let mut env = Recorder {
            inner: &mut inner,
            seen: Vec::new(),
        };
        let mut d = Derivation::new(&l, 0).unwrap();
        d.communicate(&t, &mut env).unwrap();
        let a = l.symbol("A").unwrap();
        for _ in 0..p.steps {
            d.step_open(&t, &mut env).unwrap();
        }
        // Every message comes from a ?E directly before an apex, one per
        // apex of that step, but for each whorl's node on the axiom.
        for msgs in &env.seen[1..] {
            assert!(msgs.iter().all(|m| m.next_symbol == Some(a)));
        }
        let apices = env.seen[0].iter().filter(|m| m.next_symbol == Some(a));
        assert_eq!(apices.count(), 10, "two whorls of five");
        assert_eq!(env.seen[0].len(), 12, "and the two whorls' nodes");
        let (run, clusters) = tiers(&p).unwrap();
        let segs = run.count("F");
        // Without competition each tier has 5·(2^(n+1) − 1) segments.
        let free = 2 * 5 * ((1 << (p.steps + 1)) - 1);
        assert!(
            segs < free && segs > 10 * (p.steps as usize),
            "{segs} of {free}"
        );
        assert_eq!(
            clusters.clusters.len(),
            env.seen.iter().map(Vec::len).sum::<usize>()
        );
        assert_eq!(run.geometry().unwrap().segment_count(), segs);
    }

    /// Segments and clusters of the two tiers at `rho` and `spacing`.
    fn counts(rho: f64, spacing: f64) -> (usize, usize) {
        let (run, env) = tiers(&TiersParams {
            cluster_radius: rho,
            spacing,
            ..TiersParams::default()
        })
        .unwrap();
        (run.count("F"), env.clusters.len())
    }

    #[test]
    fn counts_for_table_1() {
        // The source's Table 1 for Fig. 5: 138 segments, 140 clusters.
        assert_eq!(counts(0.775, 3.04), (138, 140));
        let p = TiersParams::default();
        assert_eq!((p.cluster_radius, p.spacing), (0.775, 3.04));
        // Over the whole range the module docs derive (ρ between
        // 0.87·0.94² and 0.94⁴, tiers 2.99 to 3.08 apart)…
        for rho in [0.770, 0.775, 0.780] {
            for spacing in [2.99, 3.04, 3.08] {
                assert_eq!(
                    counts(rho, spacing),
                    (138, 140),
                    "ρ {rho}, spacing {spacing}"
                );
            }
        }
        // …and not outside it: ρ across either bound, or tiers farther
        // apart (meeting less) or nearer.
        assert_eq!(counts(0.766, 3.04).0, 178);
        assert_eq!(counts(0.785, 3.04).0, 130);
        assert_eq!(counts(0.775, 3.2).0, 142);
        assert_eq!(counts(0.775, 2.95).0, 136);
        assert_eq!(counts(0.775, 10.0).0, 174);
        // The whorls' nodes change no growth here: without them, the same
        // segments and two clusters fewer.
        let text = p.lsystem_text();
        let bare = text.replace("+(90)?E(1)-(90)", "+(90)-(90)");
        assert_eq!(bare.len() + 2 * "?E(1)".len(), text.len());
        let (run, env) = grow(&bare, p.cluster_radius, p.steps).unwrap();
        assert_eq!((run.count("F"), env.clusters.len()), (138, 138));
        // No competition (a vanishing ρ): 5·(2⁶ − 1) segments per tier.
        let (run, _) = tiers(&TiersParams {
            cluster_radius: 1e-9,
            ..TiersParams::default()
        })
        .unwrap();
        assert_eq!(run.count("F"), 630);
    }

    /// The side (sign of the vertical component of heading × lateral) to
    /// which each whorl branch sends its first lateral daughter, in the
    /// order of the whorl, for the model's text `text` grown one step
    /// without competition.
    fn lateral_sides(text: &str) -> Vec<f32> {
        let g = grow(text, 1e-9, 1).unwrap().0.geometry().unwrap();
        // Five whorl segments of length 1, each with two daughters, all in
        // the horizontal plane (a roll of other than 180° would leave it).
        assert_eq!(g.segment_count(), 15);
        assert!(g.start.iter().chain(&g.end).all(|p| p.z.abs() < 1e-5));
        let len = |i: usize| (g.end[i] - g.start[i]).length();
        let whorl: Vec<usize> = (0..15).filter(|&i| g.start[i].length() < 1e-5).collect();
        assert_eq!(whorl.len(), 5);
        whorl
            .iter()
            .map(|&w| {
                let daughters: Vec<usize> = (0..15)
                    .filter(|&i| (g.start[i] - g.end[w]).length() < 1e-5)
                    .collect();
                assert_eq!(daughters.len(), 2, "two daughters of branch {w}");
                // The lateral daughter is the shorter one (r2 < r1).
                let lat = *daughters
                    .iter()
                    .min_by(|&&a, &&b| len(a).total_cmp(&len(b)))
                    .unwrap();
                assert!((len(lat) - 0.87).abs() < 1e-4, "{}", len(lat));
                let d = g.end[w] - g.start[w];
                let side = d.cross(g.end[lat] - g.start[lat]).z;
                assert!(side.abs() > 0.1, "a lateral off the heading");
                side.signum()
            })
            .collect()
    }

    #[test]
    fn the_roll_in_two_branches_alternates_the_branching_side() {
        // With the `/` the text describes in the second and fourth branch,
        // those two branch to the other side from the first, third and fifth.
        let p = TiersParams {
            tiers: 1,
            ..TiersParams::default()
        };
        let text = p.lsystem_text();
        let s = lateral_sides(&text);
        assert_eq!(s, [s[0], -s[0], s[0], -s[0], s[0]]);
        // The listing as printed (no `/`): every branch to the same side.
        let printed = text.replace("F(1)/(180)?E(1)", "F(1)?E(1)");
        assert_ne!(printed, text);
        assert_eq!(lateral_sides(&printed), [s[0]; 5]);
    }

    #[test]
    fn bad_params() {
        let p = TiersParams {
            r1: 0.0,
            ..TiersParams::default()
        };
        assert!(tiers(&p).is_err());
    }
}
