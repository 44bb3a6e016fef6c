//! natura-plant ecosystems: simulation steps per second of the Deussen et
//! al. 1998 population model (default species) over eroded terrain on 2
//! threads, and the same run on 1 thread in the same process (the ratio is
//! the parallel speed-up; no peer crate simulates plant populations).
//!
//! The full target workload (≈1 M plants over 4 km², 25 steps) is timed once
//! by `cargo run --release --example forest`; see docs/performance.md.

use std::time::Duration;

#[path = "../examples/common/tiles.rs"]
mod tiles;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use natura::core::{HeightField, NoProgress};
use natura::plant::eco::{EcoParams, Ecosystem, Instancing};

fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .expect("thread pool")
}

fn terrain(n: usize) -> HeightField {
    tiles::eroded_tile(n, 2.0, 1998, &NoProgress).expect("terrain")
}

fn ecosystem(c: &mut Criterion) {
    let hf = terrain(256);
    let params = EcoParams {
        steps: 25,
        ..EcoParams::default()
    };
    let plants = {
        let mut e = Ecosystem::new(&hf, params.clone()).expect("ecosystem");
        e.run(&NoProgress).expect("run");
        e.plants().len() as u64
    };
    let mut g = c.benchmark_group("eco_25_steps_256sq_2m");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(6))
        .throughput(Throughput::Elements(plants));
    for threads in [1usize, 2] {
        let pool = pool(threads);
        g.bench_with_input(BenchmarkId::new("threads", threads), &threads, |b, _| {
            b.iter(|| {
                pool.install(|| {
                    let mut e = Ecosystem::new(&hf, params.clone()).expect("ecosystem");
                    e.run(&NoProgress).expect("run");
                    e.plants().len()
                })
            });
        });
    }
    g.finish();
    let mut e = Ecosystem::new(&hf, params).expect("ecosystem");
    e.run(&NoProgress).expect("run");
    let mut g = c.benchmark_group("eco_instancing_7_per_species");
    g.sample_size(10).throughput(Throughput::Elements(plants));
    g.bench_function("quantize_and_grow_prototypes", |b| {
        b.iter(|| Instancing::new(&e, 7).expect("instancing").instances.len());
    });
    g.finish();
}

criterion_group!(benches, ecosystem);
criterion_main!(benches);
