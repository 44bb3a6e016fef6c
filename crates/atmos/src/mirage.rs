//! Mirages: ray paths through air whose refractive index varies with height.
//!
//! * [`StratifiedAir`]: `n(z)` from a temperature profile through the
//!   Gladstone–Dale relation `n − 1 = K·ρ` with the ideal-gas density
//!   `ρ = pM/(RT)`; hot ground gives the **inferior** mirage, a warm layer
//!   aloft (inversion) the **superior** one.
//! * [`GrinTracer`]: the ray equation `d/ds(n dx/ds) = ∇n` integrated with an
//!   adaptive Dormand–Prince 5(4) Runge–Kutta scheme. In a smooth profile the
//!   turning point is smooth: the Khular/Fabri picture (Musgrave 1993, §4.3.2)
//!   is right for smooth profiles and Musgrave's kinked "reflected hyperbola"
//!   (Musgrave 1993, §4.3.2) only for a sharp interface, which is
//! * [`PlanarMirage`]: Musgrave's semi-physical model (Musgrave 1993, §1.2.4.4,
//!   Musgrave 1993, §4.3–4.3.3): one planar index discontinuity, optionally with a perturbed
//!   (fBm-bumped) normal, and total internal reflection for glancing rays
//!   going from higher to lower index. TIR rays are reflected, never dropped
//!   (Musgrave 1993, §4.3.3).

use glam::DVec3;

use crate::Dir3;
use crate::error::{AtmosError, Result, finite, invalid, positive};
use crate::optics::{fresnel, reflect, refract};

/// The Gladstone–Dale constant of air in the visible, m³/kg (≈ 2.26e-4).
pub const GLADSTONE_DALE_AIR: f64 = 2.26e-4;
/// Molar mass of dry air, kg/mol.
pub const MOLAR_MASS_AIR: f64 = 0.028_964_4;
/// Molar gas constant, J/(mol·K).
pub const GAS_CONSTANT: f64 = 8.314_462_618;
/// Standard gravity, m/s².
pub const GRAVITY: f64 = 9.806_65;

/// A refractive-index field.
pub trait IndexField: Send + Sync {
    /// The refractive index at `p`.
    fn n(&self, p: DVec3) -> f64;
    /// The gradient of the index at `p`.
    fn grad(&self, p: DVec3) -> DVec3;
}

/// A uniform medium (straight rays): the oracle for the tracer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UniformIndex(pub f64);

impl IndexField for UniformIndex {
    fn n(&self, _p: DVec3) -> f64 {
        self.0
    }
    fn grad(&self, _p: DVec3) -> DVec3 {
        DVec3::ZERO
    }
}

/// Air temperature as a function of height above the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum TemperatureProfile {
    /// `T(z) = T_air − Γz + ΔT·e^{−z/h}`: a hot surface (road, desert) under
    /// cooler air; `ΔT > 0` gives an inferior mirage.
    HotSurface {
        /// Air temperature far above the surface (extrapolated to z = 0), K.
        air_k: f64,
        /// Surface excess temperature, K.
        excess_k: f64,
        /// e-folding height of the excess, m.
        decay_m: f64,
        /// Lapse rate Γ, K/m (0.0065 in the standard atmosphere).
        lapse_k_per_m: f64,
    },
    /// `T(z) = T₀ − Γz + ΔT·(1 + tanh((z − z_i)/w))/2`: a warm layer above
    /// cold air (over cold sea or ice); `ΔT > 0` gives a superior mirage.
    Inversion {
        /// Temperature at the ground, K.
        ground_k: f64,
        /// Temperature jump across the inversion, K.
        jump_k: f64,
        /// Height of the inversion, m.
        height_m: f64,
        /// Thickness scale `w` of the inversion, m.
        thickness_m: f64,
        /// Lapse rate Γ, K/m.
        lapse_k_per_m: f64,
    },
}

impl TemperatureProfile {
    /// A road at 60 °C under 20 °C air, the excess decaying over 0.3 m.
    #[must_use]
    pub fn hot_road() -> Self {
        TemperatureProfile::HotSurface {
            air_k: 293.15,
            excess_k: 40.0,
            decay_m: 0.3,
            lapse_k_per_m: 0.0065,
        }
    }

    /// A 10 K inversion 20 m above cold water, 4 m thick.
    #[must_use]
    pub fn cold_sea_inversion() -> Self {
        TemperatureProfile::Inversion {
            ground_k: 273.15,
            jump_k: 10.0,
            height_m: 20.0,
            thickness_m: 4.0,
            lapse_k_per_m: 0.0065,
        }
    }

    /// `(T, dT/dz)` at height `z`.
    #[must_use]
    pub fn eval(&self, z: f64) -> (f64, f64) {
        match *self {
            TemperatureProfile::HotSurface {
                air_k,
                excess_k,
                decay_m,
                lapse_k_per_m,
            } => {
                let e = (-z / decay_m).exp();
                (
                    air_k - lapse_k_per_m * z + excess_k * e,
                    -lapse_k_per_m - excess_k / decay_m * e,
                )
            }
            TemperatureProfile::Inversion {
                ground_k,
                jump_k,
                height_m,
                thickness_m,
                lapse_k_per_m,
            } => {
                let th = ((z - height_m) / thickness_m).tanh();
                (
                    ground_k - lapse_k_per_m * z + 0.5 * jump_k * (1.0 + th),
                    -lapse_k_per_m + 0.5 * jump_k * (1.0 - th * th) / thickness_m,
                )
            }
        }
    }

    fn validate(&self) -> Result<()> {
        match *self {
            TemperatureProfile::HotSurface {
                air_k,
                excess_k,
                decay_m,
                lapse_k_per_m,
            } => {
                positive("air_k", air_k)?;
                finite("excess_k", excess_k)?;
                positive("decay_m", decay_m)?;
                finite("lapse_k_per_m", lapse_k_per_m)?;
                if air_k + excess_k.min(0.0) <= 0.0 {
                    return Err(invalid(
                        "excess_k",
                        excess_k,
                        "surface temperature must stay above 0 K",
                    ));
                }
            }
            TemperatureProfile::Inversion {
                ground_k,
                jump_k,
                height_m,
                thickness_m,
                lapse_k_per_m,
            } => {
                positive("ground_k", ground_k)?;
                finite("jump_k", jump_k)?;
                finite("height_m", height_m)?;
                positive("thickness_m", thickness_m)?;
                finite("lapse_k_per_m", lapse_k_per_m)?;
                if ground_k + jump_k.min(0.0) <= 0.0 {
                    return Err(invalid("jump_k", jump_k, "temperature must stay above 0 K"));
                }
            }
        }
        Ok(())
    }
}

/// Horizontally uniform air: `n(z) = 1 + K·p(z)M/(R·T(z))` (Gladstone–Dale),
/// with hydrostatic pressure `p(z) = p₀·e^{−gMz/(R·T_ref)}`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StratifiedAir {
    profile: TemperatureProfile,
    pressure_pa: f64,
    gladstone_dale: f64,
    t_ref: f64,
}

impl StratifiedAir {
    /// Air with temperature `profile` and ground pressure `pressure_pa` (101 325 Pa
    /// standard), Gladstone–Dale constant [`GLADSTONE_DALE_AIR`].
    ///
    /// Refuses non-physical temperatures, thicknesses or pressures.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`] for a non-physical temperature profile (non-positive or
    /// NaN temperatures or thicknesses) or pressure.
    pub fn new(profile: TemperatureProfile, pressure_pa: f64) -> Result<Self> {
        profile.validate()?;
        positive("pressure_pa", pressure_pa)?;
        let t_ref = profile.eval(0.0).0;
        Ok(Self {
            profile,
            pressure_pa,
            gladstone_dale: GLADSTONE_DALE_AIR,
            t_ref,
        })
    }

    /// The refractive index of air at temperature `t_k` and pressure `p_pa`.
    #[must_use]
    pub fn index_of(t_k: f64, p_pa: f64) -> f64 {
        1.0 + GLADSTONE_DALE_AIR * p_pa * MOLAR_MASS_AIR / (GAS_CONSTANT * t_k)
    }

    /// `(n, dn/dz)` at height `z` (below 0 the ground value is continued).
    #[must_use]
    pub fn n_and_slope(&self, z: f64) -> (f64, f64) {
        let (t, dt) = self.profile.eval(z);
        let k = GRAVITY * MOLAR_MASS_AIR / (GAS_CONSTANT * self.t_ref);
        let p = self.pressure_pa * (-k * z).exp();
        let c = self.gladstone_dale * MOLAR_MASS_AIR / GAS_CONSTANT;
        let rho_term = p / t;
        (1.0 + c * rho_term, c * (-k * p / t - p * dt / (t * t)))
    }

    /// The temperature profile.
    #[must_use]
    pub fn profile(&self) -> TemperatureProfile {
        self.profile
    }
}

impl IndexField for StratifiedAir {
    fn n(&self, p: DVec3) -> f64 {
        self.n_and_slope(p.z).0
    }
    fn grad(&self, p: DVec3) -> DVec3 {
        DVec3::new(0.0, 0.0, self.n_and_slope(p.z).1)
    }
}

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

/// Adaptive Dormand–Prince 5(4) integrator of the ray equation in a
/// gradient-index medium: state `(x, v = n·t̂)`, `dx/ds = v/n`, `dv/ds = ∇n`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    /// Accepted-step cap.
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
    /// Returns [`AtmosError::InvalidParameter`] naming the first setting that is non-positive or NaN, or a
    /// `top_z` not above `ground_z`.
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
        if self.max_steps == 0 {
            return Err(invalid("max_steps", 0, "must be > 0"));
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

/// What happens when a ray meets Musgrave's mirage plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interaction {
    /// Where the ray meets the plane.
    pub point: DVec3,
    /// The reflected direction.
    pub reflected: Dir3,
    /// The refracted direction, `None` on total internal reflection.
    pub refracted: Option<Dir3>,
    /// Unpolarised Fresnel reflectance (1 on TIR).
    pub reflectance: f64,
}

/// Musgrave's mirage: a horizontal plane at `height_m` separating air of index
/// `n_above` from hotter, optically thinner air `n_below` (Musgrave 1993, §1.2.4.4, §4.3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PlanarMirage {
    height_m: f64,
    n_above: f64,
    n_below: f64,
}

impl PlanarMirage {
    /// A mirage plane; refuses NaN heights and non-positive indices.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`] for a NaN height or a non-positive or NaN index.
    pub fn new(height_m: f64, n_above: f64, n_below: f64) -> Result<Self> {
        finite("height_m", height_m)?;
        crate::optics::check_ior("n_above", n_above)?;
        crate::optics::check_ior("n_below", n_below)?;
        Ok(Self {
            height_m,
            n_above,
            n_below,
        })
    }

    /// The plane from air temperatures above and below (Gladstone–Dale at `pressure_pa`).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`] if a temperature or the pressure is not finite and
    /// positive.
    pub fn from_temperatures(
        height_m: f64,
        above_k: f64,
        below_k: f64,
        pressure_pa: f64,
    ) -> Result<Self> {
        positive("above_k", above_k)?;
        positive("below_k", below_k)?;
        positive("pressure_pa", pressure_pa)?;
        Self::new(
            height_m,
            StratifiedAir::index_of(above_k, pressure_pa),
            StratifiedAir::index_of(below_k, pressure_pa),
        )
    }

    /// The critical *grazing* angle (from the plane) below which rays from
    /// above are totally reflected: `arccos(n_below/n_above)`, or `None` if
    /// the lower layer is not thinner.
    #[must_use]
    pub fn critical_grazing_angle(&self) -> Option<f64> {
        (self.n_below < self.n_above).then(|| (self.n_below / self.n_above).acos())
    }

    /// Intersects the ray with the plane and splits it there. `bump`, if given,
    /// is the perturbed (e.g. fBm-bumped) unit normal at the hit point; it is
    /// oriented to face the incoming ray. `None` if the ray never meets the plane.
    #[must_use]
    pub fn interact(&self, origin: DVec3, dir: Dir3, bump: Option<Dir3>) -> Option<Interaction> {
        let d = dir.get();
        if d.z == 0.0 {
            return None;
        }
        let t = (self.height_m - origin.z) / d.z;
        if t.is_nan() || t <= 0.0 {
            return None;
        }
        let point = origin + d * t;
        let from_above = d.z < 0.0;
        let (n1, n2) = if from_above {
            (self.n_above, self.n_below)
        } else {
            (self.n_below, self.n_above)
        };
        let mut normal = bump.unwrap_or(Dir3::UP);
        if normal.get().dot(d) > 0.0 {
            normal = normal.reversed();
        }
        let cos_i = -normal.get().dot(d);
        let f = fresnel(n1, n2, cos_i);
        Some(Interaction {
            point,
            reflected: reflect(dir, normal),
            refracted: refract(dir, normal, n1 / n2),
            reflectance: f.unpolarized(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn road() -> StratifiedAir {
        StratifiedAir::new(TemperatureProfile::hot_road(), 101_325.0).unwrap()
    }

    #[test]
    fn gladstone_dale_sea_level() {
        // n − 1 ≈ 2.77e-4 at 15 °C, 1 atm; hotter air is thinner.
        let n = StratifiedAir::index_of(288.15, 101_325.0);
        assert!((n - 1.0 - 2.77e-4).abs() < 3e-6, "{}", n - 1.0);
        assert!(StratifiedAir::index_of(333.15, 101_325.0) < n);
        // The slope is the derivative of n(z).
        let air = road();
        for z in [0.01, 0.2, 1.0, 30.0] {
            let h = 1e-5;
            let fd = (air.n_and_slope(z + h).0 - air.n_and_slope(z - h).0) / (2.0 * h);
            assert!(
                (fd - air.n_and_slope(z).1).abs() < 1e-6 * fd.abs() + 1e-11,
                "{z}"
            );
        }
    }

    #[test]
    fn uniform_medium_gives_straight_rays() {
        let t = GrinTracer {
            max_length_m: 500.0,
            ..GrinTracer::default()
        };
        let d = Dir3::new(DVec3::new(1.0, 0.3, 0.05)).unwrap();
        let o = DVec3::new(0.0, 0.0, 2.0);
        let p = t.trace(&UniformIndex(1.0003), o, d).unwrap();
        for q in &p.points {
            let along = (*q - o).dot(d.get());
            assert!(((*q - o) - d.get() * along).length() < 1e-9);
        }
        assert!((p.final_direction() - d.get()).length() < 1e-12);
    }

    #[test]
    fn inferior_mirage_ray_turns_up_above_the_hot_layer() {
        let air = road();
        let t = GrinTracer {
            max_length_m: 2000.0,
            top_z: 50.0,
            ..GrinTracer::default()
        };
        // From 1.5 m, 0.12° below the horizontal: the ray bends back up before the road.
        let d = Dir3::from_angles(-0.12f64.to_radians(), 0.0).unwrap();
        let p = t.trace(&air, DVec3::new(0.0, 0.0, 1.5), d).unwrap();
        assert!(p.min_z() > 0.0, "min z {}", p.min_z());
        assert!(p.final_direction().z > 0.0, "{:?}", p.end);
        assert!(
            invariant_drift(&p, &air) < 1e-9,
            "{}",
            invariant_drift(&p, &air)
        );
        // Steeper rays reach the road.
        let steep = t
            .trace(
                &air,
                DVec3::new(0.0, 0.0, 1.5),
                Dir3::from_angles(-1f64.to_radians(), 0.0).unwrap(),
            )
            .unwrap();
        assert!(matches!(steep.end, PathEnd::Ground { .. }));
    }

    #[test]
    fn superior_mirage_ray_bends_down_under_the_inversion() {
        let air = StratifiedAir::new(TemperatureProfile::cold_sea_inversion(), 101_325.0).unwrap();
        let t = GrinTracer {
            max_length_m: 30_000.0,
            top_z: 200.0,
            ..GrinTracer::default()
        };
        let d = Dir3::from_angles(0.05f64.to_radians(), 0.0).unwrap();
        let p = t.trace(&air, DVec3::new(0.0, 0.0, 5.0), d).unwrap();
        let zmax = p.points.iter().map(|q| q.z).fold(f64::MIN, f64::max);
        assert!(zmax < 30.0, "trapped below the inversion top: {zmax}");
        assert!(p.final_direction().z < 0.0 || matches!(p.end, PathEnd::Ground { .. }));
    }

    #[test]
    fn paths_are_reversible() {
        let air = road();
        let t = GrinTracer {
            max_length_m: 600.0,
            top_z: 50.0,
            tolerance_m: 1e-11,
            ..GrinTracer::default()
        };
        let o = DVec3::new(0.0, 0.0, 1.5);
        let fwd = t
            .trace(
                &air,
                o,
                Dir3::from_angles(-0.1f64.to_radians(), 0.3).unwrap(),
            )
            .unwrap();
        let end = *fwd.points.last().unwrap();
        let back_dir = Dir3::new(-fwd.final_direction()).unwrap();
        let back = GrinTracer {
            max_length_m: fwd.length_m,
            ..t
        }
        .trace(&air, end, back_dir)
        .unwrap();
        let home = *back.points.last().unwrap();
        assert!((home - o).length() < 1e-5, "returned to {home}");
    }

    #[test]
    fn total_internal_reflection_exactly_beyond_the_critical_angle() {
        let m = PlanarMirage::from_temperatures(0.5, 293.15, 333.15, 101_325.0).unwrap();
        let crit = m.critical_grazing_angle().unwrap();
        // About 0.46° for 60 °C ground air under 20 °C air.
        assert!(
            (crit.to_degrees() - 0.46).abs() < 0.03,
            "{}",
            crit.to_degrees()
        );
        let o = DVec3::new(0.0, 0.0, 2.0);
        let below = m
            .interact(o, Dir3::from_angles(-(crit * 0.999), 0.0).unwrap(), None)
            .unwrap();
        assert!(below.refracted.is_none() && below.reflectance == 1.0);
        assert!(below.reflected.get().z > 0.0);
        let above = m
            .interact(o, Dir3::from_angles(-(crit * 1.001), 0.0).unwrap(), None)
            .unwrap();
        assert!(above.refracted.is_some() && above.reflectance < 1.0);
        // Going up from the thin layer never reflects totally.
        let up = m
            .interact(
                DVec3::new(0.0, 0.0, 0.1),
                Dir3::from_angles(0.001, 0.0).unwrap(),
                None,
            )
            .unwrap();
        assert!(up.refracted.is_some());
        // A bumped normal changes the reflection but never yields NaN.
        let bump = Dir3::new(DVec3::new(0.01, 0.0, 1.0)).unwrap();
        let b = m
            .interact(o, Dir3::from_angles(-0.002, 0.0).unwrap(), Some(bump))
            .unwrap();
        assert!(b.reflected.get().is_finite());
        assert!(m.interact(o, Dir3::UP, None).is_none());
    }

    #[test]
    fn bad_input_is_refused() {
        let t = GrinTracer::default();
        assert!(
            t.trace(&road(), DVec3::new(0.0, 0.0, -1.0), Dir3::X)
                .is_err()
        );
        assert!(
            GrinTracer {
                tolerance_m: 0.0,
                ..t
            }
            .trace(&road(), DVec3::new(0.0, 0.0, 1.0), Dir3::X)
            .is_err()
        );
        assert!(StratifiedAir::new(TemperatureProfile::hot_road(), -1.0).is_err());
        let bad = TemperatureProfile::HotSurface {
            air_k: f64::NAN,
            excess_k: 1.0,
            decay_m: 1.0,
            lapse_k_per_m: 0.0,
        };
        assert!(StratifiedAir::new(bad, 101_325.0).is_err());
        assert!(PlanarMirage::new(0.0, -1.0, 1.0).is_err());
        assert!(PlanarMirage::from_temperatures(0.0, 0.0, 300.0, 1e5).is_err());
    }
}
