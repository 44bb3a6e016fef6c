//! The ray equation `d/ds(n dx/ds) = ∇n` in a gradient-index medium,
//! integrated with an adaptive Dormand–Prince 5(4) Runge–Kutta scheme.

use glam::DVec3;

use super::air::IndexField;
use crate::Dir3;
use crate::error::{AtmosError, Result, finite, invalid, positive};

/// How a traced ray ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathEnd {
    /// It reached the ground plane `z = ground_z` at this point, with this direction.
    Ground {
        /// Where.
        point: DVec3,
        /// The ray direction there.
        direction: DVec3,
    },
    /// It left the traced slab through its top (`z ≥ top_z`).
    Escaped {
        /// Direction when leaving.
        direction: DVec3,
    },
    /// It travelled `max_length_m` without ending.
    MaxLength {
        /// Direction at the end.
        direction: DVec3,
    },
}

/// A traced ray path.
#[derive(Clone, Debug, PartialEq)]
pub struct RayPath {
    /// Points along the path (accepted RK steps), starting at the origin.
    pub points: Vec<DVec3>,
    /// Unit tangent at each point.
    pub directions: Vec<DVec3>,
    /// How the path ended.
    pub end: PathEnd,
    /// Path length travelled, m.
    pub length_m: f64,
    /// Accepted steps.
    pub steps: usize,
}

impl RayPath {
    /// The lowest height reached.
    #[must_use]
    pub fn min_z(&self) -> f64 {
        self.points
            .iter()
            .map(|p| p.z)
            .fold(f64::INFINITY, f64::min)
    }

    /// The final direction.
    #[must_use]
    pub fn final_direction(&self) -> DVec3 {
        match self.end {
            PathEnd::Ground { direction, .. }
            | PathEnd::Escaped { direction }
            | PathEnd::MaxLength { direction } => direction,
        }
    }
}

/// Most accepted steps a [`GrinTracer`] may take ([`GrinTracer::max_steps`]):
/// each keeps a point and a direction of the path, 48 bytes.
pub const MAX_GRIN_STEPS: usize = 10_000_000;

/// Adaptive Dormand–Prince 5(4) integrator of the ray equation in a
/// gradient-index medium: state `(x, v = n·t̂)`, `dx/ds = v/n`, `dv/ds = ∇n`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct GrinTracer {
    /// Local error tolerance per step, m (1e-9).
    pub tolerance_m: f64,
    /// First trial step, m (1).
    pub initial_step_m: f64,
    /// Largest step, m (50).
    pub max_step_m: f64,
    /// Total path length before giving up, m.
    pub max_length_m: f64,
    /// The ground plane height (rays stop there), m.
    pub ground_z: f64,
    /// The top of the traced slab (rays stop there), m.
    pub top_z: f64,
    /// Accepted-step cap (at most [`MAX_GRIN_STEPS`]).
    pub max_steps: usize,
}

impl Default for GrinTracer {
    fn default() -> Self {
        Self {
            tolerance_m: 1e-9,
            initial_step_m: 1.0,
            max_step_m: 50.0,
            max_length_m: 5_000.0,
            ground_z: 0.0,
            top_z: 1_000.0,
            max_steps: 1_000_000,
        }
    }
}

/// Dormand–Prince tableau.
const DP_A: [[f64; 6]; 6] = [
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// 5th-order weights minus the embedded 4th-order weights (error estimate).
const DP_E: [f64; 7] = [
    35.0 / 384.0 - 5179.0 / 57600.0,
    0.0,
    500.0 / 1113.0 - 7571.0 / 16695.0,
    125.0 / 192.0 - 393.0 / 640.0,
    -2187.0 / 6784.0 + 92097.0 / 339200.0,
    11.0 / 84.0 - 187.0 / 2100.0,
    -1.0 / 40.0,
];

impl GrinTracer {
    /// Refuses non-positive or NaN settings.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`] naming the first setting that is non-positive or NaN, a
    /// `top_z` not above `ground_z`, or `max_steps` outside `1..=`[`MAX_GRIN_STEPS`].
    pub fn validate(&self) -> Result<()> {
        positive("tolerance_m", self.tolerance_m)?;
        positive("initial_step_m", self.initial_step_m)?;
        positive("max_step_m", self.max_step_m)?;
        positive("max_length_m", self.max_length_m)?;
        finite("ground_z", self.ground_z)?;
        finite("top_z", self.top_z)?;
        if self.top_z <= self.ground_z {
            return Err(invalid("top_z", self.top_z, "must exceed ground_z"));
        }
        if !(1..=MAX_GRIN_STEPS).contains(&self.max_steps) {
            return Err(invalid(
                "max_steps",
                self.max_steps,
                "must be in 1..=10⁷ (each accepted step keeps a point of the path)",
            ));
        }
        Ok(())
    }

    /// Traces the ray from `origin` in direction `dir` through `field`.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`] for bad settings, an origin outside the slab or an index
    /// field that gives NaN or non-positive values, and
    /// [`AtmosError::NoConvergence`] if the step size
    /// collapses before the path leaves the slab.
    pub fn trace(&self, field: &impl IndexField, origin: DVec3, dir: Dir3) -> Result<RayPath> {
        self.validate()?;
        crate::error::finite3("origin", origin)?;
        if origin.z < self.ground_z || origin.z > self.top_z {
            return Err(invalid(
                "origin",
                origin,
                "must lie between ground_z and top_z",
            ));
        }
        let n0 = field.n(origin);
        if !(n0.is_finite() && n0 > 0.0) {
            return Err(invalid(
                "field",
                n0,
                "refractive index must be finite and > 0",
            ));
        }
        let deriv = |x: DVec3, v: DVec3| -> (DVec3, DVec3) { (v / field.n(x), field.grad(x)) };
        let mut x = origin;
        let mut v = dir.get() * n0;
        let mut h = self.initial_step_m.min(self.max_step_m);
        let mut s = 0.0;
        let mut points = vec![x];
        let mut directions = vec![dir.get()];
        let mut steps = 0;
        let unit = |v: DVec3| v.normalize_or_zero();
        loop {
            if s >= self.max_length_m {
                return Ok(RayPath {
                    points,
                    directions,
                    end: PathEnd::MaxLength { direction: unit(v) },
                    length_m: s,
                    steps,
                });
            }
            if steps >= self.max_steps {
                return Err(AtmosError::NoConvergence {
                    what: "GRIN ray trace",
                    detail: format!(
                        "{steps} steps without reaching the ground, the top or max_length_m"
                    ),
                });
            }
            h = h.min(self.max_length_m - s);
            let mut kx = [DVec3::ZERO; 7];
            let mut kv = [DVec3::ZERO; 7];
            (kx[0], kv[0]) = deriv(x, v);
            for st in 0..6 {
                let mut dx = DVec3::ZERO;
                let mut dv = DVec3::ZERO;
                for j in 0..=st {
                    dx += kx[j] * DP_A[st][j];
                    dv += kv[j] * DP_A[st][j];
                }
                (kx[st + 1], kv[st + 1]) = deriv(x + dx * h, v + dv * h);
            }
            let mut ex = DVec3::ZERO;
            let mut ev = DVec3::ZERO;
            for j in 0..7 {
                ex += kx[j] * DP_E[j];
                ev += kv[j] * DP_E[j];
            }
            let err = (ex * h)
                .abs()
                .max_element()
                .max((ev * h).abs().max_element() * 1.0)
                / self.tolerance_m;
            if !err.is_finite() {
                return Err(invalid(
                    "field",
                    "NaN",
                    "index field produced a non-finite value",
                ));
            }
            if err <= 1.0 {
                // FSAL: the 7th stage is the 5th-order solution's slope.
                let mut dx = DVec3::ZERO;
                let mut dv = DVec3::ZERO;
                for j in 0..6 {
                    dx += kx[j] * DP_A[5][j];
                    dv += kv[j] * DP_A[5][j];
                }
                let xn = x + dx * h;
                let vn = v + dv * h;
                steps += 1;
                s += h;
                if xn.z <= self.ground_z {
                    let f = (x.z - self.ground_z) / (x.z - xn.z);
                    let p = x.lerp(xn, f);
                    points.push(p);
                    directions.push(unit(v.lerp(vn, f)));
                    return Ok(RayPath {
                        points,
                        directions,
                        end: PathEnd::Ground {
                            point: p,
                            direction: unit(v.lerp(vn, f)),
                        },
                        length_m: s - h * (1.0 - f),
                        steps,
                    });
                }
                if xn.z >= self.top_z {
                    points.push(xn);
                    directions.push(unit(vn));
                    return Ok(RayPath {
                        points,
                        directions,
                        end: PathEnd::Escaped {
                            direction: unit(vn),
                        },
                        length_m: s,
                        steps,
                    });
                }
                x = xn;
                v = vn;
                points.push(x);
                directions.push(unit(v));
            }
            let fac = if err == 0.0 {
                5.0
            } else {
                (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            };
            h = (h * fac).min(self.max_step_m);
        }
    }
}

/// Returns the largest relative drift of Snell's invariant `n(z)·cos(elevation)`
/// along a path in a horizontally stratified `field` (an accuracy check: the invariant
/// holds exactly along true paths).
#[must_use]
pub fn invariant_drift(path: &RayPath, field: &impl IndexField) -> f64 {
    let inv = |p: DVec3, d: DVec3| field.n(p) * d.truncate().length();
    let Some((&p0, &d0)) = path.points.first().zip(path.directions.first()) else {
        return 0.0;
    };
    let i0 = inv(p0, d0);
    path.points
        .iter()
        .zip(&path.directions)
        .map(|(&p, &d)| ((inv(p, d) - i0) / i0).abs())
        .fold(0.0, f64::max)
}
