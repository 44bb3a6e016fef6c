//! Scene tests: the embedded default, TOML round trips, errors that name
//! line and key, and refused values.

use super::*;

#[test]
fn embedded_default_scene_equals_the_defaults() {
    let parsed = SceneDesc::from_toml_str(DEFAULT_SCENE_TOML, "default.toml").unwrap();
    assert_eq!(parsed, SceneDesc::default());
    parsed.validate().unwrap();
}

/// The scene files shipped beside the examples load and validate, and each
/// changes the built-in scene.
#[test]
fn example_scene_files_load_and_validate() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = SceneDesc::load(&path).unwrap();
            assert_ne!(scene, SceneDesc::default(), "{}", path.display());
            n += 1;
        }
    }
    assert!(n >= 1, "no scene files in {}", dir.display());
}

#[test]
fn round_trips_through_toml() {
    let mut s = SceneDesc {
        seed: 99,
        ..SceneDesc::default()
    };
    s.water.level_m = Some(12.5);
    s.render.exposure_ev = Some(-3.5);
    s.materials.diffuse = Diffuse::Lambert;
    s.camera.kind = CameraKind::Cylindrical;
    s.render.adaptive_samples = 64;
    s.render.adaptive_contrast = 0.4;
    s.render.filter_sigma_px = 0.3;
    let text = s.to_toml_string().unwrap();
    assert_eq!(SceneDesc::from_toml_str(&text, "x").unwrap(), s);
}

#[test]
fn sampling_keys_are_read_and_refused_by_name() {
    let text = "[render]\nadaptive_samples = 36\nadaptive_contrast = 0.5\n";
    let s = SceneDesc::from_toml_str(text, "a.toml").unwrap();
    assert_eq!(
        (s.render.adaptive_samples, s.render.adaptive_contrast),
        (36, 0.5)
    );
    assert_eq!(s.render.spp, RenderDesc::default().spp);
    s.validate().unwrap();
    // Off, written either way, is valid.
    for off in [0, 4] {
        let mut s = SceneDesc::default();
        s.render.adaptive_samples = off;
        s.validate().unwrap();
    }
    type Mutation = Box<dyn Fn(&mut SceneDesc)>;
    let cases: Vec<(&str, Mutation)> = vec![
        (
            "render.adaptive_samples",
            Box::new(|s| s.render.adaptive_samples = 5000),
        ),
        (
            "render.adaptive_contrast",
            Box::new(|s| s.render.adaptive_contrast = f32::NAN),
        ),
        (
            "render.adaptive_contrast",
            Box::new(|s| s.render.adaptive_contrast = -0.1),
        ),
        (
            "render.adaptive_contrast",
            Box::new(|s| s.render.adaptive_contrast = 1.5),
        ),
        (
            "render.filter_sigma_px",
            Box::new(|s| s.render.filter_sigma_px = f32::NAN),
        ),
        (
            "render.filter_sigma_px",
            Box::new(|s| s.render.filter_sigma_px = -0.1),
        ),
        (
            "render.filter_sigma_px",
            Box::new(|s| s.render.filter_sigma_px = 1.5),
        ),
    ];
    for (key, mutate) in cases {
        let mut s = SceneDesc::default();
        mutate(&mut s);
        let err = s.validate().unwrap_err().to_string();
        assert!(err.contains(key), "{key}: {err}");
    }
    let err = SceneDesc::from_toml_str("[render]\nadaptive_samples = -4\n", "a.toml")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("a.toml:2:") && err.contains("render.adaptive_samples"),
        "{err}"
    );
}

#[test]
fn empty_file_is_the_default_scene() {
    assert_eq!(
        SceneDesc::from_toml_str("", "empty").unwrap(),
        SceneDesc::default()
    );
}

#[test]
fn unknown_key_names_line_and_key() {
    let text = "seed = 3\n\n[sun]\nelevation_deg = 10.0\nelevaton = 5\n";
    let err = SceneDesc::from_toml_str(text, "scene.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("scene.toml:5:"), "{err}");
    assert!(err.contains("sun.elevaton"), "{err}");
}

#[test]
fn a_partial_model_table_keeps_the_scene_defaults() {
    // The scene's stream power differs from the model's own defaults in
    // every key but `m` and `n`; giving only `k` must keep the scene's.
    let text = "[erosion.stream_power]\nk = 3e-6\n";
    let s = SceneDesc::from_toml_str(text, "s.toml").unwrap();
    let mut want = SceneDesc::default();
    want.erosion.stream_power.k = 3e-6;
    assert_eq!(s, want);
    assert_ne!(
        s.erosion.stream_power.dt_yr,
        natura_terrain::erosion::StreamPowerParams::default().dt_yr
    );
}

#[test]
fn unknown_key_in_a_model_table_names_line_and_key() {
    let text = "[erosion.thermal]\ntalus_rate = 0.1\ntalus_deg = 30\n";
    let err = SceneDesc::from_toml_str(text, "s.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("s.toml:3:"), "{err}");
    assert!(err.contains("erosion.thermal.talus_deg"), "{err}");
}

#[test]
fn wrong_type_names_line_and_key() {
    let text = "[camera]\nvfov_deg = 30.0\n\n[render]\nwidth = \"wide\"\n";
    let err = SceneDesc::from_toml_str(text, "s.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("s.toml:5:"), "{err}");
    assert!(err.contains("render.width"), "{err}");
}

#[test]
fn syntax_error_names_line() {
    let text = "seed = 3\n[terrain\nsize = 4\n";
    let err = SceneDesc::from_toml_str(text, "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("bad.toml:2:"), "{err}");
}

#[test]
fn impossible_values_are_refused_by_name() {
    type Mutation = Box<dyn Fn(&mut SceneDesc)>;
    let cases: Vec<(&str, Mutation)> = vec![
        ("render.spp", Box::new(|s| s.render.spp = 0)),
        ("render.width", Box::new(|s| s.render.width = 0)),
        ("terrain.size", Box::new(|s| s.terrain.size = 3)),
        (
            "terrain.cell_size_m",
            Box::new(|s| s.terrain.cell_size_m = -1.0),
        ),
        ("terrain.h", Box::new(|s| s.terrain.h = f64::NAN)),
        (
            "sun.elevation_deg",
            Box::new(|s| s.sun.elevation_deg = -5.0),
        ),
        (
            "erosion.thermal.talus_angle",
            Box::new(|s| s.erosion.thermal.talus_angle = 2.0),
        ),
        (
            "erosion.stream_power.k",
            Box::new(|s| s.erosion.stream_power.k = f64::NAN),
        ),
        (
            "erosion.droplets.radius",
            Box::new(|s| s.erosion.droplets.radius = 0),
        ),
        ("erosion.pipe.dt", Box::new(|s| s.erosion.pipe.dt = -1.0)),
        (
            "camera.target_uv",
            Box::new(|s| s.camera.target_uv = s.camera.position_uv),
        ),
        (
            "water.ocean_resolution",
            Box::new(|s| s.water.ocean_resolution = 300),
        ),
        (
            "water.wind_speed_m_s",
            Box::new(|s| s.water.wind_speed_m_s = -1.0),
        ),
        // Below a breeze the wind sea's spectrum leaves f64's range (the
        // smallest subnormal gave NaN waves at render time).
        (
            "water.wind_speed_m_s",
            Box::new(|s| s.water.wind_speed_m_s = 5e-324),
        ),
        (
            "water.wind_speed_m_s",
            Box::new(|s| s.water.wind_speed_m_s = 0.05),
        ),
    ];
    for (key, mutate) in cases {
        let mut s = SceneDesc::default();
        mutate(&mut s);
        let err = s.validate().unwrap_err().to_string();
        assert!(err.contains(key), "{key}: {err}");
    }
    // A calm is 0 exactly, for the wind sea; the ocean needs a wind.
    let mut calm = SceneDesc::default();
    calm.water.wind_speed_m_s = 0.0;
    calm.validate().unwrap();
    calm.water.waves = WaterWaves::Ocean;
    let err = calm.validate().unwrap_err().to_string();
    assert!(
        err.contains("water.wind_speed_m_s") && !err.contains("calm"),
        "{err}"
    );
    let mut twilight = SceneDesc::default();
    twilight.sun.elevation_deg = -4.0;
    twilight.sun.allow_below_horizon = true;
    twilight.validate().unwrap();
}

#[test]
fn missing_file_is_named() {
    let err = SceneDesc::load("/no/such/scene.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("/no/such/scene.toml"), "{err}");
}

#[test]
fn bad_detail_keys_are_named() {
    type Mutation = Box<dyn Fn(&mut SceneDesc)>;
    let cases: Vec<(&str, Mutation)> = vec![
        (
            "detail.amplitude_m",
            Box::new(|s| s.detail.amplitude_m = -1.0),
        ),
        (
            "detail.amplitude_m",
            Box::new(|s| s.detail.amplitude_m = f64::NAN),
        ),
        ("detail.h", Box::new(|s| s.detail.h = 3.0)),
        ("detail.lacunarity", Box::new(|s| s.detail.lacunarity = 1.0)),
        ("detail.octaves", Box::new(|s| s.detail.octaves = 25)),
    ];
    for (key, mutate) in cases {
        let mut s = SceneDesc::default();
        mutate(&mut s);
        let err = s.validate().unwrap_err().to_string();
        assert!(err.contains(key), "{key}: {err}");
    }
    // Unknown and mistyped keys in the section name line and key.
    let err = SceneDesc::from_toml_str("[detail]\nenabled = true\namplitud_m = 2\n", "d.toml")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("d.toml:3:") && err.contains("detail.amplitud_m"),
        "{err}"
    );
    let err = SceneDesc::from_toml_str("[detail]\noctaves = \"many\"\n", "d.toml")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("d.toml:2:") && err.contains("detail.octaves"),
        "{err}"
    );
    // A partial section keeps the other defaults; the section round-trips.
    let s = SceneDesc::from_toml_str("[detail]\namplitude_m = 0.0\n", "d.toml").unwrap();
    assert_eq!(s.detail.amplitude_m, 0.0);
    assert_eq!(s.detail.octaves, DetailDesc::default().octaves);
    assert_eq!(
        SceneDesc::from_toml_str(&s.to_toml_string().unwrap(), "x").unwrap(),
        s
    );
}

/// The quick preview keeps a terrain's extent whatever its size, leaves a
/// small one and fewer erosion steps alone, and touches nothing else.
#[test]
fn the_quick_preview_keeps_the_world_and_only_coarsens_it() {
    let mut s = SceneDesc::default();
    s.terrain.size = 1000;
    s.terrain.cell_size_m = 12.5;
    s.erosion.thermal_steps = 3;
    let q = s.quick();
    assert_eq!(q.terrain.size, QUICK_TERRAIN_SIZE);
    approx::assert_relative_eq!(
        q.terrain.size as f32 * q.terrain.cell_size_m,
        12_500.0,
        max_relative = 1e-6
    );
    assert_eq!(q.erosion.thermal_steps, 3);
    assert_eq!(q.erosion.stream_power_steps, 5);
    assert_eq!(q.erosion.hydraulic_steps, 20);
    assert_eq!(q.clouds.voxel_m, 4.0 * s.clouds.voxel_m);
    // Everything else is the scene's own.
    let mut back = q.clone();
    back.terrain = s.terrain.clone();
    back.erosion = s.erosion.clone();
    back.clouds = s.clouds.clone();
    assert_eq!(back, s);
    // A terrain already small is left as it is.
    s.terrain.size = 128;
    assert_eq!(s.quick().terrain, s.terrain);
}
