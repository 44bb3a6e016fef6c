//! Set-up shared by the cloudscape comparisons: the rays they trace through
//! the 1920 × 1080 frame and the reference's luminance along them.
#![allow(dead_code)] // each test binary uses its own part

use glam::Vec3;
use natura_volume::transport::{LookAtCamera, ReferenceRenderer, ReferenceSettings, Scene};
use rayon::prelude::*;

/// Relative luminance of a linear colour.
pub fn lum(c: Vec3) -> f64 {
    f64::from(natura_core::colour::luminance(c))
}

/// The unit direction through the centre of pixel `(x, y)` of `cam`.
pub fn centre_ray(cam: &LookAtCamera, x: usize, y: usize) -> Vec3 {
    cam.ray_at(x as f32 + 0.5, y as f32 + 0.5).dir
}

/// The centres of every `stride`-th pixel across and down `cam`'s frame,
/// row by row, and how many there are across.
pub fn frame_rays(cam: &LookAtCamera, stride: usize) -> (Vec<(usize, usize)>, usize) {
    let res = cam.resolution();
    let (w, h) = (res.x as usize / stride, res.y as usize / stride);
    let rays = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i * stride + stride / 2, j * stride + stride / 2)))
        .collect();
    (rays, w)
}

/// [`reference_lum`], kept under the target's temporary directory (a
/// reference takes minutes, the fast mode it is compared with seconds) and
/// keyed by `name`, the paths, the seed, the rays and a fingerprint of the
/// scene: its density at 4096 points of a lattice over its bounds, the
/// sky's radiance in 26 directions and the sun's irradiance, so a change to
/// the scene's clouds or light computes the reference anew.
pub fn cached_reference_lum(
    name: &str,
    scene: &Scene<'_>,
    cam: &LookAtCamera,
    rays: &[(usize, usize)],
    spp: u32,
    seed: u64,
) -> Vec<f64> {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    let b = scene.density.bounds();
    for i in 0..4096u32 {
        let f = Vec3::new(
            (i % 16) as f32 + 0.37,
            ((i / 16) % 16) as f32 + 0.61,
            (i / 256) as f32 + 0.13,
        ) / 16.0;
        scene
            .density
            .density(b.min + (b.max - b.min) * f)
            .to_bits()
            .hash(&mut h);
    }
    for x in -1..=1 {
        for y in -1..=1 {
            for z in -1..=1 {
                let d = Vec3::new(x as f32, y as f32, z as f32);
                if d != Vec3::ZERO {
                    let r = scene.environment.radiance(d.normalize());
                    r.to_array().map(f32::to_bits).hash(&mut h);
                }
            }
        }
    }
    if let Some(s) = &scene.sun {
        format!("{s:?}").hash(&mut h);
    }
    rays.hash(&mut h);
    let key = format!("{name}_{spp}_{seed}_{:016x}", h.finish());
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{key}.txt"));
    if let Ok(s) = std::fs::read_to_string(&path) {
        let v: Vec<f64> = s
            .split_whitespace()
            .filter_map(|x| x.parse().ok())
            .collect();
        if v.len() == rays.len() {
            return v;
        }
    }
    let v = reference_lum(scene, cam, rays, spp, seed);
    let s: Vec<String> = v.iter().map(|x| format!("{x:e}")).collect();
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, s.join(" ")).unwrap();
    std::fs::rename(&tmp, &path).unwrap();
    v
}

/// The reference path tracer's luminance along each of `rays` at `spp`
/// paths per pixel with seed `seed`.
pub fn reference_lum(
    scene: &Scene<'_>,
    cam: &LookAtCamera,
    rays: &[(usize, usize)],
    spp: u32,
    seed: u64,
) -> Vec<f64> {
    let r = ReferenceRenderer::new(
        scene,
        ReferenceSettings {
            samples_per_pixel: spp,
            seed,
            ..ReferenceSettings::default()
        },
    )
    .unwrap();
    rays.par_iter()
        .map(|&(x, y)| lum(r.pixel(cam.eye(), centre_ray(cam, x, y), x, y)))
        .collect()
}
