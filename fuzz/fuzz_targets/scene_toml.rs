//! Any text as a landscape scene: a scene or an error naming the problem,
//! never a panic; a scene that validates survives a round trip through TOML.
#![no_main]

use libfuzzer_sys::fuzz_target;
use natura_render::SceneDesc;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(scene) = SceneDesc::from_toml_str(text, "fuzz.toml") {
            if scene.validate().is_ok() {
                let again = scene.to_toml_string().expect("a valid scene writes");
                let back = SceneDesc::from_toml_str(&again, "again.toml").expect("and reads back");
                assert_eq!(back, scene);
            }
        }
    }
});
