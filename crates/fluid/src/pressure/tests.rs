use super::*;
use crate::grid::Side;

fn rhs(n: usize, seed: u64) -> Vec<f32> {
    (0..n)
        .map(|i| {
            ((natura_core::mix64(seed ^ (i as u64).wrapping_mul(0x9e37)) % 2001) as f32 / 1000.0)
                - 1.0
        })
        .collect()
}

fn kinds_with_block(d: Dims) -> Vec<CellKind> {
    (0..d.cells())
        .map(|c| {
            let [i, _, k] = d.ijk(c);
            if (d.nx / 3..d.nx / 2).contains(&i) && (d.nz / 4..d.nz / 2).contains(&k) {
                CellKind::Solid
            } else {
                CellKind::Fluid
            }
        })
        .collect()
}

fn rel_residual(sys: &PoissonSystem, b: &[f32], x: &[f64]) -> f64 {
    // Residual against the compatible (mean-removed) b, in f64.
    let ax = sys.apply(x).unwrap();
    let mut pb = vec![0.0f32; sys.levels[0].len()];
    sys.pad_into(b, &mut pb);
    sys.project_null(&mut pb);
    let mut cb = vec![0.0f32; b.len()];
    sys.unpad_into(&pb, &mut cb);
    let num: f64 = cb
        .iter()
        .zip(&ax)
        .map(|(&p, &q)| (f64::from(p) - q).powi(2))
        .sum();
    let den: f64 = cb.iter().map(|&p| f64::from(p).powi(2)).sum();
    (num / den).sqrt()
}

#[test]
fn operator_is_symmetric_and_psd() {
    let d = Dims::new(9, 7, 6).unwrap();
    let kinds = kinds_with_block(d);
    let mut bounds = Boundaries::closed();
    bounds.z[1] = Side::Open;
    let sys = PoissonSystem::new(d, &kinds, &bounds, [false; 3]).unwrap();
    let a = rhs(d.cells(), 1);
    let b = rhs(d.cells(), 2);
    let mask = |v: &[f32]| -> Vec<f64> {
        v.iter()
            .zip(&kinds)
            .map(|(&x, &k)| {
                if k == CellKind::Fluid {
                    f64::from(x)
                } else {
                    0.0
                }
            })
            .collect()
    };
    let (a, b) = (mask(&a), mask(&b));
    let aa = sys.apply(&a).unwrap();
    let ab = sys.apply(&b).unwrap();
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(&p, &q)| p * q).sum::<f64>();
    approx::assert_relative_eq!(dot(&a, &ab), dot(&b, &aa), max_relative = 1e-5);
    assert!(dot(&a, &aa) > 0.0);
}

#[test]
fn all_solvers_reach_tolerance_with_obstacle() {
    for d in [Dims::plane(64, 48).unwrap(), Dims::new(20, 16, 24).unwrap()] {
        let kinds = kinds_with_block(d);
        for bounds in [Boundaries::closed(), Boundaries::open_top()] {
            let mut sys = PoissonSystem::new(d, &kinds, &bounds, [false; 3]).unwrap();
            let b: Vec<f32> = rhs(d.cells(), 7);
            for solver in [
                PressureSolver::Multigrid,
                PressureSolver::Mic0,
                PressureSolver::GaussSeidel,
            ] {
                let tol = if solver == PressureSolver::GaussSeidel {
                    1e-3
                } else {
                    1e-6
                };
                let params = SolverParams {
                    solver,
                    tolerance: tol,
                    max_iterations: 100_000,
                };
                let mut x = vec![0.0f64; d.cells()];
                let st = sys.solve(&b, &mut x, &params).unwrap();
                assert!(st.converged, "{solver:?} {d} {st:?}");
                let rel = rel_residual(&sys, &b, &x);
                assert!(
                    rel <= tol * 1.05 + 1e-6,
                    "{solver:?} {d}: reported {st:?}, true {rel}"
                );
                if solver == PressureSolver::Multigrid {
                    assert!(
                        st.iterations <= 25,
                        "MG-PCG took {} iterations on {d}",
                        st.iterations
                    );
                }
            }
        }
    }
}

#[test]
fn singular_compatibility_and_zero_mean() {
    let d = Dims::plane(32, 32).unwrap();
    let kinds = vec![CellKind::Fluid; d.cells()];
    let mut sys = PoissonSystem::new(d, &kinds, &Boundaries::closed(), [false; 3]).unwrap();
    assert_eq!(sys.singular_components(), 1);
    let b = vec![1.0f32; d.cells()]; // incompatible: all mean
    let mut x = vec![0.0f64; d.cells()];
    let st = sys.solve(&b, &mut x, &SolverParams::default()).unwrap();
    assert_eq!(st.iterations, 0);
    assert!(x.iter().all(|&v| v == 0.0));
    let b = rhs(d.cells(), 3);
    sys.solve(&b, &mut x, &SolverParams::default()).unwrap();
    let mean: f64 = x.iter().sum::<f64>() / x.len() as f64;
    assert!(mean.abs() < 1e-5, "{mean}");
}

#[test]
fn periodic_multigrid_solves() {
    let d = Dims::new(32, 1, 32).unwrap();
    let kinds = vec![CellKind::Fluid; d.cells()];
    let mut sys = PoissonSystem::new(d, &kinds, &Boundaries::closed(), [true; 3]).unwrap();
    assert!(sys.levels() > 1);
    let b = rhs(d.cells(), 5);
    let mut x = vec![0.0f64; d.cells()];
    let st = sys
        .solve(
            &b,
            &mut x,
            &SolverParams {
                tolerance: 1e-6,
                ..Default::default()
            },
        )
        .unwrap();
    assert!(st.converged && st.iterations < 30, "{st:?}");
    assert!(rel_residual(&sys, &b, &x) < 1.1e-6);
}

#[test]
fn stam_baseline_runs_fixed_sweeps() {
    let d = Dims::plane(16, 16).unwrap();
    let kinds = vec![CellKind::Fluid; d.cells()];
    let mut sys = PoissonSystem::new(d, &kinds, &Boundaries::open_top(), [false; 3]).unwrap();
    let b = rhs(d.cells(), 9);
    let mut x = vec![0.0f64; d.cells()];
    let st = sys
        .solve(&b, &mut x, &SolverParams::stam_baseline())
        .unwrap();
    assert_eq!(st.iterations, 20);
    assert!(st.relative_residual < 1.0 && st.relative_residual > 1e-4);
}

#[test]
fn bad_params_are_refused() {
    let d = Dims::plane(4, 4).unwrap();
    let kinds = vec![CellKind::Fluid; 16];
    let mut sys = PoissonSystem::new(d, &kinds, &Boundaries::closed(), [false; 3]).unwrap();
    let mut x = vec![0.0f64; 16];
    for p in [
        SolverParams {
            tolerance: f64::NAN,
            ..Default::default()
        },
        SolverParams {
            tolerance: 0.0,
            ..Default::default()
        },
        SolverParams {
            max_iterations: 0,
            ..Default::default()
        },
    ] {
        assert!(matches!(
            sys.solve(&[0.0; 16], &mut x, &p),
            Err(FluidError::InvalidParameter { .. })
        ));
    }
    let mut b = vec![0.0; 16];
    b[5] = f32::NAN;
    assert!(matches!(
        sys.solve(&b, &mut x, &SolverParams::default()),
        Err(FluidError::NonFinite { .. })
    ));
    assert!(matches!(
        sys.solve(&[0.0; 3], &mut x, &SolverParams::default()),
        Err(FluidError::SizeMismatch { .. })
    ));
}
