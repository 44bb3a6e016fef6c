//! natura-texture throughput:
//!
//! * `texture_points/<name>`: each solid texture's `sample` at 4096 random
//!   points with a 10⁻³ footprint, 1 thread (points/s);
//! * `texture_terran_orbit/{batch,points}_{1,2}t`: the terran texture on a
//!   sphere seen from orbit at 1920×1080, one sample per pixel with every
//!   octave its footprint shows, through the SIMD batch path and the point
//!   path (pixels/s);
//! * `texture_planet/gaea_orbit_1080p_2t`: the `planet` example's render —
//!   displaced Earth-sized planet, atmosphere with umbra, clouds with
//!   shadows — at 1920×1080, 1 sample per pixel, 2 threads (target ≤ 10 s);
//! * `texture_git_filter/320x180_x4_2t`: the GIT image filter repainting a
//!   320×180 picture at four times its size, 2 threads (output pixels/s);
//! * `texture_cube/export_6x1024_2t`: the cube-sphere export of that planet,
//!   six 1024² faces of height and colour sampled and written as EXR,
//!   2 threads (target ≤ 10 s).
//!
//! ```text
//! cargo bench --bench texture -- texture_terran_orbit
//! cargo bench --bench texture -- texture_planet
//! cargo bench --bench texture -- texture_cube
//! cargo bench --bench texture -- texture_git_filter
//! ```

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use natura::core::NoProgress;
use natura::core::glam::DVec3;
use natura::core::simd::Simd;
use natura::texture::earth::{SphereView, Terran, TerranParams, TerranSphere};
use natura::texture::planet::{Planet, PlanetParams, SurfaceParams, TraceSettings, direction};
use natura::texture::{Footprint, SolidTexture};

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn textures() -> Vec<(&'static str, Box<dyn SolidTexture>)> {
    use natura::texture::air::*;
    use natura::texture::earth::*;
    use natura::texture::fire::*;
    use natura::texture::giants::*;
    use natura::texture::multicolor::*;
    use natura::texture::water::*;
    vec![
        (
            "puffy",
            Box::new(PuffyClouds::new(PuffyCloudsParams::default()).unwrap()),
        ),
        (
            "planet_clouds",
            Box::new(PlanetClouds::new(PlanetCloudsParams::default()).unwrap()),
        ),
        (
            "cyclone",
            Box::new(Cyclone::new(CycloneParams::default()).unwrap()),
        ),
        (
            "venus",
            Box::new(Venus::new(VenusParams::default()).unwrap()),
        ),
        (
            "flame",
            Box::new(Flame::new(FlameParams::default()).unwrap()),
        ),
        (
            "ripples",
            Box::new(Ripples::new(RipplesParams::default()).unwrap()),
        ),
        (
            "windywave",
            Box::new(WindyWave::new(WindyWaveParams::default()).unwrap()),
        ),
        (
            "strata",
            Box::new(Strata::new(StrataParams::default()).unwrap()),
        ),
        (
            "terran",
            Box::new(Terran::new(TerranParams::default()).unwrap()),
        ),
        ("gaea", Box::new(Terran::new(TerranParams::gaea()).unwrap())),
        ("luna", Box::new(Luna::new(LunaParams::default()).unwrap())),
        (
            "gas_giant",
            Box::new(GasGiant::new(GasGiantParams::default()).unwrap()),
        ),
        (
            "rings",
            Box::new(Rings::new(RingsParams::default()).unwrap()),
        ),
        (
            "multicolor",
            Box::new(Multicolor::new(MulticolorParams::default()).unwrap()),
        ),
        (
            "git",
            Box::new(natura::texture::git::Git::new(Default::default()).unwrap()),
        ),
    ]
}

fn points(c: &mut Criterion) {
    let mut group = c.benchmark_group("texture_points");
    let pts: Vec<DVec3> = (0..4096)
        .map(|i| {
            let a = f64::from(i) * 0.618_033_988_7;
            DVec3::new(
                a.sin() * 1.3,
                (a * 1.7).cos() * 0.9,
                (f64::from(i) * 0.001) - 1.7,
            )
        })
        .collect();
    let fp = Footprint::new(1e-3).unwrap();
    group.throughput(Throughput::Elements(pts.len() as u64));
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(3));
    group.warm_up_time(Duration::from_secs(1));
    for (name, t) in textures() {
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for &p in &pts {
                    acc += t.sample(p, fp).colour.x;
                }
                black_box(acc)
            })
        });
    }
    group.finish();
}

fn terran_orbit(c: &mut Criterion) {
    let (w, h) = (1920u32, 1080u32);
    let terran = Terran::new(TerranParams::default()).unwrap();
    let view = SphereView::orbit(2.6, 0.35, 0.3, 0.75, w, h, DVec3::new(1.0, 0.6, 0.5)).unwrap();
    let r = TerranSphere::new(&terran);
    let mut group = c.benchmark_group("texture_terran_orbit");
    group.throughput(Throughput::Elements(u64::from(w) * u64::from(h)));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(20));
    group.warm_up_time(Duration::from_secs(2));
    for threads in [1usize, 2] {
        let p = pool(threads);
        group.bench_function(BenchmarkId::new("batch", format!("{threads}t")), |b| {
            p.install(|| {
                b.iter(|| {
                    black_box(
                        r.render_batch_with(Simd::best(), &view, &NoProgress)
                            .unwrap(),
                    )
                })
            })
        });
        group.bench_function(BenchmarkId::new("points", format!("{threads}t")), |b| {
            p.install(|| b.iter(|| black_box(r.render_points(&view, &NoProgress).unwrap())))
        });
    }
    group.finish();
}

/// The `planet` example's default orbit view.
fn gaea() -> Planet {
    let mut params = PlanetParams::gaea();
    if let SurfaceParams::Terrain(t) = &mut params.surface {
        t.terran.seed = 3;
    }
    if let Some(c) = &mut params.clouds {
        c.clouds.seed = 3;
    }
    params.light.sun = direction(0.2, 0.25 + 1.3);
    Planet::new(params).unwrap()
}

fn planet(c: &mut Criterion) {
    let planet = gaea();
    let view = planet
        .orbit_view(1.55e7, 0.35, 0.25, 0.62, 1920, 1080)
        .unwrap();
    // One ray a pixel, as this row has always measured.
    let settings = TraceSettings {
        supersample: 1,
        ..TraceSettings::default()
    };
    let p = pool(2);
    let mut group = c.benchmark_group("texture_planet");
    group.throughput(Throughput::Elements(1920 * 1080));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(40));
    group.warm_up_time(Duration::from_secs(3));
    group.bench_function("gaea_orbit_1080p_2t", |b| {
        p.install(|| b.iter(|| black_box(planet.render(&view, &settings, &NoProgress).unwrap())))
    });
    group.finish();
}

fn git_filter(c: &mut Criterion) {
    use natura::core::Image;
    use natura::core::glam::Vec3;
    use natura::texture::git::{GitFilterParams, git_filter};
    let picture = Image::from_fn(320, 180, |x, y| {
        let (u, v) = (x as f32 / 320.0, y as f32 / 180.0);
        Vec3::new(u, 0.5 + 0.4 * (u * 17.0).sin() * v, v * v)
    })
    .unwrap();
    let params = GitFilterParams::default();
    let p = pool(2);
    let mut group = c.benchmark_group("texture_git_filter");
    group.throughput(Throughput::Elements(320 * 180 * 16));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    group.bench_function("320x180_x4_2t", |b| {
        p.install(|| b.iter(|| black_box(git_filter(&picture, &params, &NoProgress).unwrap())))
    });
    group.finish();
}

fn cube(c: &mut Criterion) {
    let planet = gaea();
    let dir = std::env::temp_dir().join(format!("natura-bench-cube-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let p = pool(2);
    let mut group = c.benchmark_group("texture_cube");
    group.throughput(Throughput::Elements(6 * 1024 * 1024));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(40));
    group.warm_up_time(Duration::from_secs(3));
    group.bench_function("export_6x1024_2t", |b| {
        p.install(|| {
            b.iter(|| {
                let map = planet.cube_map(1024, &NoProgress).unwrap();
                black_box(map.write_exr(&dir, "bench").unwrap())
            })
        })
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, points, terran_orbit, planet, git_filter, cube);
criterion_main!(benches);
