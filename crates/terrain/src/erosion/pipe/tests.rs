use super::*;
use crate::erosion::Edges;
use natura_core::simd::Simd;
use natura_core::{NoProgress, Seed};

fn hills(n: usize) -> HeightField {
    let s = Seed(2);
    HeightField::from_fn(n, n, 2.0, |i, j| {
        let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
        30.0 * (3.0 * x).sin() * (2.0 * y).cos() + 40.0 * x + s.gaussian2(i as i64, j as i64) as f32
    })
    .unwrap()
}

#[test]
fn conserves_mass_closed_and_open() {
    for edges in [Edges::Closed, Edges::Open, Edges::Periodic] {
        let mut hf = hills(40);
        let mut m = PipeModel::new(
            PipeParams {
                edges,
                ..Default::default()
            },
            &hf,
        )
        .unwrap();
        let mat0 = hf.heights().sum();
        m.run(&mut hf, 500, &NoProgress).unwrap();
        let l = m.ledger();
        let mat = hf.heights().sum() + m.total_sediment() + l.outflow_sediment;
        assert!(
            (mat - mat0).abs() <= 1e-4 * mat0.abs(),
            "{edges:?}: material {mat0} → {mat}"
        );
        let water = m.total_water();
        let budget = l.rain - l.evaporated - l.outflow_water;
        assert!(
            (water - budget).abs() <= 1e-4 * l.rain,
            "{edges:?}: water {water} vs {budget}"
        );
        assert!(m.water.iter().all(|&w| w >= 0.0) && m.sediment.iter().all(|&s| s >= 0.0));
        if edges == Edges::Open {
            assert!(l.outflow_water > 0.0);
        }
    }
}

/// The row kernels (interior cells) against the general per-cell path on
/// rough random fields with random water and sediment, for every edge
/// mode, both transports and with an erodibility map: same operations in
/// the same order, so every field must match bit for bit (±0 aside), and
/// the ledgers (summed in a different order) to 1e-9.
#[test]
fn fast_interior_path_equals_general_path() {
    let s = Seed(11);
    for (case, (edges, transport, erodible)) in [
        (Edges::Closed, SedimentTransport::Conservative, false),
        (Edges::Open, SedimentTransport::Conservative, true),
        (Edges::Periodic, SedimentTransport::Conservative, false),
        (Edges::Closed, SedimentTransport::SemiLagrangian, true),
        (Edges::Open, SedimentTransport::SemiLagrangian, false),
        (Edges::Periodic, SedimentTransport::SemiLagrangian, true),
    ]
    .into_iter()
    .enumerate()
    {
        // Odd sizes and more than one block of the row kernel (129 > 128 interior cells).
        let (nx, ny) = [(37, 23), (131, 9), (5, 40)][case % 3];
        let g = |k: i64, i: usize, j: usize| s.derive_index(k as u64).uniform2(i as i64, j as i64);
        let hf = HeightField::from_fn(nx, ny, 1.5, |i, j| 20.0 * g(1, i, j) as f32).unwrap();
        let water = Grid2::from_fn(nx, ny, |i, j| {
            let w = g(2, i, j);
            if w < 0.2 { 0.0 } else { 2.0 * w as f32 }
        })
        .unwrap();
        let p = PipeParams {
            edges,
            transport,
            dt: 0.2,
            k_c: 0.5,
            ..Default::default()
        };
        let build = |path: Path| {
            let mut m = PipeModel::new(p.clone(), &hf).unwrap();
            if erodible {
                let e = Grid2::from_fn(nx, ny, |i, j| 0.5 + g(3, i, j) as f32).unwrap();
                m = m.with_erodibility(Erodibility::new(e).unwrap()).unwrap();
            }
            m.set_water(&water).unwrap();
            m.record_velocity = true;
            let mut h = hf.clone();
            m.run_on(&mut h, 40, &NoProgress, path).unwrap();
            (m, h)
        };
        let (slow, hf_slow) = build(Path::Reference);
        // The fast path at every instruction set this CPU supports.
        for simd in Simd::supported() {
            let (fast, hf_fast) = build(Path::Fused {
                chunk_rows: CHUNK_ROWS,
                simd,
            });
            let same = |what: &str, a: &[f32], b: &[f32]| {
                for (k, (x, y)) in a.iter().zip(b).enumerate() {
                    assert!(x == y, "case {case}: {what}[{k}] fast {x} vs general {y}");
                }
            };
            same(
                "bed",
                hf_fast.heights().as_slice(),
                hf_slow.heights().as_slice(),
            );
            same("water", &fast.water, &slow.water);
            same("sediment", &fast.sediment, &slow.sediment);
            same("deposit", &fast.deposit, &slow.deposit);
            same("u", &fast.vel[0], &slow.vel[0]);
            same("v", &fast.vel[1], &slow.vel[1]);
            for k in 0..4 {
                same("flux", &fast.flux[k], &slow.flux[k]);
            }
            assert!(fast.total_sediment() > 0.0, "case {case}: nothing eroded");
            let (a, b) = (fast.ledger(), slow.ledger());
            assert_eq!(a.rain, b.rain);
            assert_eq!(a.outflow_water, b.outflow_water);
            assert_eq!(a.outflow_sediment, b.outflow_sediment);
            assert!(
                (a.evaporated - b.evaporated).abs() <= 1e-9 * b.evaporated.max(1.0),
                "case {case}: evaporated {} vs {}",
                a.evaporated,
                b.evaporated
            );
        }
    }
}

/// The fused sweep (chunks, halos, in-place updates, row rings) against
/// the previous three-pass path, with and without the row kernels, on
/// rough random fields for every edge mode, with and without an
/// erodibility map, for chunkings from one row per chunk to one chunk
/// (and grids only three rows tall): every field must match bit for bit,
/// the outflow ledgers exactly and the evaporation ledger to 1e-7 (the row
/// kernel sums it in `f32` blocks). The
/// fused sweep must also give the same bits on one and on two threads.
#[test]
fn fused_sweep_equals_three_pass_path() {
    let s = Seed(23);
    let g = |k: u64, i: usize, j: usize| s.derive_index(k).uniform2(i as i64, j as i64);
    let cases = [
        (Edges::Closed, false, 41, 57, 7),
        (Edges::Open, true, 40, 57, 9),
        (Edges::Periodic, false, 19, 50, 6),
        (Edges::Open, false, 23, 11, 1),
        (Edges::Periodic, true, 17, 3, 1),
        (Edges::Closed, true, 9, 3, 64),
        (Edges::Periodic, false, 21, 30, 64),
        (Edges::Open, true, 6, 70, 64),
    ];
    for (case, &(edges, erodible, nx, ny, chunk_rows)) in cases.iter().enumerate() {
        let hf = HeightField::from_fn(nx, ny, 1.5, |i, j| 20.0 * g(1, i, j) as f32).unwrap();
        let water = Grid2::from_fn(nx, ny, |i, j| {
            let w = g(2, i, j);
            if w < 0.2 { 0.0 } else { 2.0 * w as f32 }
        })
        .unwrap();
        let p = PipeParams {
            edges,
            dt: 0.2,
            k_c: 0.5,
            ..Default::default()
        };
        let build = |path: Path, threads: usize| {
            let mut m = PipeModel::new(p.clone(), &hf).unwrap();
            if erodible {
                let e = Grid2::from_fn(nx, ny, |i, j| 0.5 + g(3, i, j) as f32).unwrap();
                m = m.with_erodibility(Erodibility::new(e).unwrap()).unwrap();
            }
            m.set_water(&water).unwrap();
            m.record_velocity = true;
            let mut h = hf.clone();
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| m.run_on(&mut h, 30, &NoProgress, path))
                .unwrap();
            (m, h)
        };
        let best = Simd::best();
        let fused_at = |simd| Path::Fused { chunk_rows, simd };
        let (fused, hf_fused) = build(fused_at(best), 2);
        let mut others = vec![
            ("three passes".to_string(), build(Path::Rows(best), 2)),
            ("general".to_string(), build(Path::Reference, 1)),
            ("fused, 1 thread".to_string(), build(fused_at(best), 1)),
        ];
        // The row kernels at every instruction set this CPU supports.
        for simd in Simd::supported().filter(|&s| s != best) {
            let name = format!("fused at {}", simd.level().name());
            others.push((name, build(fused_at(simd), 2)));
        }
        for (what, (other, hf_other)) in others {
            let same = |field: &str, a: &[f32], b: &[f32]| {
                for (k, (x, y)) in a.iter().zip(b).enumerate() {
                    assert!(
                        x.to_bits() == y.to_bits() || (*x == 0.0 && *y == 0.0),
                        "case {case}: {field}[{k}] fused {x} vs {what} {y}"
                    );
                }
            };
            same(
                "bed",
                hf_fused.heights().as_slice(),
                hf_other.heights().as_slice(),
            );
            same("water", &fused.water, &other.water);
            same("sediment", &fused.sediment, &other.sediment);
            same("deposit", &fused.deposit, &other.deposit);
            same("u", &fused.vel[0], &other.vel[0]);
            same("v", &fused.vel[1], &other.vel[1]);
            for k in 0..4 {
                same("flux", &fused.flux[k], &other.flux[k]);
            }
            let (a, b) = (fused.ledger(), other.ledger());
            assert_eq!(a.rain, b.rain);
            assert_eq!(a.outflow_water, b.outflow_water, "case {case}: {what}");
            assert_eq!(
                a.outflow_sediment, b.outflow_sediment,
                "case {case}: {what}"
            );
            // The row kernel sums evaporation in f32 per block of cells.
            assert!(
                (a.evaporated - b.evaporated).abs() <= 1e-7 * b.evaporated.max(1.0),
                "case {case}: evaporated {} vs {what} {}",
                a.evaporated,
                b.evaporated
            );
        }
        assert!(fused.total_sediment() > 0.0, "case {case}: nothing eroded");
        if edges == Edges::Open {
            assert!(fused.ledger().outflow_sediment > 0.0, "case {case}");
        }
    }
}

/// Recording the velocity changes nothing else (bit for bit, fused and
/// three-pass paths); without it `velocity()` is a typed error. The
/// deposit mirrors the bed: after runs and single steps (split in several
/// calls) it equals the field's change since the model was built to
/// within the rounding of the heights, and calls that split the same steps
/// differently agree to that rounding too.
#[test]
fn velocity_on_request_and_deposit_from_the_bed() {
    let s = Seed(31);
    let (nx, ny) = (45, 38);
    let g = |k: u64, i: usize, j: usize| s.derive_index(k).uniform2(i as i64, j as i64);
    let hf0 = HeightField::from_fn(nx, ny, 1.5, |i, j| 20.0 * g(1, i, j) as f32).unwrap();
    let water = Grid2::from_fn(nx, ny, |i, j| 2.0 * g(2, i, j) as f32).unwrap();
    for edges in [Edges::Closed, Edges::Open, Edges::Periodic] {
        let p = PipeParams {
            edges,
            dt: 0.2,
            k_c: 0.5,
            ..Default::default()
        };
        let build = |record: bool, fused: bool, calls: &[u32]| {
            let mut m = PipeModel::new(p.clone(), &hf0)
                .unwrap()
                .with_velocity(record);
            m.set_water(&water).unwrap();
            let path = if fused {
                Path::Fused {
                    chunk_rows: 8,
                    simd: Simd::best(),
                }
            } else {
                Path::Rows(Simd::best())
            };
            let mut h = hf0.clone();
            for &n in calls {
                if n == 0 {
                    m.step_on(&mut h, path).unwrap();
                } else {
                    m.run_on(&mut h, n, &NoProgress, path).unwrap();
                }
            }
            (m, h)
        };
        let (plain, h_plain) = build(false, true, &[25]);
        assert!(
            plain.velocity().is_err(),
            "{edges:?}: velocity not recorded"
        );
        assert!(plain.vel[0].is_empty() && plain.vel[1].is_empty());
        for (what, (m, h)) in [
            ("recorded", build(true, true, &[25])),
            ("three passes", build(false, false, &[25])),
        ] {
            let same = |field: &str, a: &[f32], b: &[f32]| {
                assert_eq!(a.len(), b.len());
                for (k, (x, y)) in a.iter().zip(b).enumerate() {
                    assert!(
                        x.to_bits() == y.to_bits(),
                        "{edges:?}: {field}[{k}] {x} vs {what} {y}"
                    );
                }
            };
            same("bed", h_plain.heights().as_slice(), h.heights().as_slice());
            same("water", &plain.water, &m.water);
            same("sediment", &plain.sediment, &m.sediment);
            same("deposit", &plain.deposit, &m.deposit);
            for k in 0..4 {
                same("flux", &plain.flux[k], &m.flux[k]);
            }
        }
        let (rec, _) = build(true, true, &[25]);
        let (u, v) = rec.velocity().unwrap();
        assert!(u.as_slice().iter().chain(v.as_slice()).any(|&x| x != 0.0));
        // The deposit against the field's change, for one call and for several.
        let (split, h_split) = build(false, true, &[0, 7, 0, 0, 16]);
        same_to_rounding(&plain.deposit, &h_plain, &hf0, edges);
        same_to_rounding(&split.deposit, &h_split, &hf0, edges);
        let eroded = plain.deposit.iter().filter(|&&d| d < 0.0).count();
        assert!(eroded > 0, "{edges:?}: nothing eroded");
    }
    /// `dep = h − h₀` cell by cell, to a few roundings of the heights
    /// (the field is at most 20 m high: an ulp of 2⁻¹⁹ m).
    fn same_to_rounding(dep: &[f32], h: &HeightField, h0: &HeightField, edges: Edges) {
        let tol = 6.0 * 2f32.powi(-19);
        for (k, ((&d, &a), &b)) in dep
            .iter()
            .zip(h.heights().as_slice())
            .zip(h0.heights().as_slice())
            .enumerate()
        {
            assert!(
                (d - (a - b)).abs() <= tol,
                "{edges:?}: deposit[{k}] {d} vs change {}",
                a - b
            );
        }
    }
}

/// A few steps at 1024² (`PIPE_N`, `PIPE_STEPS` to change) on a spectral
/// terrain, for profilers (`valgrind --tool=callgrind` runs the AVX2 build):
/// `cargo test --release -p natura-terrain --lib pipe_profile_run -- --ignored`.
#[test]
#[ignore = "profiling harness"]
fn pipe_profile_run() {
    let var = |k: &str, d: usize| {
        std::env::var(k)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(d)
    };
    let n = var("PIPE_N", 1024);
    let sp = crate::synth::SpectralParams {
        sigma_m: 200.0,
        ..Default::default()
    };
    let mut hf = crate::synth::spectral_synthesis(n, n, 10.0, &sp, Seed(1)).unwrap();
    let mut m = PipeModel::new(PipeParams::default(), &hf).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let t0 = std::time::Instant::now();
    let steps = var("PIPE_STEPS", 5) as u32;
    pool.install(|| m.run(&mut hf, steps, &NoProgress)).unwrap();
    let s = t0.elapsed().as_secs_f64();
    eprintln!(
        "{:.1} M cell-steps/s",
        (n * n) as f64 * f64::from(steps) / s / 1e6
    );
}

#[test]
fn extreme_params_stay_finite_or_are_refused() {
    let mut hf = hills(16);
    for p in [
        PipeParams {
            dt: 10.0,
            rain_m_per_s: 1.0,
            k_e: 0.0,
            ..Default::default()
        },
        PipeParams {
            k_c: 100.0,
            k_s: 1.0,
            ..Default::default()
        },
        PipeParams {
            transport: SedimentTransport::SemiLagrangian,
            dt: 5.0,
            ..Default::default()
        },
    ] {
        let mut m = PipeModel::new(p, &hf).unwrap();
        m.run(&mut hf, 100, &NoProgress).unwrap();
        assert!(hf.check_finite().is_ok());
        assert!(m.water.iter().all(|w| w.is_finite() && *w >= 0.0));
    }
    for p in [
        PipeParams {
            dt: 0.0,
            ..Default::default()
        },
        PipeParams {
            dt: -1.0,
            ..Default::default()
        },
        PipeParams {
            dt: 1e9,
            ..Default::default()
        },
        PipeParams {
            k_s: 2.0,
            ..Default::default()
        },
        PipeParams {
            rain_m_per_s: -1.0,
            ..Default::default()
        },
    ] {
        assert!(PipeModel::new(p, &hf).is_err());
    }
}
