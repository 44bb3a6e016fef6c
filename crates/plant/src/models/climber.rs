//! A climbing plant growing on a tree.
//!
//! Měch & Prusinkiewicz 1996, §8, Fig. 13: "the effect of seeding a
//! hypothetical climbing plant near the same tree. The plant follows the
//! surface of the tree trunk and branches, and avoids excessively dense
//! colonization of any particular area"; its leaves are cubic patches. The
//! source prints neither the climber's rules nor its environment, so both
//! are ours:
//!
//! - Each apex `K(b)` sends `?E(ok, θ, φ)` every step. The environment
//!   ([`Support`]) finds the nearest point of the tree's bark (its segments
//!   as capsules of their drawn widths) and answers with the turn that
//!   brings the heading onto the bark's tangent plane, upwards, and back to
//!   `offset` metres from the bark: `t = ĥ + ŵ − n·(d − offset)/step`, where
//!   `ĥ` and `ŵ` are the heading and the world's up projected onto the
//!   tangent plane of normal `n` and normalised, `d` the distance to the
//!   bark. `/(φ)+(θ)` turns the heading onto `t` (the turn of the 3-D roots
//!   model).
//! - An apex dies (`ok = 0`) farther than `reach` from any bark, and where
//!   the climber is crowded: the environment counts the segments grown in
//!   each cube of side `cell`, and an apex whose cube already holds
//!   `crowding` stops there.
//! - Each step grows a segment of `step` metres and a leaf (`~L`) on
//!   alternate sides; every `branch_every` steps the apex also starts a
//!   lateral apex turned `branch_deg` away, which the bark then steers. A
//!   lateral's first request carries a side `s = ±1` (alternating from fork
//!   to fork), and its first turn adds `2s·(n × ẑ)`, round the bark: the
//!   laterals wind round the trunk and the branches instead of climbing in
//!   their mother's track, where the crowding would stop them.

use glam::DVec3;
use natura_core::check;
use std::collections::HashMap;

use super::roots3d::turn_towards;
use super::{Run, run_open};
use crate::error::{PlantError, Result};
use crate::lang::LSystem;
use crate::open::{Environment, Message, Reply};
use crate::turtle::{Geometry, TurtleFrame, TurtleParams};

/// Parameters of the climber (our own; the source prints none).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct ClimberParams {
    /// Where the seed germinates, m.
    pub start: [f64; 3],
    /// Segment length, m a step.
    pub step: f64,
    /// Steps between laterals.
    pub branch_every: u32,
    /// Turn of a lateral from its mother, degrees.
    pub branch_deg: f64,
    /// Length of a leaf, m.
    pub leaf: f64,
    /// Distance kept from the bark, m.
    pub offset: f64,
    /// An apex farther than this from every bark dies, m.
    pub reach: f64,
    /// Side of the cubes in which crowding is counted, m.
    pub cell: f64,
    /// Segments in a cube beyond which apices stop there.
    pub crowding: u32,
    /// Stem width, m.
    pub width: f64,
    /// Derivation steps.
    pub steps: u32,
}

impl Default for ClimberParams {
    fn default() -> Self {
        Self {
            start: [0.3, 0.0, 0.0],
            step: 0.05,
            branch_every: 7,
            branch_deg: 60.0,
            leaf: 0.07,
            offset: 0.02,
            reach: 0.3,
            cell: 0.25,
            crowding: 14,
            width: 0.012,
            steps: 400,
        }
    }
}

impl ClimberParams {
    /// Checks every value is finite and in range.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        for v in self.start {
            check::finite("ClimberParams::start", v)?;
        }
        for (n, v) in [
            ("ClimberParams::step", self.step),
            ("ClimberParams::leaf", self.leaf),
            ("ClimberParams::reach", self.reach),
            ("ClimberParams::cell", self.cell),
            ("ClimberParams::width", self.width),
        ] {
            check::positive(n, v)?;
        }
        check::non_negative("ClimberParams::offset", self.offset)?;
        check::in_range(
            "ClimberParams::branch_deg",
            self.branch_deg,
            -180.0,
            180.0,
            "an angle in [−180, 180]",
        )?;
        check::count(
            "ClimberParams::branch_every",
            self.branch_every as usize,
            1,
            10_000,
            "1 to 10 000 steps",
        )?;
        check::count(
            "ClimberParams::crowding",
            self.crowding as usize,
            1,
            100_000,
            "1 to 100 000 segments",
        )?;
        check::count(
            "ClimberParams::steps",
            self.steps as usize,
            0,
            5000,
            "at most 5000 steps",
        )?;
        Ok(())
    }

    /// The climber's L-system text (see the module docs).
    #[must_use]
    pub fn lsystem_text(&self) -> String {
        format!(
            "#define ST {}\n#define BR {}\n#define BA {}\n#define LF {}\n#define W {}\n\
             ω: !(W)K(0,1)?E(1,0,0,0)\n\
             K(b,sd) > ?E(ok,th,ph,s) : ok == 0 -> ε\n\
             K(b,sd) > ?E(ok,th,ph,s) : (ok > 0) && (b+1 < BR) -> /(ph)+(th)F(ST)[&(60)~L(LF)]/(180)K(b+1,sd)?E(1,0,0,0)\n\
             K(b,sd) > ?E(ok,th,ph,s) : (ok > 0) && (b+1 >= BR) -> /(ph)+(th)F(ST)[&(60)~L(LF)][+(BA)K(0,sd)?E(1,0,0,sd)]/(180)K(0,-sd)?E(1,0,0,0)\n\
             ?E(ok,th,ph,s) -> ε\n",
            self.step, self.branch_every, self.branch_deg, self.leaf, self.width,
        )
    }
}

/// A capsule of bark: a segment's axis and radius.
#[derive(Clone, Copy, Debug)]
struct Capsule {
    a: DVec3,
    b: DVec3,
    r: f64,
}

impl Capsule {
    /// The nearest point of the axis to `p`, and the distance from the bark
    /// (negative inside).
    fn nearest(&self, p: DVec3) -> (DVec3, f64) {
        let ab = self.b - self.a;
        let len2 = ab.length_squared();
        let s = if len2 > 0.0 {
            ((p - self.a).dot(ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = self.a + ab * s;
        (q, (p - q).length() - self.r)
    }
}

/// The climber's environment: the tree's bark, binned into cubes for the
/// nearest-bark query, and the count of climber segments in each cube of
/// [`ClimberParams::cell`].
#[derive(Clone, Debug)]
pub struct Support {
    capsules: Vec<Capsule>,
    /// Bin side for the bark (at least the reach).
    bin: f64,
    bins: HashMap<[i64; 3], Vec<u32>>,
    cell: f64,
    crowd: HashMap<[i64; 3], u32>,
    p: ClimberParams,
    /// Apices stopped by crowding so far.
    pub crowded: usize,
    /// Apices stopped for want of bark so far.
    pub unsupported: usize,
}

impl Support {
    /// The bark of `tree` (each drawn segment a capsule of its larger end
    /// width) for a climber of parameters `p`.
    ///
    /// # Errors
    ///
    /// [`ClimberParams::validate`]'s errors; [`PlantError::InvalidParameter`]
    /// naming `tree` if it has no segment or a coordinate or width is not
    /// finite.
    pub fn new(tree: &Geometry, p: &ClimberParams) -> Result<Self> {
        p.validate()?;
        if tree.start.is_empty() {
            return Err(PlantError::InvalidParameter {
                name: "tree",
                value: "no segments".into(),
                reason: "a climber needs bark to climb".into(),
            });
        }
        let mut capsules = Vec::with_capacity(tree.start.len());
        for k in 0..tree.start.len() {
            let c = Capsule {
                a: tree.start[k].as_dvec3(),
                b: tree.end[k].as_dvec3(),
                r: 0.5 * f64::from(tree.width0[k].max(tree.width1[k])),
            };
            if !(c.a.is_finite() && c.b.is_finite() && c.r.is_finite()) {
                return Err(PlantError::InvalidParameter {
                    name: "tree",
                    value: format!("segment {k}"),
                    reason: "finite ends and widths".into(),
                });
            }
            capsules.push(c);
        }
        let bin = p.reach.max(0.25);
        let key = |q: DVec3| (q / bin).floor().as_i64vec3().to_array();
        let mut bins: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (k, c) in capsules.iter().enumerate() {
            let pad = DVec3::splat(c.r + p.reach);
            let (lo, hi) = (key(c.a.min(c.b) - pad), key(c.a.max(c.b) + pad));
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        bins.entry([x, y, z]).or_default().push(k as u32);
                    }
                }
            }
        }
        Ok(Self {
            capsules,
            bin,
            bins,
            cell: p.cell,
            crowd: HashMap::new(),
            p: p.clone(),
            crowded: 0,
            unsupported: 0,
        })
    }

    /// The nearest bark to `p` within the reach: the nearest axis point and
    /// the distance from the bark.
    fn bark(&self, p: DVec3) -> Option<(DVec3, f64)> {
        let key = (p / self.bin).floor().as_i64vec3().to_array();
        let mut best: Option<(DVec3, f64)> = None;
        for &k in self.bins.get(&key)? {
            let (q, d) = self.capsules[k as usize].nearest(p);
            if best.is_none_or(|b| d < b.1) {
                best = Some((q, d));
            }
        }
        best.filter(|b| b.1 <= self.p.reach)
    }

    /// The reply to an apex at frame `f` (a new lateral setting off to
    /// `side` ±1, else 0): `(ok, θ, φ)`.
    fn steer(&mut self, f: &TurtleFrame, side: f64) -> [f64; 3] {
        let Some((axis, d)) = self.bark(f.p) else {
            self.unsupported += 1;
            return [0.0, 0.0, 0.0];
        };
        let cube = (f.p / self.cell).floor().as_i64vec3().to_array();
        let n_here = self.crowd.entry(cube).or_insert(0);
        if *n_here >= self.p.crowding {
            self.crowded += 1;
            return [0.0, 0.0, 0.0];
        }
        *n_here += 1;
        let n = (f.p - axis).normalize_or(DVec3::X);
        let tangent = |v: DVec3| (v - n * v.dot(n)).normalize_or_zero();
        // A new lateral (side ±1) sets off round the bark, to the side the
        // fork alternates.
        let round = n.cross(DVec3::Z).normalize_or_zero() * (2.0 * side);
        let t = tangent(f.h) + 0.5 * tangent(DVec3::Z) + round
            - n * ((d - self.p.offset) / self.p.step);
        let (th, ph) = turn_towards(f, if t == DVec3::ZERO { f.h } else { t });
        [1.0, th, ph]
    }
}

impl Environment for Support {
    fn respond(&mut self, _step: u32, m: &[Message], r: &mut Vec<Reply>) -> Result<()> {
        for msg in m {
            r.push(Reply {
                address: msg.address,
                values: self
                    .steer(&msg.state.frame, msg.values.get(3).copied().unwrap_or(0.0))
                    .to_vec(),
            });
        }
        Ok(())
    }
}

/// Grows the climber on `tree` (the geometry of a drawn plant, e.g. the
/// extended crowns model of Fig. 12); returns the run and the environment
/// as it is left.
///
/// # Errors
///
/// [`Support::new`]'s errors; derivation, turtle and environment errors.
pub fn climber(p: &ClimberParams, tree: &Geometry) -> Result<(Run, Support)> {
    let mut env = Support::new(tree, p)?;
    let l = LSystem::parse(&p.lsystem_text())?;
    let mut t = TurtleParams::for_lsystem(&l);
    t.start.p = DVec3::from_array(p.start);
    let run = run_open(l, t, &mut env, p.steps, 0)?;
    Ok((run, env))
}

#[cfg(test)]
mod tests;
