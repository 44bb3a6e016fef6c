//! Ebert's microstructure: noise and turbulence from `natura-noise`
//! normalised to fixed ranges, the basic gas function, the shaping
//! functions, and two gases built from them: teacup steam and ground fog.
//!
//! Ebert 2001, "Procedural Techniques for Gases" (slides "Basic gas
//! procedure", "Gas shaping primitives", "Steam rising from a teacup",
//! "Example: Fog"): `density = (turbulence(p)·denseness)^wispiness`,
//! shaped by power, exponential and sine functions. The source never
//! defines its turbulence; here it is Perlin's sum of absolute noise octaves
//! (Perlin 1985, §"turbulence") divided by its bound, so it lies in `[0, 1]`
//! and every density built from it does too.

use glam::Vec3;
use natura_core::Aabb;
use natura_noise::{Field, GainConvention, Perlin, Spectral, Turbulence};

use crate::density::{Density, check_bounds};
use crate::detail::{Detail, DetailParams};
use crate::error::{Result, in_range, non_negative, positive};

/// Noise `∈ [−1, 1]` and turbulence `∈ [0, 1]` from one seed, the two
/// stochastic functions every gas and cloud model calls.
#[derive(Clone, Debug)]
pub struct GasNoise {
    noise: Perlin,
    turb: Turbulence<Perlin>,
    inv_noise: f64,
    inv_turb: f64,
}

impl GasNoise {
    /// Noise with `seed` and turbulence of `octaves` octaves at lacunarity 2
    /// with amplitudes `1/f` (Perlin's definition).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter)
    /// for octaves outside `[1, 16]`.
    pub fn new(seed: u64, octaves: u32) -> Result<Self> {
        in_range("octaves", octaves as f32, 1.0, 16.0, "must lie in [1, 16]")?;
        let noise = Perlin::new(seed);
        let spectral = Spectral::default()
            .with_h(1.0)
            .with_lacunarity(2.0)
            .with_octaves(f64::from(octaves))
            .with_convention(GainConvention::H);
        let turb = Turbulence::new(Perlin::new(seed ^ 0x7475_7262), spectral)?;
        let inv_noise = 1.0 / noise.bound();
        let inv_turb = 1.0 / turb.bound();
        Ok(Self {
            noise,
            turb,
            inv_noise,
            inv_turb,
        })
    }

    /// Noise at `p` in `[−1, 1]` (Ebert's `peachey_noise`).
    #[inline]
    #[must_use]
    pub fn noise(&self, p: Vec3) -> f32 {
        (self.noise.eval3(p.as_dvec3()) * self.inv_noise).clamp(-1.0, 1.0) as f32
    }

    /// Turbulence at `p` in `[0, 1]` (Ebert's `fast_turbulence`).
    #[inline]
    #[must_use]
    pub fn turbulence(&self, p: Vec3) -> f32 {
        (self.turb.eval3(p.as_dvec3()) * self.inv_turb).clamp(0.0, 1.0) as f32
    }

    /// [`noise`](GasNoise::noise) at many points (struct of arrays), through
    /// `natura-noise`'s SIMD point kernel: equal to the point path within
    /// `2·10⁻⁵`.
    ///
    /// # Errors
    ///
    /// [`VolumeError::SizeMismatch`](crate::VolumeError::SizeMismatch) if
    /// the slices differ in length.
    pub fn noise_batch(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> Result<()> {
        crate::density::check_batch(x, y, z, out)?;
        let k = self.inv_noise as f32;
        for_chunks(x, y, z, out, |px, py, pz, o| {
            self.noise.fill_points3(px, py, pz, o)?;
            for v in o.iter_mut() {
                *v = (*v * k).clamp(-1.0, 1.0);
            }
            Ok(())
        })
    }

    /// [`turbulence`](GasNoise::turbulence) at many points (struct of
    /// arrays): each octave's noise through `natura-noise`'s SIMD point
    /// kernel, the sum `Σ_k w_k·|N(f_k p)|` in `f32`; equal to the point path
    /// within `2·10⁻⁵`.
    ///
    /// # Errors
    ///
    /// [`VolumeError::SizeMismatch`](crate::VolumeError::SizeMismatch) if
    /// the slices differ in length.
    pub fn turbulence_batch(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> Result<()> {
        crate::density::check_batch(x, y, z, out)?;
        let oct = self.turb.octaves();
        let basis = self.turb.basis();
        let k = self.inv_turb as f32;
        for_chunks(x, y, z, out, |px, py, pz, o| {
            let m = o.len();
            let (mut sx, mut sy, mut sz) = ([0.0f64; CHUNK], [0.0f64; CHUNK], [0.0f64; CHUNK]);
            let mut n = [0.0f32; CHUNK];
            o.fill(0.0);
            for j in 0..oct.count() {
                let f = oct.frequency(j);
                for i in 0..m {
                    sx[i] = px[i] * f;
                    sy[i] = py[i] * f;
                    sz[i] = pz[i] * f;
                }
                basis.fill_points3(&sx[..m], &sy[..m], &sz[..m], &mut n[..m])?;
                let w = oct.weight(j) as f32;
                for (a, v) in o.iter_mut().zip(&n[..m]) {
                    *a += w * v.abs();
                }
            }
            for v in o.iter_mut() {
                *v = (*v * k).clamp(0.0, 1.0);
            }
            Ok(())
        })
    }
}

/// Points per chunk of the batch evaluations (stack buffers, no allocation).
const CHUNK: usize = 64;

/// Calls `f` on chunks of at most [`CHUNK`] points, the coordinates widened
/// to `f64` (the lattice index of `natura-noise` is exact in `f64`).
fn for_chunks(
    x: &[f32],
    y: &[f32],
    z: &[f32],
    out: &mut [f32],
    mut f: impl FnMut(&[f64], &[f64], &[f64], &mut [f32]) -> Result<()>,
) -> Result<()> {
    let (mut px, mut py, mut pz) = ([0.0f64; CHUNK], [0.0f64; CHUNK], [0.0f64; CHUNK]);
    for (c, o) in out.chunks_mut(CHUNK).enumerate() {
        let r = c * CHUNK..c * CHUNK + o.len();
        let m = o.len();
        for (i, j) in r.enumerate() {
            px[i] = f64::from(x[j]);
            py[i] = f64::from(y[j]);
            pz[i] = f64::from(z[j]);
        }
        f(&px[..m], &py[..m], &pz[..m], o)?;
    }
    Ok(())
}

/// The shaping functions of Ebert's slides (power, exponential, sine), each
/// mapping `[0, 1]` to `[0, 1]` monotonically.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum DensityShaping {
    /// `d^e` (`e > 1` sharpens into wisps, `e < 1` thickens).
    Pow(f32),
    /// `(1 − e^{−k·d}) / (1 − e^{−k})`: soft saturation, normalised to reach 1.
    Exp(f32),
    /// `sin(d·π/2)`: soft saturation.
    Sine,
}

impl DensityShaping {
    /// Applies the shaping function to `d` (clamped to `[0, 1]` first).
    #[inline]
    #[must_use]
    pub fn apply(self, d: f32) -> f32 {
        let d = d.clamp(0.0, 1.0);
        match self {
            DensityShaping::Pow(e) => d.powf(e),
            DensityShaping::Exp(k) => (1.0 - (-k * d).exp()) / (1.0 - (-k).exp()),
            DensityShaping::Sine => (d * std::f32::consts::FRAC_PI_2).sin(),
        }
        .clamp(0.0, 1.0)
    }

    /// Checks the exponent or rate is finite and `> 0`.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter) otherwise.
    pub fn validate(&self) -> Result<()> {
        match *self {
            DensityShaping::Pow(e) => positive("exponent", e).map(|_| ()),
            DensityShaping::Exp(k) => positive("rate", k).map(|_| ()),
            DensityShaping::Sine => Ok(()),
        }
    }
}

/// Ebert's basic gas: `(turbulence(p·frequency)·denseness)^wispiness`, in `[0, 1]`.
#[inline]
#[must_use]
pub fn basic_gas(noise: &GasNoise, p: Vec3, frequency: f32, denseness: f32, wispiness: f32) -> f32 {
    DensityShaping::Pow(wispiness).apply(noise.turbulence(p * frequency) * denseness)
}

/// Parameters of [`Steam`] rising from a teacup.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct SteamParams {
    /// Centre of the cup's mouth (m).
    pub mouth: Vec3,
    /// Radius of the column of steam (m).
    pub radius: f32,
    /// Height of the column (m); density is 0 at and above it.
    pub height: f32,
    /// Noise frequency (1/m).
    pub frequency: f32,
    /// Denseness (scale of the turbulence).
    pub denseness: f32,
    /// Wispiness (exponent).
    pub wispiness: f32,
    /// Radial falloff exponent `k` of `(1 − r²)^k`.
    pub radial_falloff: f32,
    /// Vertical falloff exponent `m` of `(1 − h/H)^m`.
    pub vertical_falloff: f32,
    /// Rise speed (m/s): the turbulence space drifts down so the steam rises.
    pub rise_speed: f32,
    /// Time (s).
    pub time: f32,
    /// Erosion by noise octaves down to the pixel footprint of a camera
    /// ([`crate::detail`]); `None`: Ebert's steam alone, bit for bit.
    pub detail: Option<DetailParams>,
}

impl Default for SteamParams {
    /// A 4 cm column 12 cm tall over a cup at the origin.
    fn default() -> Self {
        Self {
            mouth: Vec3::ZERO,
            radius: 0.04,
            height: 0.12,
            frequency: 60.0,
            denseness: 1.4,
            wispiness: 2.0,
            radial_falloff: 2.0,
            vertical_falloff: 1.5,
            rise_speed: 0.03,
            time: 0.0,
            detail: None,
        }
    }
}

impl SteamParams {
    /// Checks every field is finite and positive (time: finite).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter) naming the bad field
    /// (as [`DetailParams::validate`] for the detail's).
    pub fn validate(&self) -> Result<()> {
        crate::error::finite3("mouth", self.mouth)?;
        positive("radius", self.radius)?;
        positive("height", self.height)?;
        positive("frequency", self.frequency)?;
        positive("denseness", self.denseness)?;
        positive("wispiness", self.wispiness)?;
        non_negative("radial_falloff", self.radial_falloff)?;
        non_negative("vertical_falloff", self.vertical_falloff)?;
        crate::error::finite3("rise_speed", Vec3::splat(self.rise_speed))?;
        crate::error::finite3("time", Vec3::splat(self.time))?;
        if let Some(d) = &self.detail {
            d.validate()?;
        }
        Ok(())
    }
}

/// Steam over a teacup: the basic gas "shaped spherically" (radial falloff
/// about the cup's axis) and "shaped vertically" (dissipating with height),
/// drifting up with time.
#[derive(Clone, Debug)]
pub struct Steam {
    params: SteamParams,
    noise: GasNoise,
    detail: Option<Detail>,
}

impl Steam {
    /// Steam with `params` and noise `seed`.
    ///
    /// # Errors
    ///
    /// As [`SteamParams::validate`].
    pub fn new(params: SteamParams, seed: u64) -> Result<Self> {
        params.validate()?;
        let detail = match &params.detail {
            Some(d) => Some(Detail::new(d, seed ^ 0x0073_7465_616d)?),
            None => None,
        };
        Ok(Self {
            params,
            noise: GasNoise::new(seed, 5)?,
            detail,
        })
    }
}

impl Density for Steam {
    fn density(&self, p: Vec3) -> f32 {
        let s = &self.params;
        let q = p - s.mouth;
        let h = q.z / s.height;
        let r2 = (q.x * q.x + q.y * q.y) / (s.radius * s.radius);
        if !(0.0..1.0).contains(&h) || r2 >= 1.0 {
            return 0.0;
        }
        let anim = q - Vec3::Z * (s.rise_speed * s.time);
        let d = basic_gas(&self.noise, anim, s.frequency, s.denseness, s.wispiness);
        let d = d * (1.0 - r2).powf(s.radial_falloff) * (1.0 - h).powf(s.vertical_falloff);
        match &self.detail {
            // The detail drifts with the steam, like its turbulence.
            Some(f) => f.erode_drifting(p, anim - q, d, 1.0),
            None => d,
        }
    }
    fn bounds(&self) -> Aabb {
        let s = &self.params;
        Aabb {
            min: s.mouth - Vec3::new(s.radius, s.radius, 0.0),
            max: s.mouth + Vec3::new(s.radius, s.radius, s.height),
        }
    }
    fn max_density(&self) -> f32 {
        1.0
    }
}

/// GroundPlane fog: the basic gas inside a box, thinning exponentially with height
/// above its floor (Ebert's "Example: Fog").
#[derive(Clone, Debug)]
pub struct Fog {
    region: Aabb,
    scale_height: f32,
    frequency: f32,
    denseness: f32,
    wispiness: f32,
    noise: GasNoise,
}

impl Fog {
    /// Fog filling `region`, with density `e^{−(z − z_min)/scale_height}` times
    /// the basic gas of `frequency`, `denseness` and `wispiness`.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidBounds`](crate::VolumeError::InvalidBounds) for a bad
    /// box; [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter)
    /// for a non-positive or non-finite number.
    pub fn new(
        region: Aabb,
        scale_height: f32,
        frequency: f32,
        denseness: f32,
        wispiness: f32,
        seed: u64,
    ) -> Result<Self> {
        check_bounds("region", &region)?;
        positive("scale_height", scale_height)?;
        positive("frequency", frequency)?;
        positive("denseness", denseness)?;
        positive("wispiness", wispiness)?;
        Ok(Self {
            region,
            scale_height,
            frequency,
            denseness,
            wispiness,
            noise: GasNoise::new(seed, 4)?,
        })
    }
}

impl Density for Fog {
    fn density(&self, p: Vec3) -> f32 {
        if !self.region.contains(p) {
            return 0.0;
        }
        let falloff = (-(p.z - self.region.min.z) / self.scale_height).exp();
        falloff
            * basic_gas(
                &self.noise,
                p,
                self.frequency,
                self.denseness,
                self.wispiness,
            )
    }
    fn bounds(&self) -> Aabb {
        self.region
    }
    fn max_density(&self) -> f32 {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_and_turbulence_ranges() {
        let g = GasNoise::new(3, 6).unwrap();
        for i in 0..2000 {
            let p = Vec3::new(
                i as f32 * 0.137,
                (i % 17) as f32 * 0.31,
                (i % 5) as f32 * 1.7,
            );
            let n = g.noise(p);
            let t = g.turbulence(p);
            assert!((-1.0..=1.0).contains(&n));
            assert!((0.0..=1.0).contains(&t));
        }
        assert!(GasNoise::new(3, 0).is_err());
        assert!(GasNoise::new(3, 99).is_err());
    }

    #[test]
    fn steam_is_zero_outside_and_fades_to_the_top() {
        let s = Steam::new(SteamParams::default(), 1).unwrap();
        let b = s.bounds();
        assert_eq!(s.density(b.max + Vec3::ONE), 0.0);
        assert_eq!(s.density(Vec3::new(0.0, 0.0, 0.12)), 0.0);
        let near_top: f32 = (0..50)
            .map(|i| s.density(Vec3::new(i as f32 * 1e-4, 0.0, 0.119)))
            .fold(0.0, f32::max);
        assert!(near_top < 0.01, "{near_top}");
        let p = SteamParams {
            radius: f32::NAN,
            ..SteamParams::default()
        };
        assert!(Steam::new(p, 1).is_err());
    }
}
