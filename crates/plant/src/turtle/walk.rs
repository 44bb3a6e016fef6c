//! The turtle's walk along a module string: the state machine of the
//! interpretation (Prusinkiewicz & Lindenmayer 1990, §1.3–1.5 for moves,
//! turns and branches, §2.3 for tropism, §5.1 for polygons; the cpfg
//! symbol set), one method per kind of module.

use glam::DVec3;

use super::{
    Geometry, MAX_EXTENT, Op, Polygon, SurfaceInstance, Turtle, TurtleParams, TurtleState,
};
use crate::error::{PlantError, Result};
use crate::string::ModuleString;

/// The state of one walk: the turtle, the branch stack, the open polygons
/// and, when drawing, the geometry being built.
struct Walk<'w, 'a> {
    turtle: &'w Turtle<'a>,
    s: &'w ModuleString,
    st: TurtleState,
    stack: Vec<TurtleState>,
    polys: Vec<Polygon>,
    geo: Option<&'w mut Geometry>,
    tropism: bool,
}

impl Turtle<'_> {
    /// Walks `s`, calling `visit(i, state)` with the state before each
    /// module `i`, and drawing into `geo` when given.
    pub(super) fn walk(
        &self,
        s: &ModuleString,
        visit: &mut dyn FnMut(usize, &TurtleState),
        geo: Option<&mut Geometry>,
    ) -> Result<()> {
        let p = &self.params;
        let mut w = Walk {
            turtle: self,
            s,
            st: TurtleState {
                frame: p.start,
                width: p.width,
                colour: 0,
                distance: 0.0,
                last_seg: u32::MAX,
                taper_from: p.width,
            },
            stack: Vec::new(),
            polys: Vec::new(),
            geo,
            tropism: p.elasticity != 0.0 && p.tropism != DVec3::ZERO,
        };
        for i in 0..s.len() {
            visit(i, &w.st);
            w.module(i)?;
        }
        w.finish()
    }
}

impl Walk<'_, '_> {
    fn params(&self) -> &TurtleParams {
        &self.turtle.params
    }

    /// Applies module `i`.
    fn module(&mut self, i: usize) -> Result<()> {
        let s = self.s;
        let op = self
            .turtle
            .ops
            .get(s.symbol(i) as usize)
            .copied()
            .unwrap_or(Op::None);
        if op == Op::None {
            return Ok(());
        }
        let a = s.params(i);
        if let Some(v) = a.iter().find(|v| !v.is_finite()) {
            return Err(self
                .turtle
                .bad(s, i, format!("parameter {v} is not finite")));
        }
        let deg = std::f64::consts::PI / 180.0;
        let angle = a.first().copied().unwrap_or(self.params().angle_deg) * deg;
        let st = &mut self.st;
        match op {
            Op::None => {}
            Op::Forward { draw, record } => {
                let len = a.first().copied().unwrap_or(self.params().step);
                self.forward(i, len, draw, record)?;
            }
            Op::Turn(sg) => st.frame.turn(f64::from(sg) * angle),
            Op::Pitch(sg) => st.frame.pitch(f64::from(sg) * angle),
            Op::Roll(sg) => st.frame.roll(f64::from(sg) * angle),
            Op::TurnAround => st.frame.turn(std::f64::consts::PI),
            Op::Horizontal => st.frame.roll_horizontal(),
            Op::Push => {
                self.stack.push(*st);
                st.last_seg = u32::MAX;
            }
            Op::Pop => {
                *st = self
                    .stack
                    .pop()
                    .ok_or_else(|| self.turtle.bad(s, i, "`]` without a matching `[`"))?;
            }
            Op::Width => self.width(i, a)?,
            Op::Taper => {
                st.taper_from = st.width;
                st.width = a.first().copied().unwrap_or(st.width).abs();
                if st.width > MAX_EXTENT {
                    return Err(self.turtle.out_of_reach(s, i, "width", st.width, ""));
                }
            }
            Op::Colour => {
                st.colour = match a.first() {
                    None => st.colour.wrapping_add(1),
                    Some(&c) => c.max(0.0).min(f64::from(u32::MAX)) as u32,
                };
            }
            Op::PolyStart => {
                let mut poly = Polygon {
                    vertices: Vec::new(),
                    colour: st.colour,
                    distance: st.distance as f32,
                };
                poly.push_vertex(st.frame.p);
                self.polys.push(poly);
            }
            Op::PolyVertex => {
                if let Some(poly) = self.polys.last_mut() {
                    poly.push_vertex(st.frame.p);
                    self.turtle.check_polygon(s, i, poly)?;
                }
            }
            Op::PolyEnd => self.close_polygon(i)?,
            Op::Surface(c) => self.surface(i, c, a)?,
            Op::Disc | Op::Sphere => {
                let r = a.first().copied().unwrap_or(st.width * 0.5).abs();
                if r > MAX_EXTENT {
                    return Err(self.turtle.out_of_reach(s, i, "radius", r, ""));
                }
                let name = if op == Op::Disc { 'o' } else { 'O' };
                self.place(name, r, r);
            }
        }
        Ok(())
    }

    /// `F`, `f`, `G`, `g`: a move of `len`, drawing a segment (`draw`) or,
    /// inside a polygon, recording a vertex (`record`); a drawn segment
    /// then bends towards the tropism vector (ABOP §2.3, p. 58).
    fn forward(&mut self, i: usize, len: f64, draw: bool, record: bool) -> Result<()> {
        let (s, p) = (self.s, &self.turtle.params);
        let st = &mut self.st;
        let start = st.frame.p;
        st.frame.p += st.frame.h * len;
        if !st.frame.p.is_finite() || st.frame.p.abs().max_element() > MAX_EXTENT {
            return Err(self.turtle.out_of_reach(
                s,
                i,
                "step length",
                len,
                "the default step, from `step:` or `TurtleParams::step`",
            ));
        }
        let d0 = st.distance;
        st.distance += len.abs();
        if let Some(poly) = self.polys.last_mut() {
            if record {
                poly.push_vertex(st.frame.p);
                self.turtle.check_polygon(s, i, poly)?;
            }
            st.last_seg = u32::MAX;
        } else if draw {
            if let Some(g) = self.geo.as_deref_mut() {
                let k = g.push_segment(start, st, d0, st.taper_from);
                st.last_seg = k;
            }
        } else {
            st.last_seg = u32::MAX;
        }
        st.taper_from = st.width;
        if self.tropism && draw {
            st.frame.tropism(p.tropism, p.elasticity);
        }
        Ok(())
    }

    /// `!`: the width times the width factor, or `!(w)`: the width `w`.
    fn width(&mut self, i: usize, a: &[f64]) -> Result<()> {
        let factor = self.params().width_factor;
        let st = &mut self.st;
        st.width = match a.first() {
            None => st.width * factor,
            Some(&w) => w.abs(),
        };
        if st.width > MAX_EXTENT {
            return Err(self.turtle.out_of_reach(
                self.s,
                i,
                "width",
                st.width,
                "the width times `TurtleParams::width_factor`",
            ));
        }
        st.taper_from = st.width;
        Ok(())
    }

    /// `}`: closes the innermost polygon; a closing vertex on the first one
    /// (up to rounding) is dropped, and one of fewer than 3 vertices is not
    /// drawn.
    fn close_polygon(&mut self, i: usize) -> Result<()> {
        let mut poly = self
            .polys
            .pop()
            .ok_or_else(|| self.turtle.bad(self.s, i, "`}` without a matching `{`"))?;
        if let (Some(a), Some(b)) = (poly.vertices.first(), poly.vertices.last()) {
            let scale = a.abs().max(b.abs()).max_element().max(1.0);
            if poly.vertices.len() > 1 && a.distance(*b) <= 1e-5 * scale {
                poly.vertices.pop();
            }
        }
        if let Some(g) = self.geo.as_deref_mut()
            && poly.vertices.len() >= 3
        {
            g.polygons.push(poly);
        }
        Ok(())
    }

    /// `~X`, `~X(s)`, `~X(l, w)`: predefined surface `X` at the turtle,
    /// scaled by `l` along the heading and `w` across it.
    fn surface(&mut self, i: usize, name: char, a: &[f64]) -> Result<()> {
        if self.geo.is_none() {
            return Ok(());
        }
        let (sl, sw) = match a {
            [] => (1.0, 1.0),
            [x] => (*x, *x),
            [x, y, ..] => (*x, *y),
        };
        if sl.abs().max(sw.abs()) > MAX_EXTENT {
            return Err(self.turtle.out_of_reach(
                self.s,
                i,
                "surface size",
                sl.abs().max(sw.abs()),
                "",
            ));
        }
        self.place(name, sl, sw);
        Ok(())
    }

    /// Places surface `name` of `length × width` at the turtle (when drawing).
    fn place(&mut self, name: char, length: f64, width: f64) {
        if let Some(g) = self.geo.as_deref_mut() {
            g.surfaces.push(SurfaceInstance {
                name,
                frame: self.st.frame,
                length,
                width,
                colour: self.st.colour,
                distance: self.st.distance as f32,
            });
        }
    }

    /// The end of the string: every polygon must be closed.
    fn finish(self) -> Result<()> {
        if self.polys.is_empty() {
            return Ok(());
        }
        Err(PlantError::Interpret {
            index: self.s.len(),
            module: "{".into(),
            message: format!(
                "{} polygon(s) left open at the end of the string",
                self.polys.len()
            ),
        })
    }
}
