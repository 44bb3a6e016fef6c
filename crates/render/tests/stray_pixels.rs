//! Stray bright pixels (natura-render's `stray::stray_pixels`) in quick
//! renders of the landscape, a panorama of the same world and the valley
//! morning scene, at the scene's 4 samples a pixel: none in the landscape,
//! and no more than the few edge pixels still known elsewhere, so a change
//! that adds specks fails here.
//!
//! Fixed at their causes:
//!
//! * Rows of lone white pixels on the far snowy slopes: the snow's edge
//!   noise was band-limited to the pixel's width across the view, while on
//!   a slope seen at a slant the pixel covers ten times more along it; the
//!   cover now sees the footprint on the ground (as the water's waves do).
//! * Lone bright pixels in the water along far shores: a ray reflected off
//!   the water met the shore triangle of its cell within centimetres of the
//!   level and was taken for water, mirroring the sky at the horizon; a
//!   rising ray now always meets the bare bank.
//!
//! Left: pixels on a silhouette against a far brighter background, one
//! of whose four samples passes over the crest (the valley's ridge against
//! the sky, 0.9 m and 1.3 m above it at 2.3 km; in the panorama a near
//! ridge against the lake 8 km away, 0.12 m above the crest at 3.7 km,
//! through a saddle the terrain's detail lowers). The background covers a
//! few per cent of such a pixel where the crest runs along its top edge;
//! four samples count a quarter or nothing, and the sky is 15 to 20 times
//! brighter than the ridge in the shade. Nothing is computed wrong there:
//! only more samples where a pixel's samples disagree would find the
//! coverage.
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
fn quick_landscape_has_no_stray_pixels() {
    let s = quick(SceneDesc::default());
    at_most(&s, 0);
}

#[test]
fn quick_panorama_has_at_most_the_known_stray_pixels() {
    let mut s = quick(SceneDesc::default());
    s.camera.kind = CameraKind::Cylindrical;
    s.camera.hfov_deg = 220.0;
    s.camera.vfov_deg = 40.0;
    s.render.width = 480;
    s.render.height = 87;
    // One: the near ridge against the lake beyond (see the module docs).
    at_most(&s, 1);
}

#[test]
fn quick_valley_morning_has_at_most_the_known_stray_pixels() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scenes/valley_morning.toml"
    );
    let s = quick(SceneDesc::load(path).unwrap());
    // Two: the ridge against the sky (see the module docs).
    at_most(&s, 2);
}
