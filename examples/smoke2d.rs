//! A 2-D smoke plume rising past an obstacle, with and without vorticity
//! confinement (Fedkiw, Stam & Jensen 2001), written as PNG frames and a
//! side-by-side comparison.
//!
//! ```text
//! cargo run --release --example smoke2d                 # 192 × 384 cells
//! cargo run --release --example smoke2d -- --quick      # small, for CI
//! cargo run --release --example smoke2d -- --nx 256 --epsilon 8 --out renders
//! cargo run --release --example smoke2d -- --help       # every flag and its default
//! ```
//!
//! Writes `smoke2d.png` (without confinement on the left, with it on the
//! right) and frames in `smoke2d_frames/` into `--out` (default:
//! `./smoke2d/`), with a progress bar per run.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::core::glam::Vec3;
use natura::core::{Grid2, Image, Progress};
use natura::fluid::advect::Advection;
use natura::fluid::export::smoke_image;
use natura::fluid::grid::Dims;
use natura::fluid::interp::{CubicLimiter, Interpolation};
use natura::fluid::shape::{Obstacle, Shape};
use natura::fluid::smoke::{Smoke, SmokeParams, SmokeSource};

/// A 2-D smoke plume rising past an obstacle, simulated twice: without
/// and with vorticity confinement. Writes smoke2d.png (the two side by
/// side) and PNG frames of both runs in smoke2d_frames/.
#[derive(Parser)]
#[command(name = "smoke2d", version)]
struct Cli {
    /// Small and fast (CI): a coarser grid, a shorter run, fewer frames
    #[arg(long)]
    quick: bool,
    /// Cells across (the height is twice that) [default: 192; 48 with
    /// --quick]
    #[arg(long, value_parser = common::in_range(8usize, 2048))]
    nx: Option<usize>,
    /// Simulated time, seconds [default: 6; 2 with --quick]
    #[arg(long, value_parser = common::in_range(0.01f32, 600.0))]
    seconds: Option<f32>,
    /// Confinement strength ε (1/s) of the second run
    #[arg(long, default_value_t = 4.0, value_parser = common::in_range(0.0f32, 100.0))]
    epsilon: f32,
    /// PNG frames per run [default: 6; 2 with --quick]
    #[arg(long, value_parser = common::in_range(1usize, 1000))]
    frames: Option<usize>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "smoke2d")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(smoke2d)
}

fn smoke2d() -> Run {
    let cli: Cli = common::parse();
    let quick = cli.quick;
    let nx = cli.nx.unwrap_or(if quick { 48 } else { 192 });
    let seconds = cli.seconds.unwrap_or(if quick { 2.0 } else { 6.0 });
    let epsilon = cli.epsilon;
    let frames = cli.frames.unwrap_or(if quick { 2 } else { 6 });
    let out = common::out_dir(&cli.out)?;

    let width_m = 1.2f32;
    let h = width_m / nx as f32;
    let dims = Dims::plane(nx, 2 * nx)?;
    let dt = 0.5 * h / 0.6; // about half a cell per step at the plume's speed
    let steps = (seconds / dt).ceil() as usize;
    let frame_dir = out.join("smoke2d_frames");
    std::fs::create_dir_all(&frame_dir)?;
    let bar = common::Bar::new();
    let mut finals = Vec::new();
    for eps in [0.0, epsilon] {
        let params = SmokeParams {
            epsilon: eps,
            advection: Advection {
                interpolation: Interpolation::MonotoneCubic(CubicLimiter::FritschCarlson),
                ..Advection::default()
            },
            ..SmokeParams::default()
        };
        let mut smoke = Smoke::new(dims, h, params)?;
        smoke.add_obstacle(Obstacle::fixed(Shape::Sphere {
            centre: Vec3::new(0.45 * width_m, 0.5 * h, 1.05 * width_m),
            radius: 0.13 * width_m,
        }))?;
        smoke.add_source(SmokeSource {
            shape: Shape::Sphere {
                centre: Vec3::new(0.5 * width_m, 0.5 * h, 0.12 * width_m),
                radius: 0.06 * width_m,
            },
            density: 1.0,
            temperature: 330.0,
            velocity: Some(Vec3::new(0.0, 0.0, 0.3)),
        })?;
        bar.start(&format!("ε = {eps}"), steps as u64);
        let mut iters = 0u64;
        for s in 0..steps {
            let rep = smoke.step(dt)?;
            iters += u64::from(rep.pressure_iterations);
            bar.advance(1);
            if frames > 0 && (s + 1) % (steps / frames).max(1) == 0 {
                let img = render(&smoke, h)?;
                let p = frame_dir.join(format!("eps{eps}_{:04}.png", s + 1));
                img.save_png(&p)?;
            }
        }
        bar.finish();
        outln(format_args!(
            "ε = {eps}: {steps} steps of {dt:.4} s, mean {:.1} CG iterations per step",
            iters as f64 / steps as f64
        ))?;
        finals.push(render(&smoke, h)?);
    }
    // Side by side: without (left) and with (right) confinement.
    let (w, hh) = (finals[0].width(), finals[0].height());
    let gap = 4;
    let pair = Image::from_grid(Grid2::from_fn(2 * w + gap, hh, |x, y| {
        if x < w {
            finals[0].get(x, y).unwrap_or(Vec3::ONE)
        } else if x < w + gap {
            Vec3::ONE
        } else {
            finals[1].get(x - w - gap, y).unwrap_or(Vec3::ONE)
        }
    })?);
    let path = out.join("smoke2d.png");
    pair.save_png(&path)?;
    outln(format_args!(
        "wrote {} and frames in {}",
        path.display(),
        frame_dir.display()
    ))
}

fn render(smoke: &Smoke, h: f32) -> natura::fluid::Result<Image> {
    smoke_image(
        smoke.density(),
        Some(smoke.cell_kinds()),
        1,
        h,
        60.0,
        Vec3::new(0.95, 0.93, 0.9),
        Vec3::new(0.05, 0.07, 0.12),
    )
}
