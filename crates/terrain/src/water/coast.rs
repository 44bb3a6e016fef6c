//! A coast sunk below the sea along the border of a terrain, so the land
//! ends in a sea instead of a cliff at the edge of the data (natura's own
//! construction; no source).

use glam::DVec2;
use natura_core::{HeightField, Seed, smoothstep};
use natura_noise::{Fbm, Field, Perlin, Spectral};

use crate::error::{Result, in_range, min_size};

/// Parameters of [`sink_coast`]. The defaults are natura's own.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct CoastParams {
    /// Width of the coastal border as a share of each side, in `[0, 0.5]`;
    /// 0 leaves the terrain as it is. Default 0.1.
    pub fraction: f32,
    /// Depth of the sea floor at the very edge, metres below the datum, in
    /// `[0, 20 000]`. Default 300.
    pub depth_m: f32,
    /// How far the coastline wanders, as a share of `fraction` per unit of
    /// the wander's fBm, in `[0, 10]`. Default 0.35.
    pub wander: f32,
    /// The wander fBm's first-octave frequency, cycles across the field. Default 6.
    pub wander_frequency: f64,
    /// The wander fBm's Hurst exponent H. Default 0.6.
    pub wander_h: f64,
    /// The wander fBm's octaves. Default 5.
    pub wander_octaves: f64,
}

impl Default for CoastParams {
    fn default() -> Self {
        Self {
            fraction: 0.1,
            depth_m: 300.0,
            wander: 0.35,
            wander_frequency: 6.0,
            wander_h: 0.6,
            wander_octaves: 5.0,
        }
    }
}

impl CoastParams {
    /// Checks the coast's own parameters (the wander fBm's are checked when
    /// [`sink_coast`] builds it).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
    /// naming `fraction`, `depth_m` or `wander` if it is NaN or outside its
    /// range (see the fields).
    pub fn validate(&self) -> Result<()> {
        in_range("fraction", f64::from(self.fraction), 0.0, 0.5)?;
        in_range("depth_m", f64::from(self.depth_m), 0.0, 20_000.0)?;
        in_range("wander", f64::from(self.wander), 0.0, 10.0)?;
        Ok(())
    }
}

/// Sinks the border of `hf` below the datum over `p.fraction` of each side,
/// along a coastline that wanders with low-frequency fBm of Perlin noise
/// seeded by `seed.derive("coast")`. With `(u, v)` the sample's position
/// in `[0, 1]²`, its distance to the nearest edge `e = min(u, 1 − u, v, 1 − v)`
/// moved by the wander, `d = e + wander · fraction · fBm(u, v)`, and
/// `m = smoothstep(0, fraction, d)`, each height `h` becomes
/// `−depth + (h + depth) · m`: `−depth` at the edge, unchanged beyond the
/// border. No height above `−depth` rises, and a deeper `depth_m` lowers
/// every sample at least as much.
///
/// # Errors
///
/// Returns the errors of [`CoastParams::validate`];
/// [`TerrainError::Noise`](crate::TerrainError::Noise) for invalid wander
/// fBm parameters; [`TerrainError::BadSize`](crate::TerrainError::BadSize)
/// if `hf` has fewer than 2 × 2 samples; [`TerrainError::Core`](crate::TerrainError::Core)
/// naming the first NaN or infinite height.
pub fn sink_coast(hf: &mut HeightField, p: &CoastParams, seed: Seed) -> Result<()> {
    p.validate()?;
    let (nx, ny) = (hf.nx(), hf.ny());
    min_size("sink_coast", nx, ny, 2, 2)?;
    hf.check_finite()?;
    let coast = p.fraction;
    if coast <= 0.0 {
        return Ok(());
    }
    let depth = p.depth_m;
    let wander = Fbm::new(
        Perlin::new(seed.derive("coast").0),
        Spectral::default()
            .with_h(p.wander_h)
            .with_octaves(p.wander_octaves)
            .with_frequency(p.wander_frequency),
    )?;
    let g = hf.heights_mut();
    for j in 0..ny {
        let v = j as f32 / (ny - 1) as f32;
        for i in 0..nx {
            let u = i as f32 / (nx - 1) as f32;
            let edge = u.min(1.0 - u).min(v).min(1.0 - v);
            let d = edge
                + p.wander * coast * wander.eval2(DVec2::new(f64::from(u), f64::from(v))) as f32;
            let m = smoothstep(0.0, coast, d);
            let h = g[(i, j)];
            g[(i, j)] = -depth + (h + depth) * m;
        }
    }
    Ok(())
}
