//! A 2-D smoke plume rising past an obstacle, with and without vorticity
//! confinement (Fedkiw, Stam & Jensen 2001), written as PNG frames and a
//! side-by-side comparison.
//!
//! ```text
//! cargo run --release --example smoke2d                 # 192 × 384 cells
//! cargo run --release --example smoke2d -- --quick      # small, for CI
//! ```

mod common;

use natura::core::glam::Vec3;
use natura::core::{Grid2, Image};
use natura::fluid::advect::Advection;
use natura::fluid::export::smoke_image;
use natura::fluid::grid::Dims;
use natura::fluid::interp::{CubicLimiter, Interpolation};
use natura::fluid::shape::{Obstacle, Shape};
use natura::fluid::smoke::{Smoke, SmokeParams, SmokeSource};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let nx: usize = args.ranged(
        "--nx",
        if quick { 48 } else { 192 },
        8..=2048,
        "cells across (height is 2×)",
    );
    let seconds: f32 = args.ranged(
        "--seconds",
        if quick { 2.0 } else { 6.0 },
        0.01..=600.0,
        "simulated time (s)",
    );
    let epsilon: f32 = args.ranged(
        "--epsilon",
        4.0,
        0.0..=100.0,
        "confinement strength ε (1/s) of the second run",
    );
    let frames: usize = args.ranged(
        "--frames",
        if quick { 2 } else { 6 },
        1..=1000,
        "PNG frames per run",
    );
    let out = args.out_dir("docs/gallery/fluid");
    args.finish();

    let width_m = 1.2f32;
    let h = width_m / nx as f32;
    let dims = common::check(Dims::plane(nx, 2 * nx));
    let dt = 0.5 * h / 0.6; // about half a cell per step at the plume's speed
    let steps = (seconds / dt).ceil() as usize;
    let frame_dir = out.join("smoke2d_frames");
    common::check(std::fs::create_dir_all(&frame_dir));
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
        let mut smoke = common::check(Smoke::new(dims, h, params));
        common::check(smoke.add_obstacle(Obstacle::fixed(Shape::Sphere {
            centre: Vec3::new(0.45 * width_m, 0.5 * h, 1.05 * width_m),
            radius: 0.13 * width_m,
        })));
        common::check(smoke.add_source(SmokeSource {
            shape: Shape::Sphere {
                centre: Vec3::new(0.5 * width_m, 0.5 * h, 0.12 * width_m),
                radius: 0.06 * width_m,
            },
            density: 1.0,
            temperature: 330.0,
            velocity: Some(Vec3::new(0.0, 0.0, 0.3)),
        }));
        natura::core::Progress::start(&bar, &format!("ε = {eps}"), steps as u64);
        let mut iters = 0u64;
        for s in 0..steps {
            let rep = common::check(smoke.step(dt));
            iters += u64::from(rep.pressure_iterations);
            natura::core::Progress::advance(&bar, 1);
            if frames > 0 && (s + 1) % (steps / frames).max(1) == 0 {
                let img = render(&smoke, h);
                let p = frame_dir.join(format!("eps{eps}_{:04}.png", s + 1));
                common::check(img.save_png(&p));
            }
        }
        natura::core::Progress::finish(&bar);
        println!(
            "ε = {eps}: {steps} steps of {dt:.4} s, mean {:.1} CG iterations per step",
            iters as f64 / steps as f64
        );
        finals.push(render(&smoke, h));
    }
    // Side by side: without (left) and with (right) confinement.
    let (w, hh) = (finals[0].width(), finals[0].height());
    let gap = 4;
    let pair = Image::from_grid(common::check(Grid2::from_fn(2 * w + gap, hh, |x, y| {
        if x < w {
            finals[0].get(x, y).unwrap_or(Vec3::ONE)
        } else if x < w + gap {
            Vec3::ONE
        } else {
            finals[1].get(x - w - gap, y).unwrap_or(Vec3::ONE)
        }
    })));
    let path = out.join("smoke2d.png");
    common::check(pair.save_png(&path));
    println!(
        "wrote {} and frames in {}",
        path.display(),
        frame_dir.display()
    );
}

fn render(smoke: &Smoke, h: f32) -> Image {
    common::check(smoke_image(
        smoke.density(),
        Some(smoke.cell_kinds()),
        1,
        h,
        60.0,
        Vec3::new(0.95, 0.93, 0.9),
        Vec3::new(0.05, 0.07, 0.12),
    ))
}
