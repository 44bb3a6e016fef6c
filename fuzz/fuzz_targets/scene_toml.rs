//! Any text as a landscape scene: a scene or an error naming the problem,
//! never a panic, an abort or an allocation past the memory budget. A scene
//! that validates survives a round trip through TOML, gives a still or an
//! error naming a key at its first, middle and last frames, and — made tiny — builds its world and
//! renders a finite image (every section: terrain, erosion, terraces,
//! water, sun, atmosphere, materials, detail, clouds, textures, the forest,
//! camera, animation).
#![no_main]

use libfuzzer_sys::fuzz_target;
use natura_core::NoProgress;
use natura_render::{RenderError, SceneDesc, render_scene};

/// An error must name something: a key, a file, a line.
fn named(e: &RenderError) {
    let m = e.to_string();
    assert!(!m.is_empty() && m.len() < 2000, "{m}");
}

/// The scene made small and quick where its keys make it slow.
fn tiny(s: &mut SceneDesc) {
    s.terrain.size = s.terrain.size.min(64);
    let e = &mut s.erosion;
    e.stream_power_steps = e.stream_power_steps.min(2);
    e.droplets_per_sample = e.droplets_per_sample.min(0.5);
    e.hydraulic_steps = e.hydraulic_steps.min(3);
    e.thermal_steps = e.thermal_steps.min(2);
    s.water.ocean_resolution = s.water.ocean_resolution.min(32);
    let c = &mut s.clouds;
    c.voxel_m = c.voxel_m.max(4000.0);
    c.shadow_table_nodes = c.shadow_table_nodes.min(32);
    c.shadow_cell_m = c.shadow_cell_m.max(2000.0);
    c.step_m = c.step_m.max(500.0);
    let v = &mut s.vegetation;
    v.steps = v.steps.min(2);
    v.radius_m = v.radius_m.min(200.0);
    v.prototypes_per_species = 1;
    s.render.width = s.render.width.min(4);
    s.render.height = s.render.height.min(3);
    s.render.spp = 1;
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let scene = match SceneDesc::from_toml_str(text, "fuzz.toml") {
        Ok(s) => s,
        Err(e) => return named(&e),
    };
    if let Err(e) = scene.validate() {
        return named(&e);
    }
    let again = scene.to_toml_string().expect("a valid scene writes");
    let back = SceneDesc::from_toml_str(&again, "again.toml").expect("and reads back");
    assert_eq!(back, scene);
    let last = scene.animation.frames - 1;
    for frame in [0, last / 2, last] {
        // An interpolated frame may still be refused (a camera path that
        // crosses its target's), by name.
        if let Err(e) = scene.at_frame(frame) {
            return named(&e);
        }
    }
    let mut small = scene.clone();
    tiny(&mut small);
    if let Err(e) = small.validate() {
        return named(&e);
    }
    match render_scene(&small, &NoProgress) {
        Ok(r) => {
            assert!(r.image.pixels().as_slice().iter().all(|c| c.is_finite()));
            assert!(r.exposure_ev.is_finite());
        }
        Err(e) => named(&e),
    }
});
