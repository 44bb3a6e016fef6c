//! Roots growing in soil water, in a vertical section of the soil.
//!
//! Měch & Prusinkiewicz 1996, §7, Fig. 8–9 (after Clausnitzer & Hopmans
//! 1994 for the root parameters and Diggle 1988 for the architecture): each
//! root apex `A(n, s, b)` (branch order `n`, axis length `s`, distance `b`
//! from the last branch initial) sends `?E(c, θ)` with its requested uptake
//! `c = Req[n]` and its sensitivity to the water gradient `θ = Sens[n]`. The
//! environment ([`SoilWater`]) answers with the water the apex received and
//! the angle it should turn; the apex grows `h = c/Req[n]·ElRate[n]` with a
//! heading perturbed by `nran(θ, Dev[n])`, leaves a branch initial `B` every
//! `BrSpace[n]`, which waits `Del[n]` steps before starting an axis of order
//! `n + 1`, and dies when its axis exceeds `MaxLen[n]` or it receives less
//! than `MinReq[n]`.
//!
//! The soil is a field of water amounts in square cells of a vertical
//! section (`x` across, `z` up, soil below the start). In each communication
//! phase the water first diffuses one explicit finite-difference step
//! `C += k·(ΣC_neighbours − 4C)` with no flux through the field's edges (so
//! diffusion alone keeps the total), then the apices are served in string
//! order: an apex in a cell receives `min(requested, available)`, which is
//! taken from the cell. The turning angle is the signed angle between the
//! heading `H` and `T = H + θ·∇C`, the gradient estimated by central
//! differences over the neighbouring cells (one-sided at the edges).
//!
//! Errata and readings: p5's successor is printed `[(BrAngle[n])A(…)…]`; the
//! turn symbol was lost and is restored as `+(BrAngle[n])`. The source
//! combines `H` and `∇C` linearly without printing the weights; `T = H +
//! Sens·∇C` is our reading. The arrays `Del`, `BrAngle` and `BrSpace` have a
//! third, unused entry here so that conditions evaluated for the highest
//! order stay within bounds. The initial water is painted in the source
//! (values not printed); the default layout (a drier top layer, wet soil
//! below on the left, dry on the right) and the diffusion rate are ours.
//! An apex outside the field finds no water.
//!
//! Table 1 of the source gives Fig. 9 4 194 branch segments and 34 active
//! apices after 186 steps. The defaults here make 2 375 to 2 537 segments
//! and 23 to 32 active apices over seeds 0 to 7 (the default seed 1: 2 479
//! and 32): the apices come close to the table's, the segments do not.
//! Served in full everywhere (plenty of water, a field no root leaves), the
//! listing grows exactly 2 472 segments and 32 apices in 186 steps whatever
//! the seed (a test checks): the main axis's 186, a lateral every second
//! step after its 30-step delay, each of up to 21 segments, and rootlets of
//! two. More segments come only from apices served less than they ask,
//! whose segments are shorter; but drier soil here stops the laterals
//! (below `MinReq`) rather than slowing them, and none of the soils tried
//! (uniform water from 0.2 to 1 000 a cell with diffusion rates from 0.02
//! to 0.25, and the default layout's levels from 0.5 to 6) gives more than
//! about 2 800. The source's soil also had painted boundary values, water
//! the field's edges may feed in; this environment has no flux through its
//! edges, and the source prints neither.

use glam::DVec3;
use natura_core::check;

use super::{Patch, Run, check_layout, check_patches, rasterize, run_open};
use crate::error::{PlantError, Result};
use crate::lang::LSystem;
use crate::open::{Environment, Message, Reply};
use crate::turtle::{TurtleFrame, TurtleParams};

/// Parameters of the root system and its soil (defaults: the source's listing).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct RootParams {
    /// Requested water intake per step by branch order (`Req`).
    pub request: [f64; 3],
    /// Minimum intake below which an apex dies (`MinReq`).
    pub min_request: [f64; 3],
    /// Maximum elongation per step (`ElRate`).
    pub elongation: [f64; 3],
    /// Maximum axis length (`MaxLen`).
    pub max_length: [f64; 3],
    /// Sensitivity to the water gradient (`Sens`).
    pub sensitivity: [f64; 3],
    /// Standard deviation of the heading change, degrees (`Dev`).
    pub deviation_deg: [f64; 3],
    /// Steps a branch initial of order 0, 1 waits (`Del`).
    pub delay: [u32; 2],
    /// Branching angle of orders 0, 1, degrees (`BrAngle`).
    pub branch_angle_deg: [f64; 2],
    /// Distance between branch initials on orders 0, 1 (`BrSpace`).
    pub branch_spacing: [f64; 2],
    /// Derivation steps (186 for Fig. 9).
    pub steps: u32,
    /// Seed of the random heading changes.
    pub seed: u64,
    /// Lower corner `[x, z]` of the soil field.
    pub origin: [f64; 2],
    /// Size `[width, depth]` of the soil field.
    pub size: [f64; 2],
    /// Side of a soil cell.
    pub cell: f64,
    /// Water of a cell where no patch lies.
    pub background: f64,
    /// Regions of given water per cell, painted in order over the background.
    pub patches: Vec<Patch>,
    /// Diffusion rate per step `k = D·Δt/cell²`, in [0, 1/4] (0: no diffusion).
    pub diffusion: f64,
    /// Where the main root starts, `[x, z]`; it heads down (−z).
    pub start: [f64; 2],
}

impl Default for RootParams {
    fn default() -> Self {
        Self {
            request: [0.1, 0.4, 0.05],
            min_request: [0.01, 0.06, 0.01],
            elongation: [0.55, 0.25, 0.55],
            max_length: [200.0, 5.0, 0.8],
            sensitivity: [10.0, 0.0, 0.0],
            deviation_deg: [30.0, 75.0, 75.0],
            delay: [30, 60],
            branch_angle_deg: [90.0, 90.0],
            branch_spacing: [1.0, 0.5],
            steps: 186,
            seed: 1,
            origin: [-40.0, -100.0],
            size: [80.0, 100.0],
            cell: 1.0,
            background: 0.5,
            patches: vec![
                Patch {
                    min: [-40.0, -100.0],
                    max: [40.0, -4.0],
                    value: 2.0,
                },
                Patch {
                    min: [-40.0, -100.0],
                    max: [-5.0, -12.0],
                    value: 6.0,
                },
                Patch {
                    min: [5.0, -100.0],
                    max: [40.0, -12.0],
                    value: 0.05,
                },
            ],
            diffusion: 0.1,
            start: [0.0, -0.5],
        }
    }
}

impl RootParams {
    /// Checks rates and lengths are positive and finite, minima do not exceed
    /// requests, the diffusion rate lies in [0, 1/4] (the explicit scheme's
    /// stability bound), water is non-negative and the field has at most
    /// 4096 × 4096 cells.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        for k in 0..3 {
            check::positive("RootParams::request", self.request[k])?;
            check::in_range(
                "RootParams::min_request",
                self.min_request[k],
                0.0,
                self.request[k],
                "in [0, request]",
            )?;
            check::positive("RootParams::elongation", self.elongation[k])?;
            check::positive("RootParams::max_length", self.max_length[k])?;
            check::finite("RootParams::sensitivity", self.sensitivity[k])?;
            check::non_negative("RootParams::deviation_deg", self.deviation_deg[k])?;
        }
        for k in 0..2 {
            check::finite("RootParams::branch_angle_deg", self.branch_angle_deg[k])?;
            check::positive("RootParams::branch_spacing", self.branch_spacing[k])?;
        }
        check::count(
            "RootParams::steps",
            self.steps as usize,
            0,
            10_000,
            "at most 10000",
        )?;
        check_layout(
            ["RootParams::origin", "RootParams::size", "RootParams::cell"],
            self.origin,
            self.size,
            self.cell,
        )?;
        check::non_negative("RootParams::background", self.background)?;
        check_patches(
            "RootParams::patches",
            &self.patches,
            0.0,
            f64::MAX,
            "non-negative water",
        )?;
        check::in_range(
            "RootParams::diffusion",
            self.diffusion,
            0.0,
            0.25,
            "in [0, 1/4]",
        )?;
        check::finite("RootParams::start", self.start[0])?;
        check::finite("RootParams::start", self.start[1])?;
        Ok(())
    }

    /// The model's L-system text (the source's listing with the readings above).
    #[must_use]
    pub fn lsystem_text(&self) -> String {
        self.text(false)
    }

    /// The listing for a 2-D section, or for 3-D soil: there `?E(c, θ, φ)`
    /// carries a third value, the roll `φ` about the heading that brings the
    /// turn's direction into the turning plane, and the heading also pitches
    /// by `nran(0, Dev[n])`.
    pub(crate) fn text(&self, three_d: bool) -> String {
        self.text_from(three_d, "A(0,0,0)?E(Req[0],Sens[0]{z})")
    }

    /// The L-system text with the axiom `axiom` (`{z}` in it stands for the
    /// third value of a 3-D query).
    pub(crate) fn text_from(&self, three_d: bool, axiom: &str) -> String {
        let a3 = |v: [f64; 3]| format!("{{{}, {}, {}}}", v[0], v[1], v[2]);
        let a2 = |v: [f64; 2]| format!("{{{}, {}, 0}}", v[0], v[1]);
        let (e, roll, pitch, z) = if three_d {
            ("?E(c,th,ph)", "/(ph)", "&(nran(0,Dev[n]))", ",0")
        } else {
            ("?E(c,th)", "", "", "")
        };
        format!(
            "#define N 3\n\
             Define: {{ array Req[3] = {}, MinReq[3] = {}, ElRate[3] = {}, MaxLen[3] = {},\n\
             Sens[3] = {}, Dev[3] = {}, Del[3] = {}, BrAngle[3] = {}, BrSpace[3] = {} }}\n\
             ω: {axiom}\n\
             p1: A(n,s,b) > {e} : (s > MaxLen[n]) || (c < MinReq[n]) -> ε\n\
             p2: A(n,s,b) > {e} : (n >= N-1) || (b < BrSpace[n]) {{ h = c/Req[n]*ElRate[n]; }} \
             -> {roll}+(nran(th,Dev[n])){pitch}F(h)A(n,s+h,b+h)?E(Req[n],Sens[n]{z})\n\
             p3: A(n,s,b) > {e} : (n < N-1) && (b >= BrSpace[n]) {{ h = c/Req[n]*ElRate[n]; }} \
             -> {roll}+(nran(th,Dev[n])){pitch}B(n,0)F(h)/(180)A(n,s+h,h)?E(Req[n],Sens[n]{z})\n\
             p4: B(n,t) : t < Del[n] -> B(n,t+1)\n\
             p5: B(n,t) : t >= Del[n] -> [+(BrAngle[n])A(n+1,0,0)?E(Req[n+1],Sens[n+1]{z})]\n\
             p6: {e} -> ε\n",
            a3(self.request),
            a3(self.min_request),
            a3(self.elongation),
            a3(self.max_length),
            a3(self.sensitivity),
            a3(self.deviation_deg),
            a2([f64::from(self.delay[0]), f64::from(self.delay[1])]),
            a2(self.branch_angle_deg),
            a2(self.branch_spacing),
            axiom = axiom.replace("{z}", z),
        )
    }

    /// The soil this run starts in.
    ///
    /// # Errors
    ///
    /// [`RootParams::validate`]'s errors.
    pub fn soil(&self) -> Result<SoilWater> {
        self.validate()?;
        let (nx, nz, values) = rasterize(
            &self.patches,
            self.background,
            self.origin,
            self.cell,
            self.size,
        );
        Ok(SoilWater {
            origin: self.origin,
            cell: self.cell,
            nx,
            nz,
            water: values,
            diffusion: self.diffusion,
            taken: 0.0,
        })
    }
}

/// The environment: water amounts in the cells of a vertical soil section.
#[derive(Clone, Debug, Default)]
pub struct SoilWater {
    /// Lower corner `[x, z]` of the field.
    pub origin: [f64; 2],
    /// Side of a cell.
    pub cell: f64,
    /// Cells across (x).
    pub nx: usize,
    /// Cells down (z).
    pub nz: usize,
    /// Water of each cell, row by row from the bottom (`water[j·nx + i]`).
    pub water: Vec<f64>,
    /// Diffusion rate per step `k = D·Δt/cell²`.
    pub diffusion: f64,
    /// Total water taken up by the roots so far.
    pub taken: f64,
}

impl SoilWater {
    /// Total water in the field.
    #[must_use]
    pub fn total(&self) -> f64 {
        self.water.iter().sum()
    }

    /// The cell `(i, j)` holding the point `(x, z)`, if inside.
    #[must_use]
    pub fn cell_of(&self, x: f64, z: f64) -> Option<(usize, usize)> {
        let i = ((x - self.origin[0]) / self.cell).floor();
        let j = ((z - self.origin[1]) / self.cell).floor();
        (i >= 0.0 && j >= 0.0 && i < self.nx as f64 && j < self.nz as f64)
            .then_some((i as usize, j as usize))
    }

    /// One explicit diffusion step with no flux through the edges.
    pub fn diffuse(&mut self) {
        let k = self.diffusion;
        if k == 0.0 {
            return;
        }
        let (nx, nz) = (self.nx, self.nz);
        let c = self.water.clone();
        for j in 0..nz {
            for i in 0..nx {
                let me = c[j * nx + i];
                let mut d = 0.0;
                if i > 0 {
                    d += c[j * nx + i - 1] - me;
                }
                if i + 1 < nx {
                    d += c[j * nx + i + 1] - me;
                }
                if j > 0 {
                    d += c[(j - 1) * nx + i] - me;
                }
                if j + 1 < nz {
                    d += c[(j + 1) * nx + i] - me;
                }
                self.water[j * nx + i] = me + k * d;
            }
        }
    }

    /// The water gradient `[∂C/∂x, ∂C/∂z]` at cell `(i, j)`.
    #[must_use]
    pub fn gradient(&self, i: usize, j: usize) -> [f64; 2] {
        let nx = self.nx;
        let at = |i: usize, j: usize| self.water[j * nx + i];
        let diff = |lo: usize, hi: usize, a: f64, b: f64| {
            if hi > lo {
                (b - a) / ((hi - lo) as f64 * self.cell)
            } else {
                0.0
            }
        };
        let (il, ih) = (i.saturating_sub(1), (i + 1).min(nx - 1));
        let (jl, jh) = (j.saturating_sub(1), (j + 1).min(self.nz - 1));
        [
            diff(il, ih, at(il, j), at(ih, j)),
            diff(jl, jh, at(i, jl), at(i, jh)),
        ]
    }
}

impl Environment for SoilWater {
    fn respond(&mut self, _step: u32, m: &[Message], r: &mut Vec<Reply>) -> Result<()> {
        self.diffuse();
        for msg in m {
            let (Some(&req), Some(&sens)) = (msg.values.first(), msg.values.get(1)) else {
                return Err(PlantError::Environment {
                    message: format!("?E at {} needs two parameters", msg.address),
                });
            };
            let f = &msg.state.frame;
            let (got, grad) = match self.cell_of(f.p.x, f.p.z) {
                Some((i, j)) => {
                    let w = &mut self.water[j * self.nx + i];
                    let got = req.max(0.0).min(*w);
                    *w -= got;
                    self.taken += got;
                    (got, self.gradient(i, j))
                }
                None => (0.0, [0.0, 0.0]),
            };
            let t = f.h + sens * DVec3::new(grad[0], 0.0, grad[1]);
            let angle = t.dot(f.l).atan2(t.dot(f.h)).to_degrees();
            r.push(Reply {
                address: msg.address,
                values: vec![got, angle],
            });
        }
        Ok(())
    }
}

/// The turtle of the roots: heading down (−z), turning in the x–z plane.
pub(crate) fn turtle(p: &RootParams, l: &LSystem) -> TurtleParams {
    TurtleParams {
        start: TurtleFrame::new(
            DVec3::new(p.start[0], 0.0, p.start[1]),
            DVec3::NEG_Z,
            DVec3::X,
        ),
        ..TurtleParams::for_lsystem(l)
    }
}

/// Grows the roots; returns the run and the soil as it is left.
///
/// # Errors
///
/// [`RootParams::validate`]'s errors; derivation, turtle and environment errors.
pub fn roots(p: &RootParams) -> Result<(Run, SoilWater)> {
    let mut env = p.soil()?;
    let l = LSystem::parse(&p.lsystem_text())?;
    let t = turtle(p, &l);
    let run = run_open(l, t, &mut env, p.steps, p.seed)?;
    Ok((run, env))
}

#[cfg(test)]
mod tests;
