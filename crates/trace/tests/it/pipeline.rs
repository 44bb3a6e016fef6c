//! The pipeline from files: a height field written by natura-core as a 16-bit
//! PNG and as EXR, loaded back, traced and rendered
//! deterministically on 1 and 2 threads.

use glam::{Vec2, Vec3};
use natura_core::{HeightField, NoProgress, Seed};
use natura_trace::{
    Camera, MipmapTracer, PinholeCamera, RenderOptions, Tracer, render, render_camera,
};

fn field() -> HeightField {
    let s = Seed(21);
    HeightField::from_fn(97, 81, 12.5, |i, j| {
        80.0 * ((i as f32 * 0.11).sin() * (j as f32 * 0.07).cos())
            + 10.0 * s.gaussian2(i as i64, j as i64) as f32
            + 300.0
    })
    .unwrap()
}

#[test]
fn files_round_trip_into_the_tracer() {
    let hf = field();
    let dir = std::env::temp_dir().join(format!("natura-trace-pipeline-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (lo, hi) = hf.min_max();
    hf.save_png16(dir.join("f.png"), (lo, hi)).unwrap();
    hf.save_exr(dir.join("f.exr")).unwrap();
    let png = HeightField::load(dir.join("f.png"), None, None).unwrap();
    let exr = HeightField::load(dir.join("f.exr"), None, None).unwrap();
    let e = hf.extent();
    let cam = PinholeCamera::look_at(
        Vec3::new(0.1 * e.x, 0.1 * e.y, hi + 200.0),
        Vec3::new(0.7 * e.x, 0.8 * e.y, lo),
        Vec3::Z,
        0.8,
        64,
        36,
    )
    .unwrap();
    let (a, b, c) = (
        MipmapTracer::new(&hf).unwrap(),
        MipmapTracer::new(&png).unwrap(),
        MipmapTracer::new(&exr).unwrap(),
    );
    let step = (hi - lo) / 65535.0;
    for y in 0..36 {
        for x in 0..64 {
            let r = cam.ray(x, y, Vec2::splat(0.5));
            let (ha, hb, hc) = (
                a.trace(&r, 0.0, f32::INFINITY),
                b.trace(&r, 0.0, f32::INFINITY),
                c.trace(&r, 0.0, f32::INFINITY),
            );
            assert_eq!(ha, hc, "EXR round trip is bit exact");
            if let (Some(ha), Some(hb)) = (ha, hb) {
                // 16-bit quantisation moves the surface by at most one step
                // (more along the ray at grazing angles).
                assert!((ha.point.z - hb.point.z).abs() <= 50.0 * step + 1e-3);
            }
        }
    }
}

#[test]
fn rendering_is_identical_on_one_and_two_threads() {
    let hf = field();
    let tracer = MipmapTracer::new(&hf).unwrap();
    let e = hf.extent();
    let cam = PinholeCamera::look_at(
        Vec3::new(0.05 * e.x, 0.5 * e.y, 500.0),
        Vec3::new(e.x, 0.5 * e.y, 250.0),
        Vec3::Z,
        0.9,
        96,
        54,
    )
    .unwrap();
    let sun = Vec3::new(0.3, -0.5, 0.4).normalize();
    let opts = RenderOptions {
        samples_per_pixel: 3,
        seed: Seed(4),
        ..RenderOptions::default()
    };
    let run = |threads: usize, tile: u32| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            render_camera(
                &cam,
                &RenderOptions { tile, ..opts },
                &NoProgress,
                |r| match tracer.trace(r, 0.0, f32::INFINITY) {
                    None => Vec3::new(0.4, 0.6, 0.9),
                    Some(h) => {
                        let lit = !tracer.occluded(
                            &natura_trace::Ray::new(h.point + 0.01 * h.geometric_normal, sun),
                            0.0,
                            f32::INFINITY,
                        );
                        Vec3::splat(if lit {
                            h.smooth_normal.dot(sun).max(0.0)
                        } else {
                            0.05
                        })
                    }
                },
            )
            .unwrap()
        })
    };
    let one = run(1, 32);
    let two = run(2, 7);
    let bits = |img: &natura_core::Image| -> Vec<u32> {
        img.pixels()
            .as_slice()
            .iter()
            .flat_map(|c| c.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&one), bits(&two));
    // The generic driver too.
    let grid = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(50, 30, 8, &NoProgress, |x, y| x * 1000 + y).unwrap())
    };
    assert_eq!(grid(1), grid(2));
    assert_eq!(grid(2)[(49, 29)], 49029);
}
