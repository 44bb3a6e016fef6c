//! Curl noise (natura-noise's `CurlNoise`): the f32 batch by forward
//! differences through Perlin's SIMD point kernel against the f64 analytic
//! point evaluation, and against the gradient of one noise (`DNoise`, the
//! displacement the clouds' detail used before), on one million random 3-D
//! points, one thread.
//!
//! `cargo bench --bench curl`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use natura::noise::{CurlNoise, DNoise, Perlin, VectorField};
use std::hint::black_box;

const POINTS: usize = 1 << 20;

/// A fixed quasi-random point set in a 64-unit cube.
fn points() -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut s = 0x1234_5678_9abc_def0u64;
    let mut next = move || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (s >> 11) as f64 / (1u64 << 53) as f64 * 64.0
    };
    let mut p = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..POINTS {
        p.0.push(next());
        p.1.push(next());
        p.2.push(next());
    }
    p
}

/// One f64 evaluation of `f` a point, summed so none is optimised away.
fn per_point(f: &impl VectorField, x: &[f64], y: &[f64], z: &[f64]) -> f64 {
    let mut s = 0.0;
    for i in 0..x.len() {
        s += f.eval3(DVec3::new(x[i], y[i], z[i])).x;
    }
    s
}

fn curl(c: &mut Criterion) {
    let (x, y, z) = points();
    let curl = CurlNoise::new(Perlin::new(7));
    let grad = DNoise(Perlin::new(7));
    let (mut u, mut v, mut w) = (
        vec![0.0f32; POINTS],
        vec![0.0f32; POINTS],
        vec![0.0f32; POINTS],
    );
    let mut g = c.benchmark_group("curl3");
    g.sample_size(10);
    g.throughput(Throughput::Elements(POINTS as u64));
    g.bench_function("batch_f32", |b| {
        b.iter(|| {
            curl.fill_points3(&x, &y, &z, &mut u, &mut v, &mut w)
                .expect("equal slices");
            black_box(u[0])
        });
    });
    g.bench_function("analytic_f64_per_point", |b| {
        b.iter(|| black_box(per_point(&curl, &x, &y, &z)));
    });
    g.bench_function("dnoise_gradient_f64_per_point", |b| {
        b.iter(|| black_box(per_point(&grad, &x, &y, &z)));
    });
    g.finish();
}

criterion_group!(benches, curl);
criterion_main!(benches);
