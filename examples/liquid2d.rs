//! A 2-D dam break (Foster & Fedkiw 2001): a column of water collapses in a
//! closed tank with a small obstacle on the floor. Writes PNG frames and a
//! strip of three frames; prints the volume drift.
//!
//! ```text
//! cargo run --release --example liquid2d                # 160 × 80 cells
//! cargo run --release --example liquid2d -- --quick     # small, for CI
//! cargo run --release --example liquid2d -- --nx 240 --paper-correction --out renders
//! cargo run --release --example liquid2d -- --help      # every flag and its default
//! ```
//!
//! Writes `liquid2d.png` (three frames, one above the other) and frames in
//! `liquid2d_frames/` into `--out` (default: `./liquid2d/`), with a
//! progress bar over the simulation.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::core::glam::Vec3;
use natura::core::{Grid2, Image, Progress};
use natura::fluid::grid::Dims;
use natura::fluid::liquid::{Liquid, LiquidParams, ParticleCorrection};
use natura::fluid::shape::{Obstacle, Shape};

/// A 2-D dam break: a column of water collapses in a closed tank with a
/// small obstacle on the floor. Writes liquid2d.png (three frames, one
/// above the other) and PNG frames in liquid2d_frames/; prints the volume
/// drift.
#[derive(Parser)]
#[command(name = "liquid2d", version)]
struct Cli {
    /// Small and fast (CI): a coarser grid, a shorter run, fewer frames
    #[arg(long)]
    quick: bool,
    /// Cells across (the height is half that) [default: 160; 48 with
    /// --quick]
    #[arg(long, value_parser = common::in_range(8usize, 2048))]
    nx: Option<usize>,
    /// Simulated time, seconds [default: 2.4; 0.6 with --quick]
    #[arg(long, value_parser = common::in_range(0.01f32, 600.0))]
    seconds: Option<f32>,
    /// PNG frames [default: 12; 3 with --quick]
    #[arg(long, value_parser = common::in_range(1usize, 1000))]
    frames: Option<usize>,
    /// Foster & Fedkiw's curvature-gated particle correction instead of the
    /// particle level set
    #[arg(long)]
    paper_correction: bool,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "liquid2d")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(liquid2d)
}

fn liquid2d() -> Run {
    let cli: Cli = common::parse();
    let quick = cli.quick;
    let nx = cli.nx.unwrap_or(if quick { 48 } else { 160 });
    let seconds = cli.seconds.unwrap_or(if quick { 0.6 } else { 2.4 });
    let frames = cli.frames.unwrap_or(if quick { 3 } else { 12 });
    let paper = cli.paper_correction;
    let out = common::out_dir(&cli.out)?;

    let width = 2.0f32;
    let h = width / nx as f32;
    let dims = Dims::plane(nx, nx / 2)?;
    let params = LiquidParams {
        correction: if paper {
            ParticleCorrection::Curvature
        } else {
            ParticleCorrection::Escaped
        },
        ..LiquidParams::default()
    };
    let mut liquid = Liquid::new(dims, h, params)?;
    liquid.fill(
        Shape::Cuboid {
            min: Vec3::new(0.0, 0.0, 0.0),
            max: Vec3::new(0.35 * width, h, 0.4 * width),
        },
        Vec3::ZERO,
    )?;
    liquid.add_obstacle(Obstacle::fixed(Shape::Cuboid {
        min: Vec3::new(0.62 * width, 0.0, 0.0),
        max: Vec3::new(0.68 * width, h, 0.08 * width),
    }))?;
    let v0 = liquid.volume();
    let frame_dt = seconds / frames as f32;
    let frame_dir = out.join("liquid2d_frames");
    std::fs::create_dir_all(&frame_dir)?;
    let bar = common::Bar::new();
    bar.start("simulation", frames as u64);
    let mut shots = Vec::new();
    let mut ns = 0u64;
    let mut volumes = Vec::new();
    for f in 0..frames {
        let rep = liquid.step(frame_dt)?;
        ns += u64::from(rep.substeps);
        volumes.push(liquid.volume());
        let img = render(&liquid, 4)?;
        img.save_png(frame_dir.join(format!("frame_{:03}.png", f + 1)))?;
        if f + 1 == frames / 4 || f + 1 == frames / 2 || f + 1 == frames {
            shots.push(img);
        }
        bar.advance(1);
    }
    bar.finish();
    let v1 = liquid.volume();
    let drift: Vec<String> = volumes
        .iter()
        .map(|v| format!("{:+.1}", 100.0 * (v - v0) / v0))
        .collect();
    outln(format_args!(
        "volume drift per frame (%): {}",
        drift.join(" ")
    ))?;
    outln(format_args!(
        "{} particles, {ns} surface sub-steps, volume {:.4} → {:.4} m² ({:+.2} %)",
        liquid.particles().len(),
        v0,
        v1,
        100.0 * (v1 - v0) / v0
    ))?;
    let (w, hh) = (shots[0].width(), shots[0].height());
    let strip = Image::from_grid(Grid2::from_fn(
        w,
        hh * shots.len() + 4 * (shots.len() - 1),
        |x, y| {
            let k = y / (hh + 4);
            let r = y % (hh + 4);
            if r >= hh {
                Vec3::ONE
            } else {
                shots[k].get(x, r).unwrap_or(Vec3::ONE)
            }
        },
    )?);
    let path = out.join("liquid2d.png");
    strip.save_png(&path)?;
    outln(format_args!(
        "wrote {} and frames in {}",
        path.display(),
        frame_dir.display()
    ))
}

/// Water (φ < 0) in blue, marker particles as light dots, objects grey; `s`
/// pixels per cell, +z up.
fn render(l: &Liquid, s: usize) -> natura::core::Result<Image> {
    let d = l.dims();
    let h = l.h();
    let (w, hh) = (d.nx * s, d.nz * s);
    let mut img = Image::from_fn(w, hh, |x, r| {
        let p = Vec3::new(
            (x as f32 + 0.5) / s as f32 * h,
            0.5 * h,
            (hh - r) as f32 / s as f32 * h,
        );
        let (i, k) = (x / s, (hh - 1 - r) / s);
        if l.cells()[(i, 0, k)] == natura::fluid::liquid::LiquidCell::Object {
            return Vec3::splat(0.35);
        }
        let phi = l.level_set().value_at(p);
        let t = (0.5 - phi / h).clamp(0.0, 1.0);
        Vec3::new(0.92, 0.94, 0.96) * (1.0 - t) + Vec3::new(0.08, 0.3, 0.65) * t
    })?;
    for p in l.particles() {
        let x = (p.x / h * s as f32) as usize;
        let r = hh.saturating_sub(1 + (p.z / h * s as f32) as usize);
        if let Some(c) = img.get(x, r) {
            img.set(x, r, c * 0.6 + Vec3::new(0.6, 0.8, 1.0) * 0.4);
        }
    }
    Ok(img)
}
