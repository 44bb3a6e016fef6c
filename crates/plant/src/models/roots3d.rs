//! Roots growing in soil water in three dimensions.
//!
//! Měch & Prusinkiewicz 1996, §7, Fig. 10: the 3-D extension of the roots
//! model of [`super::roots`]. The source shows the result and its counts
//! only; the extension here is ours, and the smallest one that keeps the
//! 2-D model's rules:
//!
//! * the soil is a block of cubic cells. Its initial water is the 2-D
//!   section's painted layout (`x` across, `z` up) repeated along `y`;
//!   diffusion is the explicit 7-point step `C += k·(ΣC_neighbours − 6C)`
//!   with no flux through the faces, stable for `k ≤ 1/6`;
//! * an apex receives `min(requested, available)` from its cell, as in 2-D,
//!   and the turn `T = H + Sens·∇C` uses the 3-D gradient (central
//!   differences, one-sided at the faces);
//! * the reply `?E(c, θ, φ)` adds a roll `φ` about the heading that brings
//!   `T` into the plane of `H` and `L`, so that `/(φ)+(θ)` turns `H` onto
//!   `T`. The random deviation `nran(θ, Dev[n])` of the turn is joined by a
//!   pitch `nran(0, Dev[n])` so the heading wanders in both directions
//!   across it.
//!
//! Roots that take water from a region lower the water there, so
//! neighbouring roots, which follow the gradient, grow apart (the source's
//! observation for Fig. 10). Several root systems may share the block
//! ([`Roots3dParams::systems`]), as the source's figure shows two, each
//! drinking what the others leave.
//!
//! Table 1 of the source gives Fig. 10 37 228 segments and 448 active apices
//! after 301 steps. The defaults here make 4 793 segments and 22 apices: the
//! source prints neither its 3-D soil and water nor its extension's rules,
//! and its much larger count suggests a wetter soil or different parameters
//! than the 2-D listing's.

use glam::DVec3;
use natura_core::check;

use super::roots::{RootParams, turtle};
use super::{Run, run_open};
use crate::error::{PlantError, Result};
use crate::lang::LSystem;
use crate::open::{Environment, Message, Reply};

/// Parameters of the 3-D root system: the 2-D model's parameters and the
/// soil's extent along `y`.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct Roots3dParams {
    /// The plant, the painted section (`origin`, `size`, `cell`, `patches`
    /// in `x`–`z`), the diffusion rate (at most 1/6 here), steps and seed.
    pub roots: RootParams,
    /// Extent of the soil along `y`, centred on the start.
    pub breadth: f64,
    /// Where each root system starts: `[x, y]` offsets from `roots.start`
    /// on the surface (one system at the start by default; at most
    /// [`MAX_ROOT_SYSTEMS`]). The systems share the soil and compete for
    /// its water.
    pub systems: Vec<[f64; 2]>,
}

/// The most root systems one block of soil holds.
pub const MAX_ROOT_SYSTEMS: usize = 64;

impl Default for Roots3dParams {
    /// The 2-D defaults on 2-unit cells, 301 steps (Fig. 10), 60 units broad.
    fn default() -> Self {
        Self {
            roots: RootParams {
                cell: 2.0,
                steps: 301,
                ..RootParams::default()
            },
            breadth: 60.0,
            systems: vec![[0.0, 0.0]],
        }
    }
}

impl Roots3dParams {
    /// The L-system text: the listing's, its axiom one apex and query at
    /// each system's start (reached by turtle moves, inside a branch).
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming `Roots3dParams::systems` if
    /// there are none or more than [`MAX_ROOT_SYSTEMS`], or an offset is
    /// not finite or starts outside the block of soil.
    pub fn lsystem_text(&self) -> Result<String> {
        let bad = |v: String, reason: &str| PlantError::InvalidParameter {
            name: "Roots3dParams::systems",
            value: v,
            reason: reason.into(),
        };
        if self.systems.is_empty() || self.systems.len() > MAX_ROOT_SYSTEMS {
            return Err(bad(
                format!("{} systems", self.systems.len()),
                "1 to 64 root systems",
            ));
        }
        let r = &self.roots;
        for s in &self.systems {
            let x = r.start[0] + s[0];
            let inside = s.iter().all(|v| v.is_finite())
                && x >= r.origin[0]
                && x <= r.origin[0] + r.size[0]
                && s[1].abs() <= 0.5 * self.breadth;
            if !inside {
                return Err(bad(
                    format!("{s:?}"),
                    "finite offsets starting inside the soil",
                ));
            }
        }
        if self.systems == [[0.0, 0.0]] {
            return Ok(r.text(true));
        }
        // From the start frame (heading down, left +x, up −y): `+` turns
        // towards +x and `&` towards +y.
        let axiom: String = self
            .systems
            .iter()
            .map(|[x, y]| {
                format!("[+(90)f({x:?})-(90)&(90)f({y:?})^(90)A(0,0,0)?E(Req[0],Sens[0]{{z}})]")
            })
            .collect();
        Ok(r.text_from(true, &axiom))
    }
}

/// The environment: water amounts in the cubic cells of a block of soil.
#[derive(Clone, Debug, Default)]
pub struct SoilWater3 {
    /// Lower corner `[x, y, z]` of the block.
    pub origin: [f64; 3],
    /// Side of a cell.
    pub cell: f64,
    /// Cells along x, y and z.
    pub n: [usize; 3],
    /// Water of each cell, `water[(k·ny + j)·nx + i]` (k along z).
    pub water: Vec<f64>,
    /// Diffusion rate per step `k = D·Δt/cell²`.
    pub diffusion: f64,
    /// Total water taken up by the roots so far.
    pub taken: f64,
}

impl SoilWater3 {
    /// The soil a run of `p` starts in.
    ///
    /// # Errors
    ///
    /// [`RootParams::validate`]'s errors, a diffusion rate above 1/6, or a
    /// breadth that is not positive or spans more than 4096 cells.
    pub fn new(p: &Roots3dParams) -> Result<Self> {
        let r = &p.roots;
        let sec = r.soil()?;
        check::in_range(
            "Roots3dParams::roots.diffusion",
            r.diffusion,
            0.0,
            1.0 / 6.0,
            "in [0, 1/6] in 3-D",
        )?;
        check::positive("Roots3dParams::breadth", p.breadth)?;
        let ny = (p.breadth / r.cell).round();
        check::in_range("Roots3dParams::breadth", ny, 1.0, 4096.0, "1 to 4096 cells")?;
        let ny = ny as usize;
        let cells = sec.nx * ny * sec.nz;
        if cells > 1 << 26 {
            return Err(PlantError::InvalidParameter {
                name: "Roots3dParams::breadth",
                value: format!("{cells} cells"),
                reason: "at most 2^26 soil cells".into(),
            });
        }
        let mut water = Vec::with_capacity(cells);
        for k in 0..sec.nz {
            let row = &sec.water[k * sec.nx..(k + 1) * sec.nx];
            for _ in 0..ny {
                water.extend_from_slice(row);
            }
        }
        Ok(Self {
            origin: [r.origin[0], -0.5 * ny as f64 * r.cell, r.origin[1]],
            cell: r.cell,
            n: [sec.nx, ny, sec.nz],
            water,
            diffusion: r.diffusion,
            taken: 0.0,
        })
    }

    /// Total water in the block.
    #[must_use]
    pub fn total(&self) -> f64 {
        self.water.iter().sum()
    }

    /// Index of the cell holding `p`, if inside.
    #[must_use]
    pub fn cell_of(&self, p: DVec3) -> Option<[usize; 3]> {
        let mut out = [0; 3];
        for a in 0..3 {
            let c = ((p[a] - self.origin[a]) / self.cell).floor();
            if !(c >= 0.0 && c < self.n[a] as f64) {
                return None;
            }
            out[a] = c as usize;
        }
        Some(out)
    }

    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.n[1] + c[1]) * self.n[0] + c[0]
    }

    /// One explicit diffusion step with no flux through the faces.
    pub fn diffuse(&mut self) {
        let k = self.diffusion;
        if k == 0.0 {
            return;
        }
        let [nx, ny, nz] = self.n;
        let c = self.water.clone();
        let (sy, sz) = (nx, nx * ny);
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let i = z * sz + y * sy + x;
                    let me = c[i];
                    let mut d = 0.0;
                    if x > 0 {
                        d += c[i - 1] - me;
                    }
                    if x + 1 < nx {
                        d += c[i + 1] - me;
                    }
                    if y > 0 {
                        d += c[i - sy] - me;
                    }
                    if y + 1 < ny {
                        d += c[i + sy] - me;
                    }
                    if z > 0 {
                        d += c[i - sz] - me;
                    }
                    if z + 1 < nz {
                        d += c[i + sz] - me;
                    }
                    self.water[i] = me + k * d;
                }
            }
        }
    }

    /// The water gradient at cell `c`.
    #[must_use]
    pub fn gradient(&self, c: [usize; 3]) -> DVec3 {
        let mut g = DVec3::ZERO;
        for a in 0..3 {
            let (mut lo, mut hi) = (c, c);
            lo[a] = c[a].saturating_sub(1);
            hi[a] = (c[a] + 1).min(self.n[a] - 1);
            if hi[a] > lo[a] {
                g[a] = (self.water[self.index(hi)] - self.water[self.index(lo)])
                    / ((hi[a] - lo[a]) as f64 * self.cell);
            }
        }
        g
    }
}

/// The turn and roll, in degrees, that bring the heading of `f` onto `t`:
/// rolling by `φ` about `H` and then turning by `θ` about the new `U`
/// (`/(φ)+(θ)`) makes `H` parallel to `t`.
#[must_use]
pub fn turn_towards(f: &crate::turtle::TurtleFrame, t: DVec3) -> (f64, f64) {
    let (th, tl, tu) = (t.dot(f.h), t.dot(f.l), t.dot(f.u));
    let side = tl.hypot(tu);
    if side == 0.0 {
        return if th >= 0.0 { (0.0, 0.0) } else { (180.0, 0.0) };
    }
    (side.atan2(th).to_degrees(), tu.atan2(tl).to_degrees())
}

impl Environment for SoilWater3 {
    fn respond(&mut self, _step: u32, m: &[Message], r: &mut Vec<Reply>) -> Result<()> {
        self.diffuse();
        for msg in m {
            let (Some(&req), Some(&sens)) = (msg.values.first(), msg.values.get(1)) else {
                return Err(PlantError::Environment {
                    message: format!("?E at {} needs three parameters", msg.address),
                });
            };
            let f = &msg.state.frame;
            let (got, grad) = match self.cell_of(f.p) {
                Some(c) => {
                    let i = self.index(c);
                    let got = req.max(0.0).min(self.water[i]);
                    self.water[i] -= got;
                    self.taken += got;
                    (got, self.gradient(c))
                }
                None => (0.0, DVec3::ZERO),
            };
            let (theta, phi) = turn_towards(f, f.h + sens * grad);
            r.push(Reply {
                address: msg.address,
                values: vec![got, theta, phi],
            });
        }
        Ok(())
    }
}

/// Grows the roots in 3-D soil; returns the run and the soil as it is left.
///
/// # Errors
///
/// [`SoilWater3::new`]'s errors; derivation, turtle and environment errors.
pub fn roots_3d(p: &Roots3dParams) -> Result<(Run, SoilWater3)> {
    let mut env = SoilWater3::new(p)?;
    let l = LSystem::parse(&p.lsystem_text()?)?;
    let t = turtle(&p.roots, &l);
    let run = run_open(l, t, &mut env, p.roots.steps, p.roots.seed)?;
    Ok((run, env))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::turtle::TurtleFrame;

    #[test]
    fn roll_and_turn_bring_the_heading_onto_the_target() {
        let f0 = TurtleFrame::new(DVec3::ZERO, DVec3::NEG_Z, DVec3::X);
        for t in [
            DVec3::new(1.0, 2.0, -0.5),
            DVec3::new(-0.3, -1.0, 2.0),
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(0.2, 0.0, 1.0),
        ] {
            let (th, ph) = turn_towards(&f0, t);
            let mut f = f0;
            f.roll(ph.to_radians());
            f.turn(th.to_radians());
            assert!((f.h - t.normalize()).length() < 1e-9, "{t}: {:?}", f.h);
        }
    }

    fn small(seed: u64) -> Roots3dParams {
        Roots3dParams {
            roots: RootParams {
                steps: 120,
                seed,
                ..Roots3dParams::default().roots
            },
            breadth: 40.0,
            ..Roots3dParams::default()
        }
    }

    #[test]
    fn two_systems_share_the_soil() {
        // One system at the start is the listing's own axiom; two systems
        // 20 apart both grow from their starts, drink from one soil (water
        // is conserved) and refuse to start outside it.
        let one = small(3);
        assert_eq!(one.lsystem_text().unwrap(), one.roots.text(true));
        let two = Roots3dParams {
            systems: vec![[-10.0, 0.0], [10.0, 0.0]],
            ..small(3)
        };
        let soil0 = SoilWater3::new(&two).unwrap();
        let (run, soil) = roots_3d(&two).unwrap();
        let total0 = soil0.total();
        assert!((soil.total() + soil.taken - total0).abs() < 1e-9 * total0);
        let g = run.geometry().unwrap();
        let x0 = two.roots.start[0];
        for dx in [-10.0, 10.0] {
            let at = DVec3::new(x0 + dx, 0.0, two.roots.start[1]);
            let near = g.start.iter().any(|s| s.as_dvec3().distance(at) < 1e-6);
            assert!(near, "a root starts at {at}");
        }
        let (_, soil1) = roots_3d(&small(3)).unwrap();
        assert!(
            soil.taken > 1.3 * soil1.taken,
            "{} against {}",
            soil.taken,
            soil1.taken
        );
        for systems in [
            vec![],
            vec![[f64::NAN, 0.0]],
            vec![[0.0, 100.0]],
            vec![[500.0, 0.0]],
        ] {
            let p = Roots3dParams {
                systems,
                ..small(3)
            };
            let e = roots_3d(&p).unwrap_err().to_string();
            assert!(e.contains("Roots3dParams::systems"), "{e}");
        }
    }

    #[test]
    fn water_is_conserved_and_roots_prefer_the_wet_side() {
        let p = small(2);
        let soil0 = SoilWater3::new(&p).unwrap();
        let (run, soil) = roots_3d(&p).unwrap();
        let total0 = soil0.total();
        assert!(
            (soil.total() + soil.taken - total0).abs() < 1e-9 * total0,
            "{} + {} vs {total0}",
            soil.total(),
            soil.taken
        );
        let g = run.geometry().unwrap();
        assert!(g.start.len() > 200, "{}", g.start.len());
        // Root length in the wet (x < 0) and dry (x > 0) halves.
        let (mut wet, mut dry) = (0.0, 0.0);
        let mut off_plane = 0.0f32;
        for (a, b) in g.start.iter().zip(&g.end) {
            let len = f64::from(a.distance(*b));
            if a.x + b.x < 0.0 {
                wet += len
            } else {
                dry += len
            }
            off_plane = off_plane.max(b.y.abs());
        }
        assert!(wet > 2.0 * dry, "wet {wet} dry {dry}");
        // The roots leave the plane of the section: the model is 3-D.
        assert!(off_plane > 3.0, "{off_plane}");
    }

    #[test]
    fn environment_sees_every_apex_with_three_values() {
        let p = small(4);
        let l = LSystem::parse(&p.roots.text(true)).unwrap();
        let (run, _) = roots_3d(&Roots3dParams {
            roots: RootParams {
                steps: 40,
                ..p.roots.clone()
            },
            ..p.clone()
        })
        .unwrap();
        // After the last step every live apex is followed by its ?E.
        assert_eq!(run.count("A"), run.count("?E"));
        let e = l.symbol("?E").unwrap();
        let s = &run.string;
        assert!(
            (0..s.len())
                .filter(|&i| s.symbol(i) == e)
                .all(|i| s.params(i).len() == 3)
        );
    }

    #[test]
    fn bad_soil_is_a_typed_error() {
        let d = Roots3dParams::default;
        for p in [
            Roots3dParams {
                breadth: 0.0,
                ..d()
            },
            Roots3dParams {
                breadth: f64::NAN,
                ..d()
            },
            Roots3dParams {
                roots: RootParams {
                    diffusion: 0.2,
                    ..d().roots
                },
                ..d()
            },
        ] {
            assert!(matches!(
                SoilWater3::new(&p),
                Err(PlantError::InvalidParameter { .. })
            ));
        }
    }
}
