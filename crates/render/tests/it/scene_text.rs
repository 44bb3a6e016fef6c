//! Scene files as a careless or hostile user writes them: random edits of the
//! default scene's TOML give a scene or an error, never a panic, and every
//! scene that validates survives a round trip through TOML unchanged.

use natura_render::SceneDesc;
use proptest::prelude::*;

fn default_text() -> String {
    SceneDesc::default().to_toml_string().unwrap()
}

fn check(text: &str) {
    if let Ok(scene) = SceneDesc::from_toml_str(text, "edited.toml")
        && scene.validate().is_ok()
    {
        let again = scene.to_toml_string().unwrap();
        let back = SceneDesc::from_toml_str(&again, "again.toml").unwrap();
        assert_eq!(back, scene);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, .. ProptestConfig::default() })]

    /// A byte range replaced by arbitrary text (numbers, brackets, quotes).
    #[test]
    fn edited_scenes_are_read_or_refused(
        at in any::<prop::sample::Index>(),
        len in 0usize..12,
        insert in "[-0-9a-z_.=\\[\\]\"' \n]{0,12}",
    ) {
        let text = default_text();
        let a = at.index(text.len());
        let b = (a + len).min(text.len());
        if text.is_char_boundary(a) && text.is_char_boundary(b) {
            check(&format!("{}{insert}{}", &text[..a], &text[b..]));
        }
    }

    /// Any value on a line of the default scene (huge, negative, NaN, text).
    #[test]
    fn any_value_for_any_key_is_read_or_refused(
        line in any::<prop::sample::Index>(),
        value in prop_oneof![
            Just("nan".to_string()), Just("inf".to_string()), Just("-inf".to_string()),
            Just("1e308".to_string()), Just("-1".to_string()), Just("0".to_string()),
            Just("18446744073709551615".to_string()), Just("\"x\"".to_string()),
            Just("[]".to_string()), Just("{}".to_string()), any::<f64>().prop_map(|v| format!("{v:e}")),
            any::<i64>().prop_map(|v| v.to_string()),
        ],
    ) {
        let text = default_text();
        let lines: Vec<&str> = text.lines().collect();
        let k = line.index(lines.len());
        let edited: Vec<String> = lines.iter().enumerate().map(|(i, l)| {
            match (i == k, l.split_once(" = ")) {
                (true, Some((key, _))) => format!("{key} = {value}"),
                _ => (*l).to_string(),
            }
        }).collect();
        check(&edited.join("\n"));
    }
}
