//! The natura-noise fractals the textures are built from, set up the way
//! Musgrave's listings call them (`fBm`, `DistfBm`, `VLfBm`, `vfBm`).

use natura_core::Seed;
use natura_noise::{
    DistNoise, Fbm, GainConvention, Perlin, Spectral, Turbulence, VecNoise, VectorFbm, VlNoise,
};

use crate::error::Result;

/// The Perlin basis for the sub-field `name` of a texture seeded `seed`.
pub(crate) fn perlin(seed: u64, name: &str) -> Perlin {
    Perlin::new(Seed(seed).derive(name).0)
}

/// Spectral parameters in the listings' `fBm(p, fw, octaves, lacunarity, H)`
/// form: octave `k` has amplitude `λ^(−kH)`, base frequency 1.
pub(crate) fn spectral(h: f64, lacunarity: f64, octaves: f64) -> Spectral {
    Spectral {
        h,
        lacunarity,
        octaves,
        frequency: 1.0,
        convention: GainConvention::H,
    }
}

/// Spectral parameters with a raw per-octave gain (the listings' `vfBm(…, gain)`).
pub(crate) fn spectral_gain(gain: f64, lacunarity: f64, octaves: f64) -> Spectral {
    Spectral {
        h: gain,
        lacunarity,
        octaves,
        frequency: 1.0,
        convention: GainConvention::Raw,
    }
}

/// `fBm` of Perlin noise.
pub(crate) fn fbm(seed: u64, name: &str, s: Spectral) -> Result<Fbm<Perlin>> {
    Ok(Fbm::new(perlin(seed, name), s)?)
}

/// `turbulence`: fBm of `|noise|`.
pub(crate) fn turbulence(seed: u64, name: &str, s: Spectral) -> Result<Turbulence<Perlin>> {
    Ok(Turbulence::new(perlin(seed, name), s)?)
}

/// `DistfBm`: fBm whose basis is `DistNoise(p, distortion)` (Musgrave 1998,
/// "A Variety of fBm").
pub(crate) fn dist_fbm(
    seed: u64,
    name: &str,
    s: Spectral,
    distortion: f64,
) -> Result<Fbm<DistNoise<Perlin>>> {
    let basis = DistNoise::dist_noise(perlin(seed, name), distortion)?;
    Ok(Fbm::new(basis, s)?)
}

/// `VLfBm`: fBm whose basis is the dissertation's `VLNoise(p, 1)`
/// (Musgrave 1993, §5.2).
pub(crate) fn vl_fbm(seed: u64, name: &str, s: Spectral) -> Result<Fbm<VlNoise<Perlin>>> {
    let basis = VlNoise::vl_noise(perlin(seed, name), 1.0)?;
    Ok(Fbm::new(basis, s)?)
}

/// RenderMan `vfBm`: vector fBm of `vsnoise` (three misregistered noises).
pub(crate) fn vfbm(seed: u64, name: &str, s: Spectral) -> Result<VectorFbm<VecNoise<Perlin>>> {
    Ok(VectorFbm::new(VecNoise::new(perlin(seed, name)), s)?)
}
