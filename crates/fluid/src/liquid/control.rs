//! Control of a liquid along a space curve (Foster & Fedkiw 2001, §10).
//!
//! The source controls liquid through the moving-object mechanism with
//! "fake surfaces" that carry a velocity but occupy no cells: points
//! `x_p = F(φ_p)` on a parametric curve `F` move along it at
//! `dφ_p/dt = C(t)`, a monotonic key-framed rate, with velocity
//! `v_p = C(t) dF/dφ(φ_p)`. Their velocities are set on the grid before the
//! pressure solve, normal and tangential components both, so the projection
//! smooths what is not divergence-free; the liquid pockets they touch are
//! led along the curve and the liquid around them follows.
//!
//! The source leaves the curve's form and the points' reach open: here `F`
//! is the uniform Catmull–Rom spline through [`ControlCurve::points`] (each
//! segment an equal share of the parameter `φ ∈ [0, 1]`, the end tangents
//! by reflection), and each point sets the faces of liquid cells within
//! [`ControlCurve::radius`] of it: a point whose liquid has been left
//! behind pulls no more.

use glam::Vec3;

use crate::error::{FluidError, Result};

/// A control curve with its moving points (Foster & Fedkiw 2001, §10).
///
/// With the `serde` feature it reads from a table with these fields.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct ControlCurve {
    /// Points the curve passes through, in order (m); at least two.
    pub points: Vec<Vec3>,
    /// The key-framed rate `C(t)` (1/s, the curve's parameter per second):
    /// `(time s, rate)` pairs in increasing time, linear between them and
    /// held beyond the ends. Rates are non-negative (the source's `C` is
    /// monotonic: the points only move forward).
    pub rate: Vec<(f32, f32)>,
    /// The parameters `φ_p ∈ [0, 1]` of the moving points at time 0; a
    /// point that passes the curve's end (`φ_p > 1`) stops acting.
    pub points_at: Vec<f32>,
    /// Reach of each point (m): the grid's faces within it take the
    /// point's velocity.
    pub radius: f32,
}

impl ControlCurve {
    /// Checks the curve.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] naming `points` (fewer than
    /// two, or not finite), `rate` (empty, a time or rate not finite, times
    /// not increasing, a negative rate), `points_at` (outside `[0, 1]` or NaN)
    /// or `radius` (not finite and positive).
    pub fn validate(&self) -> Result<()> {
        let bad = |name: &'static str, value: String, reason: &'static str| {
            Err(FluidError::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        if self.points.len() < 2 || !self.points.iter().all(|p| p.is_finite()) {
            return bad(
                "points",
                format!("{:?}", self.points),
                "at least two finite points",
            );
        }
        if self.rate.is_empty()
            || !self
                .rate
                .iter()
                .all(|&(t, c)| t.is_finite() && c.is_finite() && c >= 0.0)
            || self.rate.windows(2).any(|w| w[1].0 <= w[0].0)
        {
            return bad(
                "rate",
                format!("{:?}", self.rate),
                "at least one (time, rate) pair, finite, times increasing, rates non-negative",
            );
        }
        if !self.points_at.iter().all(|s| (0.0..=1.0).contains(s)) {
            return bad(
                "points_at",
                format!("{:?}", self.points_at),
                "each in [0, 1]",
            );
        }
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return bad(
                "radius",
                self.radius.to_string(),
                "must be finite and positive",
            );
        }
        Ok(())
    }

    /// The rate `C(t)` (1/s).
    #[must_use]
    pub fn rate_at(&self, t: f32) -> f32 {
        let r = &self.rate;
        let Some(i) = r.iter().position(|&(ti, _)| ti > t) else {
            return r[r.len() - 1].1;
        };
        if i == 0 {
            return r[0].1;
        }
        let ((t0, c0), (t1, c1)) = (r[i - 1], r[i]);
        c0 + (c1 - c0) * (t - t0) / (t1 - t0)
    }

    /// How far the parameter moves from `t` to `t + dt`: `∫ C` (exact for
    /// the piecewise-linear rate).
    #[must_use]
    pub fn advance(&self, t: f32, dt: f32) -> f32 {
        // Integrate piece by piece between the key times inside the step.
        let mut knots: Vec<f32> = vec![t];
        knots.extend(
            self.rate
                .iter()
                .map(|&(k, _)| k)
                .filter(|&k| k > t && k < t + dt),
        );
        knots.push(t + dt);
        knots
            .windows(2)
            .map(|w| 0.5 * (self.rate_at(w[0]) + self.rate_at(w[1])) * (w[1] - w[0]))
            .sum()
    }

    /// The curve's point `F(φ)` and derivative `dF/dφ` (m per unit of φ) at
    /// `φ` (clamped to `[0, 1]`).
    #[must_use]
    pub fn at(&self, phi: f32) -> (Vec3, Vec3) {
        let p = &self.points;
        let segs = p.len() - 1;
        let u = phi.clamp(0.0, 1.0) * segs as f32;
        let i = (u.floor() as usize).min(segs - 1);
        let t = u - i as f32;
        let p1 = p[i];
        let p2 = p[i + 1];
        let p0 = if i > 0 { p[i - 1] } else { 2.0 * p1 - p2 };
        let p3 = if i + 2 < p.len() {
            p[i + 2]
        } else {
            2.0 * p2 - p1
        };
        let a = 2.0 * p1;
        let b = p2 - p0;
        let c = 2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3;
        let d = -p0 + 3.0 * p1 - 3.0 * p2 + p3;
        let pos = 0.5 * (a + b * t + c * t * t + d * t * t * t);
        let dpos = 0.5 * (b + 2.0 * c * t + 3.0 * d * t * t) * segs as f32;
        (pos, dpos)
    }
}

/// A control curve and where its points are now.
#[derive(Clone, Debug)]
pub(crate) struct Control {
    pub(crate) curve: ControlCurve,
    pub(crate) at: Vec<f32>,
}

impl Control {
    /// The points still on the curve: position and velocity `C(t) dF/dφ`.
    pub(crate) fn points(&self, t: f32) -> impl Iterator<Item = (Vec3, Vec3)> + '_ {
        let c = self.curve.rate_at(t);
        self.at.iter().filter(|&&s| s <= 1.0).map(move |&s| {
            let (x, dx) = self.curve.at(s);
            (x, c * dx)
        })
    }

    /// Moves the points on from `t` by `dt`.
    pub(crate) fn advance(&mut self, t: f32, dt: f32) {
        let ds = self.curve.advance(t, dt);
        for s in &mut self.at {
            *s += ds;
        }
    }
}

impl super::Liquid {
    /// Leads the liquid along `curve` from now on (Foster & Fedkiw 2001,
    /// §10): at each step, before the pressure solve, the faces within the
    /// curve's radius of each of its moving points take that point's
    /// velocity.
    ///
    /// # Errors
    ///
    /// Returns the errors of [`ControlCurve::validate`].
    pub fn add_control(&mut self, curve: ControlCurve) -> Result<()> {
        curve.validate()?;
        let at = curve.points_at.clone();
        self.controls.push(Control { curve, at });
        Ok(())
    }

    /// The control curves' points still on their curves: position (m) and
    /// velocity (m/s) now.
    #[must_use]
    pub fn control_points(&self) -> Vec<(Vec3, Vec3)> {
        let t = self.time as f32;
        self.controls.iter().flat_map(|c| c.points(t)).collect()
    }

    /// Sets the faces around the control points to their velocities, those
    /// of liquid cells only: the pressure solve makes the liquid's velocity
    /// divergence-free but not the air's, and a velocity set in the air
    /// converges there and drags the level set's liquid out of nothing.
    pub(super) fn apply_controls(&mut self) {
        if self.controls.is_empty() {
            return;
        }
        let (d, h) = (self.dims, self.h);
        let n = d.n();
        let t = self.time as f32;
        let cells = self.cells.as_slice();
        let liquid = |c: [usize; 3]| {
            matches!(
                cells[d.idx(c[0], c[1], c[2])],
                super::LiquidCell::Full | super::LiquidCell::Surface
            )
        };
        let points: Vec<(Vec3, Vec3, f32)> = self
            .controls
            .iter()
            .flat_map(|c| c.points(t).map(|(x, v)| (x, v, c.curve.radius)))
            .collect();
        for a in 0..3 {
            if !d.active(a) {
                continue;
            }
            let fd = d.face_dims(a);
            let g = self.vel.comp_mut(a);
            for &(x, v, r) in &points {
                // Face (i, j, k) of axis a sits at i·h along a and at the
                // cell centres (j + ½)·h across it.
                let range = |b: usize| {
                    let off = if b == a { 0.0 } else { 0.5 };
                    let lo = ((x[b] - r) / h - off).ceil().max(0.0) as usize;
                    let hi = ((x[b] + r) / h - off).floor();
                    (hi >= 0.0).then(|| (lo, (hi as usize).min(fd[b] - 1)))
                };
                let (Some((i0, i1)), Some((j0, j1)), Some((k0, k1))) =
                    (range(0), range(1), range(2))
                else {
                    continue;
                };
                for k in k0..=k1 {
                    for j in j0..=j1 {
                        for i in i0..=i1 {
                            let f = crate::grid::face_position(a, [i, j, k], h);
                            if (f - x).length_squared() > r * r {
                                continue;
                            }
                            // The cells on either side of the face.
                            let c = [i, j, k];
                            let mut lo = c;
                            let wet_lo = c[a] > 0 && {
                                lo[a] -= 1;
                                liquid(lo)
                            };
                            let wet_hi = c[a] < n[a] && liquid(c);
                            if wet_lo || wet_hi {
                                g[(i, j, k)] = v[a];
                            }
                        }
                    }
                }
            }
        }
    }
}
