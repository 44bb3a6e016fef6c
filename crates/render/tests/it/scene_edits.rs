//! Any one key of the documented scene (the built-in scene's text, as
//! `--print-scene` prints it) set to any value of any type — huge, tiny,
//! negative, not a number, a string, a table, an array of the wrong length —
//! or an unknown key added to any section: the scene is refused by an error
//! that names a key, or it renders a finite image at a tiny size.

use natura_core::NoProgress;
use natura_render::{DEFAULT_SCENE_TOML, RenderError, SceneDesc, render_scene};
use proptest::prelude::*;

/// The dotted paths of every key of the documented scene (array elements
/// as the array).
fn keys() -> Vec<Vec<String>> {
    fn walk(t: &toml::Table, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
        for (k, v) in t {
            path.push(k.clone());
            out.push(path.clone());
            if let toml::Value::Table(t) = v {
                walk(t, path, out);
            }
            path.pop();
        }
    }
    let table: toml::Table = toml::from_str(DEFAULT_SCENE_TOML).unwrap();
    let mut out = Vec::new();
    walk(&table, &mut Vec::new(), &mut out);
    out
}

fn value() -> impl Strategy<Value = toml::Value> {
    use toml::Value as V;
    let float = prop_oneof![
        Just(1e300),
        Just(-1e300),
        Just(1e39),
        Just(-3.5e38),
        Just(1e-300),
        Just(5e-324),
        Just(-1.0),
        Just(-1e6),
        Just(0.0),
        Just(0.5),
        Just(2.0),
        Just(1e5),
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        any::<f64>(),
    ];
    prop_oneof![
        4 => float.clone().prop_map(V::Float),
        2 => prop_oneof![Just(i64::MAX), Just(i64::MIN), Just(-1), Just(0), Just(1), Just(70_000)]
            .prop_map(V::Integer),
        1 => Just(V::String("x".into())),
        1 => Just(V::Boolean(true)),
        1 => Just(V::Table(toml::Table::new())),
        2 => prop::collection::vec(float.prop_map(V::Float), 0..5).prop_map(V::Array),
        1 => Just(V::Array(vec![V::String("spruce".into()), V::String("oak".into())])),
    ]
}

/// Sets `path` in `t` (the last part a new key if absent).
fn set(t: &mut toml::Table, path: &[String], v: toml::Value) {
    match path {
        [] => {}
        [k] => {
            t.insert(k.clone(), v);
        }
        [k, rest @ ..] => {
            if let Some(toml::Value::Table(sub)) = t.get_mut(k) {
                set(sub, rest, v);
            }
        }
    }
}

/// The scene made small and quick where its keys make it slow, keeping
/// every value already smaller.
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
    s.render.width = s.render.width.min(8);
    s.render.height = s.render.height.min(6);
    s.render.spp = 1;
}

/// Asserts `e` names a key of the scene.
fn names_a_key(e: &RenderError, edited: &str) {
    let m = e.to_string();
    let sections: Vec<String> = keys().into_iter().map(|k| k.join(".")).collect();
    assert!(
        m.contains(edited)
            || sections
                .iter()
                .any(|k| k.contains('.') && m.contains(k.as_str())),
        "{edited}: {m}"
    );
    assert!(m.len() < 1000, "{m}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, .. ProptestConfig::default() })]

    #[test]
    fn any_key_at_any_value_is_named_or_renders(
        which in any::<prop::sample::Index>(),
        unknown in prop::bool::weighted(0.1),
        v in value(),
    ) {
        let keys = keys();
        let mut path = keys[which.index(keys.len())].clone();
        if unknown {
            *path.last_mut().unwrap() = "no_such_key".into();
        }
        let edited = path.join(".");
        let mut table: toml::Table = toml::from_str(DEFAULT_SCENE_TOML).unwrap();
        set(&mut table, &path, v);
        let Ok(text) = toml::to_string(&table) else {
            return Ok(());
        };
        let scene = SceneDesc::from_toml_str(&text, "edited.toml").and_then(|mut s| {
            s.validate()?;
            tiny(&mut s);
            s.validate()?;
            Ok(s)
        });
        match scene {
            Err(e) => names_a_key(&e, &edited),
            Ok(s) => match render_scene(&s, &NoProgress) {
                Err(e) => names_a_key(&e, &edited),
                Ok(r) => {
                    for c in r.image.pixels().as_slice() {
                        prop_assert!(c.is_finite(), "{edited}: {c}");
                    }
                    prop_assert!(r.exposure_ev.is_finite());
                }
            },
        }
    }
}
