//! A rainbow over a plain: primary and secondary bows with reversed colours
//! and Alexander's dark band between them, from Musgrave's precomputed drop
//! table (natura-atmos `rainbow`) lit by the physical sky's sunlight, plus a
//! plot of the table itself.
//!
//! ```text
//! cargo run --release --example rainbow                  # ./rainbow/rainbow*.png
//! cargo run --release --example rainbow -- --quick       # small and fast
//! cargo run --release --example rainbow -- --sun 20 --rain 1e-3
//! cargo run --release --example rainbow -- --help        # every flag and its default
//! ```
//!
//! Writes `rainbow.png` (the bow) and `rainbow_table.png` (the drop table
//! as a colour strip and R, G, B curves from 30° to 60°) into `--out`
//! (default: `./rainbow/`).

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::atmos::Dir3;
use natura::atmos::rainbow::{Rainbow, RainbowParams};
use natura::atmos::sky::{Atmosphere, AtmosphereParams, Ground, SkyProjection, auto_exposure};
use natura::core::glam::{DVec3, Vec3};
use natura::core::{Image, ToneMap};

/// A rainbow over a plain, with Alexander's dark band between the primary
/// and secondary bows, from Musgrave's precomputed drop table lit by the
/// physical sky's sunlight. Writes rainbow.png (the bow) and
/// rainbow_table.png (the table as a colour strip and R, G, B curves).
#[derive(Parser)]
#[command(name = "rainbow", version)]
struct Cli {
    /// Small and fast (CI)
    #[arg(long)]
    quick: bool,
    /// Image width, pixels (the height is 9/16 of it)
    /// [default: 960; 240 with --quick]
    #[arg(long, value_parser = common::in_range(16usize, 8192))]
    width: Option<usize>,
    /// Sun elevation behind the camera, degrees (the bow sinks below the
    /// horizon above 42°)
    #[arg(
        long,
        default_value_t = 8.0,
        allow_negative_numbers = true,
        value_parser = common::in_range(0.0, 40.0)
    )]
    sun: f64,
    /// Rain extinction, 1/m (drop cross-section per volume; finite, ≥ 0)
    #[arg(long, default_value_t = 2e-4, allow_negative_numbers = true)]
    rain: f64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "rainbow")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(rainbow)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn rainbow() -> Run {
    let cli: Cli = common::parse();
    let quick = cli.quick;
    let width = cli.width.unwrap_or(if quick { 240 } else { 960 });
    let (sun_el, rain) = (cli.sun, cli.rain);
    let out = common::out_dir(&cli.out)?;
    let height = width * 9 / 16;

    let params = RainbowParams {
        rays_per_wavelength: if quick { 5_000 } else { 50_000 },
        ..RainbowParams::default()
    };
    let bow = Rainbow::new(&params)?;
    let bar = common::Bar::new();
    let atm = Atmosphere::with_progress(AtmosphereParams::default(), &bar)?;
    // The sun behind the camera (azimuth 180°), the camera looking at azimuth 0.
    let sun = Dir3::from_angles(sun_el.to_radians(), std::f64::consts::PI)?;
    let view = atm.sky_view(DVec3::new(0.0, 0.0, 2.0), sun)?;
    let projection = SkyProjection::Pinhole {
        fov_y: 62f64.to_radians(),
        yaw: 0.0,
        pitch: 18f64.to_radians(),
    };
    let ground = Ground {
        albedo: Vec3::new(0.10, 0.14, 0.07),
    };
    let camera = projection.camera(width, height)?;
    let background = view.render_camera(&camera, Some(ground), true)?;
    let e_sun = view.sun_irradiance().as_dvec3();
    // A rain curtain from 400 m to 2400 m in front of the camera.
    let (near, depth) = (400.0f32, 2000.0f32);
    let img = Image::from_fn(width, height, |x, y| {
        let bg = background.get(x, y).unwrap_or(Vec3::ZERO);
        let Some(d) = camera.direction(x, y) else {
            return bg;
        };
        let reach = view.ground_distance(d).unwrap_or(f32::INFINITY);
        let rain_depth = (reach - near).clamp(0.0, depth);
        let dir = common::check(Dir3::from_f32(d));
        common::check(bow.apply(bg.as_dvec3(), dir, sun, e_sun, rain, f64::from(rain_depth)))
            .as_vec3()
    })?;
    let ev = auto_exposure(&img, 0.18);
    let path = out.join("rainbow.png");
    img.tone_mapped(ev, ToneMap::AcesFilmic).save_png(&path)?;
    outln(format_args!("wrote {}", path.display()))?;

    // The table: colour strip and R, G, B curves from 30° to 60°.
    let (pw, strip, plot) = (if quick { 300 } else { 900 }, 40usize, 200usize);
    let t = bow.table();
    let at = |x: usize| t.lookup((30.0 + 30.0 * (x as f64 + 0.5) / pw as f64).to_radians());
    let peak = (0..pw).map(|x| at(x).max_element()).fold(0.0, f64::max);
    let chart = Image::from_fn(pw, strip + plot, |x, y| {
        let c = at(x) / peak;
        if y < strip {
            return ToneMap::AcesFilmic.apply(c.as_vec3() * 3.0);
        }
        let level = 1.0 - (y - strip) as f64 / plot as f64;
        let hit = |v: f64| (v - level).abs() < 1.2 / plot as f64;
        let mut px = Vec3::splat(0.03);
        if hit(c.x) {
            px.x = 1.0;
        }
        if hit(c.y) {
            px.y = 1.0;
        }
        if hit(c.z) {
            px.z = 1.0;
        }
        // Degree ticks every 5°.
        if (x * 30 / pw) % 5 == 0 && (x * 30) % pw < 30 {
            px += Vec3::splat(0.15);
        }
        px
    })?;
    let path = out.join("rainbow_table.png");
    chart.save_png(&path)?;
    outln(format_args!("wrote {}", path.display()))?;
    outln(format_args!(
        "table: primary+secondary carry {:.2}% of intercepted light",
        100.0 * t.total().y
    ))
}
