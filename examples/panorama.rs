//! The landscape world seen through Musgrave's cylindrical virtual screen
//! (dissertation appendix B): a panorama wider than any pinhole camera allows.
//!
//! ```text
//! cargo run --release --example panorama                 # 220° × 40° panorama
//! cargo run --release --example panorama -- --hfov 360 --spherical
//! ```

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use common::Run;
use natura::render::scene::CameraKind;
use natura::render::{SceneDesc, render_scene};

fn main() -> ExitCode {
    common::run(panorama)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn panorama() -> Run {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small terrain and image (CI)");
    let spherical = args.switch("--spherical", "equirectangular instead of cylindrical");
    let scene_file: Option<PathBuf> = args.optional("--scene", "scene description (TOML)");
    let hfov: f64 = args.ranged(
        "--hfov",
        220.0,
        1.0..=360.0,
        "horizontal field of view, degrees",
    );
    let vfov: f64 = args.ranged(
        "--vfov",
        40.0,
        1.0..=179.0,
        "vertical field of view, degrees",
    );
    let width: u32 = args.ranged(
        "--width",
        if quick { 480 } else { 2400 },
        16..=16384,
        "image width, pixels",
    );
    let spp: u32 = args.ranged(
        "--spp",
        if quick { 1 } else { 4 },
        1..=4096,
        "samples per pixel",
    );
    let out = args.out_dir("docs/gallery/render");
    args.finish();

    let mut scene = match &scene_file {
        Some(p) => SceneDesc::load(p)?,
        None => SceneDesc::default(),
    };
    scene.camera.kind = if spherical {
        CameraKind::Spherical
    } else {
        CameraKind::Cylindrical
    };
    scene.camera.hfov_deg = hfov;
    scene.camera.vfov_deg = vfov;
    scene.render.width = width;
    // Square pixels: the height follows the angular aspect ratio.
    scene.render.height = ((f64::from(width) * vfov / hfov).round() as u32).max(1);
    scene.render.spp = spp;
    if quick {
        scene.terrain.size = 256;
        scene.terrain.cell_size_m *= 8.0;
        scene.erosion.stream_power_steps = scene.erosion.stream_power_steps.min(5);
        scene.erosion.thermal_steps = scene.erosion.thermal_steps.min(5);
        scene.clouds.voxel_m *= 4.0;
        scene.clouds.shadow_cell_m *= 4.0;
    }
    scene.validate()?;
    let png = out.join("panorama.png");
    natura::core::io::check_writable(&png)?;
    let bar = common::Bar::new();
    let rendered = render_scene(&scene, &bar)?;
    rendered.display().save_png(&png)?;
    common::outln(format_args!("wrote {}", png.display()))
}
