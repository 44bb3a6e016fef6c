//! Steam rising from a teacup (Ebert 2001, slides "Steam rising from a
//! teacup"): the basic gas shaped radially and vertically, drifting up with
//! time. Four moments, lit from behind and the side, with Ebert's
//! shadow-table march.
//!
//! ```text
//! cargo run --release --example steam                 # 320 × 400 frames
//! cargo run --release --example steam -- --quick      # small, for CI
//! ```

mod common;

use natura::core::glam::Vec3;
use natura::core::{Image, ToneMap};
use natura::volume::gas::{Steam, SteamParams};
use natura::volume::phase::CloudPhase;
use natura::volume::render::{
    FastRenderer, FastSettings, LookAtCamera, MediumParams, Scene, Shadows, Sun,
};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let seed: u64 = args.value("--seed", 3, "noise seed");
    let out = args.out_dir("docs/gallery/volume");
    args.finish();
    let (w, h) = if quick { (64, 80) } else { (320, 400) };
    let shots: Vec<Image> = [0.0f32, 0.5, 1.0, 1.5]
        .iter()
        .map(|&time| {
            let steam = common::check(Steam::new(
                SteamParams {
                    time,
                    ..SteamParams::default()
                },
                seed,
            ));
            let medium = MediumParams {
                extinction: 60.0,
                albedo: 0.95,
                phase: CloudPhase::HenyeyGreenstein(0.5),
            };
            let scene = Scene {
                sun: Some(Sun {
                    direction: Vec3::new(-0.3, 0.8, 0.5).normalize(),
                    irradiance: Vec3::new(2.4, 2.2, 2.0),
                }),
                ..Scene::new(&steam, medium, Vec3::new(0.03, 0.03, 0.04))
            };
            let settings = FastSettings {
                step: 0.0008,
                shadows: Shadows::Table(if quick { 32 } else { 96 }),
                ..FastSettings::default()
            }
            .multiple_scattering();
            let camera = common::check(LookAtCamera::look_at(
                Vec3::new(0.0, -0.35, 0.07),
                Vec3::new(0.0, 0.0, 0.065),
                Vec3::Z,
                22f32.to_radians(),
                w as u32,
                h as u32,
            ));
            let fast = common::check(FastRenderer::new(&scene, settings));
            common::check(fast.render(&camera)).tone_mapped(0.5, ToneMap::AcesFilmic)
        })
        .collect();
    let strip = common::check(Image::from_fn(w * 4 + 12, h, |x, y| {
        let (k, r) = (x / (w + 4), x % (w + 4));
        if r >= w {
            Vec3::ONE
        } else {
            shots[k].get(r, y).unwrap_or(Vec3::ONE)
        }
    }));
    let path = out.join("steam.png");
    common::check(strip.save_png(&path));
    println!("wrote {}", path.display());
}
