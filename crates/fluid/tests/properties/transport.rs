//! Advection, interpolation, tracing and diffusion: bounds, monotonicity,
//! obstacles, stability and energy.

use super::*;

fn swirl(d: Dims, h: f32) -> MacVelocity {
    MacVelocity::from_fn(d, h, |a, p| {
        let c = Vec3::splat(0.5);
        let r = p - c;
        match a {
            0 => -2.0 * r.z + 0.3,
            2 => 2.0 * r.x - 0.1,
            _ => 0.0,
        }
    })
    .unwrap()
}

#[test]
fn advection_keeps_constants_and_creates_no_extrema() {
    let d = Dims::plane(32, 32).unwrap();
    let h = 1.0 / 32.0;
    let v = swirl(d, h);
    let schemes = [
        AdvectionScheme::SemiLagrangian,
        AdvectionScheme::MacCormack,
        AdvectionScheme::Bfecc,
    ];
    let interps = [
        Interpolation::Linear,
        Interpolation::MonotoneCubic(CubicLimiter::FritschCarlson),
    ];
    let constant = Grid3::new(32, 1, 32, 2.5f32).unwrap();
    let bumpy = Grid3::from_fn(32, 1, 32, |i, _, k| noise(5, i + 32 * k)).unwrap();
    let (lo, hi) = bumpy.min_max();
    for scheme in schemes {
        for interpolation in interps {
            for dt in [0.01f32, 0.5, 5.0] {
                let adv = Advection {
                    scheme,
                    tracer: TraceIntegrator::Rk2,
                    interpolation,
                };
                let c = advect_scalar(&constant, &v, h, dt, &adv, None).unwrap();
                assert!(
                    c.as_slice().iter().all(|&x| (x - 2.5).abs() < 1e-6),
                    "{adv:?}"
                );
                let b = advect_scalar(&bumpy, &v, h, dt, &adv, None).unwrap();
                let (l2, h2) = b.min_max();
                assert!(
                    l2 >= lo - 1e-6 && h2 <= hi + 1e-6,
                    "{adv:?} dt {dt}: [{l2}, {h2}] vs [{lo}, {hi}]"
                );
            }
        }
    }
}

#[test]
fn monotone_cubic_keeps_monotone_data_monotone() {
    // A ramp with a jump advected by a uniform flow stays monotone.
    let d = Dims::plane(40, 4).unwrap();
    let h = 0.1;
    let data = [0.0f32, 10.0, 10.1, 10.2];
    let g = Grid3::from_fn(40, 1, 4, |i, _, _| data[(i / 10).min(3)] + 0.001 * i as f32).unwrap();
    let v = MacVelocity::from_fn(d, h, |a, _| if a == 0 { 0.37 } else { 0.0 }).unwrap();
    let adv = Advection {
        interpolation: Interpolation::MonotoneCubic(CubicLimiter::FritschCarlson),
        ..Default::default()
    };
    let out = advect_scalar(&g, &v, h, 0.1, &adv, None).unwrap();
    for k in 0..4 {
        for i in 1..40 {
            assert!(out[(i, 0, k)] >= out[(i - 1, 0, k)] - 1e-5);
        }
    }
    assert!(out.max() <= g.max() + 1e-5);
}

#[test]
fn traced_paths_never_end_inside_obstacles() {
    let d = Dims::plane(32, 32).unwrap();
    let h = 1.0 / 32.0;
    let kinds = obstacle_kinds(d, h);
    let v = swirl(d, h);
    for k in 0..32 {
        for i in 0..32 {
            if kinds[(i, 0, k)] == CellKind::Solid {
                continue;
            }
            let p = Vec3::new((i as f32 + 0.5) * h, 0.5 * h, (k as f32 + 0.5) * h);
            for dt in [0.05f32, 0.3] {
                let q = trace_back(p, &v, h, dt, TraceIntegrator::Rk2, Some(&kinds));
                let c = (q / h).floor();
                let (ci, ck) = (
                    (c.x.max(0.0) as usize).min(31),
                    (c.z.max(0.0) as usize).min(31),
                );
                assert_ne!(kinds[(ci, 0, ck)], CellKind::Solid, "{p} → {q}");
            }
        }
    }
}

#[test]
fn stable_fluids_are_unconditionally_stable() {
    let d = Dims::plane(32, 32).unwrap();
    let h = 1.0 / 32.0;
    let mut f = PeriodicFluid::new(
        d,
        h,
        StableParams {
            viscosity: 0.0,
            ..Default::default()
        },
    )
    .unwrap();
    for a in [0usize, 2] {
        for (i, x) in f.velocity_mut()[a].as_mut_slice().iter_mut().enumerate() {
            let [ii, _, kk] = d.ijk(i);
            let (x0, z0) = (
                ii as f32 * h * std::f32::consts::TAU,
                kk as f32 * h * std::f32::consts::TAU,
            );
            *x = if a == 0 {
                z0.sin() + 0.3 * (2.0 * x0).cos()
            } else {
                x0.cos()
            };
        }
    }
    f.project();
    let e0 = f.kinetic_energy();
    let umax = f.velocity()[0]
        .as_slice()
        .iter()
        .fold(0.0f32, |m, v| m.max(v.abs()));
    let dt = 100.0 * h / umax;
    for _ in 0..50 {
        let r = f.step(dt).unwrap();
        assert!(r.kinetic_energy.is_finite());
        assert!(r.kinetic_energy <= e0 * 1.01, "{} > {e0}", r.kinetic_energy);
    }
    // Bounded MAC version, with an obstacle.
    let mut b = BoundedFluid::new(
        d,
        h,
        StableParams {
            viscosity: 0.0,
            ..Default::default()
        },
    )
    .unwrap();
    b.add_obstacle(Obstacle::fixed(Shape::Sphere {
        centre: Vec3::new(0.5, 0.5 * h, 0.5),
        radius: 0.1,
    }))
    .unwrap();
    *b.velocity_mut() = swirl(d, h);
    b.project(0.01).unwrap();
    let e0 = b.velocity().kinetic_energy(h);
    for _ in 0..30 {
        let r = b.step(100.0 * h / 1.5).unwrap();
        assert!(r.kinetic_energy <= e0 * 1.01, "{} > {e0}", r.kinetic_energy);
    }
}

#[test]
fn diffusion_never_increases_energy() {
    let d = Dims::plane(24, 24).unwrap();
    let h = 1.0 / 24.0;
    let mut b = BoundedFluid::new(
        d,
        h,
        StableParams {
            viscosity: 0.05,
            ..Default::default()
        },
    )
    .unwrap();
    let id = b
        .add_substance(Substance {
            name: "dye".into(),
            diffusion: 0.01,
            dissipation: 0.0,
        })
        .unwrap();
    for (i, x) in b
        .substance_mut(id)
        .unwrap()
        .as_mut_slice()
        .iter_mut()
        .enumerate()
    {
        *x = noise(2, i).max(0.0);
    }
    let mass0 = b.substance(id).unwrap().sum();
    let l2 = |g: &Grid3<f32>| {
        g.as_slice()
            .iter()
            .map(|&v| f64::from(v).powi(2))
            .sum::<f64>()
    };
    let mut s_prev = l2(b.substance(id).unwrap());
    *b.velocity_mut() = swirl(d, h);
    b.project(0.01).unwrap();
    let mut e_prev = b.velocity().kinetic_energy(h);
    for _ in 0..5 {
        // Zero-velocity advection isolates diffusion for the scalar.
        let r = b.step(0.02).unwrap();
        assert!(
            r.kinetic_energy <= e_prev * (1.0 + 1e-4),
            "{} > {e_prev}",
            r.kinetic_energy
        );
        e_prev = r.kinetic_energy;
        let _ = s_prev;
        s_prev = l2(b.substance(id).unwrap());
    }
    // Diffusion alone (velocity zero) conserves the mass and lowers L2.
    let mut c = BoundedFluid::new(
        d,
        h,
        StableParams {
            viscosity: 0.0,
            ..Default::default()
        },
    )
    .unwrap();
    let id = c
        .add_substance(Substance {
            name: "dye".into(),
            diffusion: 0.01,
            dissipation: 0.0,
        })
        .unwrap();
    for (i, x) in c
        .substance_mut(id)
        .unwrap()
        .as_mut_slice()
        .iter_mut()
        .enumerate()
    {
        *x = noise(2, i).max(0.0);
    }
    let before = l2(c.substance(id).unwrap());
    c.step(0.05).unwrap();
    let after = l2(c.substance(id).unwrap());
    assert!(after < before);
    approx::assert_relative_eq!(c.substance(id).unwrap().sum(), mass0, max_relative = 1e-4);
}
