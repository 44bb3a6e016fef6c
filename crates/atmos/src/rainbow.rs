//! The rainbow: geometric optics of a spherical water drop (Descartes),
//! Fresnel weighting per polarisation, Cauchy dispersion of water, and
//! Musgrave's precomputed deviation/intensity table convolved with the sun's
//! disc (Musgrave 1993, §4.2.3.3, §4.2.4.3.2); plus his empirical 13-fog rainbow
//! (Musgrave 1993, §4.2.4.3.1).
//!
//! Angles are measured **from the antisolar point** (the direction of the
//! sunlight's propagation, seen by an observer with the sun behind them). The
//! primary bow (one internal reflection) lies near 42° with red outside; the
//! secondary (two) near 51° with the order reversed; between them no singly
//! or doubly reflected light arrives — Alexander's dark band (Musgrave 1993, §4.2.3.3).

use std::f64::consts::PI;

use glam::DVec3;
use natura_core::Seed;

use crate::Dir3;
use crate::error::{Result, invalid, non_negative, positive};
use crate::optics::{AIR_MUSGRAVE_RAINBOW, Cauchy, RefractiveIndex, fresnel};
use crate::spectrum::{SpectralRgbTable, WavelengthSampler};

/// Returns the angle from the antisolar point (radians) of a ray leaving a
/// sphere of relative index `n` after `k` internal reflections, for impact
/// parameter `b ∈ [0, 1]` (`sin i = b`).
///
/// The total deviation is `D = 2(i − r) + k(π − 2r)` (Descartes' construction, Musgrave
/// 1993, §4.2.3.3); the angle
/// from the antisolar point is `π − ψ` with `ψ ∈ [0, π]` the angle between the
/// incident and exit directions.
#[must_use]
pub fn exit_angle(b: f64, n: f64, k: u32) -> f64 {
    let i = b.clamp(0.0, 1.0).asin();
    let r = (b.clamp(0.0, 1.0) / n).asin();
    let d = (2.0 * (i - r) + k as f64 * (PI - 2.0 * r)).rem_euclid(2.0 * PI);
    let psi = if d > PI { 2.0 * PI - d } else { d };
    PI - psi
}

/// Returns the impact parameter of the Descartes (minimum-deviation) ray for
/// `k ≥ 1` internal reflections: `cos² i = (n² − 1)/(k² + 2k)` (from dD/di = 0:
/// `(n² − 1)/3` for the primary, `/8` for the secondary), or `None` if `n ≤ 1`
/// or `n ≥ k + 1` (no stationary point).
#[must_use]
pub fn descartes_impact(n: f64, k: u32) -> Option<f64> {
    if k == 0 || n.is_nan() || n <= 1.0 {
        return None;
    }
    let kk = k as f64;
    let c2 = (n * n - 1.0) / (kk * kk + 2.0 * kk);
    (c2 < 1.0).then(|| (1.0 - c2).sqrt())
}

/// Returns the angle of the bow of order `k` from the antisolar point (radians),
/// i.e. [`exit_angle`] at the [`descartes_impact`] parameter.
#[must_use]
pub fn descartes_angle(n: f64, k: u32) -> Option<f64> {
    descartes_impact(n, k).map(|b| exit_angle(b, n, k))
}

/// One ray through a drop: where it goes and how much of each polarisation survives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DropPath {
    /// Angle from the antisolar point, radians.
    pub angle: f64,
    /// Transmitted fraction for polarisation parallel to the plane of incidence.
    pub intensity_par: f64,
    /// Transmitted fraction for polarisation perpendicular to it.
    pub intensity_perp: f64,
}

/// Traces a ray of impact parameter `b` through a sphere of relative index `n`
/// with `k` internal reflections (Musgrave 1993, §4.2.4.3.2): refraction in, `k` internal
/// reflections, refraction out. All internal incidence angles equal the first
/// refraction angle, and each polarisation keeps its orientation, so the
/// fractions are `(1 − R)²·R^k` per polarisation.
#[must_use]
pub fn trace_drop(b: f64, n: f64, k: u32) -> DropPath {
    let b = b.clamp(0.0, 1.0);
    let cos_i = (1.0 - b * b).sqrt();
    let f = fresnel(1.0, n, cos_i);
    let t = |r: f64| (1.0 - r) * (1.0 - r) * r.powi(k as i32);
    DropPath {
        angle: exit_angle(b, n, k),
        intensity_par: t(f.r_par),
        intensity_perp: t(f.r_perp),
    }
}

/// How impact parameters are weighted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum ImpactWeight {
    /// Each impact parameter weighs `2b`: the annulus a 3-D drop presents to
    /// parallel light (physically correct).
    Annulus,
    /// Uniform in `b`, as in the dissertation's 2-D simulation (Musgrave 1993, §4.2.4.3.2).
    UniformSource,
}

/// Parameters of the precomputed rainbow table. `Default` is the
/// dissertation's: 13 wavelengths over 380–800 nm, 50 000 rays per wavelength,
/// 1800 bins of 0.1° over 180°, orders 1 and 2, Musgrave's water and air,
/// a 0.5° sun (Musgrave 1993, §4.2.4.3.2); with jittered wavelengths and 3-D impact weights.
#[derive(Clone, Debug, PartialEq)]
pub struct RainbowParams {
    /// Wavelength strata.
    pub wavelengths: WavelengthSampler,
    /// Jitter each ray's wavelength within its stratum (fix (a) of Musgrave 1993, §4.2.4.3.2)
    /// instead of using the stratum centre (which shows spectral aliasing rings).
    pub jitter: bool,
    /// Rays per wavelength.
    pub rays_per_wavelength: usize,
    /// Angular bins over 0–180°.
    pub bins: usize,
    /// Internal-reflection orders to include (1 = primary, 2 = secondary, …).
    pub orders: Vec<u32>,
    /// Impact-parameter weighting.
    pub weight: ImpactWeight,
    /// Dispersion of water.
    pub water: Cauchy,
    /// Refractive index of air.
    pub n_air: f64,
    /// Apparent diameter of the sun, degrees (0.5); 0 disables the convolution.
    pub sun_diameter_deg: f64,
    /// Seed of the wavelength jitter.
    pub seed: Seed,
}

impl Default for RainbowParams {
    fn default() -> Self {
        Self {
            wavelengths: WavelengthSampler::musgrave13(),
            jitter: true,
            rays_per_wavelength: 50_000,
            bins: 1800,
            orders: vec![1, 2],
            weight: ImpactWeight::Annulus,
            water: Cauchy::WATER_MUSGRAVE,
            n_air: AIR_MUSGRAVE_RAINBOW,
            sun_diameter_deg: 0.5,
            seed: Seed(1993),
        }
    }
}

impl RainbowParams {
    /// Refuses empty or oversized tables, bad orders or indices.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) naming the first bad field: empty or oversized tables,
    /// an order list that is empty or out of range, or non-physical indices and sun size.
    pub fn validate(&self) -> Result<()> {
        if self.rays_per_wavelength == 0 || self.rays_per_wavelength > 100_000_000 {
            return Err(invalid(
                "rays_per_wavelength",
                self.rays_per_wavelength,
                "must be in 1..=1e8",
            ));
        }
        if self.bins < 2 || self.bins > 10_000_000 {
            return Err(invalid("bins", self.bins, "must be in 2..=1e7"));
        }
        if self.orders.is_empty() || self.orders.iter().any(|&k| k == 0 || k > 20) {
            return Err(invalid(
                "orders",
                format!("{:?}", self.orders),
                "need 1..=20 internal reflections",
            ));
        }
        positive("n_air", self.n_air)?;
        positive("water.a", self.water.a)?;
        non_negative("water.b_nm2", self.water.b_nm2)?;
        non_negative("sun_diameter_deg", self.sun_diameter_deg)?;
        if self.sun_diameter_deg > 20.0 {
            return Err(invalid(
                "sun_diameter_deg",
                self.sun_diameter_deg,
                "must be at most 20°",
            ));
        }
        let (lo, _) = self.wavelengths.range();
        if self.water.ior(lo) / self.n_air <= 1.0 {
            return Err(invalid(
                "water",
                self.water.a,
                "water must be denser than air",
            ));
        }
        Ok(())
    }
}

/// The precomputed rainbow: linear RGB scattering per steradian by angle from
/// the antisolar point, for unit white sunlight on unit geometric cross-section.
///
/// `∫ table(θ)·2π sin θ dθ` is the fraction of intercepted light scattered into
/// the included orders (≈ 4% primary + secondary, spectral colours summing to
/// white, eq. "4.2.14" Musgrave 1993, §4.2.4.2).
#[derive(Clone, Debug, PartialEq)]
pub struct RainbowTable {
    bin_rad: f64,
    rgb: Vec<DVec3>,
}

impl RainbowTable {
    /// Simulates the table (Musgrave 1993, §4.2.4.3.2): for each wavelength, rays over impact
    /// parameter (stratified), each order, Fresnel-weighted per polarisation,
    /// binned by angle; each wavelength's bins coloured by the CIE-derived
    /// spectral rgb table (columns summing to white) and summed; then convolved
    /// with the sun's disc (Musgrave 1993, §4.2.4.3.2).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `p` fails [`RainbowParams::validate`].
    pub fn simulate(p: &RainbowParams) -> Result<Self> {
        p.validate()?;
        let colours = SpectralRgbTable::from_cie(p.wavelengths, crate::spectrum::Illuminant::E)?;
        let nl = p.wavelengths.len();
        let bins = p.bins;
        let bin_rad = PI / bins as f64;
        let one = |li: usize| -> Vec<DVec3> {
            let mut acc = vec![DVec3::ZERO; bins];
            let seed = p.seed.derive_index(li as u64);
            let nr = p.rays_per_wavelength;
            for j in 0..nr {
                let u = if p.jitter {
                    seed.uniform1(j as i64)
                } else {
                    0.5
                };
                let lambda = p.wavelengths.sample(li, u);
                let rgb = if p.jitter {
                    colours.rgb_at(lambda)
                } else {
                    colours.samples()[li]
                };
                let n = p.water.ior(lambda) / p.n_air;
                let b = (j as f64 + 0.5) / nr as f64;
                let w = match p.weight {
                    ImpactWeight::Annulus => 2.0 * b,
                    ImpactWeight::UniformSource => 1.0,
                } / nr as f64;
                for &k in &p.orders {
                    let path = trace_drop(b, n, k);
                    let e = 0.5 * (path.intensity_par + path.intensity_perp) * w;
                    let i = ((path.angle / bin_rad) as usize).min(bins - 1);
                    acc[i] += rgb * e;
                }
            }
            acc
        };
        #[cfg(feature = "parallel")]
        let parts: Vec<Vec<DVec3>> = {
            use rayon::prelude::*;
            (0..nl).into_par_iter().map(one).collect()
        };
        #[cfg(not(feature = "parallel"))]
        let parts: Vec<Vec<DVec3>> = (0..nl).map(one).collect();
        // Sum in wavelength order (deterministic), then energy per bin → per steradian.
        let mut rgb = vec![DVec3::ZERO; bins];
        for part in &parts {
            for (a, b) in rgb.iter_mut().zip(part) {
                *a += *b;
            }
        }
        let mut t = RainbowTable { bin_rad, rgb };
        if p.sun_diameter_deg > 0.0 {
            t.convolve_sun_disc(p.sun_diameter_deg.to_radians());
        }
        for (i, c) in t.rgb.iter_mut().enumerate() {
            let (a0, a1) = (i as f64 * bin_rad, (i + 1) as f64 * bin_rad);
            *c /= 2.0 * PI * (a0.cos() - a1.cos());
        }
        Ok(t)
    }

    /// The semicircular sun-disc kernel for `bins` of width `bin_rad` and a sun
    /// of angular diameter `diameter_rad`: taps at whole bins within the
    /// radius, weights `√(1 − (x/ρ)²)`, normalised to sum 1 (Musgrave 1993, §4.2.4.3.2; 5 taps for
    /// 0.5° at 0.1°).
    #[must_use]
    pub fn sun_kernel(bin_rad: f64, diameter_rad: f64) -> Vec<f64> {
        let rho = 0.5 * diameter_rad;
        let half = ((rho / bin_rad) - 1e-9).floor().max(0.0) as i64;
        let mut w: Vec<f64> = (-half..=half)
            .map(|k| (1.0 - (k as f64 * bin_rad / rho).powi(2)).max(0.0).sqrt())
            .collect();
        let s: f64 = w.iter().sum();
        for x in &mut w {
            *x /= s;
        }
        w
    }

    /// Convolves the (energy-per-bin) table with the sun-disc kernel, preserving
    /// its integral except what is pushed past 0° or 180°.
    fn convolve_sun_disc(&mut self, diameter_rad: f64) {
        let k = Self::sun_kernel(self.bin_rad, diameter_rad);
        let half = (k.len() / 2) as i64;
        let n = self.rgb.len() as i64;
        let mut out = vec![DVec3::ZERO; self.rgb.len()];
        for (i, &v) in self.rgb.iter().enumerate() {
            for (t, &w) in k.iter().enumerate() {
                // Reflect at the ends so nothing is lost.
                let mut j = i as i64 + t as i64 - half;
                if j < 0 {
                    j = -j - 1;
                }
                if j >= n {
                    j = 2 * n - j - 1;
                }
                out[j as usize] += v * w;
            }
        }
        self.rgb = out;
    }

    /// Bin width, radians.
    #[must_use]
    pub fn bin_width(&self) -> f64 {
        self.bin_rad
    }

    /// The RGB values per steradian, one per bin.
    #[must_use]
    pub fn bins(&self) -> &[DVec3] {
        &self.rgb
    }

    /// RGB per steradian at `angle` (radians from the antisolar point), linear
    /// between bin centres; 0 outside `[0, π]` or for NaN.
    #[must_use]
    pub fn lookup(&self, angle: f64) -> DVec3 {
        if !(0.0..=PI).contains(&angle) {
            return DVec3::ZERO;
        }
        let x = angle / self.bin_rad - 0.5;
        let n = self.rgb.len();
        if x <= 0.0 {
            return self.rgb[0];
        }
        let i = x as usize;
        if i + 1 >= n {
            return self.rgb[n - 1];
        }
        self.rgb[i].lerp(self.rgb[i + 1], x - i as f64)
    }

    /// Fraction of intercepted light scattered into the table's orders,
    /// `∫ table·dω`, per channel.
    #[must_use]
    pub fn total(&self) -> DVec3 {
        self.rgb
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let (a0, a1) = (i as f64 * self.bin_rad, (i + 1) as f64 * self.bin_rad);
                *c * (2.0 * PI * (a0.cos() - a1.cos()))
            })
            .sum()
    }
}

/// A rain sheet that shows the rainbow: the precomputed table plus the rain's
/// geometric extinction.
#[derive(Clone, Debug)]
pub struct Rainbow {
    table: RainbowTable,
}

impl Rainbow {
    /// Simulates the table for `params`.
    ///
    /// # Errors
    ///
    /// As [`RainbowTable::simulate`].
    pub fn new(params: &RainbowParams) -> Result<Self> {
        Ok(Self {
            table: RainbowTable::simulate(params)?,
        })
    }

    /// The table.
    #[must_use]
    pub fn table(&self) -> &RainbowTable {
        &self.table
    }

    /// Returns the angle (radians) between `view` and the antisolar point for
    /// the sun towards `sun`.
    #[must_use]
    pub fn antisolar_angle(view: Dir3, sun: Dir3) -> f64 {
        view.dot(sun.reversed()).acos()
    }

    /// Radiance (linear RGB) added by rain along `view` over `distance_m`
    /// metres of rain with geometric extinction `rain_extinction` (m⁻¹: drop
    /// cross-section per volume), lit by sunlight of irradiance
    /// `sun_irradiance`: single scattering `E·P(θ)·(1 − e^{−βd})`, the additive
    /// in-scatter, rather than the source's fog replacement, which leaves
    /// unclear what the bow's colour replaces (Musgrave 1993, §4.2.4.3.2).
    ///
    /// Fails on negative or NaN extinction or distance.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for a negative or NaN `rain_extinction` or `distance_m`, or a
    /// negative or non-finite `sun_irradiance`.
    pub fn radiance(
        &self,
        view: Dir3,
        sun: Dir3,
        sun_irradiance: DVec3,
        rain_extinction: f64,
        distance_m: f64,
    ) -> Result<DVec3> {
        non_negative("rain_extinction", rain_extinction)?;
        if distance_m.is_nan() || distance_m < 0.0 {
            return Err(invalid(
                "distance_m",
                distance_m,
                "must be >= 0 (may be infinite)",
            ));
        }
        crate::error::non_negative3("sun_irradiance", sun_irradiance)?;
        let cover = if rain_extinction == 0.0 {
            0.0
        } else {
            -(-rain_extinction * distance_m).exp_m1()
        };
        Ok(sun_irradiance * self.table.lookup(Self::antisolar_angle(view, sun)) * cover)
    }
}

impl Rainbow {
    /// Returns `background` seen through `distance_m` of rain plus the rainbow:
    /// `background·e^{−βd} + E·P(θ)·(1 − e^{−βd})` (see [`Rainbow::radiance`]).
    ///
    /// # Errors
    ///
    /// As [`Rainbow::radiance`].
    pub fn apply(
        &self,
        background: DVec3,
        view: Dir3,
        sun: Dir3,
        sun_irradiance: DVec3,
        rain_extinction: f64,
        distance_m: f64,
    ) -> Result<DVec3> {
        let add = self.radiance(view, sun, sun_irradiance, rain_extinction, distance_m)?;
        let t = if rain_extinction == 0.0 {
            1.0
        } else {
            (-rain_extinction * distance_m).exp()
        };
        Ok(background * t + add)
    }
}

/// Musgrave's empirical ("impressionistic") rainbow: 13 coloured fogs in
/// cones about the antisolar vector, indexed linearly in the cosine
/// (Musgrave 1993, §4.2.4.3.1, verbatim semantics).
///
/// `rainbow_angle` is a **cosine** (cos 42° ≈ 0.743), not an angle (a
/// pitfall of the listing); index 0 is the outer edge and should be red.
#[derive(Clone, Debug, PartialEq)]
pub struct EmpiricalRainbow {
    /// The 13 band colours, outermost first.
    pub bands: Vec<DVec3>,
    /// `rainbow_angle`: the cosine where band 0 starts.
    pub cos_start: f64,
    /// `rainbow_width`: bands per unit of cosine.
    pub width_scale: f64,
}

impl EmpiricalRainbow {
    /// The band index for `view` and the sun towards `sun`, with the index
    /// jitter `jitter ∈ [−δ/2, δ/2]` (0 for none); `None` outside the bow.
    #[must_use]
    pub fn band(&self, view: Dir3, sun: Dir3, jitter: f64) -> Option<usize> {
        let index = (view.dot(sun.reversed()) - self.cos_start) * self.width_scale + jitter;
        (index >= 0.0 && index < self.bands.len() as f64).then_some(index as usize)
    }

    /// The band colour for `view`, if inside the bow.
    #[must_use]
    pub fn colour(&self, view: Dir3, sun: Dir3, jitter: f64) -> Option<DVec3> {
        self.band(view, sun, jitter).map(|i| self.bands[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n_at(l: f64) -> f64 {
        Cauchy::WATER_MUSGRAVE.ior(l) / AIR_MUSGRAVE_RAINBOW
    }

    #[test]
    fn descartes_angles_match_the_spec_table() {
        let deg = |l: f64, k: u32| descartes_angle(n_at(l), k).unwrap().to_degrees();
        // 42.4° ± 0.2° at 656 nm, 40.6° ± 0.2° at 400 nm.
        assert!((deg(656.3, 1) - 42.41).abs() < 0.02, "{}", deg(656.3, 1));
        assert!((deg(656.0, 1) - 42.4).abs() < 0.2);
        assert!((deg(400.0, 1) - 40.6).abs() < 0.2, "{}", deg(400.0, 1));
        assert!((deg(405.0, 1) - 40.72).abs() < 0.02);
        assert!((deg(656.3, 2) - 50.30).abs() < 0.02, "{}", deg(656.3, 2));
        assert!((deg(405.0, 2) - 53.35).abs() < 0.02);
        // Secondary within 50.3°–53.5° over 400-656 nm, colours reversed.
        for l in [400.0, 450.0, 500.0, 550.0, 600.0, 656.0] {
            let s = deg(l, 2);
            assert!((50.29..=53.5).contains(&s), "{l}: {s}");
        }
        assert!(deg(656.3, 1) > deg(405.0, 1), "primary: red outside");
        assert!(deg(656.3, 2) < deg(405.0, 2), "secondary: red inside");
        assert!((descartes_impact(n_at(550.0), 1).unwrap() - 0.8604).abs() < 2e-4);
        assert!((descartes_impact(n_at(700.0), 2).unwrap() - 0.9508).abs() < 2e-4);
        assert!(descartes_impact(1.0, 1).is_none());
    }

    /// Closed-form stationary points equal a brute-force search.
    #[test]
    fn descartes_matches_brute_force() {
        for l in [400.0, 550.0, 700.0] {
            let n = n_at(l);
            let (mut best1, mut best2) = (0.0f64, f64::INFINITY);
            for j in 0..=200_000 {
                let b = j as f64 / 200_000.0;
                best1 = best1.max(exit_angle(b, n, 1));
                best2 = best2.min(exit_angle(b, n, 2));
            }
            assert!((best1 - descartes_angle(n, 1).unwrap()).to_degrees().abs() < 1e-3);
            assert!((best2 - descartes_angle(n, 2).unwrap()).to_degrees().abs() < 1e-3);
        }
    }

    #[test]
    fn drop_paths_conserve_energy() {
        for j in 0..100 {
            let b = j as f64 / 99.0;
            let n = n_at(550.0);
            let f = fresnel(1.0, n, (1.0 - b * b).sqrt());
            // Light split among orders 0..∞ sums to 1 per polarisation.
            let mut sum = f.r_par;
            for k in 0..2000 {
                sum += trace_drop(b, n, k).intensity_par;
            }
            if b < 0.999 {
                assert!((sum - 1.0).abs() < 1e-9, "b={b}: {sum}");
            }
        }
    }

    /// The table's geometry (before the sun's smear).
    #[test]
    fn table_has_bows_and_alexanders_band() {
        let p = RainbowParams {
            sun_diameter_deg: 0.0,
            weight: ImpactWeight::UniformSource,
            jitter: false,
            ..RainbowParams::default()
        };
        let t = RainbowTable::simulate(&p).unwrap();
        let at = |deg: f64| t.bins()[(deg / 0.1) as usize];
        // Alexander's band: nothing between 42.8° and 49.6° for 380-800 nm.
        for i in 429..496 {
            assert_eq!(t.bins()[i], DVec3::ZERO, "bin {}°", i as f64 / 10.0);
        }
        assert!(at(30.0).min_element() > 0.0, "bright inside the primary");
        assert!(at(60.0).min_element() > 0.0, "light outside the secondary");
        // No primary light beyond its Descartes angle at any wavelength here.
        for i in 430..1800 {
            if i < 496 {
                continue;
            }
            assert!(t.bins()[i].max_element() >= 0.0);
        }
        // Energy fractions with uniform b: ≈ 3.1% + 0.35%.
        let tot = t.total();
        assert!((tot.y - 0.0345).abs() < 0.003, "{tot}");
    }

    #[test]
    fn default_table_is_darker_in_the_band_and_coloured() {
        let t = RainbowTable::simulate(&RainbowParams::default()).unwrap();
        let band = t.lookup(46.0f64.to_radians());
        let inside = t.lookup(38.0f64.to_radians());
        let outside = t.lookup(55.0f64.to_radians());
        let y = |c: DVec3| c.x + c.y + c.z;
        assert!(
            y(band) < 0.2 * y(inside) && y(band) < 0.2 * y(outside),
            "{band} {inside} {outside}"
        );
        // Primary: red outermost, blue inner; secondary reversed.
        let primary_red = (380..440)
            .max_by(|&a, &b| t.bins()[a].x.total_cmp(&t.bins()[b].x))
            .unwrap();
        let primary_blue = (380..440)
            .max_by(|&a, &b| t.bins()[a].z.total_cmp(&t.bins()[b].z))
            .unwrap();
        assert!(primary_red > primary_blue, "{primary_red} {primary_blue}");
        let sec_red = (490..560)
            .max_by(|&a, &b| t.bins()[a].x.total_cmp(&t.bins()[b].x))
            .unwrap();
        let sec_blue = (490..560)
            .max_by(|&a, &b| t.bins()[a].z.total_cmp(&t.bins()[b].z))
            .unwrap();
        assert!(sec_red < sec_blue, "{sec_red} {sec_blue}");
        assert!((t.lookup(0.7) - t.lookup(0.7)).length() == 0.0);
        assert_eq!(t.lookup(-1.0), DVec3::ZERO);
    }

    /// The sun kernel has 5 taps summing to 1; convolution keeps the integral.
    #[test]
    fn sun_kernel_preserves_energy() {
        let k = RainbowTable::sun_kernel(0.1f64.to_radians(), 0.5f64.to_radians());
        assert_eq!(k.len(), 5);
        assert!((k.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        let mut p = RainbowParams {
            rays_per_wavelength: 5000,
            sun_diameter_deg: 0.0,
            ..RainbowParams::default()
        };
        let a = RainbowTable::simulate(&p).unwrap().total();
        p.sun_diameter_deg = 0.5;
        let b = RainbowTable::simulate(&p).unwrap().total();
        assert!(((a - b).abs() / a).max_element() < 1e-3, "{a} vs {b}");
    }

    #[test]
    fn radiance_and_bad_input() {
        let rb = Rainbow::new(&RainbowParams {
            rays_per_wavelength: 4000,
            ..RainbowParams::default()
        })
        .unwrap();
        let sun = Dir3::from_angles(0.3, 0.0).unwrap();
        let anti = sun.reversed().get();
        // A view 41.5° from the antisolar point, in the vertical plane.
        let axis = anti.cross(DVec3::Y).normalize();
        let rot = |deg: f64| {
            let a = deg.to_radians();
            Dir3::new(anti * a.cos() + axis.cross(anti) * a.sin()).unwrap()
        };
        let e = DVec3::splat(1.8);
        let bow = rb.radiance(rot(41.5), sun, e, 1e-3, 2000.0).unwrap();
        let band = rb.radiance(rot(46.0), sun, e, 1e-3, 2000.0).unwrap();
        assert!(bow.max_element() > 3.0 * band.max_element());
        assert_eq!(
            rb.radiance(rot(41.5), sun, e, 0.0, 2000.0).unwrap(),
            DVec3::ZERO
        );
        assert!(rb.radiance(rot(41.5), sun, e, -1.0, 1.0).is_err());
        assert!(rb.radiance(rot(41.5), sun, e, 1e-3, f64::NAN).is_err());
        assert!(rb.radiance(rot(41.5), sun, e, 1e-3, f64::INFINITY).is_ok());
        let bad = RainbowParams {
            bins: 0,
            ..RainbowParams::default()
        };
        assert!(RainbowTable::simulate(&bad).is_err());
        let bad = RainbowParams {
            orders: vec![],
            ..RainbowParams::default()
        };
        assert!(RainbowTable::simulate(&bad).is_err());
        let bad = RainbowParams {
            water: Cauchy { a: 0.9, b_nm2: 0.0 },
            ..RainbowParams::default()
        };
        assert!(RainbowTable::simulate(&bad).is_err());
    }

    /// The empirical rainbow's index is None outside [0, 13) and monotone in cos θ.
    #[test]
    fn empirical_rainbow() {
        let r = EmpiricalRainbow {
            bands: SpectralRgbTable::linear_musgrave13()
                .samples()
                .iter()
                .rev()
                .copied()
                .collect(),
            cos_start: 42f64.to_radians().cos(),
            width_scale: 400.0,
        };
        let sun = Dir3::from_angles(0.0, 0.0).unwrap();
        let anti = sun.reversed().get();
        let mut last = None;
        let mut seen = 0;
        for k in 0..400 {
            let a = (43.0 - k as f64 * 0.01).to_radians();
            let v = Dir3::new(anti * a.cos() + DVec3::Z * a.sin()).unwrap();
            let b = r.band(v, sun, 0.0);
            if let (Some(p), Some(c)) = (last, b) {
                assert!(c >= p);
            }
            if b.is_some() {
                seen += 1;
                last = b;
            }
        }
        assert!(seen > 0);
        assert!(r.band(Dir3::new(anti).unwrap(), sun, 0.0).is_none());
        assert!(r.colour(sun, sun, 0.0).is_none());
    }
}
