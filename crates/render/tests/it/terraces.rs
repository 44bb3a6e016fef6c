//! Terraces in the landscape: cliffs where layered rock shows on the
//! hillsides and nowhere else, the strata's hue on the rock, the section's
//! round trip, and its bad keys named before any work.

use glam::Vec3;
use natura_core::{HeightField, NoProgress, Seed};
use natura_render::material::Materials;
use natura_render::surface_textures::SurfaceTextures;
use natura_render::{SceneDesc, World};

use crate::common;

use common::cliff;

/// A 192² patch of the default range at 30 m, lightly eroded, no coast.
fn patch(terraces: bool) -> HeightField {
    let mut s = SceneDesc::default();
    s.terrain.size = 192;
    s.terrain.coast_fraction = 0.0;
    // Hillsides about as steep as the full range's.
    s.terrain.relief_m = 1200.0;
    s.erosion.stream_power_steps = 3;
    s.erosion.droplets_per_sample = 0.05;
    s.erosion.thermal_steps = 3;
    s.terraces.enabled = terraces;
    World::build_terrain(&s, &NoProgress).unwrap()
}

/// Slope magnitude (rise over run) at every sample, by central differences
/// (one-sided at the edges).
fn slopes(hf: &HeightField) -> Vec<f32> {
    let (nx, ny) = (hf.nx(), hf.ny());
    let h = hf.heights();
    let c = hf.cell_size();
    let mut out = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (i0, i1) = (i.saturating_sub(1), (i + 1).min(nx - 1));
            let (j0, j1) = (j.saturating_sub(1), (j + 1).min(ny - 1));
            let gx = (h[(i1, j)] - h[(i0, j)]) / (c * (i1 - i0) as f32);
            let gy = (h[(i, j1)] - h[(i, j0)]) / (c * (j1 - j0) as f32);
            out.push(gx.hypot(gy));
        }
    }
    out
}

#[test]
fn terraces_raise_cliffs_on_hillsides_and_leave_gentle_and_low_ground() {
    let scene = SceneDesc::default();
    let t = &scene.terraces;
    let s = &scene.textures.strata;
    let bed = (1.0 / (s.zscale * s.txtscale)) as f32 / t.beds_per_cycle as f32;
    let (plain, terraced) = (patch(false), patch(true));
    let (sp, st) = (slopes(&plain), slopes(&terraced));
    let rock = scene.materials.rock_slope_deg.to_radians().tan();
    let share = |v: &[f32]| v.iter().filter(|&&g| g > rock).count() as f64 / v.len() as f64;
    let (before, after) = (share(&sp), share(&st));
    assert!(
        after > 0.01 && after > 2.0 * before,
        "cliffs steeper than the rock slope: {after} of the samples (before: {before})"
    );
    let gentle = t.min_slope_deg.to_radians().tan();
    let (mut kept, mut moved) = (0, 0);
    for (k, (a, b)) in plain
        .heights()
        .as_slice()
        .iter()
        .zip(terraced.heights().as_slice())
        .enumerate()
    {
        assert!(
            (a - b).abs() <= bed,
            "sample {k} moved more than a bed: {a} → {b}"
        );
        if sp[k] < gentle || *a < t.min_altitude_m {
            assert_eq!(a.to_bits(), b.to_bits(), "gentle or low sample {k} moved");
            kept += 1;
        } else if a != b {
            moved += 1;
        }
    }
    assert!(kept > 0 && moved > 1000, "kept {kept}, moved {moved}");
}

#[test]
fn terraced_worlds_are_the_same_on_one_and_two_threads() {
    let build = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| patch(true))
    };
    assert_eq!(build(1), build(2));
}

#[test]
fn strata_tint_takes_the_bands_from_the_rocks_grey_to_the_listings_tans() {
    let mut s = SceneDesc::default();
    s.materials.rock = [0.4, 0.4, 0.4];
    s.materials.snow_line_m = 1e5;
    let with_tint = |tint: f32| {
        let mut t = s.textures.clone();
        t.strata_tint = tint;
        t.grain_strength = 0.0;
        Materials::new(&s.materials, Some(100.0), Seed(1))
            .unwrap()
            .with_textures(SurfaceTextures::new(&t, Seed(2)).unwrap())
    };
    let (grey, tan) = (with_tint(0.0), with_tint(1.0));
    let (mut lum_lo, mut lum_hi) = (f32::INFINITY, 0.0f32);
    for k in 0..400 {
        let p = cliff(600.0 + k as f32);
        let g = grey.albedo_at(&p, 0.05);
        let ratio = |c: Vec3| c.x / c.z;
        // Grey rock keeps its hue within the mottling's rounding...
        assert!((ratio(g) - 1.0).abs() < 1e-3, "tint 0 is grey: {g}");
        // ... and the listing's tans are warmer.
        assert!(ratio(tan.albedo_at(&p, 0.05)) > 1.2, "tint 1 is tan");
        let l = g.x;
        lum_lo = lum_lo.min(l);
        lum_hi = lum_hi.max(l);
    }
    assert!(
        lum_hi > 1.3 * lum_lo,
        "the bands show as brightness: {lum_lo}..{lum_hi}"
    );
}

#[test]
fn scene_round_trips_with_terraces() {
    let mut s = SceneDesc::default();
    s.terraces.beds_per_cycle = 5;
    s.terraces.cliff_fraction = 0.5;
    s.terraces.min_altitude_m = 800.0;
    s.textures.strata_tint = 0.8;
    let text = s.to_toml_string().unwrap();
    assert_eq!(SceneDesc::from_toml_str(&text, "x").unwrap(), s);
    let p = SceneDesc::from_toml_str("[terraces]\nenabled = false\n", "p").unwrap();
    assert!(!p.terraces.enabled);
    assert_eq!(p.terraces.flatness, SceneDesc::default().terraces.flatness);
}

/// A change that makes a scene invalid.
type Spoil = fn(&mut SceneDesc);

#[test]
fn bad_terrace_keys_are_named_before_any_work() {
    let cases: [(&str, Spoil); 9] = [
        ("terraces.beds_per_cycle", |s| s.terraces.beds_per_cycle = 0),
        ("terraces.cliff_fraction", |s| {
            s.terraces.cliff_fraction = 0.0
        }),
        ("terraces.cliff_fraction", |s| {
            s.terraces.cliff_fraction = 1.5
        }),
        ("terraces.flatness", |s| s.terraces.flatness = f32::NAN),
        ("terraces.min_slope_deg", |s| {
            s.terraces.min_slope_deg = -5.0
        }),
        ("textures.strata.zscale", |s| s.textures.strata.zscale = 0.0),
        // Beds of infinite height in f32 (found by the scene-edit property
        // test under another seed: named by natura-terrain, not by key),
        // and beds taller than the terraces take.
        ("textures.strata.zscale", |s| {
            s.textures.strata.zscale = 6.674_344_689_176_268e-239
        }),
        ("textures.strata.zscale", |s| {
            s.textures.strata.zscale = 1e-9
        }),
        ("textures.strata_tint", |s| s.textures.strata_tint = 2.0),
    ];
    for (key, spoil) in cases {
        let mut s = SceneDesc::default();
        spoil(&mut s);
        let err = World::build(&s, &NoProgress).unwrap_err().to_string();
        assert!(err.contains(key), "{key}: {err}");
    }
    // Off, the strata need not repeat in altitude.
    let mut s = SceneDesc::default();
    s.terraces.enabled = false;
    s.textures.strata.zscale = 0.0;
    s.validate().unwrap();
}
