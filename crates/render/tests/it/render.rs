//! Image sanity of the landscape integrator on small worlds.

use glam::Vec3;
use natura_core::{Grid2, HeightField, NoProgress};
use natura_render::{Renderer, SceneDesc, World, render_world, sun_direction};
use natura_trace::Ray;

use crate::common;

use common::bits;

/// The default scene shrunk to a 128² terrain and a 64 × 36 image.
fn small_scene() -> SceneDesc {
    let mut s = common::small_scene();
    // The plain sky and materials these tests were written for.
    s.clouds.enabled = false;
    s.textures.enabled = false;
    s
}

/// A flat world at sea level with no water: terrain shading and sky only.
fn flat_world(scene: &mut SceneDesc, hf: HeightField) -> World {
    scene.water.enabled = false;
    scene.camera.position_uv = [0.1, 0.5];
    scene.camera.target_uv = [0.9, 0.5];
    scene.camera.height_above_ground_m = 200.0;
    scene.camera.pitch_deg = -2.0;
    World::from_height_field(scene, hf, &NoProgress).unwrap()
}

fn luma(c: Vec3) -> f32 {
    natura_core::colour::luminance(c)
}

#[test]
fn same_image_on_one_and_two_threads() {
    let scene = small_scene();
    let world = World::build(&scene, &NoProgress).unwrap();
    let render = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| render_world(&world, &NoProgress).unwrap())
    };
    let a = render(1);
    let b = render(2);
    assert_eq!(bits(&a), bits(&b));
    assert_eq!(a.exposure_ev.to_bits(), b.exposure_ev.to_bits());
}

/// The tile renderer traces each tile's primary rays together (the mipmap
/// tracer's lanes); every pixel must equal the one-ray-at-a-time
/// [`Renderer::pixel`] bit for bit: with lakes, sea and rain, for one, two and
/// three samples per pixel (a non-square stratification), through a
/// panoramic camera, and with the Gaussian pixel filter (whose pixels mix
/// their neighbours' samples, refined where they disagree together).
#[test]
fn tile_render_equals_per_pixel_samples() {
    for (spp, panorama, sigma) in [
        (1, false, 0.0),
        (2, false, 0.0),
        (3, true, 0.0),
        (4, false, 0.5),
        (2, true, 0.8),
    ] {
        let mut scene = small_scene();
        scene.render.width = 40;
        scene.render.height = 24;
        scene.render.spp = spp;
        scene.render.filter_sigma_px = sigma;
        scene.atmosphere.rain_extinction_per_m = 2e-4;
        if panorama {
            scene.camera.kind = natura_render::CameraKind::Cylindrical;
        }
        let world = World::build(&scene, &NoProgress).unwrap();
        let r = Renderer::new(&world, &NoProgress).unwrap();
        let image = r.render(&NoProgress).unwrap();
        let px = image.pixels();
        for y in 0..24u32 {
            for x in 0..40u32 {
                let (a, b) = (px[(x as usize, y as usize)], r.pixel(x, y));
                assert_eq!(
                    a.to_array().map(f32::to_bits),
                    b.to_array().map(f32::to_bits),
                    "spp {spp}, σ {sigma}, pixel ({x}, {y}): {a} vs {b}"
                );
            }
        }
    }
}

#[test]
fn default_scene_small_render_is_finite_and_has_sky_and_land() {
    let scene = small_scene();
    let world = World::build(&scene, &NoProgress).unwrap();
    let out = render_world(&world, &NoProgress).unwrap();
    let px = out.image.pixels().as_slice();
    assert!(px.iter().all(|c| c.is_finite() && c.min_element() >= 0.0));
    // The top row is sky, the bottom row is land or water: they differ.
    let top: f32 = out.image.pixels().row(0).iter().map(|&c| luma(c)).sum();
    assert!(top > 0.0);
    let display = out.display();
    assert!(
        display
            .pixels()
            .as_slice()
            .iter()
            .all(|c| c.max_element() <= 1.0)
    );
}

#[test]
fn zenith_is_bluer_than_horizon_at_noon() {
    let mut scene = small_scene();
    scene.sun.elevation_deg = 75.0;
    let world = flat_world(&mut scene, HeightField::flat(64, 64, 50.0, 0.0).unwrap());
    let r = Renderer::new(&world, &NoProgress).unwrap();
    let eye = world.eye();
    let blue = |c: Vec3| c.z / (c.x + c.y + c.z);
    let zenith = r.radiance(&Ray::new(eye, Vec3::Z));
    let horizon = r.radiance(&Ray::new(eye, Vec3::new(1.0, 0.0, 0.02).normalize()));
    assert!(
        blue(zenith) > blue(horizon),
        "zenith {zenith} horizon {horizon}"
    );
}

#[test]
fn aerial_perspective_lowers_terrain_contrast_with_distance() {
    let mut scene = small_scene();
    scene.sun.elevation_deg = 30.0;
    let world = flat_world(&mut scene, HeightField::flat(512, 512, 100.0, 0.0).unwrap());
    let r = Renderer::new(&world, &NoProgress).unwrap();
    let eye = world.eye();
    let horizon = r.radiance(&Ray::new(eye, Vec3::new(1.0, 0.0, 0.01).normalize()));
    // Average ground radiance over a fan of rays hitting at distance ≈ `dist`.
    let ground = |dist: f32| {
        let mut sum = Vec3::ZERO;
        for k in 0..32 {
            let yaw = (k as f32 - 15.5) * 0.01;
            let d = Vec3::new(dist * yaw.cos(), dist * yaw.sin(), -eye.z).normalize();
            sum += r.radiance(&Ray::new(eye, d));
        }
        sum / 32.0
    };
    let contrast = |g: Vec3| (luma(g) - luma(horizon)).abs() / (luma(g) + luma(horizon));
    let near = contrast(ground(400.0));
    let far = contrast(ground(40_000.0));
    assert!(far < 0.6 * near, "near {near} far {far}");
}

#[test]
fn shadowed_ground_is_darker_than_lit_ground() {
    // Flat ground with a 600 m wall along x = 3.2 km; the sun in the west
    // (azimuth 270°, the −x side) at 10° casts the wall's shadow eastward.
    let n = 128;
    let cell = 50.0;
    let hf = HeightField::new(
        Grid2::from_fn(
            n,
            n,
            |i, _| if (63..=65).contains(&i) { 600.0 } else { 0.0 },
        )
        .unwrap(),
        cell,
    )
    .unwrap();
    let mut scene = small_scene();
    scene.sun.elevation_deg = 10.0;
    scene.sun.azimuth_deg = 270.0;
    scene.materials.bump_strength = 0.0;
    let world = flat_world(&mut scene, hf);
    assert!((world.sun - sun_direction(10.0, 270.0)).length() < 1e-6);
    let r = Renderer::new(&world, &NoProgress).unwrap();
    let look_down = |x: f32, y: f32| r.radiance(&Ray::new(Vec3::new(x, y, 1000.0), Vec3::NEG_Z));
    let mut lit = 0.0;
    let mut shadow = 0.0;
    for k in 0..16 {
        let y = 1000.0 + 250.0 * k as f32;
        lit += luma(look_down(2000.0, y)); // west of the wall: in the sun
        shadow += luma(look_down(3700.0, y)); // 400 m east of the wall: in its shadow
    }
    assert!(
        lit > 2.0 * shadow && shadow > 0.0,
        "lit {lit} shadow {shadow}"
    );
}

/// Luminance of a flat sea seen 8.5° below the horizon on a 4 km grid of
/// points (rays start 60 m before the water), for the given water setup.
fn sea_luminances(setup: impl Fn(&mut SceneDesc)) -> Vec<f32> {
    let hf = HeightField::new(Grid2::from_fn(128, 128, |_, _| -20.0).unwrap(), 50.0).unwrap();
    let mut scene = small_scene();
    scene.water.enabled = true;
    scene.water.level_m = Some(0.0);
    setup(&mut scene);
    let world = World::from_height_field(&scene, hf, &NoProgress).unwrap();
    let r = Renderer::new(&world, &NoProgress).unwrap();
    let mut out = Vec::new();
    for j in 0..24 {
        for i in 0..24 {
            let (x, y) = (
                1200.0 + 170.0 * i as f32 + 0.37 * j as f32,
                1200.0 + 170.0 * j as f32,
            );
            let d = Vec3::new(0.9, 0.2, -0.15).normalize();
            let c = r.radiance(&Ray::new(Vec3::new(x, y, 0.0) - d * 60.0, d));
            assert!(c.is_finite() && c.min_element() >= 0.0);
            out.push(luma(c));
        }
    }
    out
}

fn spread(v: &[f32]) -> f32 {
    let mean = v.iter().sum::<f32>() / v.len() as f32;
    (v.iter().map(|x| (x - mean).powi(2)).sum::<f32>() / v.len() as f32).sqrt() / mean
}

#[test]
fn ocean_waves_roughen_the_water_and_calm_water_is_a_mirror() {
    use natura_render::WaterWaves;
    let calm = sea_luminances(|s| {
        s.water.ripple_height_m = 0.0;
        s.water.wind_speed_m_s = 0.0;
    });
    let ocean = sea_luminances(|s| {
        s.water.waves = WaterWaves::Ocean;
        s.water.ocean_resolution = 64;
        s.water.ocean_patch_m = 128.0;
        s.water.wind_speed_m_s = 12.0;
    });
    // A flat sea under a uniform view is the same everywhere; a wind sea's
    // tilted facets reflect different parts of the sky.
    assert!(spread(&calm) < 1e-3, "calm {}", spread(&calm));
    assert!(spread(&ocean) > 0.02, "ocean {}", spread(&ocean));
    // Deterministic: the same scene gives the same water.
    let again = sea_luminances(|s| {
        s.water.waves = WaterWaves::Ocean;
        s.water.ocean_resolution = 64;
        s.water.ocean_patch_m = 128.0;
        s.water.wind_speed_m_s = 12.0;
    });
    assert_eq!(ocean, again);
}

#[test]
fn rain_shows_a_bow_with_a_dark_band_outside_it() {
    let mut scene = small_scene();
    scene.sun.elevation_deg = 5.0;
    scene.sun.azimuth_deg = 270.0; // sun in the west, bow in the east
    scene.atmosphere.rain_extinction_per_m = 2e-3;
    scene.atmosphere.rain_distance_m = 100.0;
    let world = flat_world(&mut scene, HeightField::flat(64, 64, 50.0, 0.0).unwrap());
    let r = Renderer::new(&world, &NoProgress).unwrap();
    let eye = world.eye();
    // The antisolar point is 5° below the eastern horizon; look up from it by θ.
    let at = |theta_deg: f32| {
        let e = (theta_deg - 5.0).to_radians();
        r.radiance(&Ray::new(eye, Vec3::new(e.cos(), 0.0, e.sin())))
    };
    let bow = luma(at(41.5));
    let band = luma(at(46.5));
    let inside = luma(at(30.0));
    assert!(bow > band, "bow {bow} band {band}");
    assert!(inside > band, "inside {inside} band {band}");
    // Red outside, blue inside the primary bow.
    let red = at(42.3);
    let blue = at(40.6);
    assert!(
        red.x / red.z > blue.x / blue.z,
        "red edge {red} blue edge {blue}"
    );
}

#[test]
fn unwritable_output_and_bad_scene_are_refused_before_work() {
    let mut scene = small_scene();
    scene.render.spp = 0;
    assert!(
        World::build(&scene, &NoProgress)
            .unwrap_err()
            .to_string()
            .contains("render.spp")
    );
    assert!(natura_core::io::check_writable("/no/such/dir/landscape.png").is_err());
}

/// Refinement where a pixel's samples disagree: the pixels that take only
/// their four base samples equal the render without refinement bit for
/// bit, the others took the scene's `adaptive_samples`, and the tile
/// render equals the per-pixel samples with it, on one thread as on two.
#[test]
fn refinement_leaves_agreeing_pixels_as_they_were() {
    let mut scene = small_scene();
    scene.render.spp = 4;
    scene.render.adaptive_samples = 16;
    // The box filter: a pixel is its own samples only.
    scene.render.filter_sigma_px = 0.0;
    let world = World::build(&scene, &NoProgress).unwrap();
    let on = Renderer::new(&world, &NoProgress).unwrap();
    let mut plain = scene.clone();
    plain.render.adaptive_samples = 0;
    let plain_world = World::build(&plain, &NoProgress).unwrap();
    let off = Renderer::new(&plain_world, &NoProgress).unwrap();
    let (a, b) = (
        on.render(&NoProgress).unwrap(),
        off.render(&NoProgress).unwrap(),
    );
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| on.render(&NoProgress).unwrap());
    assert_eq!(common::image_bits(&a), common::image_bits(&one_thread));
    let (pa, pb) = (a.pixels(), b.pixels());
    let bits = |c: Vec3| c.to_array().map(f32::to_bits);
    let mut refined = 0;
    for y in 0..scene.render.height {
        for x in 0..scene.render.width {
            let (v, taken) = on.pixel_samples(x, y);
            let (ia, ib) = (pa[(x as usize, y as usize)], pb[(x as usize, y as usize)]);
            assert_eq!(bits(ia), bits(v), "pixel ({x}, {y})");
            match taken {
                4 => assert_eq!(bits(ia), bits(ib), "pixel ({x}, {y})"),
                16 => refined += 1,
                n => panic!("pixel ({x}, {y}) took {n} samples"),
            }
            assert_eq!(off.pixel_samples(x, y).1, 4);
        }
    }
    let all = (scene.render.width * scene.render.height) as usize;
    assert!(
        refined > 0 && refined < all / 2,
        "{refined} of {all} refined"
    );
}

/// The Gaussian pixel filter moves light between neighbouring pixels but
/// neither makes nor loses it: the image's mean luminance is the box's
/// within a per cent (the edges of the frame, where a pixel has fewer
/// neighbours, and the samples' noise), while the pixel-to-pixel
/// differences shrink.
#[test]
fn the_gaussian_filter_keeps_the_image_s_light_and_softens_it() {
    let render = |sigma: f32| {
        let mut scene = small_scene();
        scene.render.width = 64;
        scene.render.height = 36;
        scene.render.spp = 4;
        scene.render.filter_sigma_px = sigma;
        scene.render.exposure_ev = Some(0.0);
        let world = World::build(&scene, &NoProgress).unwrap();
        Renderer::new(&world, &NoProgress)
            .unwrap()
            .render(&NoProgress)
            .unwrap()
    };
    let stats = |img: &natura_core::Image| {
        let (w, h) = (img.width(), img.height());
        let px = img.pixels();
        let l = |x: usize, y: usize| f64::from(luma(px[(x, y)]));
        let mean = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| l(x, y))
            .sum::<f64>()
            / (w * h) as f64;
        let steps = (0..h)
            .flat_map(|y| (1..w).map(move |x| (x, y)))
            .map(|(x, y)| (l(x, y) - l(x - 1, y)).abs())
            .sum::<f64>();
        (mean, steps)
    };
    let (box_mean, box_steps) = stats(&render(0.0));
    let (g_mean, g_steps) = stats(&render(0.5));
    assert!(
        (g_mean / box_mean - 1.0).abs() < 0.01,
        "mean {g_mean} vs {box_mean}"
    );
    assert!(g_steps < 0.9 * box_steps, "steps {g_steps} vs {box_steps}");
}
