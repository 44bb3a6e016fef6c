//! User-supplied functions and curves that L-system expressions call:
//! `func(id, x)`, `curveX/Y/Z(id, s)`, `tanX/Y/Z(id, s)`, `curveLen(id)`
//! (Prusinkiewicz et al. 2001, §2, the built-in functions of L-studio's
//! language; there they are edited graphically, here the caller supplies them).

use crate::error::{PlantError, Result};
use glam::DVec3;
use std::collections::BTreeMap;

/// A function of one variable given by control points, evaluated by
/// Catmull–Rom interpolation (a smooth curve through the points) and held
/// constant outside them.
#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    xs: Vec<f64>,
    ys: Vec<f64>,
}

impl Function {
    /// Returns the function through `points` (`x` strictly increasing).
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] if there are no points, a value is not
    /// finite or the `x` are not strictly increasing.
    pub fn new(points: &[(f64, f64)]) -> Result<Self> {
        if points.is_empty() {
            return Err(PlantError::InvalidParameter {
                name: "Function::points",
                value: "[]".into(),
                reason: "needs at least one point".into(),
            });
        }
        for (k, &(x, y)) in points.iter().enumerate() {
            natura_core::check::finite("Function::points.x", x)?;
            natura_core::check::finite("Function::points.y", y)?;
            if k > 0 && x <= points[k - 1].0 {
                return Err(PlantError::InvalidParameter {
                    name: "Function::points",
                    value: format!("x = {x} after {}", points[k - 1].0),
                    reason: "x must increase strictly".into(),
                });
            }
        }
        Ok(Self {
            xs: points.iter().map(|p| p.0).collect(),
            ys: points.iter().map(|p| p.1).collect(),
        })
    }

    /// Returns the value at `x`.
    #[must_use]
    pub fn eval(&self, x: f64) -> f64 {
        let n = self.xs.len();
        if n == 1 || x <= self.xs[0] {
            return self.ys[0];
        }
        if x >= self.xs[n - 1] {
            return self.ys[n - 1];
        }
        let i = self
            .xs
            .partition_point(|&v| v <= x)
            .saturating_sub(1)
            .min(n - 2);
        let (x0, x1) = (self.xs[i], self.xs[i + 1]);
        let t = (x - x0) / (x1 - x0);
        let y0 = self.ys[i];
        let y1 = self.ys[i + 1];
        // Catmull–Rom tangents (finite differences in x), clamped at the ends.
        let m0 = if i > 0 {
            (y1 - self.ys[i - 1]) / (x1 - self.xs[i - 1]) * (x1 - x0)
        } else {
            y1 - y0
        };
        let m1 = if i + 2 < n {
            (self.ys[i + 2] - y0) / (self.xs[i + 2] - x0) * (x1 - x0)
        } else {
            y1 - y0
        };
        let t2 = t * t;
        let t3 = t2 * t;
        (2.0 * t3 - 3.0 * t2 + 1.0) * y0
            + (t3 - 2.0 * t2 + t) * m0
            + (-2.0 * t3 + 3.0 * t2) * y1
            + (t3 - t2) * m1
    }
}

/// A space curve parametrised by arc length: a polyline, densely resampled
/// from Catmull–Rom splines through the control points.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    pts: Vec<DVec3>,
    /// Arc length at each point.
    s: Vec<f64>,
}

impl Curve {
    /// Returns the curve through `points` (at least two, finite, consecutive
    /// points distinct).
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] if there are fewer than two points, a
    /// coordinate is not finite or two consecutive points coincide.
    pub fn new(points: &[DVec3]) -> Result<Self> {
        if points.len() < 2 {
            return Err(PlantError::InvalidParameter {
                name: "Curve::points",
                value: format!("{} points", points.len()),
                reason: "needs at least two points".into(),
            });
        }
        for (k, p) in points.iter().enumerate() {
            natura_core::check::finite3("Curve::points", *p)?;
            if k > 0 && p.distance(points[k - 1]) == 0.0 {
                return Err(PlantError::InvalidParameter {
                    name: "Curve::points",
                    value: format!("{p}"),
                    reason: "consecutive points must differ".into(),
                });
            }
        }
        const SUB: usize = 64;
        let n = points.len();
        let at = |i: isize| points[i.clamp(0, n as isize - 1) as usize];
        let mut pts = Vec::with_capacity((n - 1) * SUB + 1);
        for i in 0..n - 1 {
            let (p0, p1, p2, p3) = (
                at(i as isize - 1),
                at(i as isize),
                at(i as isize + 1),
                at(i as isize + 2),
            );
            for k in 0..SUB {
                let t = k as f64 / SUB as f64;
                let t2 = t * t;
                let t3 = t2 * t;
                pts.push(
                    0.5 * ((2.0 * p1)
                        + (p2 - p0) * t
                        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2
                        + (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3),
                );
            }
        }
        pts.push(points[n - 1]);
        let mut s = Vec::with_capacity(pts.len());
        let mut acc = 0.0;
        for (k, p) in pts.iter().enumerate() {
            if k > 0 {
                acc += p.distance(pts[k - 1]);
            }
            s.push(acc);
        }
        Ok(Self { pts, s })
    }

    /// Returns the total arc length.
    #[must_use]
    pub fn length(&self) -> f64 {
        self.s.last().copied().unwrap_or(0.0)
    }

    fn locate(&self, s: f64) -> (usize, f64) {
        let s = s.clamp(0.0, self.length());
        let i = self
            .s
            .partition_point(|&v| v <= s)
            .saturating_sub(1)
            .min(self.s.len() - 2);
        let ds = self.s[i + 1] - self.s[i];
        let t = if ds > 0.0 { (s - self.s[i]) / ds } else { 0.0 };
        (i, t)
    }

    /// Returns the point at arc length `s` (clamped to the curve).
    #[must_use]
    pub fn point(&self, s: f64) -> DVec3 {
        let (i, t) = self.locate(s);
        self.pts[i].lerp(self.pts[i + 1], t)
    }

    /// Returns the unit tangent at arc length `s`.
    #[must_use]
    pub fn tangent(&self, s: f64) -> DVec3 {
        let (i, _) = self.locate(s);
        (self.pts[i + 1] - self.pts[i]).normalize_or_zero()
    }
}

/// The functions and curves an L-system's expressions may call, by id.
#[derive(Clone, Debug, Default)]
pub struct UserFns {
    funcs: BTreeMap<u32, Function>,
    curves: BTreeMap<u32, Curve>,
}

impl UserFns {
    /// Makes `f` callable as `func(id, x)`.
    pub fn set_function(&mut self, id: u32, f: Function) {
        self.funcs.insert(id, f);
    }

    /// Makes `c` callable as `curveX(id, s)`, `tanX(id, s)`, `curveLen(id)`, ….
    pub fn set_curve(&mut self, id: u32, c: Curve) {
        self.curves.insert(id, c);
    }

    pub(crate) fn func(&self, id: u32, x: f64) -> Result<f64, String> {
        self.funcs
            .get(&id)
            .map(|f| f.eval(x))
            .ok_or_else(|| format!("undefined function {id} (set it with LSystem::set_function)"))
    }

    fn curve(&self, id: u32) -> Result<&Curve, String> {
        self.curves
            .get(&id)
            .ok_or_else(|| format!("undefined curve {id} (set it with LSystem::set_curve)"))
    }

    pub(crate) fn curve_point(&self, id: u32, s: f64) -> Result<DVec3, String> {
        Ok(self.curve(id)?.point(s))
    }

    pub(crate) fn curve_tangent(&self, id: u32, s: f64) -> Result<DVec3, String> {
        Ok(self.curve(id)?.tangent(s))
    }

    pub(crate) fn curve_len(&self, id: u32) -> Result<f64, String> {
        Ok(self.curve(id)?.length())
    }
}
