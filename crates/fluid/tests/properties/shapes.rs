//! The ellipsoid against brute force: its sign against the implicit
//! equation, its distance against the nearest of many surface points, its
//! bounds against sampled extremes.

use super::*;
use glam::Quat;

/// The ellipsoid of semi-axes (0.3, 0.12, 0.08), turned about two axes.
fn ellipsoid() -> (Shape, Vec3, Vec3, Quat) {
    let (centre, radii) = (Vec3::new(0.5, 0.4, 0.3), Vec3::new(0.3, 0.12, 0.08));
    let rotation = Quat::from_rotation_z(0.7) * Quat::from_rotation_x(0.4);
    (
        Shape::Ellipsoid {
            centre,
            radii,
            rotation,
        },
        centre,
        radii,
        rotation,
    )
}

/// Points on the surface, dense in both angles.
fn surface(centre: Vec3, radii: Vec3, rotation: Quat) -> Vec<Vec3> {
    let mut v = Vec::new();
    let (nu, nv) = (400, 200);
    for i in 0..nu {
        let a = std::f32::consts::TAU * i as f32 / nu as f32;
        for j in 0..=nv {
            let b = std::f32::consts::PI * j as f32 / nv as f32;
            let q = Vec3::new(b.sin() * a.cos(), b.sin() * a.sin(), b.cos()) * radii;
            v.push(centre + rotation * q);
        }
    }
    v
}

#[test]
fn the_ellipsoid_is_signed_exact_on_its_surface_and_bounded() {
    let (shape, centre, radii, rotation) = ellipsoid();
    shape.validate().unwrap();
    let pts = surface(centre, radii, rotation);
    // Zero on the surface.
    for p in pts.iter().step_by(97) {
        assert!(shape.sdf(*p).abs() < 1e-5, "{} at {p}", shape.sdf(*p));
    }
    // Sign from the implicit equation; the distance within the documented
    // factor of the nearest surface point's (and equal to first order close
    // to the surface).
    let ratio = radii.max_element() / radii.min_element();
    let mut seed = 7u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    for _ in 0..300 {
        let p = centre + Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 0.8;
        let q = rotation.inverse() * (p - centre);
        let inside = (q / radii).length() < 1.0;
        let d = shape.sdf(p);
        assert_eq!(d < 0.0, inside, "sign at {p}: {d}");
        let nearest = pts
            .iter()
            .map(|s| (*s - p).length())
            .fold(f32::MAX, f32::min);
        // The surface sampling is within about 0.005 m of any surface point.
        assert!(
            d.abs() <= nearest * ratio + 0.005 && d.abs() >= nearest / ratio - 0.005,
            "|{d}| against the nearest surface point at {nearest}"
        );
        if nearest < 0.01 {
            assert!(
                (d.abs() - nearest).abs() < 0.1 * nearest + 0.005,
                "{d} vs {nearest}"
            );
        }
    }
    // The bounds are the surface's extremes.
    let (lo, hi) = shape.bounds();
    let (mut slo, mut shi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for p in &pts {
        slo = slo.min(*p);
        shi = shi.max(*p);
    }
    assert!((lo - slo).abs().max_element() < 2e-3, "{lo} vs {slo}");
    assert!((hi - shi).abs().max_element() < 2e-3, "{hi} vs {shi}");
    // Moving it moves its zero set; turning it keeps its semi-axes.
    let m = shape.moved(Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.5));
    assert!(m.sdf(centre + Vec3::new(0.1, 0.0, 0.0)) < 0.0);
    match m {
        Shape::Ellipsoid { radii: r, .. } => assert_eq!(r, radii),
        other => panic!("{other:?}"),
    }
    // Degenerate or non-unit rotations are refused.
    for bad in [
        Shape::Ellipsoid {
            centre,
            radii: Vec3::new(0.1, 0.0, 0.1),
            rotation,
        },
        Shape::Ellipsoid {
            centre,
            radii,
            rotation: Quat::from_xyzw(0.0, 0.0, 0.0, 2.0),
        },
        Shape::Ellipsoid {
            centre: Vec3::new(f32::NAN, 0.0, 0.0),
            radii,
            rotation,
        },
    ] {
        assert!(bad.validate().is_err(), "{bad:?}");
    }
}
