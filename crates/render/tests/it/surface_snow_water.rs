//! The snow's cover (slope, sun, wind shelter, footprint filtering) and the
//! wind sea on the water: scene keys, oracles and renders.

use glam::Vec3;
use natura_core::colour::luminance;
use natura_core::{Grid2, HeightField, NoProgress};
use natura_render::scene::WaterWaves;
use natura_render::snow::{Shelter, SnowCover};
use natura_render::{MaterialDesc, SceneDesc, World, render_world};

use crate::common;

use common::bits;

fn snow() -> SnowCover {
    SnowCover::new(&MaterialDesc::default(), 7).unwrap()
}

/// A unit normal tilted `deg` from up toward the horizontal direction `toward`.
fn tilted(deg: f32, toward: Vec3) -> Vec3 {
    let (s, c) = deg.to_radians().sin_cos();
    (toward.normalize() * s + Vec3::Z * c).normalize()
}

#[test]
fn snow_thins_on_steeper_slopes_and_sunny_faces() {
    let s = snow().with_exposure(Vec3::new(0.0, 1.0, 0.3).normalize(), None, None);
    let d = MaterialDesc::default();
    // Averages over many points, so the edge noise cancels.
    let mean = |deg: f32, toward: Vec3, z: f32| {
        (0..400)
            .map(|k| {
                let p = Vec3::new(13.7 * k as f32, 5.3 * k as f32, z);
                s.cover(p, tilted(deg, toward), 0.0, 0.0)
            })
            .sum::<f32>()
            / 400.0
    };
    let high = d.snow_line_m + 300.0;
    let mut last = f32::INFINITY;
    for deg in [0.0, 25.0, 40.0, 50.0, 65.0] {
        let c = mean(deg, Vec3::X, high);
        assert!(c <= last + 1e-6, "{deg}°: {c} after {last}");
        last = c;
    }
    assert!(mean(10.0, Vec3::X, high) > 0.95);
    assert!(mean(65.0, Vec3::X, high) < 0.05);
    // Near the line, a slope facing the sun (+y) holds less than one facing away.
    let z = d.snow_line_m + 50.0;
    let sunny = mean(35.0, Vec3::Y, z);
    let shady = mean(35.0, -Vec3::Y, z);
    assert!(sunny + 0.2 < shady, "sunny {sunny} vs shady {shady}");
}

#[test]
fn snow_lies_in_the_lee_of_a_ridge() {
    // A ridge along y at x = 32 cells; the wind blows toward +x (azimuth 90°).
    let n = 64;
    let cell = 10.0;
    let heights = Grid2::from_fn(n, n, |i, _| {
        let x = i as f32 - 32.0;
        2000.0 + 200.0 * (-(x * x) / 40.0).exp()
    })
    .unwrap();
    let hf = HeightField::new(heights, cell).unwrap();
    let shelter = Shelter::new(&hf, 90.0, 300.0).unwrap();
    let windward = Vec3::new(26.0 * cell, 320.0, 0.0);
    let lee = Vec3::new(38.0 * cell, 320.0, 0.0);
    assert!(shelter.at(windward) < -0.2, "{}", shelter.at(windward));
    assert!(shelter.at(lee) > 0.2, "{}", shelter.at(lee));
    let d = MaterialDesc::default();
    let s = snow().with_exposure(Vec3::Z, None, Some((shelter, d.snow_wind_m)));
    let line = |p: Vec3| s.line_at(p, Vec3::Z, 0.0);
    assert!(line(lee) + 1.5 * d.snow_wind_m < line(windward));
}

#[test]
fn snow_edge_is_filtered_at_the_footprint() {
    // The cover a wide pixel sees is close to the mean of the point-sampled
    // cover over its footprint, and the edge's spread shrinks with it.
    let s = snow().with_exposure(Vec3::new(0.3, 0.4, 0.5).normalize(), None, None);
    let d = MaterialDesc::default();
    let z = d.snow_line_m;
    let footprint = 200.0;
    let mut worst: f32 = 0.0;
    for c in 0..12 {
        let centre = Vec3::new(1000.0 * c as f32, 777.0, z + 10.0 * c as f32);
        let wide = s.cover(centre, Vec3::Z, 0.0, footprint);
        let n = 24;
        let mut sum = 0.0;
        for a in 0..n {
            for b in 0..n {
                let off = Vec3::new(a as f32 + 0.5, b as f32 + 0.5, 0.0) / n as f32 - 0.5;
                let q = centre + off * footprint;
                sum += s.cover(Vec3::new(q.x, q.y, centre.z), Vec3::Z, 0.0, 0.0);
            }
        }
        worst = worst.max((wide - sum / (n * n) as f32).abs());
    }
    assert!(
        worst < 0.2,
        "filtered cover departs from the mean by {worst}"
    );
}

#[test]
fn new_keys_are_checked_and_round_trip() {
    type Edit = Box<dyn Fn(&mut SceneDesc)>;
    let cases: Vec<(&str, Edit)> = vec![
        (
            "materials.snow_slope_band_deg",
            Box::new(|s| s.materials.snow_slope_band_deg = f32::NAN),
        ),
        (
            "materials.snow_sun_m",
            Box::new(|s| s.materials.snow_sun_m = -1.0),
        ),
        (
            "materials.snow_wind_m",
            Box::new(|s| s.materials.snow_wind_m = f32::INFINITY),
        ),
        (
            "materials.snow_shelter_distance_m",
            Box::new(|s| s.materials.snow_shelter_distance_m = -5.0),
        ),
        (
            "materials.snow_edge_m",
            Box::new(|s| s.materials.snow_edge_m = f32::NAN),
        ),
        (
            "materials.snow_edge_size_m",
            Box::new(|s| s.materials.snow_edge_size_m = 0.0),
        ),
        ("water.fetch_m", Box::new(|s| s.water.fetch_m = Some(-3.0))),
        (
            "water.fetch_m",
            Box::new(|s| s.water.fetch_m = Some(f64::NAN)),
        ),
        (
            "water.wind_speed_m_s",
            Box::new(|s| s.water.wind_speed_m_s = f64::NAN),
        ),
        (
            "water.wind_speed_m_s",
            Box::new(|s| {
                s.water.waves = WaterWaves::Ocean;
                s.water.wind_speed_m_s = 0.0;
            }),
        ),
    ];
    for (key, edit) in cases {
        let mut s = SceneDesc::default();
        edit(&mut s);
        let err = s.validate().unwrap_err().to_string();
        assert!(err.contains(key), "{key}: {err}");
    }
    // A calm is allowed for the wind sea and the ripples.
    let mut calm = SceneDesc::default();
    calm.water.wind_speed_m_s = 0.0;
    calm.validate().unwrap();

    let mut s = SceneDesc::default();
    s.materials.snow_slope_band_deg = 9.5;
    s.materials.snow_sun_m = 120.0;
    s.materials.snow_wind_m = 80.0;
    s.materials.snow_shelter_distance_m = 450.0;
    s.materials.snow_edge_m = 12.0;
    s.materials.snow_edge_size_m = 33.0;
    s.water.fetch_m = Some(1234.5);
    s.water.waves = WaterWaves::Wind;
    s.water.wind_speed_m_s = 3.5;
    let text = s.to_toml_string().unwrap();
    assert_eq!(SceneDesc::from_toml_str(&text, "round.toml").unwrap(), s);
}

/// The small scene with the snow's drift off, so the wind changes only
/// the water.
fn water_scene(wind: f64) -> SceneDesc {
    let mut s = common::small_scene();
    s.clouds.enabled = false;
    s.vegetation.enabled = false;
    s.materials.snow_wind_m = 0.0;
    s.render.width = 96;
    s.render.height = 54;
    // Four samples a pixel: at two, where the sample positions set most of
    // the few hundred water pixels' differences, the variances were a
    // thousand times smaller and did not rise from 3 to 7 m/s.
    s.render.spp = 4;
    s.water.wind_speed_m_s = wind;
    s.water.ocean_resolution = 64;
    s.water.ocean_patch_m = 64.0;
    s
}

#[test]
fn calm_wind_sea_is_the_ripples_bit_for_bit() {
    let mut ripples = water_scene(0.0);
    ripples.water.waves = WaterWaves::Ripples;
    let mut calm = water_scene(0.0);
    calm.water.waves = WaterWaves::Wind;
    let a = common::render_on(&ripples, 2);
    let b = common::render_on(&calm, 2);
    assert!(
        bits(&a) == bits(&b),
        "a calm wind sea renders as the ripples"
    );
}

#[test]
fn reflection_roughens_with_the_wind() {
    let calm_scene = water_scene(0.0);
    let eroded = World::build_eroded(&calm_scene, &NoProgress).unwrap();
    // The same terrain under every wind: only the scene's water keys differ.
    let render = |wind: f64| {
        let mut scene = calm_scene.clone();
        scene.water.wind_speed_m_s = wind;
        let world = World::from_eroded(&scene, eroded.clone(), &NoProgress).unwrap();
        render_world(&world, &NoProgress).unwrap().image
    };
    let calm = render(0.0);
    let mut last = 0.0;
    let mut water: Option<Vec<bool>> = None;
    for wind in [3.0, 7.0, 14.0] {
        let img = render(wind);
        let (px, calm_px) = (img.pixels().as_slice(), calm.pixels().as_slice());
        // The water: the pixels the gentlest wind changes.
        let mask =
            water.get_or_insert_with(|| px.iter().zip(calm_px).map(|(a, b)| a != b).collect());
        let diffs: Vec<f32> = px
            .iter()
            .zip(calm_px)
            .zip(mask.iter())
            .filter(|(_, m)| **m)
            .map(|((a, b), _)| luminance(*a) - luminance(*b))
            .collect();
        assert!(diffs.len() > 50, "the view shows water: {}", diffs.len());
        let mean = diffs.iter().sum::<f32>() / diffs.len() as f32;
        let var = diffs.iter().map(|d| (d - mean).powi(2)).sum::<f32>() / diffs.len() as f32;
        assert!(var > last, "{wind} m/s: variance {var} after {last}");
        last = var;
    }
}
