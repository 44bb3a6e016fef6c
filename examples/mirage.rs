//! An inferior mirage over a hot road: rays traced through air whose
//! refractive index follows the temperature (Gladstone–Dale), bending back up
//! above the hot layer so the sky and distant objects appear mirrored below
//! the horizon; plus a plot of the ray paths.
//!
//! ```text
//! cargo run --release --example mirage                 # ./mirage/mirage*.png
//! cargo run --release --example mirage -- --quick      # small and fast
//! cargo run --release --example mirage -- --excess 15  # a cooler road
//! cargo run --release --example mirage -- --help       # every flag and its default
//! ```
//!
//! Writes `mirage.png` (the view down the road) and `mirage_paths.png` (the
//! ray paths over the temperature profile) into `--out` (default:
//! `./mirage/`), with a progress bar for the render.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::atmos::Dir3;
use natura::atmos::mirage::{GrinTracer, PathEnd, StratifiedAir, TemperatureProfile};
use natura::atmos::sky::{Atmosphere, AtmosphereParams, auto_exposure};
use natura::core::camera::PinholeCamera;
use natura::core::glam::{DVec3, Vec3};
use natura::core::{Image, Progress, ToneMap};

/// An inferior mirage over a hot road: rays traced through air whose
/// refractive index follows the temperature (Gladstone–Dale), bending back
/// up above the hot layer so the sky and distant objects appear mirrored
/// below the horizon. Writes mirage.png (the view down the road) and
/// mirage_paths.png (the ray paths over the temperature profile).
#[derive(Parser)]
#[command(name = "mirage", version)]
struct Cli {
    /// Small and fast (CI)
    #[arg(long)]
    quick: bool,
    /// Image width, pixels (the height is 3/8 of it)
    /// [default: 800; 200 with --quick]
    #[arg(long, value_parser = common::in_range(16usize, 4096))]
    width: Option<usize>,
    /// Road surface excess temperature over the 20 °C air, K (from a
    /// surface at 43 K to one at 1293 K)
    #[arg(
        long,
        default_value_t = 40.0,
        allow_negative_numbers = true,
        value_parser = common::in_range(-250.0, 1000.0)
    )]
    excess: f64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "mirage")]
    out: PathBuf,
}

/// A vertical rectangle facing the camera at distance `x` (a post or a truck).
struct Board {
    x: f64,
    y: (f64, f64),
    z: (f64, f64),
    /// Amplitude of a wavy top edge, m (0 for a rectangle).
    wave: f64,
    colour: Vec3,
}

impl Board {
    fn contains(&self, y: f64, z: f64) -> bool {
        let top = self.z.1 + self.wave * ((y / 23.0).sin() + 0.5 * (y / 9.0).sin());
        (self.y.0..=self.y.1).contains(&y) && z >= self.z.0 && z <= top
    }
}

fn main() -> ExitCode {
    common::run(mirage)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn mirage() -> Run {
    let cli: Cli = common::parse();
    let quick = cli.quick;
    let width = cli.width.unwrap_or(if quick { 200 } else { 800 });
    let excess = cli.excess;
    let out = common::out_dir(&cli.out)?;
    let height = width * 3 / 8;

    let profile = TemperatureProfile::HotSurface {
        air_k: 293.15,
        excess_k: excess,
        decay_m: 0.3,
        lapse_k_per_m: 0.0065,
    };
    let air = StratifiedAir::new(profile, 101_325.0)?;
    let tracer = GrinTracer {
        tolerance_m: 1e-7,
        max_length_m: 3_000.0,
        top_z: 40.0,
        max_step_m: 100.0,
        ..GrinTracer::default()
    };
    let eye = DVec3::new(0.0, 0.0, 1.2);
    let bar = common::Bar::new();
    let atm = Atmosphere::with_progress(AtmosphereParams::default(), &bar)?;
    let sun = Dir3::from_angles(55f64.to_radians(), 3.5)?;
    let sky = atm.sky_view(eye, sun)?;
    let e_sun = sky.sun_irradiance() * sun.get().z as f32 + sky.sky_irradiance();

    let mut boards = Vec::new();
    for k in 0..8 {
        let x = 120.0 + 70.0 * k as f64;
        for side in [-6.0, 6.0] {
            boards.push(Board {
                x,
                y: (side - 0.15, side + 0.15),
                z: (0.0, 2.2),
                wave: 0.0,
                colour: Vec3::new(0.6, 0.6, 0.55),
            });
        }
    }
    boards.push(Board {
        x: 420.0,
        y: (-2.8, -0.4),
        z: (0.0, 3.2),
        wave: 0.0,
        colour: Vec3::new(0.55, 0.08, 0.05),
    });
    boards.push(Board {
        x: 900.0,
        y: (0.5, 3.0),
        z: (0.0, 3.5),
        wave: 0.0,
        colour: Vec3::new(0.05, 0.2, 0.5),
    });
    // A line of distant hills.
    boards.push(Board {
        x: 2500.0,
        y: (-400.0, 400.0),
        z: (0.0, 14.0),
        wave: 6.0,
        colour: Vec3::new(0.25, 0.3, 0.2),
    });

    let road = |p: DVec3| -> Vec3 {
        let lane = p.y.abs() < 0.08 && (p.x / 6.0).rem_euclid(2.0) < 1.0;
        let edge = (p.y.abs() - 3.6).abs() < 0.1;
        if lane || edge {
            Vec3::splat(0.55)
        } else if p.y.abs() < 3.7 {
            Vec3::splat(0.06)
        } else {
            Vec3::new(0.32, 0.26, 0.18)
        }
    };
    // A narrow, slightly downward view: the mirage lives within a degree of the horizon.
    let pitch = -0.15f32.to_radians();
    let look = Vec3::new(pitch.cos(), 0.0, pitch.sin());
    let camera = PinholeCamera::look_at(
        eye.as_vec3(),
        eye.as_vec3() + look,
        Vec3::Z,
        1.2f32.to_radians(),
        u32::try_from(width)?,
        u32::try_from(height)?,
    )?;
    let shade = |x: usize, y: usize| -> Vec3 {
        let ray = camera.ray_at(x as f32 + 0.5, y as f32 + 0.5);
        let d = common::check(Dir3::new(ray.dir.as_dvec3()));
        let path = common::check(tracer.trace(&air, eye, d));
        for w in path.points.windows(2) {
            for b in &boards {
                if (w[0].x - b.x) * (w[1].x - b.x) <= 0.0 && w[1].x != w[0].x {
                    let f = (b.x - w[0].x) / (w[1].x - w[0].x);
                    let p = w[0].lerp(w[1], f);
                    if b.contains(p.y, p.z) {
                        return b.colour * e_sun / std::f32::consts::PI;
                    }
                }
            }
        }
        match path.end {
            PathEnd::Ground { point, .. } => road(point) * e_sun / std::f32::consts::PI,
            PathEnd::Escaped { direction } | PathEnd::MaxLength { direction } => {
                sky.radiance(Dir3::new(direction).unwrap_or(Dir3::UP))
            }
        }
    };
    // One unit per row: every row ends at x = width − 1.
    bar.start("render", height as u64);
    let img = Image::from_fn(width, height, |x, y| {
        let c = shade(x, y);
        if x + 1 == width {
            bar.advance(1);
        }
        c
    })?;
    bar.finish();
    let ev = auto_exposure(&img, 0.18);
    let path = out.join("mirage.png");
    img.tone_mapped(ev, ToneMap::AcesFilmic).save_png(&path)?;
    outln(format_args!("wrote {}", path.display()))?;

    // Ray paths: elevation −0.5° … +0.05° from the eye, x to 1 km, z to 3 m.
    let (pw, ph) = (if quick { 300 } else { 900 }, if quick { 120 } else { 320 });
    let mut plot = vec![Vec3::splat(0.03); pw * ph];
    for y in 0..ph {
        let z = 3.0 * (1.0 - (y as f64 + 0.5) / ph as f64);
        let t = air.profile().eval(z).0 - 293.15;
        let c = (t / excess).clamp(0.0, 1.0) as f32;
        for x in 0..pw {
            plot[y * pw + x] = Vec3::new(0.03 + 0.25 * c, 0.03, 0.03);
        }
    }
    let rays = 24;
    for k in 0..rays {
        let el = (-0.5 + 0.55 * k as f64 / (rays - 1) as f64).to_radians();
        let p = GrinTracer {
            max_length_m: 1_000.0,
            ..tracer
        }
        .trace(&air, eye, Dir3::from_angles(el, 0.0)?)?;
        let colour = match p.end {
            PathEnd::Ground { .. } => Vec3::new(0.9, 0.6, 0.2),
            _ => Vec3::new(0.4, 0.7, 1.0),
        };
        for w in p.points.windows(2) {
            let n = 400;
            for s in 0..n {
                let q = w[0].lerp(w[1], s as f64 / n as f64);
                let (px, py) = (
                    (q.x / 1000.0 * pw as f64) as i64,
                    ((1.0 - q.z / 3.0) * ph as f64) as i64,
                );
                if (0..pw as i64).contains(&px) && (0..ph as i64).contains(&py) {
                    plot[py as usize * pw + px as usize] = colour;
                }
            }
        }
    }
    let chart = Image::from_fn(pw, ph, |x, y| plot[y * pw + x])?;
    let path = out.join("mirage_paths.png");
    chart.save_png(&path)?;
    outln(format_args!("wrote {}", path.display()))
}
