//! A layer-cloud sky over a plain at sunset: kilometre-scale clouds (coverage,
//! type, Worley erosion) lit by the sun and sky of `natura-atmos`, seen
//! through its aerial perspective, rendered with the fast mode (shadow
//! tables and the octave multiple-scattering approximation). With
//! `--reference N`, also renders the null-scattering reference at N paths
//! per pixel and prints the fast mode's relative luminance error. The PNG is
//! written at half the render's size.
//!
//! ```text
//! cargo run --release --example cloudscape                 # 1920 × 1080
//! cargo run --release --example cloudscape -- --quick      # small, for CI
//! ```

mod common;

use std::time::Instant;

use natura::core::ToneMap;
use natura::volume::render::{FastRenderer, ReferenceRenderer, ReferenceSettings};
use natura::volume::scene::{Cloudscape, CloudscapeParams};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let seed: u64 = args.value("--seed", 11, "cloud seed");
    let sun: f32 = args.ranged("--sun", 6.0, -5.0..=90.0, "sun elevation (degrees)");
    let coverage: f32 = args.ranged("--coverage", 0.45, 0.0..=1.0, "sky coverage");
    let spp: u32 = args.ranged(
        "--reference",
        0,
        0..=100_000,
        "reference paths per pixel (0: none)",
    );
    let out = args.out_dir("docs/gallery/volume");
    args.finish();
    let mut p = CloudscapeParams {
        sun_elevation_deg: sun,
        ..CloudscapeParams::default()
    };
    p.layer.coverage = coverage;
    if quick {
        (p.width, p.height, p.cell_m) = (192, 108, 250.0);
    }
    let t = Instant::now();
    let cs = common::check(Cloudscape::new(&p, seed));
    let build = t.elapsed().as_secs_f64();
    let scene = cs.scene();
    let t = Instant::now();
    let fast = common::check(FastRenderer::new(&scene, cs.fast_settings()));
    let tables = t.elapsed().as_secs_f64();
    let img = common::check(fast.render(&cs.camera()));
    let secs = t.elapsed().as_secs_f64();
    let ev = natura::atmos::sky::auto_exposure(&img, 0.18).clamp(-20.0, 25.0);
    // The picture is box-filtered to half size (the render and its timing
    // are full size), which keeps the gallery's PNG small.
    let path = out.join("cloudscape.png");
    let half = if quick { 1 } else { 2 };
    let picture = common::check(
        img.tone_mapped(ev, ToneMap::AcesFilmic)
            .box_downsample(half),
    );
    common::check(picture.save_png(&path));
    println!(
        "{}×{}: scene {build:.1} s, fast render {secs:.2} s (of which shadow tables {tables:.2} s); wrote {}",
        p.width,
        p.height,
        path.display()
    );
    if spp > 0 {
        let t = Instant::now();
        let r = common::check(ReferenceRenderer::new(
            &scene,
            ReferenceSettings {
                samples_per_pixel: spp,
                ..ReferenceSettings::default()
            },
        ));
        let reference = common::check(r.render(&cs.camera()));
        let secs = t.elapsed().as_secs_f64();
        let path = out.join("cloudscape_reference.png");
        common::check(
            reference
                .tone_mapped(ev, ToneMap::AcesFilmic)
                .save_png(&path),
        );
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
        println!(
            "reference {spp} paths/pixel: {secs:.1} s; fast-mode relative luminance error {:.3}; wrote {}",
            d / s,
            path.display()
        );
    }
}
