//! The physical sky for a sweep of sun elevations, as fisheye domes and
//! panoramas with the ground seen through the aerial perspective
//! (natura-atmos: Hillaire 2020 LUTs with multiple scattering).
//!
//! ```text
//! cargo run --release --example sky                 # ./sky/sky_*.png
//! cargo run --release --example sky -- --quick      # small and fast
//! cargo run --release --example sky -- --spectral   # 16-band spectral evaluation
//! cargo run --release --example sky -- --help       # every flag and its default
//! ```
//!
//! Writes `sky_fisheye.png` (a sheet of fisheye domes) and
//! `sky_panorama.png` (a strip of panoramas), `_spectral` before `.png`
//! with `--spectral`, into `--out` (default: `./sky/`).

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::atmos::sky::{
    Atmosphere, AtmosphereParams, Evaluation, Ground, SkyProjection, auto_exposure,
};
use natura::core::glam::{DVec3, Vec3};
use natura::core::{Image, Progress, ToneMap};

/// The physical sky (Hillaire 2020 LUTs with multiple scattering) for a
/// sweep of sun elevations from −6° to 80°. Writes sky_fisheye.png (a
/// sheet of fisheye domes) and sky_panorama.png (a strip of panoramas with
/// the ground seen through the aerial perspective); with --spectral,
/// sky_fisheye_spectral.png and sky_panorama_spectral.png.
#[derive(Parser)]
#[command(name = "sky", version)]
struct Cli {
    /// Small and fast (CI)
    #[arg(long)]
    quick: bool,
    /// Spectral (16-band) instead of RGB evaluation
    #[arg(long)]
    spectral: bool,
    /// Fisheye diameter, pixels (the panoramas are 4 × as wide)
    /// [default: 256; 96 with --quick]
    #[arg(long, value_parser = common::in_range(8usize, 4096))]
    size: Option<usize>,
    /// Camera altitude above the ground, m
    #[arg(
        long,
        default_value_t = 300.0,
        allow_negative_numbers = true,
        value_parser = common::in_range(0.0, 1e7)
    )]
    altitude: f64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "sky")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(sky)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn sky() -> Run {
    let cli: Cli = common::parse();
    let size = cli.size.unwrap_or(if cli.quick { 96 } else { 256 });
    let out = common::out_dir(&cli.out)?;

    let mut params = AtmosphereParams::default();
    if cli.spectral {
        params.evaluation = Evaluation::Spectral;
    }
    let bar = common::Bar::new();
    let atm = Atmosphere::with_progress(params, &bar)?;
    let camera = DVec3::new(0.0, 0.0, cli.altitude);
    let elevations = [-6.0, -2.0, 0.0, 2.0, 5.0, 10.0, 25.0, 45.0, 80.0];
    let (pw, ph) = (size * 4, size);
    let cols = 3;
    let rows = elevations.len().div_ceil(cols);
    let mut fisheye = Vec::new();
    let mut panos = Vec::new();
    // The summary lines, printed once the bar is done.
    let mut lines = Vec::new();
    let ground = Ground {
        albedo: Vec3::new(0.12, 0.11, 0.09),
    };
    bar.start("sky views", elevations.len() as u64);
    for &el in &elevations {
        let sun = Atmosphere::sun_at_elevation_deg(el)?;
        let view = atm.sky_view(camera, sun)?;
        let dome = view.render(SkyProjection::Fisheye, size, size, None, true)?;
        let pano = view.render(
            SkyProjection::Panorama {
                min_elevation: (-15f64).to_radians(),
                max_elevation: 45f64.to_radians(),
            },
            pw,
            ph,
            Some(ground),
            true,
        )?;
        // Each panel gets its own camera exposure so twilight stays visible;
        // the printed stops show how much darker it really is.
        let ev = auto_exposure(&dome, 0.18).clamp(-20.0, 25.0);
        lines.push(format!(
            "sun {el:+5.1}°: exposure {ev:+.1} EV, zenith {}",
            fmt(view.radiance(natura::atmos::Dir3::UP))
        ));
        fisheye.push(dome.tone_mapped(ev, ToneMap::AcesFilmic));
        panos.push(pano.tone_mapped(ev, ToneMap::AcesFilmic));
        bar.advance(1);
    }
    bar.finish();
    for line in &lines {
        outln(line)?;
    }
    let gap = 4;
    let sheet = Image::from_fn(
        cols * (size + gap) - gap,
        rows * (size + gap) - gap,
        |x, y| {
            let (c, r) = (x / (size + gap), y / (size + gap));
            let (ix, iy) = (x % (size + gap), y % (size + gap));
            let k = r * cols + c;
            if ix >= size || iy >= size || k >= fisheye.len() {
                return Vec3::splat(0.02);
            }
            fisheye[k].get(ix, iy).unwrap_or(Vec3::ZERO)
        },
    )?;
    let strip = Image::from_fn(pw, elevations.len() * (ph + gap) - gap, |x, y| {
        let (k, iy) = (y / (ph + gap), y % (ph + gap));
        if iy >= ph {
            return Vec3::splat(0.02);
        }
        panos[k].get(x, iy).unwrap_or(Vec3::ZERO)
    })?;
    let tag = if cli.spectral { "_spectral" } else { "" };
    for (name, img) in [
        (format!("sky_fisheye{tag}.png"), sheet),
        (format!("sky_panorama{tag}.png"), strip),
    ] {
        let path = out.join(name);
        img.save_png(&path)?;
        outln(format_args!("wrote {}", path.display()))?;
    }
    Ok(())
}

fn fmt(c: Vec3) -> String {
    format!("({:.4}, {:.4}, {:.4})", c.x, c.y, c.z)
}
