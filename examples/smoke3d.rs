//! A 3-D smoke plume rising around a sphere (Fedkiw, Stam & Jensen 2001,
//! Fig. 5 in spirit), with vorticity confinement and monotone cubic
//! advection. Writes per-frame self-shadowed renderings and mid-plane slices
//! as PNG, and the final density as raw `f32` and EXR volumes.
//!
//! ```text
//! cargo run --release --example smoke3d                 # 48 × 48 × 96 cells, 3 s
//! cargo run --release --example smoke3d -- --quick      # small, for CI
//! ```

mod common;

use natura::core::glam::Vec3;
use natura::core::{Image, Ramp};
use natura::fluid::advect::Advection;
use natura::fluid::export::{
    field_image, render_smoke_volume, slice, write_exr_volume, write_raw_volume,
};
use natura::fluid::grid::Dims;
use natura::fluid::interp::{CubicLimiter, Interpolation};
use natura::fluid::shape::{Obstacle, Shape};
use natura::fluid::smoke::{Smoke, SmokeParams, SmokeSource};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let n: usize = args.ranged(
        "--n",
        if quick { 20 } else { 48 },
        4..=256,
        "cells across (height is 2×)",
    );
    let seconds: f32 = args.ranged(
        "--seconds",
        if quick { 1.0 } else { 3.0 },
        0.01..=600.0,
        "simulated time (s)",
    );
    let frames: usize = args.ranged(
        "--frames",
        if quick { 2 } else { 8 },
        1..=1000,
        "frames written",
    );
    let epsilon: f32 = args.ranged(
        "--epsilon",
        4.0,
        0.0..=100.0,
        "confinement strength ε (1/s)",
    );
    let out = args.out_dir("docs/gallery/fluid");
    args.finish();

    let width = 1.0f32;
    let h = width / n as f32;
    let dims = common::check(Dims::new(n, n, 2 * n));
    let params = SmokeParams {
        epsilon,
        advection: Advection {
            interpolation: Interpolation::MonotoneCubic(CubicLimiter::FritschCarlson),
            ..Advection::default()
        },
        ..SmokeParams::default()
    };
    let mut smoke = common::check(Smoke::new(dims, h, params));
    let c = 0.5 * width;
    common::check(smoke.add_obstacle(Obstacle::fixed(Shape::Sphere {
        centre: Vec3::new(0.45 * width, c, 0.85 * width),
        radius: 0.15 * width,
    })));
    common::check(smoke.add_source(SmokeSource {
        shape: Shape::Sphere {
            centre: Vec3::new(c, c, 0.15 * width),
            radius: 0.08 * width,
        },
        density: 1.0,
        temperature: 330.0,
        velocity: Some(Vec3::new(0.0, 0.0, 0.3)),
    }));
    let dt = 0.5 * h / 0.6;
    let steps = (seconds / dt).ceil() as usize;
    let per_frame = (steps / frames.max(1)).max(1);
    let frame_dir = out.join("smoke3d_frames");
    common::check(std::fs::create_dir_all(&frame_dir));
    let bar = common::Bar::new();
    natura::core::Progress::start(&bar, "smoke 3d", steps as u64);
    let light = Vec3::new(-0.5, -0.3, 1.0).normalize();
    let bg = Vec3::new(0.05, 0.07, 0.12);
    let mut shots = Vec::new();
    let keep = [steps / 4, steps / 2, 3 * steps / 4, steps];
    for s in 0..steps {
        common::check(smoke.step(dt));
        natura::core::Progress::advance(&bar, 1);
        if (s + 1) % per_frame == 0 || s + 1 == steps || keep.contains(&(s + 1)) {
            let img = common::check(render_smoke_volume(
                smoke.density(),
                h,
                40.0,
                0.9,
                light,
                1,
                bg,
            ));
            let img = upscale(&img, if quick { 2 } else { 4 });
            common::check(img.save_png(frame_dir.join(format!("render_{:04}.png", s + 1))));
            let sl = common::check(slice(smoke.density(), 1, n / 2));
            common::check(
                field_image(&sl, Ramp::Magma, 0.0, 1.0)
                    .save_png(frame_dir.join(format!("slice_{:04}.png", s + 1))),
            );
            if keep.contains(&(s + 1)) {
                shots.push(img);
            }
        }
    }
    natura::core::Progress::finish(&bar);
    let vol_dir = out.join("smoke3d_volumes");
    common::check(std::fs::create_dir_all(&vol_dir));
    common::check(write_raw_volume(
        vol_dir.join("density.raw"),
        smoke.density(),
        h,
    ));
    common::check(write_exr_volume(
        vol_dir.join("density.exr"),
        smoke.density(),
        h,
    ));
    // The picture: the kept frames side by side, 4 px gaps.
    let path = out.join("smoke3d.png");
    let (w, hh) = (shots[0].width(), shots[0].height());
    let strip = common::check(Image::from_fn(
        w * shots.len() + 4 * (shots.len() - 1),
        hh,
        |x, y| {
            let (k, r) = (x / (w + 4), x % (w + 4));
            if r >= w {
                Vec3::ONE
            } else {
                shots[k].get(r, y).unwrap_or(Vec3::ONE)
            }
        },
    ));
    common::check(strip.save_png(&path));
    println!(
        "{steps} steps on {dims}; wrote {}, frames in {}, volumes in {}",
        path.display(),
        frame_dir.display(),
        vol_dir.display()
    );
}

/// Bilinear enlargement by an integer factor (the renderer draws one pixel per cell).
fn upscale(img: &Image, f: usize) -> Image {
    let (w, h) = (img.width(), img.height());
    let px = |x: usize, y: usize| img.get(x.min(w - 1), y.min(h - 1)).unwrap_or(Vec3::ZERO);
    common::check(Image::from_fn(w * f, h * f, |x, y| {
        let u = ((x as f32 + 0.5) / f as f32 - 0.5).max(0.0);
        let v = ((y as f32 + 0.5) / f as f32 - 0.5).max(0.0);
        let (i, j) = (u as usize, v as usize);
        let (a, b) = (u - i as f32, v - j as f32);
        let top = px(i, j) * (1.0 - a) + px(i + 1, j) * a;
        let bot = px(i, j + 1) * (1.0 - a) + px(i + 1, j + 1) * a;
        top * (1.0 - b) + bot * b
    }))
}
