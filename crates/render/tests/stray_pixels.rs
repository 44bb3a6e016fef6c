//! Stray bright pixels (natura-render's `stray::stray_pixels`) in quick
//! renders of the landscape, a panorama of the same world and the valley
//! morning scene, at the scene's 4 samples a pixel: no more than the few
//! still known, so a change that adds specks fails here.
//!
//! The specks left: single bright pixels of the wind sea's glitter in water
//! the hills otherwise shade (most likely the sun's shadow ray slipping
//! past a ridge at the low sun), one along the far shore, and the narrowest
//! streaks of snow
//! (a pixel or two wide, lit beside darker rock), which the detector's
//! test counts though a viewer reads them as part of the streak.
//!
//! The forest is left out: its crowns at these sizes are a texture of lit
//! and shaded needles a pixel wide, which the detector's test cannot tell
//! from specks.

use natura_core::NoProgress;
use natura_render::scene::CameraKind;
use natura_render::stray::stray_pixels;
use natura_render::{SceneDesc, render_scene};

/// The `--quick` set-up of the landscape and panorama examples.
fn quick(mut s: SceneDesc) -> SceneDesc {
    s.terrain.size = 256;
    s.terrain.cell_size_m *= 8.0;
    s.erosion.stream_power_steps = s.erosion.stream_power_steps.min(5);
    s.erosion.hydraulic_steps = s.erosion.hydraulic_steps.min(20);
    s.erosion.thermal_steps = s.erosion.thermal_steps.min(5);
    s.render.width = 320;
    s.render.height = 180;
    s.render.spp = 4;
    s.clouds.voxel_m *= 4.0;
    s.clouds.shadow_cell_m *= 4.0;
    s.vegetation.enabled = false;
    s
}

/// Fails if `scene` shows more than `known` stray pixels.
fn at_most(scene: &SceneDesc, known: usize) {
    let found = count(scene);
    assert!(
        found.len() <= known,
        "{} stray pixels: {found:?}",
        found.len()
    );
}

fn count(scene: &SceneDesc) -> Vec<(usize, usize)> {
    // The picture as shown: exposed and tone-mapped.
    let r = render_scene(scene, &NoProgress).unwrap();
    stray_pixels(&r.display())
}

#[test]
fn quick_landscape_has_at_most_the_known_stray_pixels() {
    // Four since the layer clouds take their multiple scattering from the
    // cache (brighter cloud light on the water): one in the water and
    // three along one row of the far shore.
    let s = quick(SceneDesc::default());
    at_most(&s, 4);
}

#[test]
fn quick_panorama_has_at_most_the_known_stray_pixels() {
    let mut s = quick(SceneDesc::default());
    s.camera.kind = CameraKind::Cylindrical;
    s.camera.hfov_deg = 220.0;
    s.camera.vfov_deg = 40.0;
    s.render.width = 480;
    s.render.height = 87;
    at_most(&s, 6);
}

#[test]
fn quick_valley_morning_has_at_most_the_known_stray_pixels() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scenes/valley_morning.toml"
    );
    let s = quick(SceneDesc::load(path).unwrap());
    at_most(&s, 2);
}
