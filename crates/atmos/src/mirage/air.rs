//! The refractive index of stratified air: the Gladstone–Dale relation
//! `n − 1 = K·ρ` with the ideal-gas density `ρ = pM/(RT)` and the
//! hydrostatic pressure of a temperature profile.

use glam::DVec3;

use crate::error::{Result, finite, invalid, positive};

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
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
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
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for a non-physical temperature profile (non-positive or
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
