//! Scene values at and past their limits: every enum-valued key survives a
//! TOML round trip in each of its variants, a scene too large for the
//! memory budget is refused by the keys that make it so before anything is
//! allocated, and every refused value is named by the key the user wrote,
//! with the value as written and its range.

use natura_core::ToneMap;
use natura_render::{
    CameraKind, Diffuse, HydraulicModel, RenderError, SceneDesc, TerrainGenerator, WaterWaves,
};
use natura_terrain::erosion::{Depressions, SedimentTransport};
use natura_terrain::erosion::{Edges, Neighbourhood};
use natura_volume::phase::CloudPhase;

fn round_trip(s: &SceneDesc) {
    let text = s.to_toml_string().unwrap();
    let back =
        SceneDesc::from_toml_str(&text, "again.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(&back, s);
}

#[test]
fn every_enum_variant_round_trips() {
    type Edit = Box<dyn Fn(&mut SceneDesc)>;
    let mut edits: Vec<Edit> = Vec::new();
    for phase in [
        CloudPhase::Isotropic,
        CloudPhase::HenyeyGreenstein(0.8),
        CloudPhase::DualHenyeyGreenstein {
            forward: 0.8,
            back: -0.3,
            weight: 0.9,
        },
        CloudPhase::Draine { g: 0.6, alpha: 0.5 },
        CloudPhase::Cloud { diameter_um: 12.0 },
    ] {
        edits.push(Box::new(move |s| s.clouds.medium.phase = phase));
    }
    for d in [Diffuse::Lambert, Diffuse::OrenNayar { sigma_deg: 7.0 }] {
        edits.push(Box::new(move |s| s.materials.diffuse = d));
    }
    for g in [
        TerrainGenerator::Ridged,
        TerrainGenerator::Hybrid,
        TerrainGenerator::RidgedHybrid,
    ] {
        edits.push(Box::new(move |s| s.terrain.generator = g));
    }
    for m in [HydraulicModel::Droplets, HydraulicModel::Pipe] {
        edits.push(Box::new(move |s| s.erosion.hydraulic_model = m));
    }
    for w in [WaterWaves::Ripples, WaterWaves::Ocean] {
        edits.push(Box::new(move |s| s.water.waves = w));
    }
    for k in [
        CameraKind::Pinhole,
        CameraKind::Cylindrical,
        CameraKind::Spherical,
    ] {
        edits.push(Box::new(move |s| s.camera.kind = k));
    }
    for t in [
        ToneMap::Clip,
        ToneMap::Reinhard,
        ToneMap::AcesFilmic,
        ToneMap::Hable,
    ] {
        edits.push(Box::new(move |s| s.render.tone_map = t));
    }
    for d in [Depressions::Keep, Depressions::Route, Depressions::Fill] {
        edits.push(Box::new(move |s| s.erosion.stream_power.depressions = d));
    }
    for t in [
        SedimentTransport::Conservative,
        SedimentTransport::SemiLagrangian,
    ] {
        edits.push(Box::new(move |s| s.erosion.pipe.transport = t));
    }
    for e in [Edges::Closed, Edges::Periodic, Edges::Open] {
        edits.push(Box::new(move |s| s.erosion.pipe.edges = e));
        edits.push(Box::new(move |s| s.erosion.thermal.edges = e));
    }
    for n in [Neighbourhood::Four, Neighbourhood::Eight] {
        edits.push(Box::new(move |s| s.erosion.thermal.neighbourhood = n));
    }
    for edit in edits {
        let mut s = SceneDesc::default();
        edit(&mut s);
        round_trip(&s);
    }
}

#[test]
fn another_phase_in_a_partial_scene_replaces_the_default() {
    let s = SceneDesc::from_toml_str(
        "[clouds.medium]\nphase = { henyey_greenstein = 0.7 }\n",
        "p.toml",
    )
    .unwrap();
    assert_eq!(s.clouds.medium.phase, CloudPhase::HenyeyGreenstein(0.7));
    s.validate().unwrap();
    // The same variant still merges: a partial variant table keeps the
    // default's other fields.
    let s = SceneDesc::from_toml_str("[clouds.medium.phase.cloud]\ndiameter_um = 8.0\n", "p.toml")
        .unwrap();
    assert_eq!(
        s.clouds.medium.phase,
        CloudPhase::Cloud { diameter_um: 8.0 }
    );
    let s = SceneDesc::from_toml_str("[materials]\ndiffuse = \"lambert\"\n", "p.toml").unwrap();
    assert_eq!(s.materials.diffuse, Diffuse::Lambert);
}

/// The error of a scene text, parsed then validated.
fn error_of(text: &str) -> RenderError {
    match SceneDesc::from_toml_str(text, "s.toml") {
        Err(e) => e,
        Ok(s) => s.validate().expect_err(text),
    }
}

/// Asserts `text` is refused as an invalid value naming `key` and each of `words`.
fn refused(text: &str, key: &str, words: &[&str]) {
    let e = error_of(text);
    let m = e.to_string();
    assert!(
        matches!(e, RenderError::Invalid { .. } | RenderError::Scene(_)),
        "{m}"
    );
    assert!(m.contains(key), "{key}: {m}");
    for w in words {
        assert!(m.contains(w), "{w}: {m}");
    }
    assert!(m.len() < 600, "{m}");
}

#[test]
fn huge_values_are_named_and_printed_short() {
    refused("[terrain]\nh = -1e300\n", "terrain.h", &["-1e300"]);
    refused("[terrain]\ngain = 1e300\n", "terrain.gain", &["1e300"]);
    refused(
        "[terrain]\noffset = -1e300\n",
        "terrain.offset",
        &["-1e300"],
    );
    refused("[water]\nlevel_m = 1e300\n", "water.level_m", &["1e300"]);
    refused(
        "[water]\nwind_azimuth_deg = 1e300\n",
        "water.wind_azimuth_deg",
        &["1e300"],
    );
    refused(
        "[sun]\nazimuth_deg = 1e300\n",
        "sun.azimuth_deg",
        &["1e300"],
    );
    refused(
        "[materials]\nsnow_line_m = 1e300\n",
        "materials.snow_line_m",
        &["1e300"],
    );
    refused(
        "[materials]\ntree_line_m = -1e39\n",
        "materials.tree_line_m",
        &["-1e39"],
    );
    refused(
        "[clouds.layer]\ncoverage = 1e300\n",
        "clouds.layer.coverage",
        &["1e300"],
    );
    refused(
        "[render]\nexposure_ev = 1e300\n",
        "render.exposure_ev",
        &["1e300"],
    );
}

/// Keys a scene does not use are still checked: a pinhole camera's
/// `hfov_deg` (a NaN kept there broke the scene's round trip through its
/// text), and a variant's parameters written as an array.
#[test]
fn unused_keys_and_arrays_for_tables_are_named() {
    refused("[camera]\nhfov_deg = nan\n", "camera.hfov_deg", &["NaN"]);
    refused("[camera]\nhfov_deg = 1e9\n", "camera.hfov_deg", &[]);
    refused(
        "[clouds.medium.phase]\ncloud = [8.0, 2.0, 3.0]\n",
        "clouds.medium.phase.cloud",
        &["table", "[8.0, 2.0, 3.0]"],
    );
    refused("[clouds]\nmedium = [0.03]\n", "clouds.medium", &["table"]);
}

#[test]
fn animation_keys_are_checked_as_written() {
    let keys = |field: &str| {
        format!(
            "[animation]\nframes = 10\n\
             [[animation.keys]]\nframe = 0\n\
             [[animation.keys]]\nframe = 2\n\
             [[animation.keys]]\nframe = 4\n\
             [[animation.keys]]\nframe = 6\n{field}\n"
        )
    };
    refused(
        &keys("position_uv = [2.0, 0.5]"),
        "animation.keys[3].position_uv[0]",
        &["= 2", "[0, 1]"],
    );
    refused(
        &keys("target_uv = [0.5, -1.0]"),
        "animation.keys[3].target_uv[1]",
        &["[0, 1]"],
    );
    refused(
        &keys("height_above_ground_m = 0.0"),
        "animation.keys[3].height_above_ground_m",
        &[],
    );
    refused(
        &keys("pitch_deg = 95.0"),
        "animation.keys[3].pitch_deg",
        &[],
    );
    refused(
        &keys("sun_elevation_deg = -10.0"),
        "animation.keys[3].sun_elevation_deg",
        &["allow_below_horizon"],
    );
    refused(
        &keys("sun_azimuth_deg = 1e300"),
        "animation.keys[3].sun_azimuth_deg",
        &["1e300"],
    );
    // A key at the camera's own target looks nowhere.
    refused(
        &keys("position_uv = [0.3, 0.75]"),
        "animation.keys[3].position_uv",
        &["target_uv"],
    );
}

#[test]
fn arrays_of_the_wrong_length_name_the_key_and_the_length() {
    refused(
        "[clouds]\nwind_m_s = [1.0, 2.0, 3.0]\n",
        "clouds.wind_m_s",
        &["2 numbers"],
    );
    refused(
        "[clouds]\nwind_m_s = [1.0]\n",
        "clouds.wind_m_s",
        &["2 numbers"],
    );
    refused(
        "[water]\nextinction_per_m = [1.0, 2.0]\n",
        "water.extinction_per_m",
        &["3 numbers"],
    );
    refused(
        "[camera]\nposition_uv = [0.1, 0.2, 0.3]\n",
        "camera.position_uv",
        &["2 numbers"],
    );
    refused(
        "clouds = { wind_m_s = [1.0, 2.0, 3.0] }\n",
        "clouds.wind_m_s",
        &["2 numbers"],
    );
    refused(
        "[[animation.keys]]\nframe = 0\nposition_uv = [0.5]\n",
        "animation.keys",
        &["2 numbers"],
    );
}

#[test]
fn a_forest_beyond_the_memory_budget_is_refused_by_its_keys() {
    let text = "[vegetation]\ndensity_per_ha = 500\nradius_m = 20000\nsteps = 200\n";
    let e = error_of(text);
    let m = e.to_string();
    assert!(matches!(e, RenderError::Invalid { .. }), "{m}");
    assert!(
        m.contains("vegetation.density_per_ha") && m.contains("vegetation.radius_m"),
        "{m}"
    );
    assert!(m.contains("memory budget"), "{m}");
}

#[test]
fn the_far_forest_layer_counts_in_the_memory_budget() {
    // A terrain that fits alone (about 3.1 GiB with the image, the clouds
    // and the forest) but not with the canopy layer's maps over all of it.
    let big = "[terrain]\nsize = 7168\n[vegetation]\nfar_field = ";
    let e = error_of(&format!("{big}true\n"));
    let m = e.to_string();
    assert!(matches!(e, RenderError::Invalid { .. }), "{m}");
    assert!(m.contains("memory budget"), "{m}");
    let s = SceneDesc::from_toml_str(&format!("{big}false\n"), "s.toml").unwrap();
    s.validate().unwrap();
}

#[test]
fn scenes_beyond_the_memory_budget_are_refused_by_their_keys() {
    for (text, keys) in [
        ("[terrain]\nsize = 16384\n", &["terrain.size"][..]),
        (
            "[render]\nwidth = 16384\nheight = 16384\n",
            &["render.width", "render.height"][..],
        ),
        (
            "[clouds]\nshadow_cell_m = 1.0\n[terrain]\nsize = 8192\ncell_size_m = 1000.0\n",
            &["clouds.shadow_cell_m"][..],
        ),
        (
            "[clouds]\nshadow_table_nodes = 1024\nvoxel_m = 2000.0\n\
             [clouds.layer]\nregion_min = [0.0, 0.0]\nregion_max = [90000.0, 90000.0]\n\
             base_m = 5000.0\ntop_m = 95000.0\n",
            &["clouds.shadow_table_nodes"][..],
        ),
    ] {
        let e = error_of(text);
        let m = e.to_string();
        assert!(matches!(e, RenderError::Invalid { .. }), "{m}");
        assert!(m.contains("memory budget"), "{m}");
        for k in keys {
            assert!(m.contains(k), "{k}: {m}");
        }
    }
    // The defaults and the shipped scenes fit easily.
    SceneDesc::default().validate().unwrap();
}

#[test]
fn an_oversized_scene_file_is_refused_before_it_is_read() {
    let dir = std::env::temp_dir().join(format!("natura-render-big-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("big.toml");
    // A sparse file far larger than any scene: refused by its size.
    let f = std::fs::File::create(&path).unwrap();
    f.set_len(1 << 30).unwrap();
    drop(f);
    let m = SceneDesc::load(&path).unwrap_err().to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(m.contains("big.toml"), "{m}");
    assert!(
        m.contains(&natura_render::scene::MAX_SCENE_FILE_BYTES.to_string()),
        "{m}"
    );
}
