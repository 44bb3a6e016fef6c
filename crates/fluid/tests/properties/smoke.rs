//! Smoke: vorticity confinement, buoyancy and object rules.

use super::*;

fn vortex(d: Dims, h: f32) -> MacVelocity {
    // A Gaussian (Lamb–Oseen-like) vortex in the x–z plane.
    MacVelocity::from_fn(d, h, |a, p| {
        let r = p - Vec3::new(0.5, p.y, 0.5);
        let s = (-(r.length_squared()) / (2.0 * 0.08f32.powi(2))).exp();
        match a {
            0 => -r.z * s * 20.0,
            2 => r.x * s * 20.0,
            _ => 0.0,
        }
    })
    .unwrap()
}

#[test]
fn confinement_adds_energy_where_vorticity_is_concentrated() {
    let d = Dims::plane(48, 48).unwrap();
    let h = 1.0 / 48.0;
    let v = vortex(d, h);
    let f = confinement_force(&v, h, 2.0).unwrap();
    let u = natura_fluid::mac::centre_velocity(&v).unwrap();
    let mut pos = 0.0f64;
    let mut neg = 0.0f64;
    for c in 0..d.cells() {
        let p = f64::from(
            f[0].as_slice()[c] * u[0].as_slice()[c] + f[2].as_slice()[c] * u[2].as_slice()[c],
        );
        if p > 0.0 { pos += p } else { neg -= p }
    }
    assert!(pos > 5.0 * neg, "f·u: +{pos} / −{neg}");
    // ε = 0 gives no force at all, and one smoke step with ε > 0 keeps more energy.
    assert!(
        confinement_force(&v, h, 0.0)
            .unwrap()
            .iter()
            .all(|g| g.as_slice().iter().all(|&x| x == 0.0))
    );
    let run = |eps: f32| {
        let mut s = Smoke::new(
            d,
            h,
            SmokeParams {
                epsilon: eps,
                bounds: Boundaries::closed(),
                ..Default::default()
            },
        )
        .unwrap();
        *s.velocity_mut() = v.clone();
        s.step(0.01).unwrap().kinetic_energy
    };
    assert!(run(2.0) > run(0.0));
}

#[test]
fn hot_smoke_rises_and_objects_follow_the_rules() {
    let d = Dims::plane(24, 40).unwrap();
    let h = 0.05;
    let mut s = Smoke::new(d, h, SmokeParams::default()).unwrap();
    s.add_obstacle(Obstacle {
        temperature: Some(400.0),
        ..Obstacle::fixed(Shape::Cuboid {
            min: Vec3::new(0.2, 0.0, 1.2),
            max: Vec3::new(0.5, h, 1.5),
        })
    })
    .unwrap();
    s.add_source(SmokeSource {
        shape: Shape::Sphere {
            centre: Vec3::new(0.6, 0.5 * h, 0.3),
            radius: 0.12,
        },
        density: 1.0,
        temperature: 340.0,
        velocity: None,
    })
    .unwrap();
    let centroid = |s: &Smoke| {
        let g = s.density();
        let (mut m, mut z) = (0.0f64, 0.0f64);
        for (c, &v) in g.as_slice().iter().enumerate() {
            m += f64::from(v);
            z += f64::from(v) * (d.ijk(c)[2] as f64);
        }
        z / m
    };
    for _ in 0..5 {
        s.step(0.02).unwrap();
    }
    let z0 = centroid(&s);
    for _ in 0..20 {
        s.step(0.02).unwrap();
    }
    assert!(centroid(&s) > z0 + 0.5);
    for (c, k) in s.cell_kinds().as_slice().iter().enumerate() {
        if *k == CellKind::Solid {
            assert_eq!(s.temperature().as_slice()[c], 400.0);
        }
    }
}
