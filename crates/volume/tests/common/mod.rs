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
