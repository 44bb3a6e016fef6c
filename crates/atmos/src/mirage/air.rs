//! The refractive index of stratified air: the Gladstone–Dale relation
//! `n − 1 = K·ρ` with the ideal-gas density `ρ = pM/(RT)` and the
//! hydrostatic pressure of a temperature profile.

use glam::DVec3;

use crate::error::{Result, finite, in_range, invalid, positive};

/// The Gladstone–Dale constant of air in the visible, m³/kg (≈ 2.26e-4).
pub const GLADSTONE_DALE_AIR: f64 = 2.26e-4;
/// Molar mass of dry air, kg/mol.
pub const MOLAR_MASS_AIR: f64 = 0.028_964_4;
/// Molar gas constant, J/(mol·K).
pub const GAS_CONSTANT: f64 = 8.314_462_618;
/// Hottest air or surface a [`TemperatureProfile`] accepts, K.
pub const MAX_TEMPERATURE_K: f64 = 1e4;
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

    /// Checks every field against its physical range: temperatures (the
    /// air's and the surface's, or the ground's and above the inversion) in
    /// `(0, 10⁴]` K, the excess or jump between them finite, lengths in
    /// `[10⁻⁶, 10⁵]` m, the inversion's height within `±10⁵` m and lapse
    /// rates within `±1` K/m.
    fn validate(&self) -> Result<()> {
        let temperature = |n, v| {
            in_range(
                n,
                v,
                f64::MIN_POSITIVE,
                MAX_TEMPERATURE_K,
                "must be in (0, 10⁴] K",
            )
        };
        let length = |n, v| in_range(n, v, 1e-6, 1e5, "must be in [10⁻⁶, 10⁵] m");
        let lapse = |v| in_range("lapse_k_per_m", v, -1.0, 1.0, "must be in [−1, 1] K/m");
        match *self {
            TemperatureProfile::HotSurface {
                air_k,
                excess_k,
                decay_m,
                lapse_k_per_m,
            } => {
                temperature("air_k", air_k)?;
                finite("excess_k", excess_k)?;
                length("decay_m", decay_m)?;
                lapse(lapse_k_per_m)?;
                let surface = air_k + excess_k;
                if !(surface > 0.0 && surface <= MAX_TEMPERATURE_K) {
                    return Err(invalid(
                        "excess_k",
                        excess_k,
                        "surface temperature air_k + excess_k must be in (0, 10⁴] K",
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
                temperature("ground_k", ground_k)?;
                finite("jump_k", jump_k)?;
                in_range("height_m", height_m, -1e5, 1e5, "must be in [−10⁵, 10⁵] m")?;
                length("thickness_m", thickness_m)?;
                lapse(lapse_k_per_m)?;
                let above = ground_k + jump_k;
                if !(above > 0.0 && above <= MAX_TEMPERATURE_K) {
                    return Err(invalid(
                        "jump_k",
                        jump_k,
                        "temperature ground_k + jump_k must be in (0, 10⁴] K",
                    ));
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
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter)
    /// naming the field of a non-physical temperature profile (temperatures
    /// outside `(0, 10⁴]` K, lengths outside `[10⁻⁶, 10⁵]` m, lapse rates
    /// beyond `±1` K/m, NaN anywhere) or a pressure outside `(0, 10⁷]` Pa.
    pub fn new(profile: TemperatureProfile, pressure_pa: f64) -> Result<Self> {
        profile.validate()?;
        positive("pressure_pa", pressure_pa)?;
        in_range(
            "pressure_pa",
            pressure_pa,
            0.0,
            1e7,
            "must be in (0, 10⁷] Pa",
        )?;
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
