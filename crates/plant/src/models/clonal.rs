//! Foraging of a clonal plant over patches of light.
//!
//! Měch & Prusinkiewicz 1996, §6, L-system 3, Fig. 6–7: a clone spreads over the
//! ground as a network of spacers `F(len, age)` joining ramets
//! `@o(radius, age)` (a leaf on an upright stem). Each apex `A(dir)` asks the
//! environment for the light at its position with `?E(0, x)`; a ramet
//! announces itself with `?E(1, r)` and its death with `?E(2, r)`. With more
//! light an apex branches more often (`ProbB`), makes a ramet more often
//! (`ProbR`) and the ramet's leaf is smaller (`Radius`); below `MinLight` the
//! apex dies. Ramets and spacers die after `MaxAge` steps, so the clone
//! fragments; a dead spacer becomes `f(len)`, which keeps the remaining
//! elements in place.
//!
//! The environment ([`LightPatches`]) holds the ground as a raster of light
//! intensities painted from patches and the set of live ramets; a sample
//! point inside any ramet's disc gets 0 (the leaves above it are opaque),
//! elsewhere the intensity of its cell; outside the raster, 0.
//!
//! Errata and readings: the leaf radius is printed `sqrt(15-x*5)π`; it is
//! read as `sqrt((15 − 5x)/π)`, a leaf of area `15 − 5x`. The text names p7
//! the aging of spacers and p9 that of ramets; the listing has them the other
//! way round, as kept here. A predecessor's context cannot hold a literal,
//! so p1/p2's `?E(0,x)` becomes `?E(t,x)` with `t == 0` in the condition.
//! The source gives only patch II's intensity (0.6), calls patch I the best
//! and patch III unfavourable; the default layout (I = 1.0, III = 0.15, side
//! by side) is ours. The source does not say how announcements and samples
//! of one communication phase are ordered: here births and deaths are
//! applied first, then every sample is answered. The turtle's disc lies
//! across its heading, so p5 pitches up by 90° before `@o` (inside the
//! ramet's brackets; nothing moves) to lay the leaf flat over the ground.
//!
//! Fig. 7's extensions: spacer lengths and branching angles drawn from
//! normal distributions (`spacer_sd`, `alpha_sd_deg`; the source gives no
//! deviations, [`ClonalParams::fig7`]'s are ours) and ramets drawn as
//! trifoliate leaves (`trifoliate`). A drawn spacer shorter than a tenth of
//! `Len` is raised to that tenth, so no spacer runs backwards. The leaves
//! are an interpretation rule only: three leaflets `~L` as long as the
//! ramet's radius, 120° apart, replace the disc in the picture while the
//! environment still sees the disc. With both deviations 0 the L-system
//! derives exactly as the source's listing.
//!
//! Table 1 of the source gives Fig. 7 786 branch segments and 229 leaf
//! clusters after 182 steps. With [`ClonalParams::fig7`] the clone here
//! holds 1 460 to 2 374 live spacers and 348 to 633 live ramets over seeds
//! 0 to 7 where it survives (seeds 5 and 7 die out; the default seed 1:
//! 1 460 and 348), two to three times the table's. The counts follow the
//! patches' intensities and layout, of which the source prints only patch
//! II's, but no choice of them could be read back from the table: over
//! seeds 0 to 7 with patch I from 0.6 to 1.0 and patch III from 0.1 to 0.3,
//! the clones that survive hold from 135 to 2 743 live spacers, a spread
//! that covers 786 at most settings, and the table reports one run.

use glam::DVec3;
use natura_core::check;

use super::{Patch, Run, check_layout, check_patches, rasterize, run_open};
use crate::error::{PlantError, Result};
use crate::lang::LSystem;
use crate::open::{Environment, Message, Reply};
use crate::turtle::{TurtleFrame, TurtleParams};

/// Parameters of the clonal plant and its ground (defaults: the source's listing).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct ClonalParams {
    /// Branching angle α, degrees.
    pub alpha_deg: f64,
    /// Light below which an apex dies (`MinLight`).
    pub min_light: f64,
    /// Lifetime of ramets and spacers in steps (`MaxAge`).
    pub max_age: u32,
    /// Spacer length (`Len`).
    pub spacer: f64,
    /// Branching probability `ProbB(x) = b0 + b1·x`: `[b0, b1]`.
    pub prob_branch: [f64; 2],
    /// Ramet probability `ProbR(x) = r0 + r1·x`: `[r0, r1]`.
    pub prob_ramet: [f64; 2],
    /// Leaf area `a0 − a1·x` (radius `sqrt(area/π)`): `[a0, a1]`.
    pub leaf_area: [f64; 2],
    /// Derivation steps (182 for Fig. 7).
    pub steps: u32,
    /// Seed of the stochastic productions.
    pub seed: u64,
    /// Lower corner of the ground raster.
    pub origin: [f64; 2],
    /// Size of the ground raster.
    pub size: [f64; 2],
    /// Side of a raster cell.
    pub cell: f64,
    /// Light where no patch lies.
    pub background: f64,
    /// Patches of light, painted in order over the background.
    pub patches: Vec<Patch>,
    /// Where the clone starts.
    pub start: [f64; 2],
    /// Initial heading, degrees from +x.
    pub heading_deg: f64,
    /// Standard deviation of the spacer length (0: every spacer is `Len`).
    pub spacer_sd: f64,
    /// Standard deviation of the branching angle, degrees (0: every branch at α).
    pub alpha_sd_deg: f64,
    /// Draw each ramet as a trifoliate leaf instead of a disc.
    pub trifoliate: bool,
}

impl Default for ClonalParams {
    fn default() -> Self {
        Self {
            alpha_deg: 45.0,
            min_light: 0.1,
            max_age: 20,
            spacer: 2.0,
            prob_branch: [0.12, 0.42],
            prob_ramet: [0.03, 0.54],
            leaf_area: [15.0, 5.0],
            steps: 182,
            seed: 1,
            origin: [0.0, 0.0],
            size: [120.0, 80.0],
            cell: 1.0,
            // Patch III (unfavourable) everywhere, II on the left, I on the right.
            background: 0.15,
            patches: vec![
                Patch {
                    min: [0.0, 0.0],
                    max: [40.0, 80.0],
                    value: 0.6,
                },
                Patch {
                    min: [80.0, 0.0],
                    max: [120.0, 80.0],
                    value: 1.0,
                },
            ],
            start: [20.0, 40.0],
            heading_deg: 0.0,
            spacer_sd: 0.0,
            alpha_sd_deg: 0.0,
            trifoliate: false,
        }
    }
}

impl ClonalParams {
    /// The listing with Fig. 7's extensions: spacer lengths with a standard
    /// deviation of 15 % of `Len`, branching angles with one of 10°, and
    /// trifoliate leaves (the deviations are ours; the source prints none).
    #[must_use]
    pub fn fig7() -> Self {
        let d = Self::default();
        Self {
            spacer_sd: 0.15 * d.spacer,
            alpha_sd_deg: 10.0,
            trifoliate: true,
            ..d
        }
    }

    /// Checks probabilities stay in [0, 1] and leaf areas positive for light
    /// in [0, 1], lengths and sizes are positive and finite, light values lie
    /// in [0, 1] and the raster has at most 4096 × 4096 cells.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        check::finite("ClonalParams::alpha_deg", self.alpha_deg)?;
        check::in_range(
            "ClonalParams::min_light",
            self.min_light,
            0.0,
            1.0,
            "in [0, 1]",
        )?;
        check::count(
            "ClonalParams::max_age",
            self.max_age as usize,
            1,
            100_000,
            "1 to 100000",
        )?;
        check::positive("ClonalParams::spacer", self.spacer)?;
        for (name, [a, b]) in [
            ("ClonalParams::prob_branch", self.prob_branch),
            ("ClonalParams::prob_ramet", self.prob_ramet),
        ] {
            check::in_range(
                name,
                a,
                0.0,
                1.0,
                "probabilities in [0, 1] for light in [0, 1]",
            )?;
            check::in_range(
                name,
                a + b,
                0.0,
                1.0,
                "probabilities in [0, 1] for light in [0, 1]",
            )?;
        }
        let [a0, a1] = self.leaf_area;
        check::positive("ClonalParams::leaf_area", a0)?;
        check::positive("ClonalParams::leaf_area", a0 - a1)?;
        check::count(
            "ClonalParams::steps",
            self.steps as usize,
            0,
            10_000,
            "at most 10000",
        )?;
        check_layout(
            [
                "ClonalParams::origin",
                "ClonalParams::size",
                "ClonalParams::cell",
            ],
            self.origin,
            self.size,
            self.cell,
        )?;
        check::in_range(
            "ClonalParams::background",
            self.background,
            0.0,
            1.0,
            "in [0, 1]",
        )?;
        check_patches(
            "ClonalParams::patches",
            &self.patches,
            0.0,
            1.0,
            "light in [0, 1]",
        )?;
        check::finite("ClonalParams::start", self.start[0])?;
        check::finite("ClonalParams::start", self.start[1])?;
        check::finite("ClonalParams::heading_deg", self.heading_deg)?;
        check::in_range(
            "ClonalParams::spacer_sd",
            self.spacer_sd,
            0.0,
            self.spacer,
            "in [0, spacer]",
        )?;
        check::in_range(
            "ClonalParams::alpha_sd_deg",
            self.alpha_sd_deg,
            0.0,
            90.0,
            "in [0, 90] degrees",
        )?;
        Ok(())
    }

    /// The model's L-system text (the source's listing with the readings above).
    #[must_use]
    pub fn lsystem_text(&self) -> String {
        let spacer = if self.spacer_sd > 0.0 {
            format!("max(0.1*Len, nran(Len, {}))", self.spacer_sd)
        } else {
            "Len".into()
        };
        let angle = if self.alpha_sd_deg > 0.0 {
            format!("nran(α, {})", self.alpha_sd_deg)
        } else {
            "α".into()
        };
        let leaves = if self.trifoliate {
            "homomorphism:\n\
             @o(r,age) -> [[&(90)~L(r,0.7*r)]/(120)[&(90)~L(r,0.7*r)]/(120)[&(90)~L(r,0.7*r)]]\n"
        } else {
            ""
        };
        format!(
            "#define α {}\n#define MinLight {}\n#define MaxAge {}\n#define Len {}\n\
             #define Sp ({spacer})\n#define Alpha ({angle})\n\
             #define ProbB(x) ({}+x*{})\n#define ProbR(x) ({}+x*{})\n\
             #define Radius(x) (sqrt(({}-x*{})/{}))\n\
             ω: A(1)?E(0,0)\n\
             p1: A(dir) > ?E(t,x) : (t == 0) && (x >= MinLight) -> R(x)B(x,dir)F(Sp,0)A(-dir)?E(0,0)\n\
             p2: A(dir) > ?E(t,x) : (t == 0) && (x < MinLight) -> ε\n\
             p3: B(x,dir) -> [+(Alpha*dir)F(Sp,0)A(-dir)?E(0,0)] : ProbB(x)\n\
             p4: B(x,dir) -> ε : 1-ProbB(x)\n\
             p5: R(x) -> [^(90)@o(Radius(x),0)?E(1,Radius(x))] : ProbR(x)\n\
             p6: R(x) -> ε : 1-ProbR(x)\n\
             p7: @o(radius,age) : age < MaxAge -> @o(radius,age+1)\n\
             p8: @o(radius,age) : age == MaxAge -> ?E(2,radius)\n\
             p9: F(len,age) : age < MaxAge -> F(len,age+1)\n\
             p10: F(len,age) : age == MaxAge -> f(len)\n\
             p11: ?E(t,x) -> ε\n{leaves}",
            self.alpha_deg,
            self.min_light,
            self.max_age,
            self.spacer,
            self.prob_branch[0],
            self.prob_branch[1],
            self.prob_ramet[0],
            self.prob_ramet[1],
            self.leaf_area[0],
            self.leaf_area[1],
            std::f64::consts::PI,
        )
    }

    /// The ground this run starts on: the painted raster and no ramets.
    ///
    /// # Errors
    ///
    /// [`ClonalParams::validate`]'s errors.
    pub fn ground(&self) -> Result<LightPatches> {
        self.validate()?;
        let (nx, ny, values) = rasterize(
            &self.patches,
            self.background,
            self.origin,
            self.cell,
            self.size,
        );
        Ok(LightPatches {
            origin: self.origin,
            cell: self.cell,
            nx,
            ny,
            light: values,
            live: Vec::new(),
            born: Vec::new(),
        })
    }
}

/// The environment: a raster of light intensities and the clone's live ramets.
#[derive(Clone, Debug, Default)]
pub struct LightPatches {
    /// Lower corner of the raster.
    pub origin: [f64; 2],
    /// Side of a cell.
    pub cell: f64,
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Light of each cell, row by row (`light[j·nx + i]`).
    pub light: Vec<f64>,
    /// Centres and radii of the live ramets.
    pub live: Vec<(DVec3, f64)>,
    /// Centres and radii of every ramet born so far.
    pub born: Vec<(DVec3, f64)>,
}

impl LightPatches {
    /// Light of the raster at `p` (0 outside), ignoring ramets.
    #[must_use]
    pub fn ground_light(&self, p: DVec3) -> f64 {
        let i = ((p.x - self.origin[0]) / self.cell).floor();
        let j = ((p.y - self.origin[1]) / self.cell).floor();
        if i < 0.0 || j < 0.0 || i >= self.nx as f64 || j >= self.ny as f64 {
            return 0.0;
        }
        self.light[j as usize * self.nx + i as usize]
    }

    /// Light reaching the ground at `p`: 0 under a ramet, else [`Self::ground_light`].
    #[must_use]
    pub fn light_at(&self, p: DVec3) -> f64 {
        if self
            .live
            .iter()
            .any(|&(c, r)| c.distance_squared(p) < r * r)
        {
            0.0
        } else {
            self.ground_light(p)
        }
    }
}

impl Environment for LightPatches {
    fn respond(&mut self, _step: u32, m: &[Message], r: &mut Vec<Reply>) -> Result<()> {
        let kind = |msg: &Message| msg.values.first().copied().unwrap_or(-1.0);
        for msg in m {
            let p = msg.state.frame.p;
            let radius = msg.values.get(1).copied().unwrap_or(0.0);
            match kind(msg) {
                0.0 => {}
                1.0 => {
                    self.live.push((p, radius));
                    self.born.push((p, radius));
                }
                2.0 => {
                    // Dead spacers become `f`, so a ramet's position is recomputed exactly.
                    let tol = 1e-6 * (1.0 + p.length());
                    let at = self.live.iter().position(|&(c, rr)| {
                        c.distance(p) <= tol && (rr - radius).abs() <= 1e-9 * (1.0 + rr)
                    });
                    match at {
                        Some(i) => {
                            self.live.swap_remove(i);
                        }
                        None => {
                            return Err(PlantError::Environment {
                                message: format!("death of an unknown ramet at {p}"),
                            });
                        }
                    }
                }
                k => {
                    return Err(PlantError::Environment {
                        message: format!("?E of type {k}; the clonal model knows 0, 1 and 2"),
                    });
                }
            }
        }
        for msg in m.iter().filter(|msg| kind(msg) == 0.0) {
            r.push(Reply {
                address: msg.address,
                values: vec![0.0, self.light_at(msg.state.frame.p)],
            });
        }
        Ok(())
    }
}

/// The turtle of the clone: in the ground plane (`z = 0`) at the start, heading as given.
fn turtle(p: &ClonalParams, l: &LSystem) -> TurtleParams {
    let a = p.heading_deg.to_radians();
    let h = DVec3::new(a.cos(), a.sin(), 0.0);
    let left = DVec3::new(-a.sin(), a.cos(), 0.0);
    TurtleParams {
        start: TurtleFrame::new(DVec3::new(p.start[0], p.start[1], 0.0), h, left),
        ..TurtleParams::for_lsystem(l)
    }
}

/// Grows the clone; returns the run and the ground with its ramets.
///
/// # Errors
///
/// [`ClonalParams::validate`]'s errors; derivation, turtle and environment errors.
pub fn clonal(p: &ClonalParams) -> Result<(Run, LightPatches)> {
    let mut env = p.ground()?;
    let l = LSystem::parse(&p.lsystem_text())?;
    let t = turtle(p, &l);
    let run = run_open(l, t, &mut env, p.steps, p.seed)?;
    Ok((run, env))
}

#[cfg(test)]
mod tests;
