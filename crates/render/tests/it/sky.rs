//! Layer clouds and surface textures in the landscape: shadows under clouds
//! and not beside them, clouds in the sky, strata on rock, off is off,
//! determinism, and bad keys named before any work.

use glam::Vec3;
use natura_core::{HeightField, NoProgress, Seed};
use natura_render::clouds::CloudSky;
use natura_render::material::Materials;
use natura_render::surface_textures::SurfaceTextures;
use natura_render::{Renderer, SceneDesc, World};
use natura_trace::Ray;

use crate::common;

use common::{bits, cliff as rock, render_on as render};

/// The default scene at 128² and 64 × 36, with coarse cloud voxels.
fn small_scene() -> SceneDesc {
    let mut s = common::small_scene();
    s.clouds.voxel_m = 400.0;
    s.clouds.shadow_table_nodes = 128;
    s.clouds.shadow_cell_m = 300.0;
    s
}

/// A flat world at sea level without water, looking along +x, the sun high,
/// its ground dry: an open, bright ground whose shadows show through the
/// haze (the wetness of a flat field only follows the routing across its
/// flats, and where it is high the ground is dark forest).
fn flat_world(mut scene: SceneDesc) -> World {
    scene.water.enabled = false;
    scene.sun.elevation_deg = 40.0;
    scene.camera.position_uv = [0.1, 0.5];
    scene.camera.target_uv = [0.9, 0.5];
    scene.camera.height_above_ground_m = 200.0;
    scene.camera.pitch_deg = -2.0;
    let hf = HeightField::flat(128, 128, 480.0, 0.0).unwrap();
    let mut world = World::from_height_field(&scene, hf, &NoProgress).unwrap();
    world.wetness.as_mut_slice().fill(0.0);
    world
}

fn clouds_of(world: &World) -> CloudSky {
    let r = Renderer::new(world, &NoProgress).unwrap();
    let view = world
        .atmosphere
        .sky_view(world.eye().as_dvec3(), world.sun_dir())
        .unwrap();
    let angle =
        (world.scene.camera.vfov_deg as f32).to_radians() / world.scene.render.height as f32;
    CloudSky::new(world, r.camera().camera(), angle, &view, &NoProgress)
        .unwrap()
        .expect("clouds are on")
}

#[test]
fn cloud_shadows_darken_the_ground_under_a_cloud_and_not_beside_it() {
    let world = flat_world(small_scene());
    let mut clear = small_scene();
    clear.clouds.enabled = false;
    let world_clear = flat_world(clear);
    let clouds = clouds_of(&world);
    let (on, off) = (
        Renderer::new(&world, &NoProgress).unwrap(),
        Renderer::new(&world_clear, &NoProgress).unwrap(),
    );
    // Ground points ahead of the camera, within 12 km (nearer than the
    // haze): the most and least shadowed.
    let eye = world.eye();
    let mut points: Vec<(f32, Vec3)> = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            let p = Vec3::new(
                eye.x + 2_000.0 + 250.0 * i as f32,
                eye.y - 10_000.0 + 500.0 * j as f32,
                0.0,
            );
            points.push((clouds.sun_transmittance(p), p));
        }
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (t_under, under) = points[0];
    let (t_beside, beside) = points[points.len() - 1];
    assert!(t_under < 0.3, "no point under a thick cloud: {t_under}");
    assert!(t_beside > 0.999, "no point in the sun: {t_beside}");
    let seen = |r: &Renderer<'_>, p: Vec3| r.radiance(&Ray::new(eye, (p - eye).normalize()));
    let (a, b) = (seen(&on, under), seen(&off, under));
    // Red: the channel the haze in front adds least to.
    assert!(
        a.x < 0.7 * b.x,
        "under a cloud (T = {t_under}): {a} vs clear {b}"
    );
    let (a, b) = (seen(&on, beside), seen(&off, beside));
    assert!(
        (a - b).abs().max_element() <= 1e-3 * b.max_element(),
        "beside the clouds: {a} vs clear {b}"
    );
}

#[test]
fn clouds_show_in_the_sky_and_leave_the_ground_seen_from_the_eye() {
    let world = flat_world(small_scene());
    let mut clear = small_scene();
    clear.clouds.enabled = false;
    let world_clear = flat_world(clear);
    let on = Renderer::new(&world, &NoProgress).unwrap();
    let off = Renderer::new(&world_clear, &NoProgress).unwrap();
    let eye = world.eye();
    let mut changed = 0;
    let n = 400;
    for k in 0..n {
        let az = (k % 40) as f32 * 0.02 - 0.4;
        let el = 0.02 + (k / 40) as f32 * 0.03;
        let d = Vec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
        let (a, b) = (
            on.radiance(&Ray::new(eye, d)),
            off.radiance(&Ray::new(eye, d)),
        );
        assert!(a.is_finite() && a.min_element() >= 0.0, "{a}");
        if (a - b).abs().max_element() > 0.01 * b.max_element() {
            changed += 1;
        }
    }
    assert!(
        changed > n / 10,
        "only {changed} of {n} sky rays see clouds"
    );
}

#[test]
fn same_image_on_one_and_two_threads_with_clouds_and_textures() {
    let scene = small_scene();
    let (a, b) = (render(&scene, 1), render(&scene, 2));
    assert_eq!(bits(&a), bits(&b));
    assert!(a.image.pixels().as_slice().iter().all(|c| c.is_finite()));
    let mut plain = small_scene();
    plain.clouds.enabled = false;
    plain.textures.enabled = false;
    assert_ne!(bits(&a), bits(&render(&plain, 2)));
}

#[test]
fn clouds_off_coverage_zero_and_density_zero_are_the_same_image() {
    let mut off = small_scene();
    off.clouds.enabled = false;
    let reference = bits(&render(&off, 2));
    let mut clear = small_scene();
    clear.clouds.layer.coverage = 0.0;
    assert_eq!(bits(&render(&clear, 2)), reference);
    let mut thin = small_scene();
    thin.clouds.layer.density_scale = 0.0;
    assert_eq!(bits(&render(&thin, 2)), reference);
}

#[test]
fn textures_of_zero_strength_are_bit_identical_to_none() {
    let s = SceneDesc::default();
    let plain = Materials::new(&s.materials, Some(100.0), Seed(1)).unwrap();
    let mut t = s.textures.clone();
    t.strata_strength = 0.0;
    t.grain_strength = 0.0;
    let zero = Materials::new(&s.materials, Some(100.0), Seed(1))
        .unwrap()
        .with_textures(SurfaceTextures::new(&t, Seed(2)).unwrap());
    for k in 0..200 {
        let mut p = rock(50.0 + 7.3 * k as f32);
        p.normal = Vec3::new(0.01 * k as f32, 0.0, 1.0).normalize();
        for fp in [0.0, 0.1, 3.0, 100.0] {
            assert_eq!(
                plain.albedo_at(&p, fp).to_array().map(f32::to_bits),
                zero.albedo_at(&p, fp).to_array().map(f32::to_bits)
            );
        }
    }
}

#[test]
fn strata_band_the_rock_up_close_and_fade_with_the_footprint() {
    let s = SceneDesc::default();
    let textured = Materials::new(&s.materials, Some(100.0), Seed(1))
        .unwrap()
        .with_textures(SurfaceTextures::new(&s.textures, Seed(2)).unwrap());
    let plain = Materials::new(&s.materials, Some(100.0), Seed(1)).unwrap();
    // Hue (red over blue) up a cliff: the strata vary it, the plain rock barely.
    let spread = |m: &Materials, fp: f32| {
        let r: Vec<f32> = (0..400)
            .map(|k| {
                let c = m.albedo_at(&rock(600.0 + 1.0 * k as f32), fp);
                c.x / c.z
            })
            .collect();
        let mean = r.iter().sum::<f32>() / r.len() as f32;
        (r.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / r.len() as f32).sqrt()
    };
    let (near, far, none) = (
        spread(&textured, 0.05),
        spread(&textured, 500.0),
        spread(&plain, 0.05),
    );
    assert!(near > 3.0 * none, "strata {near} vs plain rock {none}");
    assert!(
        far < 0.5 * near,
        "a wide footprint fades the bands: {far} vs {near}"
    );
    let c = textured.albedo_at(&rock(700.0), 1.0);
    assert!(c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0);
}

#[test]
fn scene_round_trips_with_clouds_and_textures() {
    let mut s = SceneDesc::default();
    s.clouds.layer.coverage = 0.7;
    s.clouds.layer.base_m = 3500.0;
    s.clouds.medium.albedo = 0.95;
    s.clouds.cache_pixels = 3.0;
    s.textures.strata.zscale = 3.5;
    s.textures.grain_strength = 0.1;
    s.textures.enabled = false;
    let text = s.to_toml_string().unwrap();
    assert_eq!(SceneDesc::from_toml_str(&text, "x").unwrap(), s);
    let partial = "[clouds.layer]\ncoverage = 0.2\n[textures]\nenabled = false\n";
    let p = SceneDesc::from_toml_str(partial, "p").unwrap();
    assert_eq!(
        p.clouds.layer.base_m,
        SceneDesc::default().clouds.layer.base_m
    );
    assert_eq!(p.clouds.layer.coverage, 0.2);
}

/// A change that makes a scene invalid.
type Spoil = fn(&mut SceneDesc);

#[test]
fn bad_cloud_and_texture_keys_are_named_before_any_work() {
    let cases: [(&str, Spoil); 9] = [
        ("clouds.layer.coverage", |s| s.clouds.layer.coverage = 1.5),
        ("clouds.layer.base_m", |s| s.clouds.layer.base_m = -100.0),
        ("clouds.layer.top_m", |s| s.clouds.layer.top_m = 1000.0),
        ("clouds.layer.density_scale", |s| {
            s.clouds.layer.density_scale = -1.0
        }),
        ("clouds.medium.extinction", |s| {
            s.clouds.medium.extinction = 50.0
        }),
        ("clouds.medium.albedo", |s| {
            s.clouds.medium.albedo = f32::NAN
        }),
        ("clouds.voxel_m", |s| s.clouds.voxel_m = 11.0),
        ("textures.strata_strength", |s| {
            s.textures.strata_strength = 2.0
        }),
        ("textures.strata.txtscale", |s| {
            s.textures.strata.txtscale = 0.0
        }),
    ];
    for (key, spoil) in cases {
        let mut s = SceneDesc::default();
        spoil(&mut s);
        let err = World::build(&s, &NoProgress).unwrap_err().to_string();
        assert!(err.contains(key), "{key}: {err}");
    }
    let err = SceneDesc::from_toml_str("[clouds]\nvoxels = 3\n", "s.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("clouds.voxels"), "{err}");
}

#[test]
fn a_cloud_base_below_the_peaks_is_an_error_naming_it() {
    let mut s = small_scene();
    s.clouds.layer.base_m = 500.0;
    s.clouds.layer.top_m = 2_000.0;
    let world = World::build(&s, &NoProgress).unwrap();
    let err = Renderer::new(&world, &NoProgress).unwrap_err().to_string();
    assert!(err.contains("clouds.layer.base_m"), "{err}");
}
