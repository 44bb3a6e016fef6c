//! Turtle interpretation of module strings in 3-D (Prusinkiewicz &
//! Lindenmayer 1990, §1.3–1.5, §2.3, §5.1; the cpfg symbol set).
//!
//! | module | meaning |
//! |---|---|
//! | `F`, `F(l)` | move forward by `l` (default step), drawing a segment; in a polygon, record a vertex |
//! | `f`, `f(l)` | move forward without drawing; in a polygon, record a vertex |
//! | `G`, `g` (`(l)`) | move forward without drawing or recording |
//! | `+ -` (`(a)`) | turn left / right about `U` by `a` degrees (default angle) |
//! | `& ^` (`(a)`) | pitch down / up about `L` |
//! | `/ \` (`(a)`) | roll right / left about `H` |
//! | `\|` | turn around (180° about `U`) |
//! | `$` | roll so that `L` is horizontal |
//! | `[ ]` | push / pop the turtle state (start / end a branch) |
//! | `!`, `!(w)` | multiply the width by the width factor / set the width |
//! | `#(w)` | set the width, tapering the next segment from the old width to `w` |
//! | `'`, `'(c)` | next colour index / set the colour index |
//! | `{ . }` | start a polygon / record a vertex / close the polygon |
//! | `~X`, `~X(s)`, `~X(l,w)` | predefined surface `X` (leaf `L`, petal `P`, sphere `O`, flower `K`, or one registered by the caller) |
//! | `@o(r)` / `@O(r)` | disc / sphere of radius `r` |
//! | `?P ?H ?L ?U (x,y,z)` | query modules: receive the position or an axis ([`crate::open`]) |
//!
//! Every other module is ignored by the turtle.

mod frame;
mod geometry;
mod walk;

pub use frame::{MAX_CURVE_SAMPLES, TurtleFrame, rotate, track_curve};
pub use geometry::{Geometry, MAX_POLYGON_VERTICES, Polygon, SurfaceInstance};

/// The farthest the turtle may go from the origin along any axis, and the
/// largest width or surface size it draws: far enough for any plant, near
/// enough that meshes (in `f32`) stay finite.
pub const MAX_EXTENT: f64 = 1e12;

use crate::engine::{Cap, Limits, expand};
use crate::error::{PlantError, Result};
use crate::lang::LSystem;
use crate::lang::vm::{Env, Rng};
use crate::string::ModuleString;
use glam::DVec3;

/// Settings of the turtle.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct TurtleParams {
    /// Default turning angle in degrees (used when a rotation has no parameter).
    pub angle_deg: f64,
    /// Default step length (used when a move has no parameter).
    pub step: f64,
    /// Initial width (diameter) of segments.
    pub width: f64,
    /// Factor applied to the width by `!` without a parameter.
    pub width_factor: f64,
    /// Tropism vector `T` (ABOP §2.3, p. 58): after each `F` the heading bends towards it.
    pub tropism: DVec3,
    /// Susceptibility `e` to the tropism (0 disables it).
    pub elasticity: f64,
    /// The turtle's initial frame.
    pub start: TurtleFrame,
}

impl Default for TurtleParams {
    /// 90°, unit steps, width 0.1 narrowing by 0.7, no tropism, heading +z.
    fn default() -> Self {
        Self {
            angle_deg: 90.0,
            step: 1.0,
            width: 0.1,
            width_factor: 0.7,
            tropism: DVec3::ZERO,
            elasticity: 0.0,
            start: TurtleFrame::default(),
        }
    }
}

impl TurtleParams {
    /// Returns the defaults with the L-system's `angle:`, `step:` and
    /// `tropism:` directives applied.
    #[must_use]
    pub fn for_lsystem(l: &LSystem) -> Self {
        let mut p = Self::default();
        if let Some(a) = l.angle() {
            p.angle_deg = a;
        }
        if let Some(s) = l.step() {
            p.step = s;
        }
        if let Some((t, e)) = l.tropism() {
            p.tropism = DVec3::from_array(t);
            p.elasticity = e;
        }
        p
    }

    /// Checks every value is finite, the step and width non-negative and the frame orthonormal.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the offending field.
    pub fn validate(&self) -> Result<()> {
        use natura_core::check;
        check::finite("TurtleParams::angle_deg", self.angle_deg)?;
        check::non_negative("TurtleParams::step", self.step)?;
        check::non_negative("TurtleParams::width", self.width)?;
        check::non_negative("TurtleParams::width_factor", self.width_factor)?;
        check::finite3("TurtleParams::tropism", self.tropism)?;
        check::finite("TurtleParams::elasticity", self.elasticity)?;
        let f = &self.start;
        check::finite3("TurtleParams::start.p", f.p)?;
        let ortho = (f.h.length() - 1.0).abs() < 1e-6
            && (f.l.length() - 1.0).abs() < 1e-6
            && f.h.dot(f.l).abs() < 1e-6
            && (f.h.cross(f.l) - f.u).length() < 1e-6;
        if !ortho {
            return Err(PlantError::InvalidParameter {
                name: "TurtleParams::start",
                value: format!("{f:?}"),
                reason: "H, L, U must be orthonormal with H × L = U".into(),
            });
        }
        Ok(())
    }
}

/// What a module does to the turtle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Op {
    None,
    Forward { draw: bool, record: bool },
    Turn(i8),
    Pitch(i8),
    Roll(i8),
    TurnAround,
    Horizontal,
    Push,
    Pop,
    Width,
    Taper,
    Colour,
    PolyStart,
    PolyVertex,
    PolyEnd,
    Surface(char),
    Disc,
    Sphere,
}

fn op_for(name: &str) -> Op {
    match name {
        "F" => Op::Forward {
            draw: true,
            record: true,
        },
        "f" => Op::Forward {
            draw: false,
            record: true,
        },
        "G" | "g" => Op::Forward {
            draw: false,
            record: false,
        },
        "+" => Op::Turn(1),
        "-" => Op::Turn(-1),
        "&" => Op::Pitch(1),
        "^" => Op::Pitch(-1),
        "/" => Op::Roll(1),
        "\\" => Op::Roll(-1),
        "|" => Op::TurnAround,
        "$" => Op::Horizontal,
        "[" => Op::Push,
        "]" => Op::Pop,
        "!" => Op::Width,
        "#" => Op::Taper,
        "'" => Op::Colour,
        "{" => Op::PolyStart,
        "." => Op::PolyVertex,
        "}" => Op::PolyEnd,
        "@o" => Op::Disc,
        "@O" => Op::Sphere,
        _ => match name.strip_prefix('~').and_then(|r| r.chars().next()) {
            Some(c) => Op::Surface(c),
            None => Op::None,
        },
    }
}

/// The turtle's full state at a module.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurtleState {
    /// Position and orientation.
    pub frame: TurtleFrame,
    /// Current width (diameter).
    pub width: f64,
    /// Current colour index.
    pub colour: u32,
    /// Path length from the start along the current branch's ancestry.
    pub distance: f64,
    /// Index of the last segment drawn in this branch (continued smoothly), or `u32::MAX`.
    pub(crate) last_seg: u32,
    /// Width the next segment starts from (for `#` tapering).
    pub(crate) taper_from: f64,
}

/// Interprets module strings of one L-system.
#[derive(Clone, Debug)]
pub struct Turtle<'a> {
    lsys: &'a LSystem,
    params: TurtleParams,
    ops: Vec<Op>,
    limits: Limits,
}

impl<'a> Turtle<'a> {
    /// Returns a turtle for the modules of `lsys`.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] if `params` does not validate.
    pub fn new(lsys: &'a LSystem, params: TurtleParams) -> Result<Self> {
        params.validate()?;
        let t = lsys.symbols();
        let ops = (0..t.len() as u32).map(|id| op_for(t.name(id))).collect();
        Ok(Self {
            lsys,
            params,
            ops,
            limits: Limits::default(),
        })
    }

    /// Bounds the output of the interpretation rules by `limits` (the
    /// modules and parameters; [`Limits::default`] unless set).
    #[must_use]
    pub fn with_limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }

    /// The turtle's settings.
    #[must_use]
    pub fn params(&self) -> &TurtleParams {
        &self.params
    }

    /// Applies the L-system's interpretation rules (homomorphism) to `s`,
    /// returning the expanded string and, per expanded module, the index of
    /// the module of `s` it came from.
    ///
    /// # Errors
    ///
    /// [`PlantError::Eval`] or [`PlantError::Depth`] from the rules;
    /// [`PlantError::Growth`] if the expanded string would pass the
    /// turtle's limits ([`Turtle::with_limits`]).
    pub fn homomorphism(&self, s: &ModuleString) -> Result<(ModuleString, Vec<u32>)> {
        let l = self.lsys;
        let cap = Cap::new(&self.limits, 0);
        let mut out = ModuleString::with_capacity(
            s.len().min(self.limits.max_modules),
            s.param_count().min(self.limits.max_params),
        );
        let mut origin = Vec::with_capacity(s.len().min(self.limits.max_modules));
        let mut dslots = Vec::new();
        let mut estack = Vec::new();
        for i in 0..s.len() {
            let before = out.len();
            if l.homomorphisms.for_symbol(s.symbol(i)).is_empty() {
                cap.room(&mut out, 1, s.arity(i))?;
                out.push_from(s, i);
            } else {
                let mut env = Env {
                    arrays: &l.arrays,
                    user: &l.user,
                    rng: Rng::for_module(0x686f_6d6f, 0, i as u64),
                };
                expand(
                    l,
                    &l.homomorphisms,
                    s.symbol(i),
                    s.params(i),
                    0,
                    &mut out,
                    &mut dslots,
                    &mut estack,
                    &mut env,
                    &cap,
                )?;
            }
            origin.extend(std::iter::repeat_n(i as u32, out.len() - before));
        }
        Ok((out, origin))
    }

    /// Interprets `s` (after the interpretation rules) into geometry.
    ///
    /// # Errors
    ///
    /// [`PlantError::Interpret`] for an unbalanced `]` or `}`, a non-finite
    /// parameter or an unknown surface; errors of the interpretation rules.
    pub fn interpret(&self, s: &ModuleString) -> Result<Geometry> {
        let mut g = Geometry::default();
        if self.lsys.has_homomorphism() {
            let (e, _) = self.homomorphism(s)?;
            self.walk(&e, &mut |_, _| {}, Some(&mut g))?;
        } else {
            self.walk(s, &mut |_, _| {}, Some(&mut g))?;
        }
        Ok(g)
    }

    /// Walks `s` without drawing, calling `visit(i, state)` with the state
    /// *before* each module `i` of `s` (for query and communication modules).
    ///
    /// # Errors
    ///
    /// As [`Turtle::interpret`].
    pub fn visit(
        &self,
        s: &ModuleString,
        mut visit: impl FnMut(usize, &TurtleState),
    ) -> Result<()> {
        if self.lsys.has_homomorphism() {
            let (e, origin) = self.homomorphism(s)?;
            // Report each original module once, at the state before its first expanded module.
            let mut last = u32::MAX;
            self.walk(
                &e,
                &mut |k, st| {
                    let o = origin[k];
                    if o != last {
                        last = o;
                        visit(o as usize, st);
                    }
                },
                None,
            )
        } else {
            self.walk(s, &mut |i, st| visit(i, st), None)
        }
    }

    /// Module `i` of `s` as written: `F(1e308)`.
    fn module_text(&self, s: &ModuleString, i: usize) -> String {
        let mut t = self.lsys.symbols().name(s.symbol(i)).to_string();
        let a = s.params(i);
        if !a.is_empty() {
            let v: Vec<String> = a.iter().map(|&v| num(v)).collect();
            t = format!("{t}({})", v.join(", "));
        }
        t
    }

    /// The error for module `i` taking a size out of the turtle's range:
    /// `what` is the size (`"step length"`), `value` its value and `default`
    /// where it came from when the module has no parameter.
    fn out_of_reach(
        &self,
        s: &ModuleString,
        i: usize,
        what: &str,
        value: f64,
        default: &str,
    ) -> PlantError {
        let from = if s.arity(i) == 0 {
            format!(" ({default})")
        } else {
            String::new()
        };
        self.bad(
            s,
            i,
            format!(
                "module {} at symbol index {i}: {what} {}{from} takes the turtle beyond ±{} (positions, widths and sizes must stay within it)",
                self.module_text(s, i),
                num(value),
                num(MAX_EXTENT)
            ),
        )
    }

    /// A polygon past [`MAX_POLYGON_VERTICES`] vertices is an error at the
    /// module that adds the vertex too many.
    fn check_polygon(&self, s: &ModuleString, i: usize, poly: &Polygon) -> Result<()> {
        if poly.vertices.len() > MAX_POLYGON_VERTICES {
            return Err(self.bad(
                s,
                i,
                format!(
                    "a polygon (`{{` … `}}`) reaches {} vertices, more than the {MAX_POLYGON_VERTICES} a polygon may have",
                    poly.vertices.len()
                ),
            ));
        }
        Ok(())
    }

    fn bad(&self, s: &ModuleString, i: usize, message: impl Into<String>) -> PlantError {
        PlantError::Interpret {
            index: i,
            module: self.lsys.symbols().name(s.symbol(i)).to_string(),
            message: message.into(),
        }
    }
}

/// A number as a user would write it: `1e308`, not 309 digits.
pub(crate) fn num(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e9 || v.abs() < 1e-4) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}
