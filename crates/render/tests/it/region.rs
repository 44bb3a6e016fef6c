//! Shards of a frame: a rectangle rendered alone equals the same rectangle
//! of the full image bit for bit (on 1 and 2 threads), a world rebuilt from
//! its eroded terrain equals the world built in one go, and regions outside
//! the image are refused.

use crate::common;

use common::image_bits as bits;
use natura_core::{Image, NoProgress};
use natura_render::{Renderer, SceneDesc, World};

fn small_scene() -> SceneDesc {
    let mut s = SceneDesc::default();
    s.terrain.size = 128;
    s.terrain.cell_size_m = 480.0;
    s.erosion.stream_power_steps = 3;
    s.erosion.droplets_per_sample = 0.05;
    s.erosion.thermal_steps = 2;
    s.atmosphere.multiple_scattering = false;
    // Coarse cloud voxels and shadow tables: the clouds' preparation at the
    // default resolution was most of these tests' time.
    s.clouds.voxel_m = 400.0;
    s.clouds.shadow_table_nodes = 128;
    s.clouds.shadow_cell_m = 300.0;
    s.render.width = 61;
    s.render.height = 37;
    s.render.spp = 2;
    s
}

fn crop(img: &Image, x0: usize, y0: usize, w: usize, h: usize) -> Vec<u32> {
    let full = img.pixels().as_slice();
    (y0..y0 + h)
        .flat_map(|y| &full[y * img.width() + x0..y * img.width() + x0 + w])
        .flat_map(|c| c.to_array().map(f32::to_bits))
        .collect()
}

#[test]
fn regions_equal_the_full_render_on_any_thread_count() {
    for sigma in [0.0, 0.5] {
        let mut scene = small_scene();
        scene.render.filter_sigma_px = sigma;
        regions_equal_the_full_render(&scene);
    }
}

/// With the Gaussian pixel filter, a region's edge pixels mix samples of
/// pixels outside it: they are traced alike.
fn regions_equal_the_full_render(scene: &SceneDesc) {
    let world = World::build(scene, &NoProgress).unwrap();
    let renderer = Renderer::new(&world, &NoProgress).unwrap();
    let full = renderer.render(&NoProgress).unwrap();
    // Odd sizes and offsets that straddle the renderer's own tiles.
    let regions = [
        (0, 0, 61, 37),
        (3, 5, 17, 9),
        (40, 20, 21, 17),
        (60, 36, 1, 1),
    ];
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        for (x, y, w, h) in regions {
            let part = pool
                .install(|| renderer.render_region(x, y, w, h, &NoProgress))
                .unwrap();
            assert_eq!((part.width(), part.height()), (w as usize, h as usize));
            assert!(
                bits(&part) == crop(&full, x as usize, y as usize, w as usize, h as usize),
                "region {w}×{h} at ({x}, {y}) on {threads} threads"
            );
        }
    }
}

#[test]
fn a_world_from_its_eroded_terrain_equals_the_built_world() {
    let scene = small_scene();
    let built = World::build(&scene, &NoProgress).unwrap();
    let eroded = World::build_eroded(&scene, &NoProgress).unwrap();
    assert_eq!(eroded.terrain, built.terrain);
    assert_eq!(eroded.deposition, built.deposition);
    assert_eq!(eroded.wetness, built.wetness);
    // Another frame's camera and sun over the same eroded terrain.
    let mut moved = scene.clone();
    moved.camera.position_uv = [0.7, 0.5];
    moved.sun.elevation_deg = 14.0;
    let a = World::from_eroded(&moved, eroded, &NoProgress).unwrap();
    let b = World::build(&moved, &NoProgress).unwrap();
    let render = |w: &World| {
        Renderer::new(w, &NoProgress)
            .unwrap()
            .render(&NoProgress)
            .unwrap()
    };
    assert!(bits(&render(&a)) == bits(&render(&b)));
}

#[test]
fn regions_outside_the_image_are_refused() {
    let scene = small_scene();
    let world = World::build(&scene, &NoProgress).unwrap();
    let renderer = Renderer::new(&world, &NoProgress).unwrap();
    for (x, y, w, h) in [
        (0, 0, 0, 5),
        (60, 0, 2, 1),
        (0, 37, 1, 1),
        (u32::MAX, 0, 2, 2),
    ] {
        let e = renderer.render_region(x, y, w, h, &NoProgress).unwrap_err();
        assert!(e.to_string().contains("region"), "{e}");
    }
    let small = World::build_eroded(&scene, &NoProgress).unwrap();
    let mut wrong = small.clone();
    wrong.wetness = natura_core::Grid2::new(3, 3, 0.0).unwrap();
    let e = World::from_eroded(&scene, wrong, &NoProgress).unwrap_err();
    assert!(e.to_string().contains("wetness"), "{e}");
}

#[test]
fn a_frame_prepared_once_renders_as_the_frame_and_its_clouds_round_trip() {
    use natura_render::clouds::CloudSky;
    use natura_render::{FramePrep, StageTimes, scene_renderer, scene_renderer_prepared};
    use std::path::Path;

    let scene = small_scene();
    let world = World::build(&scene, &NoProgress).unwrap();
    let whole = scene_renderer(&world, &mut StageTimes::default(), &NoProgress)
        .unwrap()
        .render(&NoProgress)
        .unwrap();
    let prep = FramePrep::new(&world, &NoProgress).unwrap();
    let plants = prep.plants.clone().unwrap();
    assert!(!plants.is_empty());
    let bytes = prep.clouds.as_ref().unwrap().to_bytes();
    let back = CloudSky::from_bytes(&bytes, Path::new("frame")).unwrap();
    assert_eq!(back.to_bytes(), bytes, "the round trip is exact");
    let prepared = FramePrep {
        clouds: Some(back),
        plants: Some(plants),
    };
    let tiles = scene_renderer_prepared(&world, prepared, &mut StageTimes::default(), &NoProgress)
        .unwrap()
        .render(&NoProgress)
        .unwrap();
    assert!(bits(&tiles) == bits(&whole), "prepared frame differs");

    // Damaged bytes are refused, never a panic.
    let mut nan = bytes.clone();
    // The first dome cell follows the magic, format, 7 floats, wrap flag and two sizes.
    nan[68..72].copy_from_slice(&f32::NAN.to_bits().to_le_bytes());
    let mut trailing = bytes.clone();
    trailing.push(0);
    let mut huge = bytes.clone();
    huge[52..60].copy_from_slice(&u64::MAX.to_le_bytes());
    for (what, bad) in [
        ("truncated", &bytes[..bytes.len() - 1]),
        ("header only", &bytes[..20]),
        ("not a cloud sky", &b"natura cloud skx\x01\0\0\0"[..]),
        ("trailing byte", &trailing[..]),
        ("NaN cell", &nan[..]),
        ("absurd size", &huge[..]),
    ] {
        let e = CloudSky::from_bytes(bad, Path::new("frame")).unwrap_err();
        assert!(e.to_string().contains("cloud sky"), "{what}: {e}");
    }

    // Clouds missing for a cloudy scene, or prepared for another eye.
    assert!(Renderer::with_clouds(&world, None, &NoProgress).is_err());
    let mut moved = scene.clone();
    moved.camera.position_uv = [0.7, 0.5];
    let other = World::build(&moved, &NoProgress).unwrap();
    let theirs = CloudSky::for_world(&other, &NoProgress).unwrap();
    let e = Renderer::with_clouds(&world, theirs, &NoProgress).unwrap_err();
    assert!(e.to_string().contains("another eye"), "{e}");
    let mut clear = scene.clone();
    clear.clouds.enabled = false;
    let clear = World::build(&clear, &NoProgress).unwrap();
    let ours = CloudSky::for_world(&world, &NoProgress).unwrap();
    assert!(Renderer::with_clouds(&clear, ours, &NoProgress).is_err());
}
