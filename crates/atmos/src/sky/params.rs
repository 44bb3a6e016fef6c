//! Parameters of the physical sky: planet, Rayleigh, Mie, ozone, sun, LUT sizes.

use crate::error::{Result, in_range, invalid, non_negative, positive};

/// Rayleigh (molecular) scattering.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct RayleighParams {
    /// Scale height of the exponential density profile, m (8000).
    pub scale_height_m: f64,
    /// Sea-level refractive index minus one, held fixed over wavelength so the
    /// coefficient follows λ⁻⁴ exactly (0.0003, Musgrave 1993, §4.2.4.3.2).
    pub n_minus_1: f64,
    /// Sea-level molecular number density, m⁻³ (2.545e25).
    pub number_density: f64,
    /// King correction factor for depolarisation (1.0: none).
    pub king_factor: f64,
}

impl Default for RayleighParams {
    fn default() -> Self {
        Self {
            scale_height_m: 8000.0,
            n_minus_1: 3e-4,
            number_density: 2.545e25,
            king_factor: 1.0,
        }
    }
}

/// Which phase function the aerosols (Mie) use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum MiePhase {
    /// Henyey–Greenstein.
    HenyeyGreenstein,
    /// Cornette–Shanks (the default; used by Bruneton and Hillaire).
    CornetteShanks,
}

/// Mie (aerosol) scattering and absorption.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct MieParams {
    /// Scale height of the exponential density profile, m (1200).
    pub scale_height_m: f64,
    /// Sea-level scattering coefficient at 550 nm, m⁻¹ (3.996e-6, Hillaire 2020).
    pub scattering: f64,
    /// Sea-level absorption coefficient at 550 nm, m⁻¹ (0.444e-6, Hillaire 2020).
    pub absorption: f64,
    /// Ångström exponent α of `β ∝ (λ/550)^{−α}` (0: wavelength-independent, Musgrave 1993, §4.1.7).
    pub angstrom_exponent: f64,
    /// Asymmetry parameter `g` (0.8).
    pub g: f64,
    /// Phase function.
    pub phase: MiePhase,
}

impl Default for MieParams {
    fn default() -> Self {
        Self {
            scale_height_m: 1200.0,
            scattering: 3.996e-6,
            absorption: 0.444e-6,
            angstrom_exponent: 0.0,
            g: 0.8,
            phase: MiePhase::CornetteShanks,
        }
    }
}

/// The ozone layer: a tent-shaped density profile that only absorbs.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct OzoneParams {
    /// Whether ozone absorbs at all (true).
    pub enabled: bool,
    /// Altitude of peak density, m (25 000).
    pub peak_altitude_m: f64,
    /// Half-width of the tent, m (15 000: density from 10 km to 40 km).
    pub half_width_m: f64,
    /// Total column in Dobson units (300).
    pub column_dobson: f64,
}

impl Default for OzoneParams {
    fn default() -> Self {
        Self {
            enabled: true,
            peak_altitude_m: 25_000.0,
            half_width_m: 15_000.0,
            column_dobson: 300.0,
        }
    }
}

/// How radiance is carried through the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Evaluation {
    /// Three channels holding spectral radiance at 680, 550 and 440 nm, used
    /// directly as linear RGB (the common real-time approximation).
    Rgb,
    /// [`SPECTRAL_BANDS`](crate::sky::SPECTRAL_BANDS) bands of 25 nm over
    /// 380–780 nm, converted to linear sRGB through the CIE 1931 CMFs. Costs
    /// more only in precomputation: lookups are RGB either way.
    Spectral,
}

/// Resolutions and step counts of the Hillaire 2020 look-up tables.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct LutSettings {
    /// Transmittance LUT `(μ, r)` size (256 × 64).
    pub transmittance: (usize, usize),
    /// Multiple-scattering LUT `(μ_s, r)` size (32 × 32).
    pub multiple_scattering: (usize, usize),
    /// Sky-view LUT `(azimuth, zenith)` size (192 × 108).
    pub sky_view: (usize, usize),
    /// Ray-march steps per sky-view texel (32).
    pub sky_view_steps: usize,
    /// Aerial-perspective volume `(azimuth, zenith, distance)` size (32 × 64 × 32).
    pub aerial: (usize, usize, usize),
    /// Distance covered by the aerial-perspective volume, m (64 000).
    pub aerial_max_distance_m: f64,
}

impl Default for LutSettings {
    fn default() -> Self {
        Self {
            transmittance: (256, 64),
            multiple_scattering: (32, 32),
            sky_view: (192, 108),
            sky_view_steps: 32,
            aerial: (32, 64, 32),
            aerial_max_distance_m: 64_000.0,
        }
    }
}

/// Everything that defines a physical atmosphere. `Default` is Earth with the
/// constants of Bruneton & Neyret 2008 / Hillaire 2020 (planet 6360 km,
/// atmosphere 100 km thick).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct AtmosphereParams {
    /// Planet (ground, sea level) radius, m (6 360 000).
    pub bottom_radius_m: f64,
    /// Radius of the top of the atmosphere, m (6 460 000).
    pub top_radius_m: f64,
    /// Molecular scattering.
    pub rayleigh: RayleighParams,
    /// Aerosol scattering.
    pub mie: MieParams,
    /// Ozone absorption.
    pub ozone: OzoneParams,
    /// Lambertian ground albedo for light bounced into the multiple-scattering LUT (0.3).
    pub ground_albedo: f64,
    /// Angular radius of the sun, radians (0.004675).
    pub sun_angular_radius: f64,
    /// Scale on the solar spectrum (1: the real sun at 1 AU).
    pub sun_intensity_scale: f64,
    /// Whether the multiple-scattering LUT is used (Hillaire 2020 §5.5). Off,
    /// the model is single scattering only (Nishita 1993).
    pub multiple_scattering: bool,
    /// RGB or spectral evaluation.
    pub evaluation: Evaluation,
    /// LUT sizes.
    pub lut: LutSettings,
}

impl Default for AtmosphereParams {
    fn default() -> Self {
        Self {
            bottom_radius_m: 6_360_000.0,
            top_radius_m: 6_460_000.0,
            rayleigh: RayleighParams::default(),
            mie: MieParams::default(),
            ozone: OzoneParams::default(),
            ground_albedo: 0.3,
            sun_angular_radius: 0.004_675,
            sun_intensity_scale: 1.0,
            multiple_scattering: true,
            evaluation: Evaluation::Rgb,
            lut: LutSettings::default(),
        }
    }
}

impl AtmosphereParams {
    /// Refuses NaN, negative or inconsistent values with a typed error naming the field.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) naming the first field that is NaN, negative or
    /// inconsistent with the others.
    pub fn validate(&self) -> Result<()> {
        positive("bottom_radius_m", self.bottom_radius_m)?;
        positive("top_radius_m", self.top_radius_m)?;
        if self.top_radius_m <= self.bottom_radius_m {
            return Err(invalid(
                "top_radius_m",
                self.top_radius_m,
                "must exceed bottom_radius_m",
            ));
        }
        let r = &self.rayleigh;
        positive("rayleigh.scale_height_m", r.scale_height_m)?;
        positive("rayleigh.n_minus_1", r.n_minus_1)?;
        positive("rayleigh.number_density", r.number_density)?;
        positive("rayleigh.king_factor", r.king_factor)?;
        let m = &self.mie;
        positive("mie.scale_height_m", m.scale_height_m)?;
        non_negative("mie.scattering", m.scattering)?;
        non_negative("mie.absorption", m.absorption)?;
        in_range(
            "mie.angstrom_exponent",
            m.angstrom_exponent,
            -4.0,
            4.0,
            "must lie in [−4, 4]",
        )?;
        in_range(
            "mie.g",
            m.g,
            -0.999,
            0.999,
            "asymmetry must lie in [−0.999, 0.999]",
        )?;
        let o = &self.ozone;
        non_negative("ozone.peak_altitude_m", o.peak_altitude_m)?;
        positive("ozone.half_width_m", o.half_width_m)?;
        non_negative("ozone.column_dobson", o.column_dobson)?;
        in_range(
            "ground_albedo",
            self.ground_albedo,
            0.0,
            1.0,
            "must lie in [0, 1]",
        )?;
        in_range(
            "sun_angular_radius",
            self.sun_angular_radius,
            1e-6,
            0.5,
            "must lie in [1e-6, 0.5] rad",
        )?;
        non_negative("sun_intensity_scale", self.sun_intensity_scale)?;
        let l = &self.lut;
        let size = |name: &'static str, v: usize, lo: usize| {
            if v < lo || v > 4096 {
                Err(invalid(
                    name,
                    v,
                    "LUT size out of range (2..4096, distance ≥ 2)",
                ))
            } else {
                Ok(())
            }
        };
        size("lut.transmittance.0", l.transmittance.0, 2)?;
        size("lut.transmittance.1", l.transmittance.1, 2)?;
        size("lut.multiple_scattering.0", l.multiple_scattering.0, 2)?;
        size("lut.multiple_scattering.1", l.multiple_scattering.1, 2)?;
        size("lut.sky_view.0", l.sky_view.0, 2)?;
        size("lut.sky_view.1", l.sky_view.1, 4)?;
        size("lut.sky_view_steps", l.sky_view_steps, 1)?;
        size("lut.aerial.0", l.aerial.0, 2)?;
        size("lut.aerial.1", l.aerial.1, 4)?;
        size("lut.aerial.2", l.aerial.2, 2)?;
        if l.aerial.0 * l.aerial.1 * l.aerial.2 > 1 << 26 {
            return Err(invalid(
                "lut.aerial",
                format!("{:?}", l.aerial),
                "aerial volume too large (at most 2^26 texels, 2 GiB)",
            ));
        }
        positive("lut.aerial_max_distance_m", l.aerial_max_distance_m)?;
        Ok(())
    }
}
