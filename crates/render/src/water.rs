//! Water under wind: a fetch-limited wind sea on the lakes and the sea,
//! filtered at the pixel's footprint.
//!
//! The waves are a Tessendorf patch (natura-ocean, Tessendorf 2001, §3.4)
//! of the JONSWAP spectrum (Hasselmann et al. 1973: the
//! peak frequency and Phillips constant of a sea the wind has blown over
//! a fetch `F`), spread about the wind with Hasselmann et al.'s (1980)
//! directional spreading. A lake's fetch is its size: the square root of
//! the water's area, unless the scene gives `water.fetch_m`.
//!
//! A pixel sees the waves averaged over its footprint. Their slopes are
//! kept as a pyramid of means and mean squares (LEAN mapping, Olano &
//! Baker 2010: the first and second moments of the slopes filter
//! linearly), so a pixel reflects about the mean normal of its footprint
//! and the slopes it does not resolve become the width of the sun's
//! glitter instead. Slopes finer than the patch's grid (the capillary and
//! short gravity waves) make up the rest of Cox & Munk's (1954, the clean surface's fit)
//! mean square slope of a wind of that speed, `0.003 + 5.12·10⁻³ U`. The
//! sun's glitter is their slope distribution, a Gaussian, seen at the
//! half-vector of the sun and the viewer (Cox & Munk 1954, the glitter's
//! radiance):
//! `L = E_sun · F · p(zₓ, z_y) / (4 cos θ_v cos⁴ β)`, with `β` the tilt of
//! the facet that mirrors the sun to the viewer. The reflection of
//! everything else (sky, terrain, trees) is traced about the mean normal of
//! the footprint, so the waves a pixel resolves break it up; the sun's
//! disc is left out of it, since the glitter carries the sun. (Blurring
//! that reflection by the unresolved slopes as well would take many rays
//! a pixel: one drawn facet a sample turns the bright sky around the sun
//! into isolated bright pixels.)

use glam::{Vec2, Vec3};
use natura_core::{Boundary, Grid2, Progress, Seed};
use natura_ocean::{Directional, Jonswap, Ocean, OceanParams, Spectrum, Surface};

use crate::error::Result;
use crate::scene::WaterDesc;

/// Cox & Munk's (1954, the clean surface's fit) mean square slope of a clean sea in a
/// wind of `speed_m_s` measured 12.5 m up (both axes together).
#[must_use]
pub fn cox_munk_mss(speed_m_s: f32) -> f32 {
    0.003 + 5.12e-3 * speed_m_s
}

/// One level of the slope pyramid: mean slope and mean squared slope per axis.
#[derive(Clone, Debug)]
struct Level {
    mean: Grid2<Vec2>,
    square: Grid2<Vec2>,
}

/// The wind sea of a scene (see the module docs).
#[derive(Clone, Debug)]
pub struct WindSea {
    levels: Vec<Level>,
    /// Side of the patch's grid cell, metres.
    cell: f32,
    /// Slope variance per axis of the waves finer than the grid.
    fine_var: f32,
}

/// A filtered look at the waves from one pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaveSample {
    /// The footprint's mean normal (unit, z up).
    pub normal: Vec3,
    /// The footprint's mean slope `(∂z/∂x, ∂z/∂y)`.
    pub slope: Vec2,
    /// Variance of the slopes about that mean, per axis.
    pub variance: Vec2,
}

/// The angle of `w`'s wind from +x, radians, counter-clockwise: the scene
/// gives it as a compass azimuth, clockwise from north (+y).
pub(crate) fn wind_angle_rad(w: &WaterDesc) -> f64 {
    (90.0 - w.wind_azimuth_deg).to_radians()
}

/// The periodic wave patch of `w` (its side, resolution and snapshot time)
/// under `spectrum`: the one construction both the wind sea and the ocean
/// waves use.
///
/// # Errors
///
/// [`RenderError::Ocean`](crate::RenderError::Ocean) if natura-ocean refuses
/// the patch or the spectrum.
pub(crate) fn wave_patch(w: &WaterDesc, spectrum: &dyn Spectrum, seed: Seed) -> Result<Surface> {
    let (n, l) = (w.ocean_resolution, w.ocean_patch_m);
    let params = OceanParams {
        nx: n,
        ny: n,
        lx: l,
        ly: l,
        choppiness: 1.0,
        ..OceanParams::default()
    };
    let ocean = Ocean::new(&params, spectrum, seed)?;
    Ok(Surface::new(&ocean.evaluate(w.ocean_time_s)?, None)?)
}

impl WindSea {
    /// The wind sea of `w` over a fetch of `fetch_m` metres, or `None` in a
    /// calm (`wind_speed_m_s` 0: the water keeps its ripples).
    ///
    /// # Errors
    ///
    /// [`RenderError::Ocean`](crate::RenderError::Ocean) if natura-ocean
    /// refuses the patch or the spectrum; [`RenderError::Core`](crate::RenderError::Core)
    /// if the pyramid cannot be allocated.
    pub fn new(
        w: &WaterDesc,
        fetch_m: f64,
        seed: Seed,
        progress: &dyn Progress,
    ) -> Result<Option<Self>> {
        if w.wind_speed_m_s <= 0.0 {
            return Ok(None);
        }
        progress.start("wind sea", 1);
        let jonswap = Jonswap {
            wind_speed: w.wind_speed_m_s,
            fetch: fetch_m,
            ..Jonswap::default()
        };
        let spectrum = Directional::new(jonswap, wind_angle_rad(w));
        let surface = wave_patch(w, &spectrum, seed.derive("wind-sea"))?;
        let (n, l) = (w.ocean_resolution, w.ocean_patch_m);
        let sea = Self::from_surface(&surface, n, l as f32, w.wind_speed_m_s as f32)?;
        progress.advance(1);
        progress.finish();
        Ok(Some(sea))
    }

    /// The pyramid of `surface`'s slopes sampled on its `n × n` grid of side
    /// `side_m`, with the waves finer than the grid from Cox & Munk.
    fn from_surface(surface: &Surface, n: usize, side_m: f32, speed: f32) -> Result<Self> {
        let cell = side_m / n as f32;
        let mean = Grid2::from_fn(n, n, |i, j| {
            surface.slope_at(Vec2::new(i as f32 + 0.5, j as f32 + 0.5) * cell)
        })?;
        let square = Grid2::from_fn(n, n, |i, j| mean[(i, j)] * mean[(i, j)])?;
        let mut levels = vec![Level { mean, square }];
        while levels.last().is_some_and(|l| l.mean.width() > 1) {
            let prev = levels.last().expect("a level");
            levels.push(Level {
                mean: prev.mean.box_downsample(2)?,
                square: prev.square.box_downsample(2)?,
            });
        }
        let top = levels.last().expect("a level");
        let patch_mss = top.square[(0, 0)].x + top.square[(0, 0)].y;
        let fine_var = 0.5 * (cox_munk_mss(speed) - patch_mss).max(0.0);
        Ok(Self {
            levels,
            cell,
            fine_var,
        })
    }

    /// The waves at `p` seen by a pixel whose footprint there is
    /// `footprint_m` metres wide: the mean and variance of the slopes
    /// over it (trilinear in the pyramid).
    #[must_use]
    pub fn sample(&self, p: Vec2, footprint_m: f32) -> WaveSample {
        let last = (self.levels.len() - 1) as f32;
        let lod = (footprint_m / self.cell).max(1.0).log2().clamp(0.0, last);
        let k = lod.floor() as usize;
        let t = lod - k as f32;
        let at = |k: usize| {
            let l = &self.levels[k];
            let scale = (1u32 << k) as f32 * self.cell;
            let g = p / scale - Vec2::splat(0.5);
            (
                l.mean.sample_bilinear(g.x, g.y, Boundary::Wrap),
                l.square.sample_bilinear(g.x, g.y, Boundary::Wrap),
            )
        };
        let (m0, s0) = at(k);
        let (m, s) = if t > 0.0 && k + 1 < self.levels.len() {
            let (m1, s1) = at(k + 1);
            (m0.lerp(m1, t), s0.lerp(s1, t))
        } else {
            (m0, s0)
        };
        let variance = (s - m * m).max(Vec2::ZERO) + Vec2::splat(self.fine_var);
        WaveSample {
            normal: Vec3::new(-m.x, -m.y, 1.0).normalize(),
            slope: m,
            variance,
        }
    }
}

/// The sun's glitter on waves of `wave` (Cox & Munk 1954, the glitter's
/// radiance): the
/// radiance toward the viewer along `-d` of the sun's irradiance `e_sun`
/// from unit direction `sun`, before the Fresnel factor `fresnel` of the
/// mirroring facet, which the caller gives as a function of the cosine
/// between the view and the facet.
#[must_use]
pub fn glitter(
    wave: &WaveSample,
    d: Vec3,
    sun: Vec3,
    e_sun: Vec3,
    fresnel: impl Fn(f32) -> f32,
) -> Vec3 {
    let v = -d;
    if sun.z <= 0.0 || v.z <= 1e-4 {
        return Vec3::ZERO;
    }
    let h = (v + sun).normalize_or_zero();
    if h.z <= 1e-4 {
        return Vec3::ZERO;
    }
    // The facet's slope that mirrors the sun to the viewer, about the mean.
    let z = Vec2::new(-h.x / h.z, -h.y / h.z) - wave.slope;
    let var = wave.variance.max(Vec2::splat(1e-6));
    let p = (-0.5 * (z.x * z.x / var.x + z.y * z.y / var.y)).exp()
        / (std::f32::consts::TAU * (var.x * var.y).sqrt());
    let cos_beta = h.z;
    let f = fresnel(v.dot(h).clamp(0.0, 1.0));
    e_sun * (f * p / (4.0 * v.z * cos_beta.powi(4)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glitter_integrates_to_the_reflected_irradiance() {
        // Over the hemisphere of views, ∫ L cos θ_v dω with F = 1 equals the
        // irradiance on the mean plane that reaches facets of the
        // distribution (all of it for a narrow lobe near zenith).
        let wave = WaveSample {
            normal: Vec3::Z,
            slope: Vec2::ZERO,
            variance: Vec2::splat(0.01),
        };
        let sun = Vec3::new(0.3, 0.1, 1.0).normalize();
        let n = 400;
        let mut sum = 0.0;
        for a in 0..n {
            for b in 0..n {
                // Uniform in (cos θ, φ) over the upper hemisphere.
                let mu = (a as f32 + 0.5) / n as f32;
                let phi = std::f32::consts::TAU * (b as f32 + 0.5) / n as f32;
                let s = (1.0 - mu * mu).sqrt();
                let v = Vec3::new(s * phi.cos(), s * phi.sin(), mu);
                let l = glitter(&wave, -v, sun, Vec3::ONE, |_| 1.0).x;
                sum += l * mu * std::f32::consts::TAU / (n * n) as f32;
            }
        }
        // Cox & Munk's radiance integrates to the irradiance on the plane,
        // E cos θ_sun, for a narrow distribution.
        approx::assert_relative_eq!(sum, sun.z, max_relative = 0.05);
    }

    #[test]
    fn calm_water_has_no_wind_sea_and_wind_roughens() {
        let mut w = WaterDesc {
            wind_speed_m_s: 0.0,
            ocean_resolution: 64,
            ocean_patch_m: 64.0,
            ..WaterDesc::default()
        };
        let calm = WindSea::new(&w, 2000.0, Seed(3), &natura_core::NoProgress).unwrap();
        assert!(calm.is_none());
        let mut last = 0.0;
        for u in [2.0, 6.0, 12.0] {
            w.wind_speed_m_s = u;
            let sea = WindSea::new(&w, 2000.0, Seed(3), &natura_core::NoProgress)
                .unwrap()
                .unwrap();
            let top = sea.levels.last().unwrap().square[(0, 0)];
            let mss = top.x + top.y;
            assert!(mss > last, "{u} m/s: {mss} vs {last}");
            last = mss;
            // Far away a pixel covers the patch: the mean normal is nearly
            // up and the variance holds the slopes.
            let far = sea.sample(Vec2::new(3.0, 7.0), 1e4);
            assert!(far.normal.z > 0.999, "{far:?}");
            assert!(far.variance.x + far.variance.y >= 0.9 * cox_munk_mss(u as f32).min(mss));
        }
    }
}
