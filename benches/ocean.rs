//! natura-ocean throughput: a full frame (height, 2 slopes, 2 displacements,
//! 3 Jacobian terms) at 256², 512² and 1024², single-threaded and on two
//! threads, against the straightforward one-complex-2-D-FFT-per-field
//! evaluation (`natura_ocean::reference`) measured in the same run.

use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use natura::ocean::reference::Reference;
use natura::ocean::{Frame, Ocean, OceanParams, Phillips, Seed};
use std::hint::black_box;

fn ocean(n: usize) -> Ocean {
    let params = OceanParams {
        nx: n,
        ny: n,
        lx: 500.0,
        ly: 500.0,
        choppiness: 1.0,
        ..OceanParams::default()
    };
    let spectrum = Phillips {
        wind_speed: 12.0,
        small_wave_length: 0.1,
        ..Phillips::default()
    };
    Ocean::new(&params, &spectrum, Seed(1)).expect("valid parameters")
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn full_frame(c: &mut Criterion) {
    let mut group = c.benchmark_group("ocean_frame");
    for n in [256usize, 512, 1024] {
        let o = ocean(n);
        group.throughput(Throughput::Elements((n * n) as u64));
        group.sample_size(if n >= 1024 { 10 } else { 20 });
        group.measurement_time(Duration::from_secs(if n >= 1024 { 6 } else { 4 }));
        group.warm_up_time(Duration::from_secs(1));
        for threads in [1usize, 2] {
            let p = pool(threads);
            let mut frame = p.install(|| Frame::new(&o).expect("frame"));
            let mut t = 0.0;
            group.bench_function(BenchmarkId::new(format!("natura_{threads}t"), n), |b| {
                p.install(|| {
                    b.iter(|| {
                        t += 0.04;
                        o.evaluate_into(t, &mut frame).expect("evaluate");
                        black_box(frame.height().as_slice()[0])
                    })
                })
            });
        }
        let mut r = Reference::new(&o).expect("reference");
        let mut t = 0.0;
        group.bench_function(BenchmarkId::new("one_fft_per_field_1t", n), |b| {
            b.iter(|| {
                t += 0.04;
                r.evaluate(t).expect("evaluate");
                black_box(r.field(natura::ocean::FrameField::Height).as_slice()[0])
            })
        });
    }
    group.finish();
}

/// The calibration workload: one 512² complex 2-D FFT with rustfft
/// and a plain transpose (batched row transforms, a plain transpose, row
/// transforms; the result stays transposed), timed on fresh input each
/// iteration, so the frame times can be compared across machines.
fn calibration(c: &mut Criterion) {
    use criterion::BatchSize;
    use natura::core::fft::{self, Complex, FftDirection};
    let n = 512;
    let fft = fft::plan_f32(n, FftDirection::Inverse);
    let input: Vec<Complex<f32>> = (0..n * n)
        .map(|i| Complex::new((i % 7) as f32, (i % 5) as f32))
        .collect();
    let mut b = vec![Complex::new(0.0f32, 0.0); n * n];
    let mut scratch = vec![Complex::new(0.0f32, 0.0); fft.get_inplace_scratch_len()];
    if selected("ocean_calibration/interleaved_ratio") {
        interleaved_ratio(&fft, &input);
    }
    let mut group = c.benchmark_group("ocean_calibration");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(3));
    group.bench_function("rustfft_complex_2d_plain_transpose_1t", |bch| {
        bch.iter_batched_ref(
            || input.clone(),
            |a| {
                calibration_transform(fft.as_ref(), a, &mut b, &mut scratch);
                black_box(b[1])
            },
            BatchSize::LargeInput,
        )
    });
    group.finish();
}

/// The calibration workload on an n × n grid `a`: row transforms, a plain
/// transpose into `b`, row transforms of `b` (the result stays transposed).
fn calibration_transform(
    fft: &dyn natura::core::fft::Fft<f32>,
    a: &mut [natura::core::fft::Complex<f32>],
    b: &mut [natura::core::fft::Complex<f32>],
    scratch: &mut [natura::core::fft::Complex<f32>],
) {
    let n = fft.len();
    fft.process_with_scratch(a, scratch);
    for y in 0..n {
        for x in 0..n {
            b[x * n + y] = a[y * n + x];
        }
    }
    fft.process_with_scratch(b, scratch);
}

/// Whether the command line's filters (criterion's positional arguments,
/// matched here as substrings) select `name`; no filter selects everything.
fn selected(name: &str) -> bool {
    let filters: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-') && a.parse::<f64>().is_err())
        .collect();
    filters.is_empty() || filters.iter().any(|f| name.contains(f.as_str()))
}

/// The frame ÷ calibration ratio measured robustly against this machine's
/// drifting speed: 512² frames (one thread) and calibration transforms
/// alternate, one of each per pair, so both see the same conditions; prints
/// the minimum and median of each and the median of the per-pair ratios.
fn interleaved_ratio(
    fft: &std::sync::Arc<dyn natura::core::fft::Fft<f32>>,
    input: &[natura::core::fft::Complex<f32>],
) {
    use std::time::Instant;
    let n = 512;
    let o = ocean(n);
    let p = pool(1);
    let mut b = vec![natura::core::fft::Complex::new(0.0f32, 0.0); n * n];
    let mut scratch =
        vec![natura::core::fft::Complex::new(0.0f32, 0.0); fft.get_inplace_scratch_len()];
    let pairs = 200;
    let (mut frames, mut calib, mut ratios) = (vec![], vec![], vec![]);
    p.install(|| {
        let mut frame = Frame::new(&o).expect("frame");
        let mut t = 0.0;
        for i in 0..pairs + 10 {
            t += 0.04;
            let s = Instant::now();
            o.evaluate_into(t, &mut frame).expect("evaluate");
            black_box(frame.height().as_slice()[0]);
            let f = s.elapsed().as_secs_f64() * 1e3;
            let mut a = input.to_vec();
            let s = Instant::now();
            calibration_transform(fft.as_ref(), &mut a, &mut b, &mut scratch);
            black_box(b[1]);
            let c = s.elapsed().as_secs_f64() * 1e3;
            if i >= 10 {
                frames.push(f);
                calib.push(c);
                ratios.push(f / c);
            }
        }
    });
    let sorted = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v
    };
    let (frames, calib, ratios) = (sorted(frames), sorted(calib), sorted(ratios));
    let mid = pairs / 2;
    println!(
        "[ocean] interleaved 512² 1 thread, {pairs} pairs: frame min {:.3} ms, median {:.3} ms; \
         calibration min {:.3} ms, median {:.3} ms; frame ÷ calibration: of the minima {:.2}×, \
         median per pair {:.2}×",
        frames[0],
        frames[mid],
        calib[0],
        calib[mid],
        frames[0] / calib[0],
        ratios[mid],
    );
}

criterion_group!(benches, full_frame, calibration);
criterion_main!(benches);
