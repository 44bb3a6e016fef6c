//! natura-fluid throughput on 2 threads: 2-D stable fluids, 3-D smoke, and the
//! projection against Gauss–Seidel.
//!
//! * 2-D Stable Fluids, 512², bounded box, projection to relative residual 1e-5;
//! * 3-D smoke, 128³, vorticity confinement, same tolerance;
//! * the same projections solved by the Gauss–Seidel baseline to the same
//!   residual (one timed run each; when the sweep cap is reached the time to
//!   the tolerance is extrapolated from the measured asymptotic rate and
//!   marked as such).
//!
//! * the pressure solve alone on the step benchmarks' systems
//!   (`cargo bench --bench fluid -- pressure`).
//!
//! No crates.io fluid solver is a maintained peer; the Gauss–Seidel baseline
//! is the comparison that matters.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use natura::core::Grid3;
use natura::core::glam::Vec3;
use natura::fluid::grid::{Boundaries, CellKind, Dims};
use natura::fluid::pressure::{PoissonSystem, PressureSolver, SolverParams};
use natura::fluid::shape::{Obstacle, Shape};
use natura::fluid::smoke::{Smoke, SmokeParams, SmokeSource};
use natura::fluid::stable::{BoundedFluid, ForceSource, ScalarSource, StableParams, Substance};

const TOL: f64 = 1e-5;

/// Makes the global rayon pool two threads wide (ignored if already built).
fn two_threads() {
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build_global();
}

fn stable2d() -> BoundedFluid {
    let n = 512;
    let h = 1.0 / n as f32;
    let dims = Dims::plane(n, n).expect("dims");
    let params = StableParams {
        solver: SolverParams {
            tolerance: TOL,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut f = BoundedFluid::new(dims, h, params).expect("fluid");
    let dye = f
        .add_substance(Substance::passive("dye"))
        .expect("substance");
    let jet = Shape::Sphere {
        centre: Vec3::new(0.5, 0.5 * h, 0.15),
        radius: 0.05,
    };
    f.add_source(
        dye,
        ScalarSource {
            shape: jet,
            rate: 1.0,
        },
    )
    .expect("source");
    f.add_force_source(ForceSource {
        shape: jet,
        acceleration: Vec3::new(3.0, 0.0, 30.0),
    })
    .expect("force");
    f.add_obstacle(Obstacle::fixed(Shape::Sphere {
        centre: Vec3::new(0.45, 0.5 * h, 0.6),
        radius: 0.08,
    }))
    .expect("obstacle");
    f
}

fn smoke3d() -> Smoke {
    let n = 128;
    let h = 1.0 / n as f32;
    let dims = Dims::new(n, n, n).expect("dims");
    let params = SmokeParams {
        solver: SolverParams {
            tolerance: TOL,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut s = Smoke::new(dims, h, params).expect("smoke");
    s.add_source(SmokeSource {
        shape: Shape::Sphere {
            centre: Vec3::new(0.5, 0.5, 0.15),
            radius: 0.08,
        },
        density: 1.0,
        temperature: 330.0,
        velocity: Some(Vec3::new(0.0, 0.0, 0.5)),
    })
    .expect("source");
    s.add_obstacle(Obstacle::fixed(Shape::Sphere {
        centre: Vec3::new(0.45, 0.5, 0.6),
        radius: 0.12,
    }))
    .expect("obstacle");
    s
}

/// The pressure system a step of `name` last solved: the operator of its
/// cell kinds and `b = A p̃` with `p̃ = p·dt` the step's solution, so the
/// right-hand side is that projection's.
fn projection_system(
    pressure: &Grid3<f32>,
    dt: f32,
    kinds: &[CellKind],
    bounds: &Boundaries,
) -> (PoissonSystem, Vec<f32>) {
    let (nx, ny, nz) = pressure.dims();
    let d = Dims::new(nx, ny, nz).expect("dims");
    let sys = PoissonSystem::new(d, kinds, bounds, [false; 3]).expect("system");
    let p: Vec<f64> = pressure
        .as_slice()
        .iter()
        .map(|&v| f64::from(v) * f64::from(dt))
        .collect();
    let b: Vec<f32> = sys
        .apply(&p)
        .expect("apply")
        .iter()
        .map(|&v| v as f32)
        .collect();
    (sys, b)
}

/// Times MG-PCG and Gauss–Seidel, both from a zero guess, on the pressure
/// system the last step solved ([`projection_system`]) and prints the figures.
fn baseline(name: &str, sys: &mut PoissonSystem, b: &[f32], cap: u32) {
    let cells = sys.dims().cells();
    let mut x = vec![0.0f64; cells];
    let t = Instant::now();
    let mg = sys
        .solve(
            b,
            &mut x,
            &SolverParams {
                tolerance: TOL,
                ..Default::default()
            },
        )
        .expect("mg");
    let t_mg = t.elapsed();
    // Gauss–Seidel in chunks to observe its rate.
    let mut x = vec![0.0f64; cells];
    let chunk = (cap / 10).max(10);
    let mut total = 0u32;
    let mut rel = 1.0f64;
    let mut rate = 1.0f64;
    let t = Instant::now();
    while total < cap {
        let st = sys
            .solve(
                b,
                &mut x,
                &SolverParams {
                    solver: PressureSolver::GaussSeidel,
                    tolerance: TOL,
                    max_iterations: chunk,
                },
            )
            .expect("gs");
        total += st.iterations;
        rate = (st.relative_residual / rel).powf(1.0 / f64::from(st.iterations.max(1)));
        rel = st.relative_residual;
        if st.converged {
            break;
        }
    }
    let t_gs = t.elapsed().as_secs_f64();
    let (t_gs_full, note) = if rel <= TOL {
        (t_gs, "measured")
    } else {
        let more = (TOL / rel).ln() / rate.ln();
        (t_gs * (1.0 + more / f64::from(total)), "extrapolated")
    };
    println!(
        "{name}: MG-PCG {:.1} ms, {} iterations, residual {:.2e}; Gauss–Seidel {} sweeps → {:.2e} in {:.1} s, to {TOL:.0e}: {:.1} s ({note}); speed-up {:.0}×",
        t_mg.as_secs_f64() * 1e3,
        mg.iterations,
        mg.relative_residual,
        total,
        rel,
        t_gs,
        t_gs_full,
        t_gs_full / t_mg.as_secs_f64()
    );
}

/// The 2-D fluid after 21 steps (the state the step benchmark times).
fn stable2d_warm() -> BoundedFluid {
    let mut f = stable2d();
    for _ in 0..20 {
        f.step(0.002).expect("step");
    }
    let r = f.step(0.002).expect("step");
    println!(
        "stable2d_512: {} CG iterations, residual {:.2e}",
        r.pressure_iterations,
        r.pressure.map_or(0.0, |p| p.relative_residual)
    );
    f
}

/// The 3-D smoke after 5 steps (the state the step benchmark times).
fn smoke3d_warm() -> Smoke {
    let mut s = smoke3d();
    for _ in 0..4 {
        s.step(0.004).expect("step");
    }
    let r = s.step(0.004).expect("step");
    println!(
        "smoke3d_128: {} CG iterations, residual {:.2e}",
        r.pressure_iterations,
        r.pressure.map_or(0.0, |p| p.relative_residual)
    );
    s
}

fn stable2d_system(f: &BoundedFluid) -> (PoissonSystem, Vec<f32>) {
    projection_system(
        &f.pressure().expect("pressure"),
        0.002,
        f.cell_kinds().as_slice(),
        &Boundaries::closed(),
    )
}

fn smoke3d_system(s: &Smoke) -> (PoissonSystem, Vec<f32>) {
    let bounds = s.params().bounds;
    projection_system(
        &s.pressure().expect("pressure"),
        0.004,
        s.cell_kinds().as_slice(),
        &bounds,
    )
}

/// Whole steps. Each workload is set up inside its benchmark, so a filter
/// (`-- stable2d`, `-- smoke3d`) builds only what it runs; the Gauss–Seidel
/// comparison follows the step it belongs to.
fn steps(c: &mut Criterion) {
    two_threads();
    let mut g = c.benchmark_group("fluid");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(8));
    // 2-D Stable Fluids 512².
    let mut state: Option<BoundedFluid> = None;
    g.throughput(Throughput::Elements(512 * 512));
    g.bench_function("stable2d_512_bounded_step", |b| {
        let f = state.get_or_insert_with(stable2d_warm);
        b.iter(|| black_box(f.step(0.002).expect("step")))
    });
    if let Some(f) = state.take() {
        let (mut sys, b) = stable2d_system(&f);
        drop(f);
        baseline("stable2d_512 projection", &mut sys, &b, 20_000);
    }
    // 3-D smoke 128³ with confinement.
    let mut state: Option<Smoke> = None;
    g.throughput(Throughput::Elements(128 * 128 * 128));
    g.measurement_time(Duration::from_secs(15));
    g.bench_function("smoke3d_128_confinement_step", |b| {
        let s = state.get_or_insert_with(smoke3d_warm);
        b.iter(|| black_box(s.step(0.004).expect("step")))
    });
    if let Some(s) = state.take() {
        let (mut sys, b) = smoke3d_system(&s);
        drop(s);
        baseline("smoke3d_128 projection", &mut sys, &b, 1_000);
    }
    g.finish();
}

/// The pressure solve alone (MG-PCG from a zero guess to relative residual
/// 1e-5) on the systems the step benchmarks solve: `-- pressure`.
fn pressure(c: &mut Criterion) {
    two_threads();
    let mut g = c.benchmark_group("pressure");
    g.sample_size(20);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(8));
    let params = SolverParams {
        tolerance: TOL,
        ..Default::default()
    };
    type System = Option<(PoissonSystem, Vec<f32>, Vec<f64>)>;
    let mut state: System = None;
    g.throughput(Throughput::Elements(512 * 512));
    g.bench_function("mgpcg_stable2d_512", |bch| {
        let (sys, b, x) = state.get_or_insert_with(|| {
            let (sys, b) = stable2d_system(&stable2d_warm());
            let x = vec![0.0; b.len()];
            (sys, b, x)
        });
        bch.iter(|| {
            x.fill(0.0);
            black_box(sys.solve(b, x, &params).expect("solve"))
        })
    });
    let mut state: System = None;
    g.throughput(Throughput::Elements(128 * 128 * 128));
    g.bench_function("mgpcg_smoke3d_128", |bch| {
        let (sys, b, x) = state.get_or_insert_with(|| {
            let (sys, b) = smoke3d_system(&smoke3d_warm());
            let x = vec![0.0; b.len()];
            (sys, b, x)
        });
        bch.iter(|| {
            x.fill(0.0);
            black_box(sys.solve(b, x, &params).expect("solve"))
        })
    });
    g.finish();
}

criterion_group!(fluid, steps, pressure);
criterion_main!(fluid);
