//! natura-atmos throughput: sky radiance by ray marching (Nishita 1993) versus
//! the Hillaire 2020 LUTs, the one-time and per-frame precomputation, a
//! 1920×1080 sky with aerial perspective on 2 threads, the closed-form
//! optical depths, the rainbow table and mirage ray tracing.
//!
//! No peer crate implements these models, so the figures that matter are the
//! in-run ratios (LUT vs ray-marched) and the absolute frame time.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use natura::atmos::Dir3;
use natura::atmos::medium::{ExponentialMist, RadialAtmosphere};
use natura::atmos::mirage::{GrinTracer, StratifiedAir, TemperatureProfile};
use natura::atmos::rainbow::{RainbowParams, RainbowTable};
use natura::atmos::sky::{
    ApSample, Atmosphere, AtmosphereParams, Evaluation, Ground, MarchSettings, SkyProjection,
};
use natura::core::glam::{DVec3, Vec3};

fn directions(n: usize) -> Vec<Dir3> {
    (0..n)
        .map(|i| {
            let el = 0.02 + 1.5 * ((i * 37) % n) as f64 / n as f64;
            let az = std::f64::consts::TAU * (i as f64 * 0.618_034).fract();
            Dir3::from_angles(el, az).unwrap()
        })
        .collect()
}

fn sky(c: &mut Criterion) {
    let atm = Atmosphere::new(AtmosphereParams::default()).unwrap();
    let camera = DVec3::new(0.0, 0.0, 300.0);
    let sun = Dir3::from_angles(0.2, 0.5).unwrap();
    let view = atm.sky_view(camera, sun).unwrap();
    let mut g = c.benchmark_group("atmos_sky_radiance");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(3))
        .warm_up_time(Duration::from_secs(1));
    let dirs = directions(256);
    g.throughput(Throughput::Elements(dirs.len() as u64));
    let settings = MarchSettings {
        view_steps: 32,
        light_steps: 16,
    };
    g.bench_function("ray_marched_nishita_32x16", |b| {
        b.iter(|| {
            let mut acc = DVec3::ZERO;
            for &d in &dirs {
                acc += atm.sky_radiance_marched(camera, d, sun, settings).unwrap();
            }
            black_box(acc)
        })
    });
    let lut_sun = MarchSettings {
        view_steps: 32,
        light_steps: 0,
    };
    g.bench_function("ray_marched_32_lut_sun", |b| {
        b.iter(|| {
            let mut acc = DVec3::ZERO;
            for &d in &dirs {
                acc += atm.sky_radiance_marched(camera, d, sun, lut_sun).unwrap();
            }
            black_box(acc)
        })
    });
    g.bench_function("lut_sky_view", |b| {
        b.iter(|| {
            let mut acc = Vec3::ZERO;
            for &d in &dirs {
                acc += view.radiance(d);
            }
            black_box(acc)
        })
    });
    let dirs_f: Vec<Vec3> = dirs.iter().map(|d| d.as_vec3()).collect();
    g.bench_function("lut_sky_view_f32", |b| {
        b.iter(|| {
            let mut acc = Vec3::ZERO;
            for &d in &dirs_f {
                acc += view.radiance_f32(d);
            }
            black_box(acc)
        })
    });
    let mut out = vec![Vec3::ZERO; dirs_f.len()];
    g.bench_function("lut_sky_view_batch", |b| {
        b.iter(|| {
            view.radiance_batch(&dirs_f, &mut out).unwrap();
            black_box(out[17])
        })
    });
    g.bench_function("lut_aerial_perspective_f32", |b| {
        b.iter(|| {
            let mut acc = Vec3::ZERO;
            for (i, &d) in dirs_f.iter().enumerate() {
                acc += view.aerial_perspective_f32(d, 250.0 * i as f32).in_scatter;
            }
            black_box(acc)
        })
    });
    let dist: Vec<f32> = (0..dirs_f.len()).map(|i| 250.0 * i as f32).collect();
    let mut ap = vec![ApSample::NONE; dirs_f.len()];
    g.bench_function("lut_aerial_perspective_batch", |b| {
        b.iter(|| {
            view.aerial_perspective_batch(&dirs_f, &dist, &mut ap)
                .unwrap();
            black_box(ap[17])
        })
    });
    g.finish();

    let mut g = c.benchmark_group("atmos_precompute");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(4))
        .warm_up_time(Duration::from_secs(1));
    g.bench_function("transmittance_and_multiscattering_luts_rgb", |b| {
        b.iter(|| black_box(Atmosphere::new(AtmosphereParams::default()).unwrap()))
    });
    let spectral = AtmosphereParams {
        evaluation: Evaluation::Spectral,
        ..AtmosphereParams::default()
    };
    g.bench_function("transmittance_and_multiscattering_luts_spectral16", |b| {
        b.iter(|| black_box(Atmosphere::new(spectral).unwrap()))
    });
    g.bench_function("per_frame_sky_view_and_aerial_volume_rgb", |b| {
        b.iter(|| black_box(atm.sky_view(camera, sun).unwrap()))
    });
    g.finish();

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let mut g = c.benchmark_group("atmos_image");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(4))
        .warm_up_time(Duration::from_secs(1));
    g.throughput(Throughput::Elements(1920 * 1080));
    let projection = SkyProjection::Pinhole {
        fov_y: 0.9,
        yaw: 1.0,
        pitch: 0.05,
    };
    let ground = Ground {
        albedo: Vec3::new(0.15, 0.13, 0.1),
    };
    let pool1 = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    g.bench_function("sky_1920x1080_aerial_perspective_1_thread", |b| {
        b.iter(|| {
            pool1.install(|| {
                black_box(
                    view.render(projection, 1920, 1080, Some(ground), true)
                        .unwrap(),
                )
            })
        })
    });
    g.bench_function("sky_1920x1080_aerial_perspective_2_threads", |b| {
        b.iter(|| {
            pool.install(|| {
                black_box(
                    view.render(projection, 1920, 1080, Some(ground), true)
                        .unwrap(),
                )
            })
        })
    });
    g.finish();
}

fn media(c: &mut Criterion) {
    let mut g = c.benchmark_group("atmos_media");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_millis(500));
    let n = 10_000;
    g.throughput(Throughput::Elements(n as u64));
    let mist = ExponentialMist::new(DVec3::splat(1e-4), DVec3::ONE, 0.0, 1000.0).unwrap();
    let planet = RadialAtmosphere::new(
        DVec3::ONE,
        DVec3::ONE,
        DVec3::new(0.0, 0.0, -6.371e6),
        6.371e6,
        8000.0,
    )
    .unwrap();
    let pts: Vec<(DVec3, DVec3)> = (0..n)
        .map(|i| {
            let f = i as f64 / n as f64;
            (
                DVec3::new(0.0, 0.0, 300.0),
                DVec3::new(50_000.0 * f, 20_000.0 * (1.0 - f), 3000.0 * f),
            )
        })
        .collect();
    g.bench_function("exponential_mist_column", |b| {
        b.iter(|| pts.iter().map(|(a, q)| mist.column(*a, *q)).sum::<f64>())
    });
    g.bench_function("radial_erfcx_column", |b| {
        b.iter(|| pts.iter().map(|(a, q)| planet.column(*a, *q)).sum::<f64>())
    });
    g.finish();

    let mut g = c.benchmark_group("atmos_rainbow_mirage");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(3))
        .warm_up_time(Duration::from_millis(500));
    let p = RainbowParams::default();
    g.throughput(Throughput::Elements(
        (p.rays_per_wavelength * p.wavelengths.len() * p.orders.len()) as u64,
    ));
    g.bench_function("rainbow_table_13x50000x2", |b| {
        b.iter(|| black_box(RainbowTable::simulate(&p).unwrap()))
    });
    let air = StratifiedAir::new(TemperatureProfile::hot_road(), 101_325.0).unwrap();
    let tracer = GrinTracer {
        tolerance_m: 1e-7,
        max_length_m: 2000.0,
        top_z: 40.0,
        max_step_m: 100.0,
        ..GrinTracer::default()
    };
    g.throughput(Throughput::Elements(100));
    g.bench_function("grin_ray_2km_hot_road", |b| {
        b.iter(|| {
            let mut s = 0;
            for k in 0..100 {
                let d = Dir3::from_angles((-0.6 + 0.006 * k as f64).to_radians(), 0.0).unwrap();
                s += tracer
                    .trace(&air, DVec3::new(0.0, 0.0, 1.2), d)
                    .unwrap()
                    .steps;
            }
            black_box(s)
        })
    });
    g.finish();
}

criterion_group!(benches, sky, media);
criterion_main!(benches);
