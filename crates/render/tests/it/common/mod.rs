//! Set-up shared by natura-render's integration tests: a small world and
//! bit-exact image comparison.
#![allow(dead_code)] // each test binary uses its own part

use glam::Vec3;
use natura_core::{Image, NoProgress};
use natura_render::material::SurfaceSample;
use natura_render::{Rendered, SceneDesc, World, render_world};

/// The default scene shrunk to a 128² terrain 480 m a cell, lightly eroded,
/// and a 64 × 36 image at 2 samples per pixel.
pub fn small_scene() -> SceneDesc {
    let mut s = SceneDesc::default();
    s.terrain.size = 128;
    s.terrain.cell_size_m = 480.0;
    s.erosion.stream_power_steps = 3;
    s.erosion.droplets_per_sample = 2_000.0 / (128.0 * 128.0);
    s.erosion.thermal_steps = 3;
    s.render.width = 64;
    s.render.height = 36;
    s.render.spp = 2;
    s
}

/// `s` as the landscape example's `--quick` makes it: [`SceneDesc::quick`]
/// in a 320 × 180 picture at 4 samples a pixel.
pub fn quick_preview(s: &SceneDesc) -> SceneDesc {
    let mut s = s.quick();
    s.render.width = 320;
    s.render.height = 180;
    s.render.spp = 4;
    s
}

/// Every channel of every pixel as its bits.
pub fn image_bits(img: &Image) -> Vec<u32> {
    img.pixels()
        .as_slice()
        .iter()
        .flat_map(|c| c.to_array().map(f32::to_bits))
        .collect()
}

/// [`image_bits`] of a rendered image.
pub fn bits(r: &Rendered) -> Vec<u32> {
    image_bits(&r.image)
}

/// Builds and renders `scene` on a pool of `threads` threads.
pub fn render_on(scene: &SceneDesc, threads: usize) -> Rendered {
    let world = World::build(scene, &NoProgress).unwrap();
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| render_world(&world, &NoProgress).unwrap())
}

/// A dry, steep (rock) surface sample at altitude `z` (normal 73° from up).
pub fn cliff(z: f32) -> SurfaceSample {
    SurfaceSample {
        point: Vec3::new(1234.0, 567.0, z),
        normal: Vec3::new(1.0, 0.0, 0.3).normalize(),
        deposition_m: 0.0,
        wetness: 0.1,
    }
}
