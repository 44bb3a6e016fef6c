//! The forest: its two-level BVH against brute force (per instance and as
//! whole images), thread independence, finiteness, and its scene keys.

use crate::common;

use common::image_bits as bits;
use glam::Vec3;
use natura_core::{HeightField, NoProgress, Seed};
use natura_render::vegetation::Forest;
use natura_render::{RenderError, Renderer, SceneDesc, World, render_world};

/// A gentle bumpy slope of 96² samples 5 m apart, no water, seen from a
/// few metres up with the forest within `radius` metres. No clouds: their
/// preparation was most of these tests' time, and the sky's tests cover them.
fn forest_world(radius: f64) -> World {
    let mut s = SceneDesc::default();
    s.water.enabled = false;
    s.clouds.enabled = false;
    s.vegetation.tree_line_m = 80.0;
    s.camera.position_uv = [0.5, 0.25];
    s.camera.target_uv = [0.5, 0.9];
    s.camera.height_above_ground_m = 6.0;
    s.camera.pitch_deg = -4.0;
    s.camera.vfov_deg = 40.0;
    s.vegetation.radius_m = radius;
    s.vegetation.density_per_ha = 20.0;
    s.vegetation.steps = 10;
    s.vegetation.lod_distance_m = 0.4 * radius;
    s.render.width = 48;
    s.render.height = 27;
    s.render.spp = 1;
    let hf = HeightField::from_fn(96, 96, 5.0, |i, j| {
        let (x, y) = (i as f32 * 0.11, j as f32 * 0.13);
        0.15 * j as f32 + 2.0 * x.sin() * y.cos()
    })
    .unwrap();
    World::from_height_field(&s, hf, &NoProgress).unwrap()
}

#[test]
fn every_instance_agrees_with_brute_force() {
    let world = forest_world(120.0);
    let forest = Forest::build(&world, &NoProgress).unwrap().unwrap();
    let st = forest.stats();
    assert!(st.instances > 20, "{st:?}");
    assert!(st.near > 0 && st.near < st.instances, "{st:?}");
    let sc = forest.instanced();
    let seed = Seed(7);
    let mut hits = 0;
    for (i, p) in sc.placements.iter().enumerate() {
        let m = &sc.meshes[p.mesh as usize];
        // Rays aimed at triangles of this instance from random points around it.
        for k in 0..6u64 {
            let u = |c: u64| seed.uniform(&[i as i64, k as i64, c as i64]) as f32;
            let tri = &m.tris[((u(0) * m.len() as f32) as usize).min(m.len() - 1)];
            let local = (tri[0] + tri[1] + tri[2]) / 3.0;
            let (c, s) = p.cos_sin;
            let target = p.position
                + p.scale
                    * Vec3::new(
                        c * local.x - s * local.y,
                        s * local.x + c * local.y,
                        local.z,
                    );
            let from = target
                + Vec3::new(u(1) - 0.5, u(2) - 0.5, u(3) - 0.3).normalize() * (5.0 + 40.0 * u(4));
            let d = (target - from).normalize();
            let a = sc.closest(from, d, 0.0, f32::INFINITY);
            let b = sc.closest_brute(from, d, 0.0, f32::INFINITY);
            assert_eq!(a, b, "instance {i}, ray {k}");
            hits += usize::from(a.is_some());
            assert_eq!(
                sc.occluded(from, d, 0.0, 60.0),
                sc.occluded_brute(from, d, 0.0, 60.0),
                "instance {i}, ray {k}"
            );
        }
    }
    // Most rays aimed at a triangle's centre hit something.
    assert!(hits * 10 > 9 * 6 * sc.placements.len(), "{hits}");
}

#[test]
fn bvh_and_brute_force_give_identical_images() {
    let world = forest_world(45.0);
    let render = |brute: bool| {
        let mut forest = Forest::build(&world, &NoProgress).unwrap().unwrap();
        forest.set_brute_force(brute);
        let r = Renderer::new(&world, &NoProgress)
            .unwrap()
            .with_forest(Some(forest));
        r.render(&NoProgress).unwrap()
    };
    let a = render(false);
    let b = render(true);
    assert_eq!(bits(&a), bits(&b));
    // The trees are in the picture: it differs from the bare terrain's.
    let bare = Renderer::new(&world, &NoProgress)
        .unwrap()
        .render(&NoProgress)
        .unwrap();
    assert_ne!(bits(&a), bits(&bare));
}

#[test]
fn one_and_two_threads_are_bit_identical_and_finite() {
    let world = forest_world(150.0);
    let render = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let f = Forest::build(&world, &NoProgress).unwrap().unwrap();
                let p = f.instanced().placements.clone();
                (render_world(&world, &NoProgress).unwrap(), p)
            })
    };
    let (a, pa) = render(1);
    let (b, pb) = render(2);
    assert_eq!(pa, pb);
    assert_eq!(bits(&a.image), bits(&b.image));
    assert!(
        a.image
            .pixels()
            .as_slice()
            .iter()
            .all(|c| c.is_finite() && c.min_element() >= 0.0)
    );
}

#[test]
fn disabled_vegetation_grows_nothing() {
    let mut world = forest_world(120.0);
    world.scene.vegetation.enabled = false;
    assert!(Forest::build(&world, &NoProgress).unwrap().is_none());
}

fn invalid_key(scene: &SceneDesc) -> String {
    match World::build(scene, &NoProgress) {
        Err(RenderError::Invalid { name, .. }) => name,
        other => panic!("expected an invalid key, got {other:?}"),
    }
}

#[test]
fn bad_vegetation_keys_are_named_before_any_work() {
    let mut s = SceneDesc::default();
    s.vegetation.density_per_ha = 1e9;
    assert_eq!(invalid_key(&s), "vegetation.density_per_ha");
    s.vegetation.density_per_ha = 0.0;
    assert_eq!(invalid_key(&s), "vegetation.density_per_ha");
    s.vegetation.density_per_ha = f64::NAN;
    assert_eq!(invalid_key(&s), "vegetation.density_per_ha");

    let mut s = SceneDesc::default();
    s.vegetation.tree_height_m = -5.0;
    assert_eq!(invalid_key(&s), "vegetation.tree_height_m");

    let mut s = SceneDesc::default();
    s.vegetation.species = vec!["spruce".into(), "baobab".into()];
    assert_eq!(invalid_key(&s), "vegetation.species[1]");
    s.vegetation.species = vec!["pine".into(), "pine".into()];
    assert_eq!(invalid_key(&s), "vegetation.species[1]");
    s.vegetation.species.clear();
    assert_eq!(invalid_key(&s), "vegetation.species");

    for (key, set) in [
        (
            "vegetation.radius_m",
            (|s: &mut SceneDesc| s.vegetation.radius_m = -1.0) as fn(&mut SceneDesc),
        ),
        ("vegetation.steps", |s| s.vegetation.steps = 0),
        ("vegetation.prototypes_per_species", |s| {
            s.vegetation.prototypes_per_species = 0
        }),
        ("vegetation.lod_distance_m", |s| {
            s.vegetation.lod_distance_m = f64::INFINITY
        }),
        ("vegetation.leaf_transmission", |s| {
            s.vegetation.leaf_transmission = 1.5
        }),
    ] {
        let mut s = SceneDesc::default();
        set(&mut s);
        assert_eq!(invalid_key(&s), key);
    }
}

#[test]
fn vegetation_round_trips_through_toml_and_unknown_keys_are_named() {
    let mut s = SceneDesc::default();
    s.vegetation.species = vec!["beech".into()];
    s.vegetation.density_per_ha = 3.5;
    s.vegetation.enabled = false;
    s.vegetation.seed_offset = 9;
    let text = s.to_toml_string().unwrap();
    assert!(text.contains("[vegetation]"), "{text}");
    assert_eq!(SceneDesc::from_toml_str(&text, "x").unwrap(), s);

    let err = SceneDesc::from_toml_str("[vegetation]\ndensity = 3\n", "s.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("s.toml:2:"), "{err}");
    assert!(err.contains("vegetation.density"), "{err}");
    let partial = SceneDesc::from_toml_str("[vegetation]\nsteps = 3\n", "s.toml").unwrap();
    assert_eq!(partial.vegetation.steps, 3);
    assert_eq!(
        partial.vegetation.species,
        SceneDesc::default().vegetation.species
    );
}

#[test]
fn trees_on_the_shore_stand_in_the_water_s_mirror_image() {
    // A slope rising through the sea level (0 m) at row 30: water below,
    // trees above.
    let mut s = SceneDesc::default();
    s.clouds.enabled = false;
    s.water.enabled = true;
    s.water.level_m = Some(0.0);
    // A still mirror, so each reflected ray goes where it is aimed.
    s.water.ripple_height_m = 0.0;
    s.vegetation.tree_line_m = 80.0;
    s.camera.position_uv = [0.5, 0.12];
    s.camera.target_uv = [0.5, 0.9];
    s.camera.height_above_ground_m = 6.0;
    s.vegetation.radius_m = 200.0;
    s.vegetation.density_per_ha = 20.0;
    s.vegetation.steps = 10;
    s.render.width = 48;
    s.render.height = 27;
    s.render.spp = 1;
    let hf = HeightField::from_fn(96, 96, 5.0, |i, j| {
        let (x, y) = (i as f32 * 0.11, j as f32 * 0.13);
        0.25 * (j as f32 - 30.0) + 1.5 * x.sin() * y.cos()
    })
    .unwrap();
    let world = World::from_height_field(&s, hf, &NoProgress).unwrap();
    let level = world.water_level.unwrap();
    let eye = world.eye();
    assert!(
        (eye.z - level - 6.0).abs() < 1e-3,
        "the eye is over the water: {eye}"
    );
    let bare = Renderer::new(&world, &NoProgress).unwrap();
    let with = |brute: bool| {
        let mut f = Forest::build(&world, &NoProgress).unwrap().unwrap();
        f.set_brute_force(brute);
        Renderer::new(&world, &NoProgress)
            .unwrap()
            .with_forest(Some(f))
    };
    let (bvh, brute) = (with(false), with(true));
    let forest = bvh.forest().unwrap().instanced();
    // Rays toward the mirror images (in the water plane) of crowns 20–150 m
    // away: each meets the water first, then the tree.
    let (mut mirrored, mut tried) = (0, 0);
    for p in &forest.placements {
        let m = &forest.meshes[p.mesh as usize];
        let crown = p.position + Vec3::Z * (0.6 * p.scale * m.bounds.1.z);
        let dist = (crown - eye).truncate().length();
        if !(20.0..150.0).contains(&dist) || crown.z <= level + 1.0 {
            continue;
        }
        let image = Vec3::new(crown.x, crown.y, 2.0 * level - crown.z);
        let d = (image - eye).normalize();
        // Only rays that reach open water (a metre deep at least) before
        // any tree.
        let to_water = (level - eye.z) / d.z;
        let w = eye + d * to_water;
        let ground = world.terrain.sample(w.x, w.y, natura_core::Boundary::Clamp);
        if ground > level - 1.0 || forest.closest(eye, d, 0.0, to_water).is_some() {
            continue;
        }
        let ray = natura_trace::Ray::new(eye, d);
        let (a, b, c) = (
            bvh.radiance(&ray),
            brute.radiance(&ray),
            bare.radiance(&ray),
        );
        assert!(a.is_finite());
        assert_eq!(
            a.to_array().map(f32::to_bits),
            b.to_array().map(f32::to_bits)
        );
        mirrored += usize::from(a != c);
        tried += 1;
    }
    assert!(
        tried >= 10 && mirrored * 10 >= 8 * tried,
        "{mirrored} of {tried} rays saw a tree in the water"
    );
}

/// The sun's light on a tree: the shadow ray through the triangles where a
/// pixel is smaller than a leaf's sun-flecks, and the crowns as turbid media
/// where it covers many leaves, with the same mean over the forest's leaves.
#[test]
fn sun_visibility_is_the_shadow_ray_near_and_its_mean_far() {
    let world = forest_world(120.0);
    let forest = Forest::build(&world, &NoProgress).unwrap().unwrap();
    let sc = forest.instanced();
    let sun = world.sun;
    let eps = 0.03;
    let (mut near, mut far, mut n) = (0.0f64, 0.0f64, 0.0f64);
    let mut between_ok = 0;
    for (i, p) in sc.placements.iter().enumerate() {
        let m = &sc.meshes[p.mesh as usize];
        if p.mesh % 2 == 1 {
            continue;
        }
        for (k, (tri, _)) in m.tris.iter().zip(&m.leaf).filter(|(_, l)| **l).enumerate() {
            if k % 7 != 0 {
                continue;
            }
            let local = (tri[0] + tri[1] + tri[2]) / 3.0;
            let q = p.position + p.scale * p.normal_to_world(local);
            let own = Some(i as u32);
            // A footprint far under a leaf: exactly the shadow ray.
            let ray = if forest.occluded(q, sun, eps, f32::INFINITY) {
                0.0
            } else {
                1.0
            };
            assert_eq!(forest.sun_visibility(q, sun, eps, 1e-4, own), ray);
            // A footprint over many leaves: a share, not a fleck.
            let v = forest.sun_visibility(q, sun, eps, 100.0, own);
            assert!((0.0..=1.0).contains(&v), "{v}");
            // Between, the blend of the two.
            let mid = forest.sun_visibility(q, sun, eps, 0.1, own);
            if mid >= ray.min(v) - 1e-6 && mid <= ray.max(v) + 1e-6 {
                between_ok += 1;
            }
            near += f64::from(ray);
            far += f64::from(v);
            n += 1.0;
        }
    }
    assert!(n > 500.0, "{n} leaf points");
    assert_eq!(between_ok, n as usize);
    let (near, far) = (near / n, far / n);
    eprintln!("mean sun on {n} leaves: rays {near:.3}, media {far:.3}");
    assert!(near > 0.1 && near < 0.9, "{near}");
    assert!((near - far).abs() < 0.05, "rays {near:.3}, media {far:.3}");
}
