//! Collision-based spiral phyllotaxis (Fowler, Prusinkiewicz & Battjes 1992).
//!
//! Fowler et al. 1992, §3: primordia are spheres centred on a receptacle, a
//! surface of revolution `(φ, ρ(t), h(t))`. The n-th primordium sits at
//! `φ_n = n·137.5°`, and at the smallest `t ≥ t'_min` where it touches no
//! earlier primordium: `‖P_i − P_n‖ ≥ r_i + r_n` for all `i < n` (the
//! recurrence of §3). `t'_min = max(t_min, t_{n−1} − δ)` with `δ` about the
//! new primordium's radius keeps small late primordia from falling into gaps
//! near the base (the source's fix for decreasing sizes). Placement ends when
//! no `t` fits.
//!
//! The source finds `t` by binary search, which assumes the feasible set is
//! an interval above some `t`; it need not be. Here `t` is scanned in small
//! steps and the first feasible step is refined by bisection against the
//! previous (infeasible) one.

use glam::DVec3;
use natura_core::check;

use crate::error::{PlantError, Result};

/// The receptacle's generating curve, `t ∈ [0, 1]` from base to tip.
#[derive(Clone, Copy, Debug, PartialEq)]
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
}

impl Receptacle {
    /// `(ρ(t), h(t))`.
    #[must_use]
    pub fn at(&self, t: f64) -> (f64, f64) {
        match *self {
            Self::Disc { radius } => (radius * (1.0 - t), 0.0),
            Self::Cone { radius, height } => (radius * (1.0 - t), height * t),
            Self::Sphere { radius } => {
                let a = std::f64::consts::PI * t;
                (radius * a.sin(), -radius * a.cos())
            }
        }
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
    /// Radius of the first primordium (at the base).
    pub r_base: f64,
    /// Radius of a primordium at the tip (`t = 1`); radii vary linearly in `t`.
    pub r_tip: f64,
    /// Use the decreasing-size fix `t'_min = max(t_min, t_{n−1} − δ)`, δ = the new radius
    /// expressed in `t` units.
    pub use_delta: bool,
    /// Scan steps over `t ∈ [0, 1]` before bisection.
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
            scan: 2000,
            max_count: 5000,
        }
    }
}

impl PhyllotaxisParams {
    /// Checks sizes are positive and finite.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        match self.receptacle {
            Receptacle::Disc { radius } | Receptacle::Sphere { radius } => {
                check::positive("PhyllotaxisParams::receptacle.radius", radius)?;
            }
            Receptacle::Cone { radius, height } => {
                check::positive("PhyllotaxisParams::receptacle.radius", radius)?;
                check::non_negative("PhyllotaxisParams::receptacle.height", height)?;
            }
        }
        check::finite("PhyllotaxisParams::divergence_deg", self.divergence_deg)?;
        check::positive("PhyllotaxisParams::r_base", self.r_base)?;
        check::positive("PhyllotaxisParams::r_tip", self.r_tip)?;
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
    let point = |phi: f64, t: f64| {
        let (rho, h) = p.receptacle.at(t);
        DVec3::new(rho * phi.cos(), rho * phi.sin(), h)
    };
    let radius = |t: f64| p.r_base + (p.r_tip - p.r_base) * t;
    // Arc length of the generating curve, to turn a radius into a t interval.
    let len = {
        let mut l = 0.0;
        let mut prev = p.receptacle.at(0.0);
        for k in 1..=256 {
            let c = p.receptacle.at(f64::from(k) / 256.0);
            l += ((c.0 - prev.0).powi(2) + (c.1 - prev.1).powi(2)).sqrt();
            prev = c;
        }
        l.max(1e-12)
    };
    let step = 1.0 / f64::from(p.scan);
    let div = p.divergence_deg.to_radians();
    let mut out: Vec<Primordium> = Vec::new();
    let fits = |out: &[Primordium], phi: f64, t: f64| {
        let c = point(phi, t);
        let r = radius(t);
        out.iter()
            .all(|q| q.centre.distance_squared(c) >= (q.radius + r) * (q.radius + r))
    };
    let mut t_prev = 0.0;
    while out.len() < p.max_count {
        let n = out.len() as f64;
        let phi = n * div;
        let t_min = if p.use_delta && !out.is_empty() {
            (t_prev - radius(t_prev) / len).max(0.0)
        } else {
            0.0
        };
        // Coarse scan, then bisection between the last infeasible and the first feasible t.
        let mut lo = None;
        let mut found = None;
        let mut t = t_min;
        while t <= 1.0 {
            if fits(&out, phi, t) {
                found = Some(t);
                break;
            }
            lo = Some(t);
            t += step;
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
            radius: radius(hi),
            phi,
            t: hi,
        });
        t_prev = hi;
    }
    if out.is_empty() {
        return Err(PlantError::InvalidParameter {
            name: "PhyllotaxisParams::r_base",
            value: p.r_base.to_string(),
            reason: "no primordium fits on the receptacle".into(),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn golden_angle_no_overlaps_and_monotone_t() {
        let p = PhyllotaxisParams::default();
        assert!((p.divergence_deg - 137.5078).abs() < 1e-3);
        let v = phyllotaxis(&p).unwrap();
        assert!(v.len() > 100, "{}", v.len());
        for (n, a) in v.iter().enumerate() {
            // φ_n = n·137.5° (mod 360).
            let d = (a.phi.to_degrees() - n as f64 * p.divergence_deg).rem_euclid(360.0);
            assert!(!(1e-6..=360.0 - 1e-6).contains(&d));
            for b in &v[..n] {
                assert!(a.centre.distance(b.centre) >= a.radius + b.radius - 1e-9);
            }
        }
        // Consecutive divergence (angle between successive organs) is the golden angle.
        let d = (v[1].phi - v[0].phi).to_degrees();
        assert!((d - 137.5).abs() < 0.01);
        // With δ, t rarely goes back by more than the new organ's size in t.
        for w in v.windows(2) {
            assert!(w[1].t >= w[0].t - 0.1);
        }
    }

    #[test]
    fn bad_params() {
        let p = PhyllotaxisParams {
            r_base: f64::NAN,
            ..PhyllotaxisParams::default()
        };
        assert!(phyllotaxis(&p).is_err());
    }
}
