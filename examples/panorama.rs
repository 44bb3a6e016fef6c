//! The landscape world seen through Musgrave's cylindrical virtual screen
//! (dissertation appendix B): a panorama wider than any pinhole camera allows.
//!
//! ```text
//! cargo run --release --example panorama                 # 220° × 40° panorama
//! cargo run --release --example panorama -- --quick      # small and fast
//! cargo run --release --example panorama -- --hfov 360 --spherical
//! cargo run --release --example panorama -- --scene my.toml --spp 16 --out renders
//! cargo run --release --example panorama -- --help       # every flag and its default
//! ```
//!
//! Writes `panorama.png` (tone-mapped sRGB) into `--out` (default:
//! `./panorama/`), with a progress bar per stage.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::Run;
use natura::render::scene::CameraKind;
use natura::render::{SceneDesc, render_scene};

/// The landscape world seen through Musgrave's cylindrical virtual screen:
/// a panorama wider than any pinhole camera allows, rendered from a scene
/// description (the built-in one unless --scene). Writes panorama.png
/// (sRGB).
#[derive(Parser)]
#[command(name = "panorama", version)]
struct Cli {
    /// A preview in seconds: the scene's world coarsened (256 terrain
    /// samples over the same extent, fewer erosion steps, coarser clouds)
    /// in a 480-pixel-wide picture
    #[arg(long)]
    quick: bool,
    /// An equirectangular (spherical) screen instead of a cylindrical one
    #[arg(long)]
    spherical: bool,
    /// Scene description (TOML; landscape --print-scene shows every key)
    /// [default: the built-in scene]
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Horizontal field of view, degrees
    #[arg(
        long,
        default_value_t = 220.0,
        allow_negative_numbers = true,
        value_parser = common::in_range(1.0, 360.0)
    )]
    hfov: f64,
    /// Vertical field of view, degrees
    #[arg(
        long,
        default_value_t = 40.0,
        allow_negative_numbers = true,
        value_parser = common::in_range(1.0, 179.0)
    )]
    vfov: f64,
    /// Image width, pixels; the height follows the angular aspect ratio
    /// [default: 2400; 480 with --quick]
    #[arg(long, value_parser = common::in_range(16u32, 16_384))]
    width: Option<u32>,
    /// Samples per pixel [default: 4]
    #[arg(long, value_parser = common::in_range(1u32, 4096))]
    spp: Option<u32>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "panorama")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(panorama)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn panorama() -> Run {
    let cli: Cli = common::parse();
    let Cli {
        quick,
        spherical,
        scene: scene_file,
        hfov,
        vfov,
        width,
        spp,
        out,
    } = cli;
    let width = width.unwrap_or(if quick { 480 } else { 2400 });
    let spp = spp.unwrap_or(4);

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
        scene = scene.quick();
    }
    scene.validate()?;
    let out = common::out_dir(&out)?;
    let png = out.join("panorama.png");
    natura::core::io::check_writable(&png)?;
    let bar = common::Bar::new();
    let rendered = render_scene(&scene, &bar)?;
    rendered.display().save_png(&png)?;
    common::outln(format_args!("wrote {}", png.display()))
}
