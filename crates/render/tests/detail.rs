//! Procedural detail in the landscape: off is off, on is deterministic and finite.

use natura_core::NoProgress;
use natura_render::{Rendered, SceneDesc, World, render_world};

/// A 128² terrain seen from low down (so detail fills the foreground) in a
/// 64 × 36 image.
fn close_scene() -> SceneDesc {
    let mut s = SceneDesc::default();
    s.terrain.size = 128;
    s.terrain.cell_size_m = 120.0;
    s.erosion.stream_power_steps = 3;
    s.erosion.droplets_per_sample = 2_000.0 / (128.0 * 128.0);
    s.erosion.thermal_steps = 3;
    s.camera.height_above_ground_m = 15.0;
    s.camera.pitch_deg = -8.0;
    s.detail.amplitude_m = 8.0;
    s.render.width = 64;
    s.render.height = 36;
    s.render.spp = 2;
    // The plain sky and materials these tests were written for.
    s.clouds.enabled = false;
    s.textures.enabled = false;
    s
}

fn bits(r: &Rendered) -> Vec<u32> {
    r.image
        .pixels()
        .as_slice()
        .iter()
        .flat_map(|c| c.to_array().map(f32::to_bits))
        .collect()
}

fn render(scene: &SceneDesc, threads: usize) -> Rendered {
    let world = World::build(scene, &NoProgress).unwrap();
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| render_world(&world, &NoProgress).unwrap())
}

#[test]
fn zero_amplitude_is_bit_identical_to_no_detail() {
    let mut off = close_scene();
    off.detail.enabled = false;
    let mut zero = close_scene();
    zero.detail.amplitude_m = 0.0;
    let mut none = close_scene();
    none.detail.octaves = 0;
    let reference = render(&off, 2);
    assert_eq!(bits(&render(&zero, 2)), bits(&reference));
    assert_eq!(bits(&render(&none, 2)), bits(&reference));
}

#[test]
fn detail_changes_the_foreground_and_is_finite_and_thread_independent() {
    let on = close_scene();
    let mut off = close_scene();
    off.detail.enabled = false;
    let a = render(&on, 1);
    let b = render(&on, 2);
    assert_eq!(bits(&a), bits(&b));
    assert_eq!(a.exposure_ev.to_bits(), b.exposure_ev.to_bits());
    assert!(a.image.pixels().as_slice().iter().all(|c| c.is_finite()));
    let plain = render(&off, 2);
    let changed = a
        .image
        .pixels()
        .as_slice()
        .iter()
        .zip(plain.image.pixels().as_slice())
        .filter(|(x, y)| (**x - **y).abs().max_element() > 1e-3 * y.max_element().max(1e-3))
        .count();
    // The lower half of the frame (the foreground) is where the detail shows.
    assert!(changed > 64 * 36 / 10, "{changed} pixels changed");
}
