//! natura-fluid: conservation, stability and oracle properties.

use glam::Vec3;
use natura_core::Grid3;
use natura_fluid::FluidError;
use natura_fluid::advect::{
    Advection, AdvectionScheme, TraceIntegrator, advect_scalar, trace_back,
};
use natura_fluid::fft::{FftVariant, solve_poisson_periodic};
use natura_fluid::grid::{Boundaries, CellKind, Dims, MacVelocity};
use natura_fluid::interp::{CubicLimiter, Interpolation};
use natura_fluid::levelset::LevelSet;
use natura_fluid::liquid::{Liquid, LiquidParams};
use natura_fluid::mac::{Projector, confinement_force, divergence};
use natura_fluid::pressure::{PoissonSystem, SolverParams};
use natura_fluid::shape::{Obstacle, Shape};
use natura_fluid::smoke::{Smoke, SmokeParams, SmokeSource};
use natura_fluid::stable::{BoundedFluid, PeriodicFluid, ScalarSource, StableParams, Substance};

mod control;
mod liquid;
mod pressure;
mod shapes;
mod smoke;
mod transport;

use liquid::dam_break;

fn noise(seed: u64, i: usize) -> f32 {
    ((natura_core::mix64(seed ^ (i as u64).wrapping_mul(0x9E37_79B9)) % 2001) as f32 / 1000.0) - 1.0
}

fn random_mac(d: Dims, seed: u64) -> MacVelocity {
    let mut v = MacVelocity::zeros(d).unwrap();
    for a in 0..3 {
        if d.active(a) {
            for (i, x) in v.comp_mut(a).as_mut_slice().iter_mut().enumerate() {
                *x = noise(seed + a as u64, i);
            }
        }
    }
    v
}

fn obstacle_kinds(d: Dims, h: f32) -> Grid3<CellKind> {
    let s = Shape::Sphere {
        centre: Vec3::new(0.4, 0.5 * h * d.ny as f32, 0.5),
        radius: 0.15,
    };
    Grid3::from_fn(d.nx, d.ny, d.nz, |i, j, k| {
        let p = Vec3::new(
            (i as f32 + 0.5) * h,
            (j as f32 + 0.5) * h,
            (k as f32 + 0.5) * h,
        );
        if s.sdf(p) < 0.0 {
            CellKind::Solid
        } else {
            CellKind::Fluid
        }
    })
    .unwrap()
}

#[test]
fn results_are_identical_on_one_and_two_threads() {
    let run_smoke = || {
        let d = Dims::plane(32, 48).unwrap();
        let mut s = Smoke::new(
            d,
            0.03,
            SmokeParams {
                advection: Advection {
                    interpolation: Interpolation::MonotoneCubic(CubicLimiter::FritschCarlson),
                    ..Default::default()
                },
                ..Default::default()
            },
        )
        .unwrap();
        s.add_source(SmokeSource {
            shape: Shape::Sphere {
                centre: Vec3::new(0.48, 0.015, 0.3),
                radius: 0.1,
            },
            density: 1.0,
            temperature: 330.0,
            velocity: None,
        })
        .unwrap();
        for _ in 0..8 {
            s.step(0.02).unwrap();
        }
        (s.density().clone(), s.velocity().clone())
    };
    let run_liquid = || {
        let mut l = dam_break(LiquidParams::default());
        for _ in 0..3 {
            l.step(0.05).unwrap();
        }
        (l.level_set().phi().clone(), l.particles().to_vec())
    };
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let (a1, b1) = pool(1).install(run_smoke);
    let (a2, b2) = pool(2).install(run_smoke);
    assert_eq!(a1, a2);
    assert_eq!(b1, b2);
    let (p1, q1) = pool(1).install(run_liquid);
    let (p2, q2) = pool(2).install(run_liquid);
    assert_eq!(p1, p2);
    assert_eq!(q1, q2);
}

#[test]
fn bad_input_gives_typed_errors() {
    assert!(matches!(
        Dims::new(0, 4, 4),
        Err(FluidError::InvalidSize { .. })
    ));
    assert!(matches!(
        Dims::plane(4, 0),
        Err(FluidError::InvalidSize { .. })
    ));
    let d = Dims::plane(16, 16).unwrap();
    let h = 0.1;
    assert!(matches!(
        BoundedFluid::new(
            d,
            h,
            StableParams {
                viscosity: -1.0,
                ..Default::default()
            }
        ),
        Err(FluidError::InvalidParameter {
            name: "viscosity",
            ..
        })
    ));
    assert!(matches!(
        Smoke::new(d, 0.0, SmokeParams::default()),
        Err(FluidError::InvalidParameter { .. })
    ));
    let mut s = Smoke::new(d, h, SmokeParams::default()).unwrap();
    for dt in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert!(
            matches!(
                s.step(dt),
                Err(FluidError::InvalidParameter { name: "dt", .. })
            ),
            "{dt}"
        );
    }
    let outside = SmokeSource {
        shape: Shape::Sphere {
            centre: Vec3::new(3.0, 0.05, 0.5),
            radius: 0.2,
        },
        density: 1.0,
        temperature: 300.0,
        velocity: None,
    };
    assert!(matches!(
        s.add_source(outside),
        Err(FluidError::OutsideGrid { .. })
    ));
    let mut b = BoundedFluid::new(d, h, StableParams::default()).unwrap();
    let id = b.add_substance(Substance::passive("dye")).unwrap();
    assert!(matches!(
        b.add_source(
            id,
            ScalarSource {
                shape: Shape::Cuboid {
                    min: Vec3::new(-0.5, 0.0, 0.0),
                    max: Vec3::new(0.2, 0.1, 0.2)
                },
                rate: 1.0
            }
        ),
        Err(FluidError::OutsideGrid { .. })
    ));
    assert!(matches!(
        Liquid::new(
            d,
            h,
            LiquidParams {
                viscosity: f32::NAN,
                ..Default::default()
            }
        ),
        Err(FluidError::InvalidParameter { .. })
    ));
    // A non-finite value is reported with its field and cell.
    s.velocity_mut().comp_mut(0)[(3, 0, 5)] = f32::NAN;
    match s.step(0.01) {
        Err(FluidError::NonFinite { field, .. }) => assert!(
            ["u", "w", "density", "temperature"].contains(&field),
            "{field}"
        ),
        other => panic!("expected NonFinite, got {other:?}"),
    }
}
