//! natura-trace throughput: primary and shadow rays over a 4096² multifractal
//! height field, grid tracing (DDA) vs maximum mipmaps vs parry3d's
//! `HeightField` ray cast, plus a scaling table over field sizes.
//!
//! The field is built here from natura-core alone (natura-noise is a separate
//! crate): octaves of bilinearly interpolated `Seed::gaussian2` lattices
//! combined as Musgrave's heterogeneous terrain (each octave's amplitude
//! scaled by the altitude so far), so valleys are smooth and peaks rough.
//!
//! Views: "grazing" is a 1920×1080 pinhole camera 30 m above the ground near
//! one corner, looking across the field toward the horizon (the hard case:
//! long rays skimming the surface); "topdown" looks straight down from high
//! above. Slow tracers (DDA, parry3d) run on a 1/64 subset of the pixels
//! (every 8th column and row) so the whole file stays within minutes; all
//! tracers are also measured on that subset single-threaded, so the ratios
//! compare like with like. Besides criterion's wall-clock figures, each
//! tracer's rate per second of *thread CPU time* is printed (`[trace] cpu`),
//! which stays meaningful when the machine is shared. The mipmap tracer is
//! measured both one `trace` call per ray and through its batch path
//! (`trace_many` over 1024-ray chunks, `trace_image` over 32 × 32 tiles),
//! which returns the same hits. Figures go to docs/performance.md.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use natura::core::glam::Vec3;
use natura::core::{Boundary, Grid2, HeightField, NoProgress, Seed};
use natura::trace::{
    Camera, Detail, DetailParams, DetailSurface, DetailTracer, GridTracer, MipmapTracer,
    PinholeCamera, Ray, RayCone, RenderOptions, Tracer, render, trace_image,
};

#[cfg(feature = "embree-peer")]
#[path = "trace/embree.rs"]
mod embree;

const CELL: f32 = 10.0;

/// A multifractal-like field of `n × n` samples (heterogeneous terrain over
/// bilinear Gaussian lattices), metres.
fn field(n: usize, seed: u64) -> HeightField {
    let s = Seed(seed);
    let mut octaves = Vec::new();
    let mut lattice = 4usize;
    while lattice <= n / 2 {
        let so = s.derive_index(lattice as u64);
        octaves.push(
            Grid2::from_fn(lattice + 1, lattice + 1, |i, j| {
                so.gaussian2(i as i64, j as i64) as f32
            })
            .unwrap(),
        );
        lattice *= 2;
    }
    let g = Grid2::<f32>::par_from_fn(n, n, |i, j| {
        let mut h = 0.0f32;
        let mut amp = 1.0f32;
        for (k, g) in octaves.iter().enumerate() {
            let f = (g.width() - 1) as f32 / (n - 1) as f32;
            let v = g.sample_bilinear(i as f32 * f, j as f32 * f, Boundary::Clamp);
            // Heterogeneous terrain: higher ground gets rougher detail.
            let w = if k == 0 {
                1.0
            } else {
                (0.6 + 0.5 * h).clamp(0.05, 1.5)
            };
            h += amp * w * v;
            amp *= 0.5;
        }
        1200.0 * h.max(-0.8) + 1000.0
    })
    .unwrap();
    HeightField::new(g, CELL).unwrap()
}

fn grazing(hf: &HeightField, w: u32, h: u32) -> PinholeCamera {
    let e = hf.extent();
    let (x, y) = (0.08 * e.x, 0.08 * e.y);
    let ground = hf.height_at(x, y).unwrap();
    let eye = Vec3::new(x, y, ground + 30.0);
    let target = Vec3::new(0.9 * e.x, 0.75 * e.y, ground - 0.02 * e.x);
    PinholeCamera::look_at(eye, target, Vec3::Z, 40f32.to_radians(), w, h).unwrap()
}

/// A view from above the highest point near one corner, looking across the
/// whole field toward the far corner: rays skim long distances at every size.
fn across(hf: &HeightField, w: u32, h: u32) -> PinholeCamera {
    let e = hf.extent();
    let (lo, hi) = hf.min_max();
    let eye = Vec3::new(0.03 * e.x, 0.03 * e.y, hi + 0.005 * e.x);
    let target = Vec3::new(0.97 * e.x, 0.9 * e.y, lo + 0.3 * (hi - lo));
    PinholeCamera::look_at(eye, target, Vec3::Z, 30f32.to_radians(), w, h).unwrap()
}

fn topdown(hf: &HeightField, w: u32, h: u32) -> PinholeCamera {
    let e = hf.extent();
    let c = Vec3::new(0.5 * e.x, 0.5 * e.y, 0.0);
    let eye = c + Vec3::new(0.0, 0.0, 1.3 * e.x);
    PinholeCamera::look_at(eye, c, Vec3::Y, 40f32.to_radians(), w, h).unwrap()
}

/// The rays through every `step`-th pixel centre in x and y.
fn rays(cam: &impl Camera, step: u32) -> Vec<Ray> {
    let r = cam.resolution();
    let mut out = Vec::new();
    for y in (0..r.y).step_by(step as usize) {
        for x in (0..r.x).step_by(step as usize) {
            out.push(cam.ray(x, y, natura::core::glam::Vec2::splat(0.5)));
        }
    }
    out
}

/// parry3d's height field for the same surface: parry is y-up with rows
/// along its z and the field centred on the origin, so world `(x, y, z)`
/// maps to parry `(x − W/2, z, y − D/2)`.
fn parry_field(hf: &HeightField) -> parry3d::shape::HeightField {
    let (nx, ny) = (hf.nx(), hf.ny());
    let h = hf.heights();
    let a = parry3d::utils::Array2::from_fn(ny, nx, |r, c| h[(c, r)]);
    let e = hf.extent();
    parry3d::shape::HeightField::new(a, parry3d::math::Vector::new(e.x, 1.0, e.y))
}

fn parry_ray(hf: &HeightField, r: &Ray) -> parry3d::query::Ray {
    let e = hf.extent();
    let o = r.origin;
    let d = r.dir;
    parry3d::query::Ray::new(
        parry3d::math::Vector::new(o.x - 0.5 * e.x, o.z, o.y - 0.5 * e.y),
        parry3d::math::Vector::new(d.x, d.z, d.y),
    )
}

/// CPU seconds used by the calling thread so far (Linux; 10 ms resolution).
fn thread_cpu() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/stat").ok()?;
    let f: Vec<&str> = s[s.rfind(')')? + 2..].split(' ').collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Rays per CPU second of `f` over `n` rays, repeating until at least 1 s of CPU.
fn cpu_rate(name: &str, n: usize, mut f: impl FnMut()) {
    let Some(c0) = thread_cpu() else { return };
    let mut reps = 0;
    let mut used;
    loop {
        f();
        reps += 1;
        used = thread_cpu().unwrap_or(c0) - c0;
        if used >= 1.0 {
            break;
        }
    }
    eprintln!(
        "[trace] cpu {name}: {:.3} Mrays per CPU-second ({} rays × {reps})",
        (n * reps) as f64 / used / 1e6,
        n
    );
}

fn trace_all(t: &impl Tracer, rays: &[Ray]) -> usize {
    rays.iter()
        .filter(|r| t.trace(r, 0.0, f32::INFINITY).is_some())
        .count()
}

/// The batch path: `trace_many` over chunks of `BATCH` rays (a 32 × 32 tile's worth).
fn trace_batched(t: &MipmapTracer<'_>, rays: &[Ray]) -> usize {
    rays.chunks(BATCH)
        .map(|c| {
            t.trace_many(c, 0.0, f32::INFINITY)
                .iter()
                .filter(|h| h.is_some())
                .count()
        })
        .sum()
}

const BATCH: usize = 1024;

fn stats_line(name: &str, t: &impl Tracer, rays: &[Ray]) {
    let (mut hits, mut nodes, mut cells, mut tests) = (0u64, 0u64, 0u64, 0u64);
    for r in rays {
        let (h, s) = t.trace_with_stats(r, 0.0, f32::INFINITY);
        hits += u64::from(h.is_some());
        nodes += u64::from(s.nodes_visited);
        cells += u64::from(s.cells_tested);
        tests += u64::from(s.triangle_tests);
    }
    let n = rays.len() as f64;
    eprintln!(
        "[trace] {name}: {:.1}% hit; per ray {:.1} steps, {:.2} cells tested, {:.2} triangle tests; per hitting ray {:.2} triangle tests",
        100.0 * hits as f64 / n,
        nodes as f64 / n,
        cells as f64 / n,
        tests as f64 / n,
        tests as f64 / hits.max(1) as f64
    );
}

/// Whether a benchmark id containing `prefix` can match the command line's
/// filter (criterion's first free argument), so filtered runs skip the
/// setup and the printed figures of groups they exclude.
fn wanted(prefix: &str) -> bool {
    let filters: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    filters.is_empty()
        || filters
            .iter()
            .any(|f| prefix.contains(f.as_str()) || f.contains(prefix))
}

fn primary(c: &mut Criterion) {
    if !wanted("trace_") && !wanted("shadow") {
        return;
    }
    let hf = field(4096, 1);
    let grid = GridTracer::new(&hf).unwrap();
    let mip = MipmapTracer::new(&hf).unwrap();
    let field_bytes = hf.nx() * hf.ny() * 4;
    eprintln!(
        "[trace] 4096² field {:.1} MB; max-mipmap {:.1} MB = {:.3}× the field",
        field_bytes as f64 / 1e6,
        mip.memory_bytes() as f64 / 1e6,
        mip.memory_bytes() as f64 / field_bytes as f64
    );
    let pf = parry_field(&hf);
    let threads = rayon::current_num_threads();

    for (view, cam) in [
        ("grazing", grazing(&hf, 1920, 1080)),
        ("topdown", topdown(&hf, 1920, 1080)),
    ] {
        let sub = rays(&cam, 8);
        stats_line(&format!("{view} dda"), &grid, &sub);
        stats_line(&format!("{view} mipmap"), &mip, &sub);
        // Agreement with parry3d (which splits cells along the other diagonal).
        let agree = sub
            .iter()
            .filter(|r| {
                let a = mip.trace(r, 0.0, f32::INFINITY).map(|h| h.t);
                let b = {
                    use parry3d::query::RayCast;
                    pf.cast_local_ray(&parry_ray(&hf, r), f32::MAX, true)
                };
                match (a, b) {
                    (Some(a), Some(b)) => (a - b).abs() <= 1e-3 * a.max(1.0) + 2.0 * CELL,
                    (None, None) => true,
                    _ => false,
                }
            })
            .count();
        eprintln!(
            "[trace] {view}: mipmap and parry3d agree on {:.2}% of rays (hit/miss and t within a cell)",
            100.0 * agree as f64 / sub.len() as f64
        );

        let pr: Vec<_> = sub.iter().map(|r| parry_ray(&hf, r)).collect();
        cpu_rate(&format!("{view} mipmap 1/64"), sub.len(), || {
            black_box(trace_all(&mip, &sub));
        });
        cpu_rate(&format!("{view} mipmap trace_many 1/64"), sub.len(), || {
            black_box(trace_batched(&mip, &sub));
        });
        cpu_rate(&format!("{view} dda 1/64"), sub.len(), || {
            black_box(trace_all(&grid, &sub));
        });
        cpu_rate(&format!("{view} parry3d 1/64"), sub.len(), || {
            use parry3d::query::RayCast;
            black_box(
                pr.iter()
                    .filter(|r| pf.cast_local_ray(r, f32::MAX, true).is_some())
                    .count(),
            );
        });
        let full = rays(&cam, 1);
        cpu_rate(
            &format!("{view} mipmap full frame, scanline order"),
            full.len(),
            || {
                black_box(trace_all(&mip, &full));
            },
        );
        cpu_rate(
            &format!("{view} mipmap trace_many full frame, scanline order"),
            full.len(),
            || {
                black_box(trace_batched(&mip, &full));
            },
        );

        let mut g = c.benchmark_group(format!("trace_{view}_1of64_1thread"));
        g.sample_size(10);
        g.warm_up_time(Duration::from_millis(500));
        g.measurement_time(Duration::from_secs(4));
        g.throughput(Throughput::Elements(sub.len() as u64));
        g.bench_function("mipmap", |b| b.iter(|| black_box(trace_all(&mip, &sub))));
        g.bench_function("mipmap_trace_many", |b| {
            b.iter(|| black_box(trace_batched(&mip, &sub)))
        });
        g.bench_function("dda", |b| b.iter(|| black_box(trace_all(&grid, &sub))));
        g.bench_function("parry3d", |b| {
            use parry3d::query::RayCast;
            b.iter(|| {
                black_box(
                    pr.iter()
                        .filter(|r| pf.cast_local_ray(r, f32::MAX, true).is_some())
                        .count(),
                )
            })
        });
        g.finish();

        let mut g = c.benchmark_group(format!("trace_{view}_1920x1080_{threads}threads"));
        g.sample_size(10);
        g.warm_up_time(Duration::from_millis(500));
        g.measurement_time(Duration::from_secs(4));
        g.throughput(Throughput::Elements(1920 * 1080));
        // The batch API: each 32 × 32 tile's rays traced together.
        g.bench_function("mipmap_trace_image", |b| {
            let options = RenderOptions::default();
            b.iter(|| {
                black_box(
                    trace_image(&mip, &cam, &options, &NoProgress, |_, h| {
                        Vec3::splat(h.map_or(0.0, |h| h.t))
                    })
                    .unwrap(),
                )
            })
        });
        // One `trace` call per pixel (as a per-pixel shader would).
        g.bench_function("mipmap_per_ray", |b| {
            b.iter(|| {
                black_box(
                    render(1920, 1080, 32, &NoProgress, |x, y| {
                        mip.trace(
                            &cam.ray(x, y, natura::core::glam::Vec2::splat(0.5)),
                            0.0,
                            f32::INFINITY,
                        )
                        .map_or(0.0f32, |h| h.t)
                    })
                    .unwrap(),
                )
            })
        });
        g.finish();
    }

    // Shadow rays toward a low sun (10° elevation) from the grazing view's hits.
    let cam = grazing(&hf, 1920, 1080);
    let sun = Vec3::new(-0.6, 0.75, 10f32.to_radians().tan()).normalize();
    let starts: Vec<Ray> = rays(&cam, 4)
        .iter()
        .filter_map(|r| mip.trace(r, 0.0, f32::INFINITY))
        .map(|h| Ray::new(h.point + 0.01 * h.geometric_normal, sun))
        .collect();
    let lit = starts
        .iter()
        .filter(|r| !mip.occluded(r, 0.0, f32::INFINITY))
        .count();
    eprintln!(
        "[trace] shadow rays: {} from grazing-view hits, {:.1}% lit",
        starts.len(),
        100.0 * lit as f64 / starts.len() as f64
    );
    // Shadowed rays counted with one batched call per chunk, or one call per ray.
    let shadowed_many = || {
        starts
            .chunks(BATCH)
            .map(|c| {
                mip.occluded_many(c, 0.0, f32::INFINITY)
                    .iter()
                    .filter(|&&o| o)
                    .count()
            })
            .sum::<usize>()
    };
    let shadowed_each = || {
        starts
            .iter()
            .filter(|r| mip.occluded(r, 0.0, f32::INFINITY))
            .count()
    };
    cpu_rate("shadow mipmap occluded_many", starts.len(), || {
        black_box(shadowed_many());
    });
    cpu_rate("shadow mipmap occluded", starts.len(), || {
        black_box(shadowed_each());
    });
    let mut g = c.benchmark_group("shadow_low_sun");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(4));
    g.throughput(Throughput::Elements(starts.len() as u64));
    g.bench_function("mipmap_occluded_1thread", |b| {
        b.iter(|| black_box(shadowed_each()))
    });
    g.bench_function("mipmap_occluded_many_1thread", |b| {
        b.iter(|| black_box(shadowed_many()))
    });
    g.bench_function(format!("mipmap_occluded_{threads}threads"), |b| {
        use rayon::prelude::*;
        b.iter(|| {
            black_box(
                starts
                    .par_iter()
                    .filter(|r| mip.occluded(r, 0.0, f32::INFINITY))
                    .count(),
            )
        })
    });
    g.finish();
}

fn scaling(c: &mut Criterion) {
    if !wanted("scaling") {
        return;
    }
    let mut g = c.benchmark_group("scaling_across_1thread");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(300));
    g.measurement_time(Duration::from_secs(3));
    for n in [512usize, 2048, 8192] {
        let hf = field(n, 2);
        let mip = MipmapTracer::new(&hf).unwrap();
        let grid = GridTracer::new(&hf).unwrap();
        let sub = rays(&across(&hf, 1920, 1080), 8);
        let field_mb = (hf.nx() * hf.ny() * 4) as f64 / 1e6;
        eprintln!(
            "[trace] {n}²: field {field_mb:.1} MB, max-mipmap {:.3}× of it",
            mip.memory_bytes() as f64 / 1e6 / field_mb
        );
        stats_line(&format!("scaling {n}² mipmap"), &mip, &sub);
        cpu_rate(&format!("scaling {n}² mipmap"), sub.len(), || {
            black_box(trace_all(&mip, &sub));
        });
        cpu_rate(
            &format!("scaling {n}² mipmap trace_many"),
            sub.len(),
            || {
                black_box(trace_batched(&mip, &sub));
            },
        );
        let few: Vec<Ray> = sub.iter().step_by(4).copied().collect();
        cpu_rate(&format!("scaling {n}² dda"), few.len(), || {
            black_box(trace_all(&grid, &few));
        });
        g.throughput(Throughput::Elements(sub.len() as u64));
        g.bench_with_input(BenchmarkId::new("mipmap", n), &sub, |b, s| {
            b.iter(|| black_box(trace_all(&mip, s)))
        });
        g.throughput(Throughput::Elements(few.len() as u64));
        g.bench_with_input(BenchmarkId::new("dda", n), &few, |b, s| {
            b.iter(|| black_box(trace_all(&grid, s)))
        });
    }
    g.finish();
}

/// Detail tracing against plain tracing over the same field and rays: a
/// 1024² field, the grazing view at 640 × 360, every 2nd pixel; detail of
/// 2 m first-octave amplitude, H = 0.8, 9 octaves from the cell's wavelength
/// down to the pixel footprint.
fn detail(c: &mut Criterion) {
    if !wanted("detail") {
        return;
    }
    let hf = field(1024, 3);
    let cam = grazing(&hf, 640, 360);
    let sub = rays(&cam, 2);
    let angle = 40f32.to_radians() / 360.0;
    let plain = MipmapTracer::new(&hf).unwrap();
    let params = DetailParams {
        amplitude_m: 2.0,
        h: 0.8,
        lacunarity: 2.0,
        octaves: 9,
        wavelength_m: CELL,
        seed: 5,
    };
    let surface = DetailSurface::new(&hf, Detail::new(&params).unwrap(), None).unwrap();
    let detailed = DetailTracer::new(surface, RayCone::cone(angle)).unwrap();
    cpu_rate("detail: plain mipmap", sub.len(), || {
        black_box(trace_all(&plain, &sub));
    });
    cpu_rate("detail: with detail", sub.len(), || {
        black_box(trace_all(&detailed, &sub));
    });
    let mut g = c.benchmark_group("detail_grazing_1thread");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(300));
    g.measurement_time(Duration::from_secs(3));
    g.throughput(Throughput::Elements(sub.len() as u64));
    g.bench_with_input(BenchmarkId::new("plain", 1024), &sub, |b, s| {
        b.iter(|| black_box(trace_all(&plain, s)))
    });
    g.bench_with_input(BenchmarkId::new("detail", 1024), &sub, |b, s| {
        b.iter(|| black_box(trace_all(&detailed, s)))
    });
    g.finish();
}

/// Embree as a peer (with the `embree-peer` feature; see `trace/embree.rs`).
#[cfg(feature = "embree-peer")]
fn embree_peer(c: &mut Criterion) {
    if !wanted("embree") {
        return;
    }
    let hf = field(4096, 1);
    embree::compare(
        c,
        &hf,
        &[
            ("grazing", grazing(&hf, 1920, 1080)),
            ("topdown", topdown(&hf, 1920, 1080)),
        ],
    );
}

#[cfg(not(feature = "embree-peer"))]
fn embree_peer(_: &mut Criterion) {}

criterion_group!(benches, primary, scaling, detail, embree_peer);
criterion_main!(benches);
