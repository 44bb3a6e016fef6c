//! Helpers shared by the texture tests: every texture built from a seed, and
//! a tiny deterministic point generator.
#![allow(dead_code, missing_docs, missing_debug_implementations)]

use glam::DVec3;
use natura_texture::SolidTexture;
use natura_texture::air::{
    CloudBasis, CloudDistortion, Cyclone, CycloneParams, PlanetClouds, PlanetCloudsParams,
    PuffyClouds, PuffyCloudsParams, Venus, VenusParams,
};
use natura_texture::earth::{
    Luna, LunaParams, Ridge, RidgeParams, Strata, StrataParams, Terran, TerranParams,
};
use natura_texture::fire::{Flame, FlameBasis, FlameParams};
use natura_texture::giants::{GasGiant, GasGiantParams, Rings, RingsParams};
use natura_texture::multicolor::{Multicolor, MulticolorParams};
use natura_texture::water::{Ripples, RipplesParams, WindyWave, WindyWaveParams};

/// splitmix64 points.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        natura_core::mix64(self.0)
    }
    pub fn f(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f()
    }
    pub fn p3(&mut self, r: f64) -> DVec3 {
        DVec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }
    pub fn unit(&mut self) -> DVec3 {
        loop {
            let v = self.p3(1.0);
            if v.length() > 0.2 && v.length() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

/// Every texture of the crate with its default parameters and seed `seed`
/// (the multifractal Gaea and the VLNoise clouds and ridged flame variants
/// included), named.
pub fn all_textures(seed: u64) -> Vec<(&'static str, Box<dyn SolidTexture>)> {
    vec![
        (
            "puffy",
            Box::new(
                PuffyClouds::new(PuffyCloudsParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "planet clouds",
            Box::new(
                PlanetClouds::new(PlanetCloudsParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "planet clouds (VLNoise, fBm distortion)",
            Box::new(
                PlanetClouds::new(PlanetCloudsParams {
                    seed,
                    basis: CloudBasis::VariableLacunarity,
                    distortion_field: CloudDistortion::Fbm,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "cyclone",
            Box::new(
                Cyclone::new(CycloneParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "venus",
            Box::new(
                Venus::new(VenusParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "flame",
            Box::new(
                Flame::new(FlameParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "flame (ridged)",
            Box::new(
                Flame::new(FlameParams {
                    seed,
                    basis: FlameBasis::Ridged,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "ripples",
            Box::new(
                Ripples::new(RipplesParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "windywave",
            Box::new(
                WindyWave::new(WindyWaveParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "strata",
            Box::new(
                Strata::new(StrataParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "terran",
            Box::new(
                Terran::new(TerranParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "gaea",
            Box::new(
                Terran::new(TerranParams {
                    seed,
                    ..TerranParams::gaea()
                })
                .unwrap(),
            ),
        ),
        (
            "luna",
            Box::new(
                Luna::new(LunaParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "gas giant",
            Box::new(
                GasGiant::new(GasGiantParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "saturn",
            Box::new(
                GasGiant::new(GasGiantParams {
                    seed,
                    ..GasGiantParams::saturn()
                })
                .unwrap(),
            ),
        ),
        (
            "rings",
            Box::new(
                Rings::new(RingsParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "multicolor",
            Box::new(
                Multicolor::new(MulticolorParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "ridge",
            Box::new(
                Ridge::new(RidgeParams {
                    seed,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
    ]
}

/// A rayon pool of `n` threads.
pub fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .expect("thread pool")
}
