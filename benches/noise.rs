//! natura-noise throughput against noise-rs, fastnoise-lite and simdnoise,
//! measured in the same run on the same workloads (single thread unless noted):
//!
//! * W1 2-D Perlin, 1 octave, frequency 0.01 per cell, 1024² grid
//! * W2 2-D simplex, 1 octave, 1024² grid
//! * W3 2-D fBm, 8 octaves of gradient noise (λ = 2, gain ½), 1024² grid; also on 2 threads
//! * W4 3-D Perlin on a 128³ grid (frequency 0.05 per cell)
//! * W5 2-D Worley F1 (Euclidean), 1024² grid
//!
//! Throughput is reported in points per second (`Throughput::Elements`).
//! Besides criterion's wall-clock figures, each single-thread contender's rate
//! per second of *thread CPU time* is printed (`[noise] cpu ...`), which stays
//! meaningful when the machine is shared (a loaded machine deschedules the
//! thread, stretching wall-clock time but not CPU time).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fastnoise_lite::{
    CellularDistanceFunction, CellularReturnType, FastNoiseLite, FractalType, NoiseType,
};
use natura::noise::{
    Fbm, Field, GainConvention, Lattice2, Lattice3, Perlin, Simplex, Spectral, Worley, WorleyParams,
};
use noise::{MultiFractal, NoiseFn};
use rayon::prelude::*;
use simdnoise::NoiseBuilder;
use std::hint::black_box;
use std::time::Duration;

const N: usize = 1024;
const FREQ: f64 = 0.01;

fn lattice2() -> Lattice2 {
    Lattice2::new(glam::DVec2::ZERO, glam::DVec2::splat(FREQ), N, N).unwrap()
}

fn fnl(kind: NoiseType) -> FastNoiseLite {
    let mut f = FastNoiseLite::with_seed(1);
    f.set_noise_type(Some(kind));
    f.set_frequency(Some(FREQ as f32));
    f
}

fn fill_fnl(f: &FastNoiseLite, out: &mut [f32]) {
    for (j, row) in out.chunks_exact_mut(N).enumerate() {
        for (i, o) in row.iter_mut().enumerate() {
            *o = f.get_noise_2d(i as f32, j as f32);
        }
    }
}

fn fill_noise_rs(f: &impl NoiseFn<f64, 2>, out: &mut [f32]) {
    for (j, row) in out.chunks_exact_mut(N).enumerate() {
        for (i, o) in row.iter_mut().enumerate() {
            *o = f.get([i as f64 * FREQ, j as f64 * FREQ]) as f32;
        }
    }
}

/// CPU seconds used by the calling thread so far (Linux; nanosecond resolution).
fn thread_cpu() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// Prints points per CPU second of `f` over `n` points, repeating until at
/// least 0.5 s of CPU time.
fn cpu_rate(name: &str, n: usize, mut f: impl FnMut()) {
    let Some(c0) = thread_cpu() else { return };
    f();
    let c0 = thread_cpu().unwrap_or(c0);
    let mut reps = 0;
    let mut used;
    loop {
        f();
        reps += 1;
        used = thread_cpu().unwrap_or(c0) - c0;
        if used >= 0.5 {
            break;
        }
    }
    eprintln!(
        "[noise] cpu {name}: {:.2} Mpts per CPU-second ({:.3} ns/pt; {n} pts x {reps})",
        (n * reps) as f64 / used / 1e6,
        used * 1e9 / (n * reps) as f64,
    );
}

fn group<'a>(
    c: &'a mut Criterion,
    name: &str,
    points: usize,
) -> criterion::BenchmarkGroup<'a, criterion::measurement::WallTime> {
    let mut g = c.benchmark_group(name);
    g.throughput(Throughput::Elements(points as u64));
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(2));
    g
}

fn w1_perlin2(c: &mut Criterion) {
    let mut out = vec![0.0f32; N * N];
    let mut g = group(c, "W1_perlin2d_1024", N * N);
    let p = Perlin::new(1);
    let l = lattice2();
    g.bench_function("natura", |b| {
        b.iter(|| p.fill_grid2(&l, black_box(&mut out)).unwrap())
    });
    let f = fnl(NoiseType::Perlin);
    g.bench_function("fastnoise-lite", |b| {
        b.iter(|| fill_fnl(&f, black_box(&mut out)))
    });
    let n = noise::Perlin::new(1);
    g.bench_function("noise-rs", |b| {
        b.iter(|| fill_noise_rs(&n, black_box(&mut out)))
    });
    g.bench_function("simdnoise", |b| {
        b.iter(|| {
            black_box(
                NoiseBuilder::gradient_2d(N, N)
                    .with_freq(FREQ as f32)
                    .with_seed(1)
                    .generate(),
            )
        })
    });
    g.finish();
    cpu_rate("W1 natura", N * N, || {
        p.fill_grid2(&l, black_box(&mut out)).unwrap()
    });
    cpu_rate("W1 fastnoise-lite", N * N, || {
        fill_fnl(&f, black_box(&mut out))
    });
}

fn w2_simplex2(c: &mut Criterion) {
    let mut out = vec![0.0f32; N * N];
    let mut g = group(c, "W2_simplex2d_1024", N * N);
    let s = Simplex::new(1);
    let l = lattice2();
    g.bench_function("natura", |b| {
        b.iter(|| s.fill_grid2(&l, black_box(&mut out)).unwrap())
    });
    g.bench_function("simdnoise_gradient_2d", |b| {
        b.iter(|| {
            black_box(
                NoiseBuilder::gradient_2d(N, N)
                    .with_freq(FREQ as f32)
                    .with_seed(1)
                    .generate(),
            )
        })
    });
    let f = fnl(NoiseType::OpenSimplex2);
    g.bench_function("fastnoise-lite", |b| {
        b.iter(|| fill_fnl(&f, black_box(&mut out)))
    });
    let n = noise::OpenSimplex::new(1);
    g.bench_function("noise-rs", |b| {
        b.iter(|| fill_noise_rs(&n, black_box(&mut out)))
    });
    g.finish();
    cpu_rate("W2 natura", N * N, || {
        s.fill_grid2(&l, black_box(&mut out)).unwrap()
    });
    cpu_rate("W2 simdnoise gradient_2d", N * N, || {
        black_box(
            NoiseBuilder::gradient_2d(N, N)
                .with_freq(FREQ as f32)
                .with_seed(1)
                .generate(),
        );
    });
}

fn fbm8() -> Fbm<Perlin> {
    let s = Spectral {
        h: 1.0,
        lacunarity: 2.0,
        octaves: 8.0,
        frequency: 1.0,
        convention: GainConvention::H,
    };
    Fbm::new(Perlin::new(1), s).unwrap()
}

fn w3_fbm2(c: &mut Criterion) {
    let mut out = vec![0.0f32; N * N];
    let mut g = group(c, "W3_fbm8_2d_1024", N * N);
    let f = fbm8();
    let l = lattice2();
    g.bench_function("natura", |b| {
        b.iter(|| f.fill_grid2(&l, black_box(&mut out)).unwrap())
    });
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    g.bench_function("natura_2_threads", |b| {
        b.iter(|| {
            pool.install(|| {
                out.par_chunks_mut(N)
                    .enumerate()
                    .for_each(|(j, row)| f.fill_row2(l.row_origin(j), FREQ, row));
            });
            black_box(&out);
        })
    });
    g.bench_function("simdnoise_fbm_2d", |b| {
        b.iter(|| {
            black_box(
                NoiseBuilder::fbm_2d(N, N)
                    .with_freq(FREQ as f32)
                    .with_octaves(8)
                    .with_lacunarity(2.0)
                    .with_gain(0.5)
                    .with_seed(1)
                    .generate(),
            )
        })
    });
    let mut fl = fnl(NoiseType::Perlin);
    fl.set_fractal_type(Some(FractalType::FBm));
    fl.set_fractal_octaves(Some(8));
    g.bench_function("fastnoise-lite", |b| {
        b.iter(|| fill_fnl(&fl, black_box(&mut out)))
    });
    let n = noise::Fbm::<noise::Perlin>::new(1).set_octaves(8);
    g.bench_function("noise-rs", |b| {
        b.iter(|| fill_noise_rs(&n, black_box(&mut out)))
    });
    g.finish();
    cpu_rate("W3 natura", N * N, || {
        f.fill_grid2(&l, black_box(&mut out)).unwrap()
    });
    cpu_rate("W3 simdnoise fbm_2d", N * N, || {
        black_box(
            NoiseBuilder::fbm_2d(N, N)
                .with_freq(FREQ as f32)
                .with_octaves(8)
                .with_lacunarity(2.0)
                .with_gain(0.5)
                .with_seed(1)
                .generate(),
        );
    });
}

fn w4_perlin3(c: &mut Criterion) {
    const M: usize = 128;
    const F3: f64 = 0.05;
    let mut out = vec![0.0f32; M * M * M];
    let mut g = group(c, "W4_perlin3d_128", M * M * M);
    let p = Perlin::new(1);
    let l = Lattice3::new(glam::DVec3::ZERO, glam::DVec3::splat(F3), M, M, M).unwrap();
    g.bench_function("natura", |b| {
        b.iter(|| p.fill_grid3(&l, black_box(&mut out)).unwrap())
    });
    let mut f = fnl(NoiseType::Perlin);
    f.set_frequency(Some(F3 as f32));
    g.bench_function("fastnoise-lite", |b| {
        b.iter(|| {
            for (r, row) in out.chunks_exact_mut(M).enumerate() {
                let (y, z) = ((r % M) as f32, (r / M) as f32);
                for (i, o) in row.iter_mut().enumerate() {
                    *o = f.get_noise_3d(i as f32, y, z);
                }
            }
            black_box(&out);
        })
    });
    g.bench_function("simdnoise_gradient_3d", |b| {
        b.iter(|| {
            black_box(
                NoiseBuilder::gradient_3d(M, M, M)
                    .with_freq(F3 as f32)
                    .with_seed(1)
                    .generate(),
            )
        })
    });
    g.finish();
    cpu_rate("W4 natura", M * M * M, || {
        p.fill_grid3(&l, black_box(&mut out)).unwrap()
    });
    cpu_rate("W4 simdnoise gradient_3d", M * M * M, || {
        black_box(
            NoiseBuilder::gradient_3d(M, M, M)
                .with_freq(F3 as f32)
                .with_seed(1)
                .generate(),
        );
    });
}

fn w5_worley2(c: &mut Criterion) {
    let mut out = vec![0.0f32; N * N];
    let mut g = group(c, "W5_worley_f1_2d_1024", N * N);
    let w = Worley::new(1, WorleyParams::default()).unwrap();
    let l = lattice2();
    g.bench_function("natura", |b| {
        b.iter(|| w.fill_grid2(&l, black_box(&mut out)).unwrap())
    });
    let mut f = fnl(NoiseType::Cellular);
    f.set_cellular_return_type(Some(CellularReturnType::Distance));
    f.set_cellular_distance_function(Some(CellularDistanceFunction::Euclidean));
    f.set_cellular_jitter(Some(1.0));
    g.bench_function("fastnoise-lite_cellular", |b| {
        b.iter(|| fill_fnl(&f, black_box(&mut out)))
    });
    g.bench_function("simdnoise_cellular_2d", |b| {
        b.iter(|| {
            black_box(
                NoiseBuilder::cellular_2d(N, N)
                    .with_freq(FREQ as f32)
                    .with_seed(1)
                    .generate(),
            )
        })
    });
    let n = noise::Worley::new(1).set_return_type(noise::core::worley::ReturnType::Distance);
    g.bench_function("noise-rs", |b| {
        b.iter(|| fill_noise_rs(&n, black_box(&mut out)))
    });
    g.finish();
    cpu_rate("W5 natura", N * N, || {
        w.fill_grid2(&l, black_box(&mut out)).unwrap()
    });
    cpu_rate("W5 fastnoise-lite cellular", N * N, || {
        fill_fnl(&f, black_box(&mut out))
    });
}

criterion_group!(
    benches,
    w1_perlin2,
    w2_simplex2,
    w3_fbm2,
    w4_perlin3,
    w5_worley2
);
criterion_main!(benches);
