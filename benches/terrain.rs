//! natura-terrain throughput: erosion cell-steps per second on 2 threads,
//! droplets per second, the stream-power step time, a 256² / 1024² / 4096²
//! scaling table, and synthesis throughput.
//!
//! No peer crate is named for these workloads (there is no maintained Rust
//! erosion crate to measure against); the figures are compared with the
//! absolute targets in docs/performance.md.

use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use natura::core::{HeightField, NoProgress, Seed};
use natura::terrain::erosion::{
    Diffusion, DiffusionParams, DropletErosion, DropletParams, MusgraveHydraulic, MusgraveParams,
    PipeModel, PipeParams, StreamPower, StreamPowerParams, Thermal, ThermalParams,
};
use natura::terrain::synth::{SpectralParams, SubdivisionParams, spectral_synthesis, subdivide};

fn pool() -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("thread pool")
}

fn terrain(n: usize) -> HeightField {
    let p = SpectralParams {
        sigma_m: 200.0,
        ..Default::default()
    };
    spectral_synthesis(n, n, 10.0, &p, Seed(1)).expect("terrain")
}

fn erosion(c: &mut Criterion) {
    let pool = pool();
    let mut g = c.benchmark_group("erosion_2threads");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    for n in [256usize, 1024, 4096] {
        let base = terrain(n);
        let steps: u32 = if n >= 4096 {
            1
        } else if n >= 1024 {
            10
        } else {
            50
        };
        g.throughput(Throughput::Elements((n * n) as u64 * u64::from(steps)));
        let mut hf = base.clone();
        let mut m = PipeModel::new(PipeParams::default(), &hf).expect("pipe");
        g.bench_function(BenchmarkId::new("pipe_cell_steps", n), |b| {
            b.iter(|| pool.install(|| m.run(&mut hf, steps, &NoProgress).expect("run")))
        });
        let mut hf = base.clone();
        let mut t = Thermal::new(
            ThermalParams {
                talus_rate: 0.1,
                ..Default::default()
            },
            &hf,
        )
        .expect("thermal");
        g.bench_function(BenchmarkId::new("thermal_cell_steps", n), |b| {
            b.iter(|| pool.install(|| t.run(&mut hf, steps, &NoProgress).expect("run")))
        });
        if n == 1024 {
            let mut hf = base.clone();
            let mut d = Diffusion::new(DiffusionParams::default(), &hf).expect("diffusion");
            g.bench_function(BenchmarkId::new("diffusion_cell_steps", n), |b| {
                b.iter(|| pool.install(|| d.run(&mut hf, steps, &NoProgress).expect("run")))
            });
            let mut hf = base.clone();
            let mut h = MusgraveHydraulic::new(
                MusgraveParams {
                    rain_period: 5,
                    ..Default::default()
                },
                &hf,
            )
            .expect("mkm");
            g.bench_function(BenchmarkId::new("musgrave_cell_steps", n), |b| {
                b.iter(|| pool.install(|| h.run(&mut hf, steps, &NoProgress).expect("run")))
            });
        }
        let mut hf = base.clone();
        let mut sp = StreamPower::new(StreamPowerParams::default(), &hf).expect("stream power");
        g.throughput(Throughput::Elements((n * n) as u64));
        g.bench_function(BenchmarkId::new("stream_power_step_cells", n), |b| {
            b.iter(|| pool.install(|| sp.run(&mut hf, 1, &NoProgress).expect("run")))
        });
    }
    let count = 20_000u64;
    g.throughput(Throughput::Elements(count));
    for batch in [1u32, 256] {
        let mut hf = terrain(1024);
        let p = DropletParams {
            batch,
            ..Default::default()
        };
        let mut d = DropletErosion::new(p, &hf, Seed(2)).expect("droplets");
        g.bench_function(
            BenchmarkId::new("droplets_1024_lifetime30_batch", batch),
            |b| b.iter(|| pool.install(|| d.run(&mut hf, count, &NoProgress).expect("run"))),
        );
    }
    g.finish();
}

fn synthesis(c: &mut Criterion) {
    let pool = pool();
    let mut g = c.benchmark_group("synthesis_2threads");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    g.throughput(Throughput::Elements(1024 * 1024));
    g.bench_function("spectral_1024", |b| {
        b.iter(|| {
            pool.install(|| {
                spectral_synthesis(1024, 1024, 10.0, &SpectralParams::default(), Seed(3))
                    .expect("spectral")
            })
        })
    });
    g.bench_function("diamond_square_1025", |b| {
        b.iter(|| {
            pool.install(|| {
                subdivide(1024, 1024, 10.0, &SubdivisionParams::default(), Seed(3))
                    .expect("subdivide")
            })
        })
    });
    g.finish();
}

criterion_group!(benches, erosion, synthesis);
criterion_main!(benches);
