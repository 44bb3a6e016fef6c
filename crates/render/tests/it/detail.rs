//! Procedural detail in the landscape: off is off, on is deterministic and finite.

use crate::common;

use common::{bits, render_on as render};
use natura_render::SceneDesc;

/// A 128² terrain seen from low down (so detail fills the foreground) in a
/// 64 × 36 image.
fn close_scene() -> SceneDesc {
    let mut s = common::small_scene();
    s.terrain.cell_size_m = 120.0;
    s.camera.height_above_ground_m = 15.0;
    s.camera.pitch_deg = -8.0;
    s.detail.amplitude_m = 8.0;
    // The plain sky and materials these tests were written for.
    s.clouds.enabled = false;
    s.textures.enabled = false;
    s
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
