//! Collision-based spiral phyllotaxis (Fowler, Prusinkiewicz & Battjes 1992).
//!
//! Fowler et al. 1992, §2.3–2.4: primordia are spheres centred on a receptacle, a
//! surface of revolution `(φ, ρ(t), h(t))`. The n-th primordium sits at
//! `φ_n = n·137.5°`, and at the smallest `t ≥ t'_min` where it touches no
//! earlier primordium: `‖P_i − P_n‖ ≥ r_i + r_n` for all `i < n` (the
//! recurrence of §2.4). `t'_min = max(t_min, t_{n−1} − δ)` with `δ` about the
//! new primordium's radius keeps small late primordia from falling into gaps
//! near the base (the source's fix for decreasing sizes). Placement ends when
//! no `t` fits.
//!
//! The source finds `t` by binary search, which assumes the feasible set is
//! an interval above some `t`; it need not be. Here `t` is scanned in small
//! steps and the first feasible step is refined by bisection against the
//! previous (infeasible) one.
//!
//! §3.1: the mature organs replace the spheres; [`organ_frames`] gives each
//! organ's placement (contact point at the centre, turned to the
//! receptacle's normal and the curve's tangent, sized by the radius). The
//! generating curve may be one or more cubic Bézier curves
//! ([`Receptacle::Bezier`]), as in the source's implementation.

use glam::DVec3;
use natura_core::check;

use crate::error::{PlantError, Result};

/// The receptacle's generating curve `(ρ(t), h(t))`, `t ∈ [0, 1]` from base
/// to tip (Fowler et al. 1992, §2.4): the receptacle is the surface swept by
/// turning it about the vertical axis `h`.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Receptacle {
    /// A flat disc of the given radius (daisies, Fig. 5): `ρ = R(1 − t)`, `h = 0`.
    Disc {
        /// Radius.
        radius: f64,
    },
    /// A cone (coneflower, Fig. 4): `ρ = R(1 − t)`, `h = H·t`.
    Cone {
        /// Base radius.
        radius: f64,
        /// Height.
        height: f64,
    },
    /// A sphere from the bottom pole to the top pole (Fig. 6): `ρ = R sin(πt)`, `h = −R cos(πt)`.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// One or more cubic Bézier curves joined end to end, each given by its
    /// four control points `[ρ, h]` (§2.4: "C is specified as one or more
    /// Bézier curves"); `t` is spread evenly over the segments, segment `k`
    /// of `n` covering `[k/n, (k+1)/n]`.
    Bezier {
        /// The segments, base first; the last point of one should be the
        /// first of the next.
        segments: Vec<[[f64; 2]; 4]>,
    },
}

/// Segment `k` and its own parameter `u ∈ [0, 1]` for the curve parameter `t`.
fn segment(n: usize, t: f64) -> (usize, f64) {
    let x = t.clamp(0.0, 1.0) * n as f64;
    let k = (x.floor() as usize).min(n - 1);
    (k, x - k as f64)
}

impl Receptacle {
    /// `(ρ(t), h(t))`.
    #[must_use]
    pub fn at(&self, t: f64) -> (f64, f64) {
        match self {
            &Self::Disc { radius } => (radius * (1.0 - t), 0.0),
            &Self::Cone { radius, height } => (radius * (1.0 - t), height * t),
            &Self::Sphere { radius } => {
                let a = std::f64::consts::PI * t;
                (radius * a.sin(), -radius * a.cos())
            }
            Self::Bezier { segments } => {
                if segments.is_empty() {
                    return (0.0, 0.0);
                }
                let (k, u) = segment(segments.len(), t);
                let c = &segments[k];
                let v = 1.0 - u;
                let w = [v * v * v, 3.0 * v * v * u, 3.0 * v * u * u, u * u * u];
                let f = |i: usize| (0..4).map(|j| w[j] * c[j][i]).sum::<f64>();
                (f(0), f(1))
            }
        }
    }

    /// The derivative `(dρ/dt, dh/dt)` of the generating curve.
    #[must_use]
    pub fn derivative(&self, t: f64) -> (f64, f64) {
        match self {
            &Self::Disc { radius } => (-radius, 0.0),
            &Self::Cone { radius, height } => (-radius, height),
            &Self::Sphere { radius } => {
                let pi = std::f64::consts::PI;
                let a = pi * t;
                (pi * radius * a.cos(), pi * radius * a.sin())
            }
            Self::Bezier { segments } => {
                if segments.is_empty() {
                    return (0.0, 0.0);
                }
                let n = segments.len();
                let (k, u) = segment(n, t);
                let c = &segments[k];
                let v = 1.0 - u;
                let w = [v * v, 2.0 * v * u, u * u];
                let f = |i: usize| {
                    3.0 * n as f64 * (0..3).map(|j| w[j] * (c[j + 1][i] - c[j][i])).sum::<f64>()
                };
                (f(0), f(1))
            }
        }
    }

    /// The point of the receptacle at angle `phi` (radians) and curve parameter `t`.
    #[must_use]
    pub fn point(&self, phi: f64, t: f64) -> DVec3 {
        let (rho, h) = self.at(t);
        DVec3::new(rho * phi.cos(), rho * phi.sin(), h)
    }

    /// Checks the sizes are positive and finite and a Bézier curve has at
    /// least one segment, finite control points and no negative `ρ`.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        match self {
            &Self::Disc { radius } | &Self::Sphere { radius } => {
                check::positive("PhyllotaxisParams::receptacle.radius", radius)?;
            }
            &Self::Cone { radius, height } => {
                check::positive("PhyllotaxisParams::receptacle.radius", radius)?;
                check::non_negative("PhyllotaxisParams::receptacle.height", height)?;
            }
            Self::Bezier { segments } => {
                if segments.is_empty() {
                    return Err(PlantError::InvalidParameter {
                        name: "PhyllotaxisParams::receptacle.segments",
                        value: "[]".into(),
                        reason: "a generating curve needs at least one Bézier segment".into(),
                    });
                }
                for c in segments.iter().flatten() {
                    check::non_negative("PhyllotaxisParams::receptacle.segments (ρ)", c[0])?;
                    check::finite("PhyllotaxisParams::receptacle.segments (h)", c[1])?;
                }
            }
        }
        Ok(())
    }
}

/// Parameters of the collision model.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct PhyllotaxisParams {
    /// The receptacle.
    pub receptacle: Receptacle,
    /// Divergence angle, degrees (360°·τ⁻² ≈ 137.5°).
    pub divergence_deg: f64,
    /// Radius of a primordium at `t = 0` (the base of the curve).
    pub r_base: f64,
    /// Radius of a primordium at `t = 1` (the tip); radii vary linearly in `t`.
    pub r_tip: f64,
    /// Shrinking by order of formation: the n-th primordium's radius is
    /// [`radius`](Self::radius)`(t)·(1 − order_decay)ⁿ`, in `[0, 1)`; 0 (the
    /// default) keeps sizes a function of position alone. §2.4's case of
    /// "consecutive primordia decrease in size (r₀ > r₁ > r₂ …)".
    pub order_decay: f64,
    /// Use the decreasing-size fix `t'_min = max(t_min, t_{n−1} − δ)`, δ = the new radius
    /// expressed in `t` units.
    pub use_delta: bool,
    /// Where placement starts on the curve, `t_min` of §2.4 (the base), in `[0, 1)`.
    pub t_min: f64,
    /// Where placement ends, `t_max` of §2.4 (the tip), in `(t_min, 1]`.
    pub t_max: f64,
    /// Scan steps over `t ∈ [t_min, t_max]` before bisection.
    pub scan: u32,
    /// Most primordia to place.
    pub max_count: usize,
}

impl Default for PhyllotaxisParams {
    /// A coneflower-like cone with primordia shrinking towards the tip.
    fn default() -> Self {
        Self {
            receptacle: Receptacle::Cone {
                radius: 1.0,
                height: 1.0,
            },
            divergence_deg: 360.0 / (1.5 + 1.25f64.sqrt()),
            r_base: 0.06,
            r_tip: 0.03,
            use_delta: true,
            order_decay: 0.0,
            t_min: 0.0,
            t_max: 1.0,
            scan: 2000,
            max_count: 5000,
        }
    }
}

impl PhyllotaxisParams {
    /// Checks the receptacle ([`Receptacle::validate`]), that sizes are
    /// positive and finite and that `0 ≤ t_min < t_max ≤ 1`.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.receptacle.validate()?;
        check::finite("PhyllotaxisParams::divergence_deg", self.divergence_deg)?;
        check::positive("PhyllotaxisParams::r_base", self.r_base)?;
        check::positive("PhyllotaxisParams::r_tip", self.r_tip)?;
        check::in_range(
            "PhyllotaxisParams::order_decay",
            self.order_decay,
            0.0,
            1.0 - 1e-12,
            "must lie in [0, 1)",
        )?;
        check::in_range(
            "PhyllotaxisParams::t_min",
            self.t_min,
            0.0,
            1.0,
            "must lie in [0, 1]",
        )?;
        check::in_range(
            "PhyllotaxisParams::t_max",
            self.t_max,
            0.0,
            1.0,
            "must lie in [0, 1]",
        )?;
        if self.t_min >= self.t_max {
            return Err(PlantError::InvalidParameter {
                name: "PhyllotaxisParams::t_min",
                value: format!("{} (t_max {})", self.t_min, self.t_max),
                reason: "must be less than t_max".into(),
            });
        }
        check::count(
            "PhyllotaxisParams::scan",
            self.scan as usize,
            8,
            1 << 20,
            "8 to 2^20 steps",
        )?;
        check::count(
            "PhyllotaxisParams::max_count",
            self.max_count,
            1,
            1 << 20,
            "1 to 2^20",
        )?;
        Ok(())
    }

    /// The primordium radius at curve parameter `t`: linear from
    /// [`r_base`](Self::r_base) at `t = 0` to [`r_tip`](Self::r_tip) at `t = 1`
    /// (Fig. 4's disk florets "decrease linearly towards the tip").
    #[must_use]
    pub fn radius(&self, t: f64) -> f64 {
        self.r_base + (self.r_tip - self.r_base) * t
    }
}

/// One placed primordium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Primordium {
    /// Centre.
    pub centre: DVec3,
    /// Radius.
    pub radius: f64,
    /// Angle φ, radians (not reduced modulo 2π).
    pub phi: f64,
    /// Curve parameter t.
    pub t: f64,
}

/// Places primordia until the receptacle is full or `max_count` is reached.
///
/// # Errors
///
/// [`PhyllotaxisParams::validate`]'s errors.
pub fn phyllotaxis(p: &PhyllotaxisParams) -> Result<Vec<Primordium>> {
    p.validate()?;
    let point = |phi: f64, t: f64| p.receptacle.point(phi, t);
    // Mean speed |dC/dt| of the generating curve, to turn a radius into a t
    // interval where the curve momentarily stops.
    let mean_speed = {
        let mut l = 0.0;
        let mut prev = p.receptacle.at(0.0);
        for k in 1..=256 {
            let c = p.receptacle.at(f64::from(k) / 256.0);
            l += ((c.0 - prev.0).powi(2) + (c.1 - prev.1).powi(2)).sqrt();
            prev = c;
        }
        l.max(1e-12)
    };
    let speed = |t: f64| {
        let (a, b) = p.receptacle.derivative(t);
        let v = a.hypot(b);
        if v > 1e-6 * mean_speed { v } else { mean_speed }
    };
    let step = (p.t_max - p.t_min) / f64::from(p.scan);
    let div = p.divergence_deg.to_radians();
    let mut out: Vec<Primordium> = Vec::new();
    let keep = 1.0 - p.order_decay;
    let size = |n: usize, t: f64| p.radius(t) * keep.powi(n.min(i32::MAX as usize) as i32);
    let fits = |out: &[Primordium], phi: f64, t: f64| {
        let c = point(phi, t);
        let r = size(out.len(), t);
        out.iter()
            .all(|q| q.centre.distance_squared(c) >= (q.radius + r) * (q.radius + r))
    };
    let mut t_prev = p.t_min;
    while out.len() < p.max_count {
        let n = out.len() as f64;
        let phi = n * div;
        let t_min = if p.use_delta && !out.is_empty() {
            (t_prev - size(out.len(), t_prev) / speed(t_prev)).max(p.t_min)
        } else {
            p.t_min
        };
        // Coarse scan, then bisection between the last infeasible and the first feasible t.
        let mut lo = None;
        let mut found = None;
        let mut k = 0u32;
        loop {
            let t = (t_min + f64::from(k) * step).min(p.t_max);
            if fits(&out, phi, t) {
                found = Some(t);
                break;
            }
            lo = Some(t);
            if t >= p.t_max {
                break;
            }
            k += 1;
        }
        let Some(mut hi) = found else { break };
        if let Some(mut a) = lo {
            for _ in 0..30 {
                let m = 0.5 * (a + hi);
                if fits(&out, phi, m) {
                    hi = m;
                } else {
                    a = m;
                }
            }
        }
        out.push(Primordium {
            centre: point(phi, hi),
            radius: size(out.len(), hi),
            phi,
            t: hi,
        });
        t_prev = hi;
    }
    // The first primordium always fits (at t_min, touching nothing).
    Ok(out)
}

/// Where one mature organ goes (Fowler et al. 1992, §3.1 "Principles"):
/// the organ's contact point moved to its primordium's centre, its vector
/// `v` turned to the receptacle's normal and its vector `w` to the tangent
/// of the generating curve, and the primordium's radius as its size.
///
/// An organ is modelled in its own frame with the contact point at the
/// origin, `v` along `+z` and `w` along `+x`; [`OrganFrame::to_world`]
/// places a point of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrganFrame {
    /// The primordium's centre, where the contact point goes.
    pub origin: DVec3,
    /// The receptacle's unit outward normal at the centre (the organ's `v`, local `+z`).
    pub normal: DVec3,
    /// The unit tangent of the generating curve, pointing towards the tip
    /// (the organ's `w`, local `+x`).
    pub tangent: DVec3,
    /// `normal × tangent`, completing the right-handed frame (local `+y`,
    /// along the circle of latitude).
    pub side: DVec3,
    /// The organ's scale: the primordium's radius.
    pub scale: f64,
}

impl OrganFrame {
    /// The world position of the organ's local point `p` (scaled by
    /// [`scale`](Self::scale), turned and moved).
    #[must_use]
    pub fn to_world(&self, p: DVec3) -> DVec3 {
        self.origin + self.scale * self.turn(p)
    }

    /// The world direction of the organ's local direction `d` (turned, not
    /// scaled or moved): for normals and axes.
    #[must_use]
    pub fn turn(&self, d: DVec3) -> DVec3 {
        d.x * self.tangent + d.y * self.side + d.z * self.normal
    }
}

/// The frames of the organs replacing `primordia` on `receptacle`
/// (Fowler et al. 1992, §3.1): one [`OrganFrame`] per primordium, in order.
///
/// The normal of the surface of revolution at `(φ, t)` is
/// `(h′ cos φ, h′ sin φ, −ρ′)`, and the tangent `(ρ′ cos φ, ρ′ sin φ, h′)`,
/// both normalised; where the curve's derivative vanishes (a Bézier
/// segment whose end control points coincide) it is taken a little inside
/// the curve.
///
/// # Errors
///
/// [`Receptacle::validate`]'s errors; [`PlantError::InvalidParameter`]
/// naming `primordia` for a centre, angle or parameter that is not finite,
/// a radius that is not positive, or a point where the curve has no
/// direction.
pub fn organ_frames(receptacle: &Receptacle, primordia: &[Primordium]) -> Result<Vec<OrganFrame>> {
    receptacle.validate()?;
    primordia
        .iter()
        .map(|q| {
            check::positive("primordia (radius)", q.radius)?;
            check::finite("primordia (phi)", q.phi)?;
            check::finite("primordia (t)", q.t)?;
            check::finite3("primordia (centre)", q.centre)?;
            let mut d = receptacle.derivative(q.t);
            for nudge in [1e-6, 1e-4, 1e-2] {
                if d.0.hypot(d.1) > 1e-12 {
                    break;
                }
                let t = if q.t > 0.5 { q.t - nudge } else { q.t + nudge };
                d = receptacle.derivative(t);
            }
            let (c, s) = (q.phi.cos(), q.phi.sin());
            let tangent = DVec3::new(d.0 * c, d.0 * s, d.1).try_normalize();
            let normal = DVec3::new(d.1 * c, d.1 * s, -d.0).try_normalize();
            let (Some(tangent), Some(normal)) = (tangent, normal) else {
                return Err(PlantError::InvalidParameter {
                    name: "primordia",
                    value: format!("t = {}", q.t),
                    reason: "the generating curve has no direction there".into(),
                });
            };
            Ok(OrganFrame {
                origin: q.centre,
                normal,
                tangent,
                side: normal.cross(tangent),
                scale: q.radius,
            })
        })
        .collect()
}
