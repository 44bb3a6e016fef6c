//! The crate's quick-start scene (the example in `src/lib.rs`): it shows sky
//! above the ground, and its automatic exposure is close to the default
//! landscape's at a small size (a camera inside haze would need several stops
//! more).

use natura_core::colour::luminance;
use natura_render::{NoProgress, Rendered, SceneCamera, SceneDesc, World, render_world};
use natura_trace::{MipmapTracer, Tracer};

use crate::common;

/// The quick-start's scene, as in `src/lib.rs`.
fn quickstart_scene() -> SceneDesc {
    let mut scene = SceneDesc::default();
    scene.terrain.size = 64;
    scene.terrain.cell_size_m = 960.0;
    scene.erosion.stream_power_steps = 3;
    scene.erosion.thermal_steps = 3;
    scene.clouds.enabled = false;
    scene.vegetation.enabled = false;
    scene.render.width = 96;
    scene.render.height = 54;
    scene.render.spp = 1;
    scene
}

fn render(scene: &SceneDesc) -> (World, Rendered) {
    let world = World::build(scene, &NoProgress).unwrap();
    let out = render_world(&world, &NoProgress).unwrap();
    (world, out)
}

/// Mean of `f` over the image's rows `rows`.
fn mean_over(out: &Rendered, rows: std::ops::Range<usize>, f: impl Fn(glam::Vec3) -> f32) -> f32 {
    let img = out.image.pixels();
    let n = rows.len() * img.width();
    rows.flat_map(|y| img.row(y).iter().copied())
        .map(f)
        .sum::<f32>()
        / n as f32
}

#[test]
fn the_quick_start_shows_sky_above_the_ground_at_a_landscape_exposure() {
    let scene = quickstart_scene();
    let (world, out) = render(&scene);
    let (w, h) = (scene.render.width as usize, scene.render.height as usize);
    assert_eq!((out.image.width(), out.image.height()), (w, h));
    assert!(out.image.first_non_finite().is_none());

    // No primary ray through the top rows meets the terrain: they see sky.
    let camera = SceneCamera::of_world(&world).unwrap();
    let tracer = MipmapTracer::new(&world.terrain).unwrap();
    let top = h / 6;
    for y in 0..top as u32 {
        for x in 0..w as u32 {
            let ray = camera.camera().ray(x, y, glam::Vec2::splat(0.5));
            assert!(
                tracer.trace(&ray, 0.0, f32::INFINITY).is_none(),
                "pixel ({x}, {y}) of the top rows hits the terrain"
            );
        }
    }
    // …and the bottom row does.
    let ray = camera
        .camera()
        .ray(w as u32 / 2, h as u32 - 1, glam::Vec2::splat(0.5));
    assert!(tracer.trace(&ray, 0.0, f32::INFINITY).is_some());

    // The sky is blue: bluer than red, and bluer than the ground below it.
    let blue_share = |c: glam::Vec3| c.z / (c.x + c.y + c.z).max(1e-6);
    let sky_blue = mean_over(&out, 0..top, blue_share);
    let ground_blue = mean_over(&out, h - top..h, blue_share);
    let sky = mean_over(&out, 0..top, |c| c.z - c.x);
    println!(
        "sky blue share {sky_blue:.3}, ground {ground_blue:.3}, exposure {:+.2} EV",
        out.exposure_ev
    );
    assert!(sky > 0.0, "the top rows are not bluer than red");
    assert!(
        sky_blue > ground_blue,
        "sky {sky_blue} not bluer than ground {ground_blue}"
    );

    // The automatic exposure is within 2 EV of the default landscape's at a
    // small size (its terrain shrunk to 128² of 480 m, the same 61 km).
    let (_, reference) = render(&common::small_scene());
    let d = out.exposure_ev - reference.exposure_ev;
    println!(
        "reference exposure {:+.2} EV, difference {d:+.2}",
        reference.exposure_ev
    );
    assert!(
        d.abs() <= 2.0,
        "exposure {:+.2} EV vs the landscape's {:+.2} EV",
        out.exposure_ev,
        reference.exposure_ev
    );

    // The same comparison by mean log luminance of the linear images.
    let log_lum = |r: &Rendered| {
        let px = r.image.pixels().as_slice();
        px.iter()
            .map(|c| luminance(*c).max(1e-6).log2())
            .sum::<f32>()
            / px.len() as f32
    };
    let dl = log_lum(&out) - log_lum(&reference);
    println!("mean log2 luminance difference {dl:+.2}");
    assert!(dl.abs() <= 2.0);
}
