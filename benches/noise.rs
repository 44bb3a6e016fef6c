//! natura-noise throughput against noise-rs, fastnoise-lite and simdnoise,
//! measured in the same run on the same workloads (single thread unless noted):
//!
//! * W1 2-D Perlin, 1 octave, frequency 0.01 per cell, 1024² grid
//! * W2 2-D simplex, 1 octave, 1024² grid
//! * W3 2-D fBm, 8 octaves of gradient noise (λ = 2, gain ½), 1024² grid; also on 2 threads
//! * W4 3-D Perlin on a 128³ grid (frequency 0.05 per cell)
//! * W5 2-D Worley F1 (Euclidean), 1024² grid
//! * P1–P8 per-point evaluation (one call per point, as textures make them)
//!   of 2-D and 3-D Perlin, simplex, Worley F1 and 8-octave fBm of Perlin
//!   noise on one fixed quasi-random point set (and simplex noise also on a
//!   coherent set, a grid walked row by row at 0.731 cells per sample, as
//!   terrain and textures call it), natura's `eval2`/`eval3`
//!   against fastnoise-lite's `get_noise_2d`/`get_noise_3d` and noise-rs's
//!   `get`; after each group the CPU-time rates and natura's ratio to each
//!   peer are printed (`[noise] ratio ...`)
//! * P9–P10 per-point 2-D and 3-D Worley F1 with seed table 4 (a Poisson
//!   number of feature points per cell, mean 4), on the same point set;
//!   natura alone (no peer has the tables)
//!
//! Throughput is reported in points per second (`Throughput::Elements`).
//! Besides criterion's wall-clock figures, each single-thread contender's rate
//! per second of *thread CPU time* is printed (`[noise] cpu ...`), which stays
//! meaningful when the machine is shared (a loaded machine deschedules the
//! thread, stretching wall-clock time but not CPU time).
//!
//! Reproduce one block with a filter: `cargo bench --bench noise
//! --no-default-features --features noise -- _point` (P1–P8), `-- W5` (the
//! Worley batch against simdnoise), or `-- W` (every batch group).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fastnoise_lite::{
    CellularDistanceFunction, CellularReturnType, FastNoiseLite, FractalType, NoiseType,
};
use glam::{DVec2, DVec3};
use natura::noise::{
    Fbm, FeaturePoints, Field, GainConvention, Lattice2, Lattice3, Perlin, Simd, SimdLevel,
    Simplex, Spectral, Worley, WorleyParams,
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

/// Whether the command line's benchmark filter (if any) selects group
/// `name`: the CPU-time passes below run outside criterion, so they skip the
/// groups a filtered run leaves out. A filter's `|`-separated alternatives
/// (`'P2_|P5_'`, as criterion's regular expressions allow) each select the
/// groups whose name contains them. Bare numbers (option values such as
/// `--profile-time 5`) are not filters.
fn selected(name: &str) -> bool {
    let filters: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-') && a.parse::<f64>().is_err())
        .collect();
    filters.is_empty()
        || filters.iter().flat_map(|f| f.split('|')).any(|alt| {
            let alt = alt.split('/').next().unwrap_or(alt);
            !alt.is_empty() && name.contains(alt)
        })
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

/// simdnoise's 2-D gradient noise over the W1/W2 grid.
fn simd_gradient2() {
    black_box(
        NoiseBuilder::gradient_2d(N, N)
            .with_freq(FREQ as f32)
            .with_seed(1)
            .generate(),
    );
}

/// `f`'s grid at SIMD level `level` (row by row, as `fill_grid2` does at
/// the best level), or `None` if this CPU lacks the level.
fn grid2_at<'a, F: Field>(
    f: &'a F,
    l: &'a Lattice2,
    level: SimdLevel,
    who: &'a str,
) -> Option<Contender<'a>> {
    let simd = Simd::new(level)?;
    Some((
        who,
        Box::new(move |o: &mut [f32]| {
            for (j, row) in o.chunks_exact_mut(l.nx).enumerate() {
                f.fill_row2_with(simd, l.row_origin(j), l.step.x, row);
            }
        }),
    ))
}

/// Interleaved CPU-time rates of a batch group's contenders (the first is
/// natura) and natura's ratio to each peer.
fn batch_ratios(name: &str, n: usize, out: &mut [f32], mut contenders: Vec<Contender<'_>>) {
    if let Some(r) = interleaved_rates(name, n, &mut contenders, out) {
        for ((who, _), rate) in contenders[1..].iter().zip(&r[1..]) {
            eprintln!("[noise] ratio {name}: natura / {who} = {:.2}", r[0] / rate);
        }
    }
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
    batch_ratios(
        "W1_perlin2d_1024",
        N * N,
        &mut out,
        vec![
            (
                "natura",
                Box::new(|o: &mut [f32]| p.fill_grid2(&l, o).unwrap()),
            ),
            ("fastnoise-lite", Box::new(|o: &mut [f32]| fill_fnl(&f, o))),
            (
                "simdnoise gradient_2d",
                Box::new(|_: &mut [f32]| simd_gradient2()),
            ),
        ],
    );
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
    let mut contenders: Vec<Contender<'_>> = vec![
        (
            "natura",
            Box::new(|o: &mut [f32]| s.fill_grid2(&l, o).unwrap()),
        ),
        (
            "simdnoise gradient_2d",
            Box::new(|_: &mut [f32]| simd_gradient2()),
        ),
        ("fastnoise-lite", Box::new(|o: &mut [f32]| fill_fnl(&f, o))),
    ];
    contenders.extend(grid2_at(
        &s,
        &l,
        SimdLevel::Avx2,
        "natura at AVX2 (8 lanes)",
    ));
    batch_ratios("W2_simplex2d_1024", N * N, &mut out, contenders);
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
                // Blocks of 8 rows, each through `fill_rows2_with` (the
                // grid fill's own blocks: the same values).
                out.par_chunks_mut(8 * N).enumerate().for_each(|(b, rows)| {
                    let ys: Vec<f64> = (0..rows.len() / N)
                        .map(|r| l.row_origin(8 * b + r).y)
                        .collect();
                    f.fill_rows2_with(Simd::best(), l.origin.x, &ys, FREQ, rows);
                });
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
    let mut contenders: Vec<Contender<'_>> = vec![
        (
            "natura",
            Box::new(|o: &mut [f32]| f.fill_grid2(&l, o).unwrap()),
        ),
        (
            "simdnoise fbm_2d",
            Box::new(|_: &mut [f32]| {
                black_box(
                    NoiseBuilder::fbm_2d(N, N)
                        .with_freq(FREQ as f32)
                        .with_octaves(8)
                        .with_lacunarity(2.0)
                        .with_gain(0.5)
                        .with_seed(1)
                        .generate(),
                );
            }),
        ),
        ("fastnoise-lite", Box::new(|o: &mut [f32]| fill_fnl(&fl, o))),
    ];
    contenders.extend(grid2_at(
        &f,
        &l,
        SimdLevel::Avx2,
        "natura at AVX2 (8 lanes)",
    ));
    batch_ratios("W3_fbm8_2d_1024", N * N, &mut out, contenders);
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
    batch_ratios(
        "W4_perlin3d_128",
        M * M * M,
        &mut out,
        vec![
            (
                "natura",
                Box::new(|o: &mut [f32]| p.fill_grid3(&l, o).unwrap()),
            ),
            (
                "simdnoise gradient_3d",
                Box::new(|_: &mut [f32]| {
                    black_box(
                        NoiseBuilder::gradient_3d(M, M, M)
                            .with_freq(F3 as f32)
                            .with_seed(1)
                            .generate(),
                    );
                }),
            ),
        ],
    );
}

/// 3-D fBm, 8 octaves, over a 128³ grid at 0.01 cells a sample: the octaves
/// at 0.02 to 0.64 cells a sample are the rows between the spans and the
/// per-lane kernel (volume and cloud textures sample there).
fn w6_fbm3(c: &mut Criterion) {
    const M: usize = 128;
    let mut out = vec![0.0f32; M * M * M];
    let mut g = group(c, "W6_fbm8_3d_128", M * M * M);
    let f = fbm8();
    let l = Lattice3::new(glam::DVec3::ZERO, glam::DVec3::splat(FREQ), M, M, M).unwrap();
    g.bench_function("natura", |b| {
        b.iter(|| f.fill_grid3(&l, black_box(&mut out)).unwrap())
    });
    let simd_fbm = || {
        NoiseBuilder::fbm_3d(M, M, M)
            .with_freq(FREQ as f32)
            .with_octaves(8)
            .with_lacunarity(2.0)
            .with_gain(0.5)
            .with_seed(1)
            .generate()
    };
    g.bench_function("simdnoise_fbm_3d", |b| b.iter(|| black_box(simd_fbm())));
    g.finish();
    batch_ratios(
        "W6_fbm8_3d_128",
        M * M * M,
        &mut out,
        vec![
            (
                "natura",
                Box::new(|o: &mut [f32]| f.fill_grid3(&l, o).unwrap()),
            ),
            (
                "simdnoise fbm_3d",
                Box::new(|_: &mut [f32]| {
                    black_box(simd_fbm());
                }),
            ),
        ],
    );
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
    batch_ratios(
        "W5_worley_f1_2d_1024",
        N * N,
        &mut out,
        vec![
            (
                "natura",
                Box::new(|o: &mut [f32]| w.fill_grid2(&l, o).unwrap()),
            ),
            (
                "simdnoise cellular_2d",
                Box::new(|_: &mut [f32]| {
                    black_box(
                        NoiseBuilder::cellular_2d(N, N)
                            .with_freq(FREQ as f32)
                            .with_seed(1)
                            .generate(),
                    );
                }),
            ),
            (
                "fastnoise-lite cellular",
                Box::new(|o: &mut [f32]| fill_fnl(&f, o)),
            ),
        ],
    );
}

/// Points per iteration of the per-point groups.
/// Points per per-point set: a million, more than a branch predictor can
/// learn. A set that repeats every few thousand points lets the predictor
/// memorise each point's data-dependent branches (simplex noise's triangle
/// test, Worley's cell walk) from one pass to the next, which no caller
/// that evaluates scattered points ever sees: with 16 384 points, a 2-D
/// simplex point whose triangle test is a branch took 7.9 ns, and 15.3 ns on
/// points that never repeat.
const POINTS: usize = 1 << 20;

/// Half the side of the cube the per-point sets fill (lattice units): wide
/// enough to cross many cells, small enough that the f32 peers see the same
/// points to within 2⁻¹⁹.
const SPREAD: f64 = 16.0;

/// The first `n` points of the `d`-dimensional additive recurrence with the
/// generalised golden ratio (Roberts' R_d sequence), scaled to
/// `[-SPREAD, SPREAD)^d`: evenly spread, quasi-random and reproducible
/// without a generator.
fn point_set(n: usize, d: usize) -> Vec<[f64; 3]> {
    // φ_d is the real root of x^(d+1) = x + 1.
    let mut phi = 2.0f64;
    for _ in 0..64 {
        phi = (1.0 + phi).powf(1.0 / (d as f64 + 1.0));
    }
    let alpha: Vec<f64> = (1..=d).map(|k| phi.powi(-(k as i32)).fract()).collect();
    (0..n)
        .map(|i| {
            let mut p = [0.0; 3];
            for (a, v) in p.iter_mut().zip(&alpha) {
                *a = ((0.5 + v * (i + 1) as f64).fract() * 2.0 - 1.0) * SPREAD;
            }
            p
        })
        .collect()
}

/// One per-point contender: a name and a function filling `out` from the
/// point set, one call per point.
type Contender<'a> = (&'a str, Box<dyn FnMut(&mut [f32]) + 'a>);

/// Runs a per-point group: criterion's figures for every contender, then
/// each one's CPU-time rate and natura's ratio to each peer (the first
/// contender is natura).
fn point_group(c: &mut Criterion, name: &str, mut contenders: Vec<Contender<'_>>) {
    let mut out = vec![0.0f32; POINTS];
    let mut g = group(c, name, POINTS);
    for (who, f) in contenders.iter_mut() {
        g.bench_function(*who, |b| b.iter(|| f(black_box(&mut out))));
    }
    g.finish();
    if let Some(rates) = interleaved_rates(name, POINTS, &mut contenders, &mut out) {
        for ((who, _), r) in contenders[1..].iter().zip(&rates[1..]) {
            eprintln!("[noise] ratio {name}: natura / {who} = {:.2}", rates[0] / r);
        }
    }
}

/// Points per CPU second of each contender (each call of which fills `out`,
/// `n` points), measured in interleaved rounds (one call of each contender
/// that has not yet used 0.5 s of CPU time), so changes in machine load
/// affect all contenders alike. Prints and returns the rates; `None`
/// if the group is not selected or thread CPU time is unavailable.
fn interleaved_rates(
    name: &str,
    n: usize,
    contenders: &mut [Contender<'_>],
    out: &mut [f32],
) -> Option<Vec<f64>> {
    if !selected(name) {
        return None;
    }
    let mut used = vec![0.0f64; contenders.len()];
    let mut calls = vec![0usize; contenders.len()];
    for (_, f) in contenders.iter_mut() {
        f(black_box(&mut *out));
    }
    while used.iter().any(|&u| u < 0.5) {
        for (k, (_, f)) in contenders.iter_mut().enumerate() {
            if used[k] >= 0.5 {
                continue;
            }
            let c0 = thread_cpu()?;
            f(black_box(&mut *out));
            used[k] += thread_cpu()? - c0;
            calls[k] += 1;
        }
    }
    let rates: Vec<f64> = used
        .iter()
        .zip(&calls)
        .map(|(&u, &c)| (n * c) as f64 / u)
        .collect();
    for ((who, _), (r, c)) in contenders.iter().zip(rates.iter().zip(&calls)) {
        eprintln!(
            "[noise] cpu {name} {who}: {:.2} Mpts per CPU-second ({:.3} ns/pt; {n} pts x {c}, interleaved)",
            r / 1e6,
            1e9 / r,
        );
    }
    Some(rates)
}

/// Lattice cells per sample of the coherent per-point sets.
const GRID_STEP: f64 = 0.731;

/// The coherent per-point set: a regular grid of `dims` samples (x fastest)
/// walked row by row, `GRID_STEP` cells apart and centred on the origin,
/// the way terrain and textures call a field one point at a time.
fn grid_set(dims: [usize; 3]) -> Vec<[f64; 3]> {
    let c = dims.map(|n| (n as f64 - 1.0) * 0.5 * GRID_STEP + 0.137);
    let mut p = Vec::with_capacity(dims.iter().product());
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let v = [i, j, k].map(|n| n as f64 * GRID_STEP);
                p.push([
                    v[0] - c[0],
                    v[1] - c[1],
                    if dims[2] > 1 { v[2] - c[2] } else { 0.0 },
                ]);
            }
        }
    }
    p
}

fn points2() -> (Vec<DVec2>, Vec<[f32; 2]>, Vec<[f64; 2]>) {
    split2(point_set(POINTS, 2))
}

/// The 2-D coherent set: a 1024 × 1024 grid.
fn grid_points2() -> (Vec<DVec2>, Vec<[f32; 2]>, Vec<[f64; 2]>) {
    split2(grid_set([1024, 1024, 1]))
}

/// The 3-D coherent set: a 128 × 128 × 64 grid.
fn grid_points3() -> (Vec<DVec3>, Vec<[f32; 3]>, Vec<[f64; 3]>) {
    split3(grid_set([128, 128, 64]))
}

fn split2(p: Vec<[f64; 3]>) -> (Vec<DVec2>, Vec<[f32; 2]>, Vec<[f64; 2]>) {
    (
        p.iter().map(|p| DVec2::new(p[0], p[1])).collect(),
        p.iter().map(|p| [p[0] as f32, p[1] as f32]).collect(),
        p.iter().map(|p| [p[0], p[1]]).collect(),
    )
}

fn points3() -> (Vec<DVec3>, Vec<[f32; 3]>, Vec<[f64; 3]>) {
    split3(point_set(POINTS, 3))
}

fn split3(p: Vec<[f64; 3]>) -> (Vec<DVec3>, Vec<[f32; 3]>, Vec<[f64; 3]>) {
    (
        p.iter().map(|p| DVec3::from_array(*p)).collect(),
        p.iter().map(|p| p.map(|v| v as f32)).collect(),
        p,
    )
}

/// natura's per-point 2-D contender: `eval2` at every point.
fn natura2<'a, F: Field>(f: &'a F, pts: &'a [DVec2]) -> Contender<'a> {
    (
        "natura",
        Box::new(move |out: &mut [f32]| {
            let f = black_box(f);
            for (o, &p) in out.iter_mut().zip(pts) {
                *o = f.eval2(p) as f32;
            }
        }),
    )
}

fn natura3<'a, F: Field>(f: &'a F, pts: &'a [DVec3]) -> Contender<'a> {
    (
        "natura",
        Box::new(move |out: &mut [f32]| {
            let f = black_box(f);
            for (o, &p) in out.iter_mut().zip(pts) {
                *o = f.eval3(p) as f32;
            }
        }),
    )
}

fn fnl2<'a>(f: &'a FastNoiseLite, pts: &'a [[f32; 2]]) -> Contender<'a> {
    (
        "fastnoise-lite",
        Box::new(move |out: &mut [f32]| {
            let f = black_box(f);
            for (o, p) in out.iter_mut().zip(pts) {
                *o = f.get_noise_2d(p[0], p[1]);
            }
        }),
    )
}

fn fnl3<'a>(f: &'a FastNoiseLite, pts: &'a [[f32; 3]]) -> Contender<'a> {
    (
        "fastnoise-lite",
        Box::new(move |out: &mut [f32]| {
            let f = black_box(f);
            for (o, p) in out.iter_mut().zip(pts) {
                *o = f.get_noise_3d(p[0], p[1], p[2]);
            }
        }),
    )
}

fn noise_rs<'a, const D: usize>(f: &'a impl NoiseFn<f64, D>, pts: &'a [[f64; D]]) -> Contender<'a> {
    (
        "noise-rs",
        Box::new(move |out: &mut [f32]| {
            let f = black_box(f);
            for (o, p) in out.iter_mut().zip(pts) {
                *o = f.get(*p) as f32;
            }
        }),
    )
}

/// fastnoise-lite at frequency 1 (it scales points by its frequency), so
/// every library sees the same coordinates.
fn fnl_unit(kind: NoiseType) -> FastNoiseLite {
    let mut f = FastNoiseLite::with_seed(1);
    f.set_noise_type(Some(kind));
    f.set_frequency(Some(1.0));
    f
}

fn fnl_cellular() -> FastNoiseLite {
    let mut f = fnl_unit(NoiseType::Cellular);
    f.set_cellular_return_type(Some(CellularReturnType::Distance));
    f.set_cellular_distance_function(Some(CellularDistanceFunction::Euclidean));
    f.set_cellular_jitter(Some(1.0));
    f
}

fn fnl_fbm() -> FastNoiseLite {
    let mut f = fnl_unit(NoiseType::Perlin);
    f.set_fractal_type(Some(FractalType::FBm));
    f.set_fractal_octaves(Some(8));
    f.set_fractal_lacunarity(Some(2.0));
    f.set_fractal_gain(Some(0.5));
    f
}

fn p_perlin(c: &mut Criterion) {
    let (n2, f2, r2) = points2();
    let (n3, f3, r3) = points3();
    let p = Perlin::new(1);
    let fl = fnl_unit(NoiseType::Perlin);
    let nr = noise::Perlin::new(1);
    point_group(
        c,
        "P1_perlin2d_point",
        vec![natura2(&p, &n2), fnl2(&fl, &f2), noise_rs(&nr, &r2)],
    );
    point_group(
        c,
        "P5_perlin3d_point",
        vec![natura3(&p, &n3), fnl3(&fl, &f3), noise_rs(&nr, &r3)],
    );
}

fn p_simplex(c: &mut Criterion) {
    let (n2, f2, r2) = points2();
    let (n3, f3, r3) = points3();
    let s = Simplex::new(1);
    let fl = fnl_unit(NoiseType::OpenSimplex2);
    let nr = noise::Simplex::new(1);
    point_group(
        c,
        "P2_simplex2d_point",
        vec![natura2(&s, &n2), fnl2(&fl, &f2), noise_rs(&nr, &r2)],
    );
    point_group(
        c,
        "P6_simplex3d_point",
        vec![natura3(&s, &n3), fnl3(&fl, &f3), noise_rs(&nr, &r3)],
    );
    let (n2, f2, r2) = grid_points2();
    let (n3, f3, r3) = grid_points3();
    point_group(
        c,
        "P2_simplex2d_grid_point",
        vec![natura2(&s, &n2), fnl2(&fl, &f2), noise_rs(&nr, &r2)],
    );
    point_group(
        c,
        "P6_simplex3d_grid_point",
        vec![natura3(&s, &n3), fnl3(&fl, &f3), noise_rs(&nr, &r3)],
    );
}

fn p_worley(c: &mut Criterion) {
    let (n2, f2, r2) = points2();
    let (n3, f3, r3) = points3();
    let w = Worley::new(1, WorleyParams::default()).unwrap();
    let fl = fnl_cellular();
    let nr = noise::Worley::new(1).set_return_type(noise::core::worley::ReturnType::Distance);
    point_group(
        c,
        "P3_worley_f1_2d_point",
        vec![natura2(&w, &n2), fnl2(&fl, &f2), noise_rs(&nr, &r2)],
    );
    point_group(
        c,
        "P7_worley_f1_3d_point",
        vec![natura3(&w, &n3), fnl3(&fl, &f3), noise_rs(&nr, &r3)],
    );
}

/// Worley F1 with seed table 4 (a Poisson number of points per cell, mean
/// 4; Musgrave 2001, "The Seed Tables"), per point: no peer has the tables,
/// so natura alone.
fn p_worley_table4(c: &mut Criterion) {
    let (n2, _, _) = points2();
    let (n3, _, _) = points3();
    let w = Worley::new(
        1,
        WorleyParams {
            points: FeaturePoints::Poisson { density: 4.0 },
            ..WorleyParams::default()
        },
    )
    .unwrap();
    point_group(c, "P9_worley_f1_table4_2d_point", vec![natura2(&w, &n2)]);
    point_group(c, "P10_worley_f1_table4_3d_point", vec![natura3(&w, &n3)]);
}

fn p_fbm(c: &mut Criterion) {
    let (n2, f2, r2) = points2();
    let (n3, f3, r3) = points3();
    let f = fbm8();
    let fl = fnl_fbm();
    let nr = noise::Fbm::<noise::Perlin>::new(1)
        .set_octaves(8)
        .set_frequency(1.0)
        .set_lacunarity(2.0)
        .set_persistence(0.5);
    point_group(
        c,
        "P4_fbm8_2d_point",
        vec![natura2(&f, &n2), fnl2(&fl, &f2), noise_rs(&nr, &r2)],
    );
    point_group(
        c,
        "P8_fbm8_3d_point",
        vec![natura3(&f, &n3), fnl3(&fl, &f3), noise_rs(&nr, &r3)],
    );
}

criterion_group!(
    benches,
    w1_perlin2,
    w2_simplex2,
    w3_fbm2,
    w4_perlin3,
    w5_worley2,
    w6_fbm3,
    p_perlin,
    p_simplex,
    p_worley,
    p_worley_table4,
    p_fbm
);
criterion_main!(benches);
