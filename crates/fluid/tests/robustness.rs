//! Hostile sizes, steps and parameters: a typed error naming the parameter,
//! never a panic, an overflow or a call that does not return.

use glam::Vec3;
use natura_fluid::FluidError;
use natura_fluid::grid::Dims;
use natura_fluid::liquid::{Liquid, LiquidParams, MAX_SUBSTEPS};
use natura_fluid::shape::Shape;

fn names(e: &FluidError, name: &str) -> bool {
    matches!(e, FluidError::InvalidParameter { name: n, .. } if *n == name)
}

#[test]
fn huge_dimensions_are_refused_without_overflow() {
    for (nx, ny, nz) in [
        (usize::MAX, 1, 1),
        (1, usize::MAX, 1),
        (usize::MAX, usize::MAX, usize::MAX),
        (1 << 11, 1 << 11, 1 << 11),
        (0, 4, 4),
    ] {
        assert!(
            matches!(Dims::new(nx, ny, nz), Err(FluidError::InvalidSize { .. })),
            "{nx}×{ny}×{nz}"
        );
    }
    assert!(Dims::new(1 << 10, 1 << 10, 1 << 10).is_ok());
}

fn pool(params: LiquidParams) -> Liquid {
    let d = Dims::plane(16, 8).unwrap();
    let h = 0.1;
    let mut l = Liquid::new(d, h, params).unwrap();
    l.fill(
        Shape::Cuboid {
            min: Vec3::ZERO,
            max: Vec3::new(0.8, h, 0.4),
        },
        Vec3::ZERO,
    )
    .unwrap();
    l
}

#[test]
fn a_step_longer_than_the_substep_cap_is_refused_up_front() {
    let mut l = pool(LiquidParams::default());
    let before = l.volume();
    for dt in [1e9f32, 1e6] {
        let e = l.step(dt).unwrap_err();
        assert!(names(&e, "dt"), "{e}");
        assert!(e.to_string().contains("MAX_SUBSTEPS"), "{e}");
    }
    // Nothing moved, and an ordinary step still works.
    assert_eq!(l.volume(), before);
    let r = l.step(0.05).unwrap();
    assert!(r.substeps >= 1 && r.substeps < MAX_SUBSTEPS);
    for dt in [0.0f32, -1.0, f32::NAN, f32::INFINITY] {
        assert!(names(&l.step(dt).unwrap_err(), "dt"), "{dt}");
    }
}

#[test]
fn absurd_gravity_and_cfl_name_themselves() {
    for g in [3e38f32, 1e5, f32::NAN] {
        let p = LiquidParams {
            gravity: Vec3::new(0.0, 0.0, -g),
            ..LiquidParams::default()
        };
        let e = Liquid::new(Dims::plane(8, 8).unwrap(), 0.1, p).unwrap_err();
        assert!(names(&e, "gravity"), "{g}: {e}");
    }
    for c in [1e30f32, 0.0, f32::NAN] {
        let p = LiquidParams {
            max_cfl: c,
            ..LiquidParams::default()
        };
        let e = Liquid::new(Dims::plane(8, 8).unwrap(), 0.1, p).unwrap_err();
        assert!(names(&e, "max_cfl"), "{c}: {e}");
    }
}
