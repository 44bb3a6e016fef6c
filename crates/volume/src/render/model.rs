//! The light-transport equations every renderer of this crate shares, in one
//! place: the transmittance and in-scatter of a homogeneous step, the
//! octave multiple-scattering sum, the powder term, emission and the lit
//! ground. The fast march and the reference path tracer both call these;
//! neither restates them.

use glam::Vec3;

use crate::phase::CloudPhase;

/// Transmittance of a step of length `dt` (m) through extinction `sigma_t`
/// (1/m): `exp(−σ_t·Δt)` (Beer–Lambert). Density enters through `σ_t = σ·ρ`:
/// the voxel transparency printed without `ρ` in Fedkiw et al. 2001, §5 is
/// corrected to `exp(−σ·ρ·h)`.
#[inline]
#[must_use]
pub fn step_transmittance(sigma_t: f32, dt: f32) -> f32 {
    (-sigma_t * dt).exp()
}

/// Radiance added by a step of length `dt` with constant extinction
/// `sigma_t` and constant source `source` (radiance per metre, `σ_s·L_i +
/// σ_a·L_e`), seen through the step itself: `source·(1 − e^{−σ_t Δt})/σ_t`,
/// which tends to `source·Δt` as `σ_t → 0`. Ebert's low-albedo sum
/// `T·albedo·ρ·L_i·Δt` is its first-order term; the exact step integral keeps
/// thick steps from adding more light than they can scatter.
#[inline]
#[must_use]
pub fn step_inscatter(source: Vec3, sigma_t: f32, dt: f32) -> Vec3 {
    let x = sigma_t * dt;
    if x < 1e-4 {
        source * (dt * (1.0 - 0.5 * x))
    } else {
        source * ((1.0 - (-x).exp()) / sigma_t)
    }
}

/// The multiple-scattering approximation of Wrenninge et al. 2013, "Multiple
/// scattering approximation" ("octaves"): `N` single-scattering terms, octave `i` with scattering
/// scaled by `a^i`, extinction toward the light by `b^i` and phase asymmetry
/// by `c^i`. `a ≤ b` keeps it from adding energy faster than the light
/// could be scattered. One octave is plain single scattering.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct ScatterOctaves {
    /// Number of octaves `N ≥ 1` (1 is single scattering).
    pub count: u32,
    /// Scattering attenuation `a ∈ (0, 1]`.
    pub a: f32,
    /// Extinction attenuation `b ∈ (0, 1]`.
    pub b: f32,
    /// Asymmetry attenuation `c ∈ [0, 1]`.
    pub c: f32,
}

impl Default for ScatterOctaves {
    /// Eight octaves with `a = b = ½`, `c = 0.85`: of the settings tried on a
    /// dense cumulus (τ ≈ 20) against the reference path tracer, the closest
    /// in mean brightness and per-pixel error.
    fn default() -> Self {
        Self {
            count: 8,
            a: 0.5,
            b: 0.5,
            c: 0.85,
        }
    }
}

impl ScatterOctaves {
    /// Single scattering (one octave).
    pub const SINGLE: ScatterOctaves = ScatterOctaves {
        count: 1,
        a: 1.0,
        b: 1.0,
        c: 1.0,
    };

    /// Checks the fields.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter)
    /// for a count outside `1..=32`, `a` or `b` outside `(0, 1]`, `c` outside
    /// `[0, 1]`, or `a > b`.
    pub fn validate(&self) -> crate::Result<()> {
        crate::error::in_range(
            "octaves.count",
            self.count as f32,
            1.0,
            32.0,
            "must lie in 1..=32",
        )?;
        crate::error::in_range("octaves.a", self.a, 1e-6, 1.0, "must lie in (0, 1]")?;
        crate::error::in_range("octaves.b", self.b, 1e-6, 1.0, "must lie in (0, 1]")?;
        crate::error::in_range("octaves.c", self.c, 0.0, 1.0, "must lie in [0, 1]")?;
        crate::error::in_range("octaves.a", self.a, 0.0, self.b, "must not exceed b")?;
        Ok(())
    }

    /// `Σ_i a^i·p_{c^i}(cos θ)·e^{−b^i τ}`: the sun's in-scatter factor at a
    /// point whose optical depth toward the sun is `tau`; the single
    /// scattering term `p(cos θ)·e^{−τ}` plus [`ScatterOctaves::sun_scattered`].
    #[inline]
    #[must_use]
    pub fn sun(&self, phase: &CloudPhase, cos_theta: f32, tau: f32) -> f32 {
        phase.eval(cos_theta) * (-tau).exp() + self.sun_scattered(phase, cos_theta, tau)
    }

    /// `Σ_{i≥1} a^i·p_{c^i}(cos θ)·e^{−b^i τ}`: the octaves beyond single
    /// scattering (0 for one octave).
    #[inline]
    #[must_use]
    pub fn sun_scattered(&self, phase: &CloudPhase, cos_theta: f32, tau: f32) -> f32 {
        let (mut sa, mut sb, mut sc) = (self.a, self.b, self.c);
        let mut s = 0.0;
        for _ in 1..self.count {
            s += sa * phase.scaled(sc).eval(cos_theta) * (-sb * tau).exp();
            sa *= self.a;
            sb *= self.b;
            sc *= self.c;
        }
        s
    }

    /// `Σ_i a^i·e^{−b^i τ}`: the same sum for isotropic ambient light.
    #[inline]
    #[must_use]
    pub fn ambient(&self, tau: f32) -> f32 {
        let (mut sa, mut sb) = (1.0f32, 1.0f32);
        let mut s = 0.0;
        for _ in 0..self.count {
            s += sa * (-sb * tau).exp();
            sa *= self.a;
            sb *= self.b;
        }
        s
    }
}

/// The similarity relations of the δ-M method (Wiscombe 1977, the scaled
/// optical depth and single-scattering albedo; Joseph, Wiscombe & Weinman
/// 1976 for the δ-Eddington case): a fraction `f`
/// of scattering into a forward peak much narrower than any feature of the
/// light is treated as no scattering at all, so `σ_t' = σ_t·(1 − ω f)`,
/// `ω' = ω(1 − f)/(1 − ω f)`, and the phase function loses the peak (see
/// [`CloudPhase::forward_peak`]). Absorption `σ_t'(1 − ω') = σ_t(1 − ω)` is
/// unchanged. Returns `(σ_t', ω')` from `(σ_t, ω, f)`.
#[inline]
#[must_use]
pub fn delta_scaled(extinction: f32, albedo: f32, f: f32) -> (f32, f32) {
    let k = 1.0 - albedo * f;
    if k <= 0.0 {
        // ω = f = 1: everything scatters into the peak, the medium is clear.
        return (0.0, 0.0);
    }
    (extinction * k, albedo * (1.0 - f) / k)
}

/// Schneider's "powder" factor (Schneider 2015, "Lighting"): inside a cloud
/// light that has travelled a little way in has been scattered toward the
/// viewer more often than at the sunlit edge, so edges facing the sun darken
/// and creases brighten: `(1 − s) + s·2(1 − e^{−2τ})`, with `τ` the optical
/// depth toward the sun and `s ∈ [0, 1]` the strength (0: off). An artistic
/// term: it is not in the reference and is off in the comparisons.
#[inline]
#[must_use]
pub fn powder(tau: f32, strength: f32) -> f32 {
    (1.0 - strength) + strength * 2.0 * (1.0 - (-2.0 * tau).exp())
}

/// Emitted radiance `colour·max(value − offset, 0)` of an emission field
/// value (for smoke: temperature above ambient).
#[inline]
#[must_use]
pub fn emitted(colour: Vec3, value: f32, offset: f32) -> Vec3 {
    colour * (value - offset).max(0.0)
}

/// Radiance leaving a Lambertian ground of `albedo` lit by the sun
/// (`sun_irradiance` normal to the beam, elevation cosine `cos_sun`, cloud
/// transmittance `t_sun`) and by the sky (`sky_irradiance` on the horizontal):
/// `albedo/π·(E_sun·max(cos, 0)·T + E_sky)`.
#[inline]
#[must_use]
pub fn lit_ground(
    albedo: Vec3,
    sun_irradiance: Vec3,
    cos_sun: f32,
    t_sun: f32,
    sky_irradiance: Vec3,
) -> Vec3 {
    albedo
        * std::f32::consts::FRAC_1_PI
        * (sun_irradiance * (cos_sun.max(0.0) * t_sun) + sky_irradiance)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_integral_matches_quadrature() {
        let s = Vec3::new(1.0, 2.0, 3.0);
        for (sigma, dt) in [(0.0, 1.0), (1e-6, 2.0), (0.5, 1.0), (20.0, 0.3)] {
            let n = 100_000;
            let mut q = 0.0f64;
            for i in 0..n {
                let t = (i as f64 + 0.5) / n as f64 * f64::from(dt);
                q += (-f64::from(sigma) * t).exp() * f64::from(dt) / n as f64;
            }
            let got = step_inscatter(s, sigma, dt);
            assert!(
                (f64::from(got.x) - q).abs() < 1e-4 * q.max(1e-3),
                "{sigma} {dt}: {got} vs {q}"
            );
        }
        assert_eq!(step_transmittance(0.0, 5.0), 1.0);
    }

    #[test]
    fn one_octave_is_single_scattering() {
        let p = CloudPhase::HenyeyGreenstein(0.6);
        for tau in [0.0f32, 0.3, 2.0] {
            let o = ScatterOctaves::SINGLE.sun(&p, 0.4, tau);
            assert!((o - p.eval(0.4) * (-tau).exp()).abs() < 1e-7);
        }
        assert!(ScatterOctaves::default().validate().is_ok());
        assert!(
            ScatterOctaves {
                a: 0.8,
                b: 0.5,
                ..ScatterOctaves::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            ScatterOctaves {
                count: 0,
                ..ScatterOctaves::default()
            }
            .validate()
            .is_err()
        );
        // More octaves add light deep inside (large τ).
        assert!(
            ScatterOctaves::default().ambient(5.0) > ScatterOctaves::SINGLE.ambient(5.0) * 10.0
        );
        assert_eq!(powder(1.0, 0.0), 1.0);
    }

    #[test]
    fn delta_scaling_keeps_absorption_and_removes_the_peak() {
        for (ext, w, f) in [
            (2.0f32, 0.99f32, 0.5f32),
            (1.0, 0.5, 0.3),
            (3.0, 0.0, 0.5),
            (1.0, 1.0, 0.0),
        ] {
            let (e2, w2) = delta_scaled(ext, w, f);
            assert!((e2 * (1.0 - w2) - ext * (1.0 - w)).abs() < 1e-6);
            // Scattering outside the peak is kept: σ_s' = σ_s·(1 − f).
            assert!((e2 * w2 - ext * w * (1.0 - f)).abs() < 1e-6);
            assert!((0.0..=1.0).contains(&w2) && e2 <= ext);
        }
        assert_eq!(delta_scaled(1.0, 0.7, 0.0), (1.0, 0.7));
        assert_eq!(delta_scaled(1.0, 1.0, 1.0), (0.0, 0.0));
    }
}
