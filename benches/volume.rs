//! natura-volume benchmarks.
//!
//! ```text
//! cargo bench --bench volume -- shadows      # shadow tables vs ray-traced shadows, and the multiple-scattering cache's cost, same cumulus
//! cargo bench --bench volume -- cloudscape   # 1920×1080 fast mode, 2 threads, with and without the detail
//! cargo bench --bench volume -- density      # cumulus with turbulence, samples/s, 1 thread
//! ```

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use natura::core::glam::Vec3;
use natura::volume::Density;
use natura::volume::cloud::{CloudParams, cloud, nine_sphere_cumulus};
use natura::volume::grid::GridDensity;
use natura::volume::scene::{Cloudscape, CloudscapeParams};
use natura::volume::transport::{
    FastRenderer, FastSettings, LookAtCamera, MediumParams, Scene, Shadows, Sun,
};

fn density(c: &mut Criterion) {
    let cu = cloud(nine_sphere_cumulus(), CloudParams::cumulus(), 7).unwrap();
    let b = cu.bounds();
    let n = 100_000usize;
    let pts: Vec<Vec3> = (0..n)
        .map(|i| {
            let u = Vec3::new(
                (i % 47) as f32 / 47.0,
                (i % 53) as f32 / 53.0,
                (i % 59) as f32 / 59.0,
            );
            b.min + (b.max - b.min) * u
        })
        .collect();
    let mut g = c.benchmark_group("density");
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("cumulus_turbulence_1thread", |bch| {
        bch.iter(|| pts.iter().map(|&p| cu.density(p)).sum::<f32>())
    });
    // The same points as struct of arrays, in batches of 16 (the fast
    // march's batch) and of 256.
    let (x, y, z): (Vec<f32>, Vec<f32>, Vec<f32>) = (
        pts.iter().map(|p| p.x).collect(),
        pts.iter().map(|p| p.y).collect(),
        pts.iter().map(|p| p.z).collect(),
    );
    let mut out = vec![0.0f32; n];
    for batch in [16usize, 256] {
        g.bench_function(format!("cumulus_turbulence_batch{batch}_1thread"), |bch| {
            bch.iter(|| {
                for (k, o) in out.chunks_mut(batch).enumerate() {
                    let r = k * batch..k * batch + o.len();
                    cu.density_batch(&x[r.clone()], &y[r.clone()], &z[r], o)
                        .unwrap();
                }
                out.iter().sum::<f32>()
            })
        });
    }
    g.finish();
}

fn shadows(c: &mut Criterion) {
    let cu = cloud(nine_sphere_cumulus(), CloudParams::cumulus(), 7).unwrap();
    let grid = GridDensity::bake(&cu, 0.1).unwrap();
    let scene = Scene {
        sun: Some(Sun {
            direction: Vec3::new(-0.5, -0.6, 0.62).normalize(),
            irradiance: Vec3::splat(3.0),
        }),
        ..Scene::new(
            &grid,
            MediumParams {
                extinction: 4.0,
                ..MediumParams::default()
            },
            Vec3::new(0.2, 0.3, 0.5),
        )
    };
    let b = grid.bounds();
    let centre = (b.min + b.max) * 0.5;
    let camera = LookAtCamera::look_at(
        centre + Vec3::new(0.0, -24.0, 2.0),
        centre,
        Vec3::Z,
        40f32.to_radians(),
        240,
        160,
    )
    .unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let mut g = c.benchmark_group("shadows");
    g.sample_size(10);
    g.throughput(Throughput::Elements(
        u64::from(camera.resolution().x) * u64::from(camera.resolution().y),
    ));
    // Same eye step; the table's nodes are 64 along the longest axis (its
    // march uses one node spacing per step), the shadow rays step 0.1 m.
    let table = FastSettings {
        step: 0.1,
        shadows: Shadows::Table(64),
        ..FastSettings::default()
    };
    let rays = FastSettings {
        shadows: Shadows::Rays(0.1),
        ..table
    };
    g.bench_function("cumulus_table_build", |bch| {
        bch.iter(|| pool.install(|| FastRenderer::new(&scene, table).unwrap()))
    });
    let built = pool.install(|| FastRenderer::new(&scene, table).unwrap());
    g.bench_function("cumulus_render_with_table", |bch| {
        bch.iter(|| pool.install(|| built.render(&camera).unwrap()))
    });
    // What multiple scattering costs: the default cache's build (with the
    // table's), and the march reading it against single scattering alone,
    // with the same table.
    let cached = table.multiple_scattering();
    g.bench_function("cumulus_table_and_cache_build", |bch| {
        bch.iter(|| pool.install(|| FastRenderer::new(&scene, cached).unwrap()))
    });
    let built_cached = pool.install(|| FastRenderer::new(&scene, cached).unwrap());
    g.bench_function("cumulus_render_with_table_and_cache", |bch| {
        bch.iter(|| pool.install(|| built_cached.render(&camera).unwrap()))
    });
    g.bench_function("cumulus_render_with_shadow_rays", |bch| {
        bch.iter(|| {
            pool.install(|| {
                FastRenderer::new(&scene, rays)
                    .unwrap()
                    .render(&camera)
                    .unwrap()
            })
        })
    });
    g.finish();
}

fn cloudscape(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let mut g = c.benchmark_group("cloudscape");
    g.sample_size(10);
    // The plain baked grid, the grid eroded by the detail (three density
    // samples a step: `cloudscape --detail`), and that detail stirred.
    for (name, detail) in [
        ("fast_1920x1080_2threads", None),
        (
            "fast_detail_1920x1080_2threads",
            Some(natura::volume::detail::DetailParams {
                warp: 0.0,
                ..Default::default()
            }),
        ),
        // The detail stirred by curl noise for wisps (`--detail --warp 0.15`).
        (
            "fast_detail_curl_1920x1080_2threads",
            Some(natura::volume::detail::DetailParams {
                warp: 0.15,
                ..Default::default()
            }),
        ),
    ] {
        let cs = Cloudscape::new(
            &CloudscapeParams {
                detail,
                ..CloudscapeParams::default()
            },
            11,
        )
        .unwrap();
        let scene = cs.scene();
        let camera = cs.camera();
        g.throughput(Throughput::Elements(
            u64::from(camera.resolution().x) * u64::from(camera.resolution().y),
        ));
        g.bench_function(name, |bch| {
            bch.iter(|| {
                pool.install(|| {
                    FastRenderer::new(&scene, cs.fast_settings())
                        .unwrap()
                        .render(&camera)
                        .unwrap()
                })
            })
        });
    }
    g.finish();
}

criterion_group!(benches, density, shadows, cloudscape);
criterion_main!(benches);
