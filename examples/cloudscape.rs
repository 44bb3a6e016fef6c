//! A layer-cloud sky over a plain at sunset: kilometre-scale clouds (coverage,
//! type, Worley erosion) lit by the sun and sky of `natura-atmos`, seen
//! through its aerial perspective, rendered with the fast mode (shadow
//! tables and the multiple-scattering cache). With
//! `--reference N`, also renders the null-scattering reference at N paths
//! per pixel and prints the fast mode's relative luminance error. The PNG is
//! written at half the render's size.
//!
//! ```text
//! cargo run --release --example cloudscape                 # 1920 × 1080
//! cargo run --release --example cloudscape -- --quick      # small, for CI
//! cargo run --release --example cloudscape -- --detail     # with noise detail down to the pixel (see --help)
//! cargo run --release --example cloudscape -- --sun 20 --coverage 0.6 --out renders
//! cargo run --release --example cloudscape -- --help       # every flag and its default
//! ```
//!
//! Writes `cloudscape.png` (and `cloudscape_reference.png` with
//! `--reference`) into `--out` (default: `./cloudscape/`), with a progress
//! bar per stage.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use common::{Run, outln};
use natura::core::ToneMap;
use natura::volume::detail::DetailParams;
use natura::volume::scene::{Cloudscape, CloudscapeParams};
use natura::volume::transport::{FastRenderer, ReferenceRenderer, ReferenceSettings};

/// A layer-cloud sky over a plain at sunset, rendered with the fast volume
/// mode (optionally also with the null-scattering reference, printing the
/// fast mode's error). Writes cloudscape.png at half the render's size (and
/// cloudscape_reference.png with --reference).
#[derive(Parser)]
#[command(name = "cloudscape", version)]
struct Cli {
    /// Small and fast (CI): a 192 × 108 render of coarser clouds
    #[arg(long)]
    quick: bool,
    /// Cloud seed
    #[arg(long, default_value_t = 11)]
    seed: u64,
    /// Sun elevation, degrees
    #[arg(long, default_value_t = 6.0, value_parser = common::in_range(-5.0f32, 90.0))]
    sun: f32,
    /// Sky coverage
    #[arg(long, default_value_t = 0.45, value_parser = common::in_range(0.0f32, 1.0))]
    coverage: f32,
    /// Reference paths per pixel (0: no reference render)
    #[arg(long, value_name = "N", default_value_t = 0, value_parser = common::in_range(0u32, 100_000))]
    reference: u32,
    /// Erode the baked grid with noise detail down to the footprint of the
    /// march's density samples (about 4 pixels at 1080 rows). The march then
    /// samples the density three times a step, the light once, so the octaves
    /// finer than a step do not fold into combed streaks along the eye rays;
    /// it costs about 1.3 times the plain frame's time (5.5 s against 4.3 s
    /// on 2 cores), which is why it is off by default
    #[arg(long)]
    detail: bool,
    /// Warp of the detail by curl noise for wisps, a fraction of its
    /// coarsest wavelength (0: none; 0.15 adds about a quarter to the
    /// render's time)
    #[arg(long, default_value_t = 0.0, value_parser = common::in_range(0.0f32, 1.0))]
    warp: f32,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "cloudscape")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(cloudscape)
}

fn cloudscape() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    let mut p = CloudscapeParams {
        sun_elevation_deg: cli.sun,
        ..CloudscapeParams::default()
    };
    p.layer.coverage = cli.coverage;
    if cli.detail {
        // Eroded by noise octaves down to each pixel's footprint (the
        // scene puts in its camera's eye and pixel angle).
        p.detail = Some(DetailParams {
            warp: cli.warp,
            ..DetailParams::default()
        });
    }
    if cli.quick {
        (p.width, p.height, p.cell_m) = (192, 108, 250.0);
    }
    let bar = common::Bar::new();
    let t = Instant::now();
    let cs = Cloudscape::new_with_progress(&p, cli.seed, &bar)?;
    let build = t.elapsed().as_secs_f64();
    let scene = cs.scene();
    let t = Instant::now();
    let fast = FastRenderer::new_with_progress(&scene, cs.fast_settings(), &bar)?;
    let tables = t.elapsed().as_secs_f64();
    let img = fast.render_with_progress(&cs.camera(), &bar)?;
    let secs = t.elapsed().as_secs_f64();
    let ev = natura::atmos::sky::auto_exposure(&img, 0.18).clamp(-20.0, 25.0);
    // The picture is box-filtered to half size (the render and its timing
    // are full size), which keeps the gallery's PNG small.
    let path = out.join("cloudscape.png");
    let half = if cli.quick { 1 } else { 2 };
    let picture = img
        .tone_mapped(ev, ToneMap::AcesFilmic)
        .box_downsample(half)?;
    picture.save_png(&path)?;
    outln(format_args!(
        "{}×{}: scene {build:.1} s, fast render {secs:.2} s (of which shadow tables {tables:.2} s); wrote {}",
        p.width,
        p.height,
        path.display()
    ))?;
    let spp = cli.reference;
    if spp > 0 {
        let t = Instant::now();
        let r = ReferenceRenderer::new(
            &scene,
            ReferenceSettings {
                samples_per_pixel: spp,
                ..ReferenceSettings::default()
            },
        )?;
        let reference = r.render_with_progress(&cs.camera(), &bar)?;
        let secs = t.elapsed().as_secs_f64();
        let path = out.join("cloudscape_reference.png");
        reference
            .tone_mapped(ev, ToneMap::AcesFilmic)
            .save_png(&path)?;
        let lum = natura::core::colour::luminance;
        let (mut d, mut s) = (0.0f64, 0.0f64);
        for (a, b) in img
            .pixels()
            .as_slice()
            .iter()
            .zip(reference.pixels().as_slice())
        {
            d += f64::from((lum(*a) - lum(*b)).abs());
            s += f64::from(lum(*b));
        }
        outln(format_args!(
            "reference {spp} paths/pixel: {secs:.1} s; fast-mode relative luminance error {:.3}; wrote {}",
            d / s,
            path.display()
        ))?;
    }
    Ok(())
}
