//! natura-core throughput: grid sampling and height-field derived maps.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use natura::core::glam::Vec3;
use natura::core::{Boundary, Grid2, HeightField, Seed};
use std::hint::black_box;

fn sampling(c: &mut Criterion) {
    let n = 1024;
    let s = Seed(1);
    let g = Grid2::from_fn(n, n, |i, j| s.gaussian2(i as i64, j as i64) as f32).unwrap();
    let mut group = c.benchmark_group("core");
    group.throughput(Throughput::Elements((n * n) as u64));
    group.bench_function("bilinear_1M_clamp", |b| {
        b.iter(|| {
            let mut acc = 0.0f32;
            for j in 0..n {
                for i in 0..n {
                    acc += g.sample_bilinear(
                        i as f32 * 0.731 + 0.3,
                        j as f32 * 0.917 + 0.1,
                        Boundary::Clamp,
                    );
                }
            }
            black_box(acc)
        })
    });
    let hf = HeightField::new(g.clone(), 10.0).unwrap();
    group.bench_function("hillshade_1M", |b| {
        b.iter(|| black_box(hf.hillshade(Vec3::new(1.0, 1.0, 1.0)).unwrap()))
    });
    group.bench_function("lattice_gaussian_1M", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for j in 0..n as i64 {
                for i in 0..n as i64 {
                    acc += s.gaussian2(i, j);
                }
            }
            black_box(acc)
        })
    });
    group.finish();
}

criterion_group!(benches, sampling);
criterion_main!(benches);
