//! Settings the renderers cannot carry out are refused up front, naming
//! what the user set: a medium too thick for delta tracking to cross, a
//! camera too far for `f32` to resolve the mean free path, a grid whose
//! majorant overflows, a density that is NaN, negative or above its bound,
//! a phase function or albedo outside its domain.

use glam::Vec3;
use natura_core::{Aabb, Grid3};
use natura_volume::VolumeError;
use natura_volume::density::Homogeneous;
use natura_volume::grid::GridDensity;
use natura_volume::phase::CloudPhase;
use natura_volume::transport::reference::MAX_COLLISIONS_PER_RAY;
use natura_volume::transport::{
    FastRenderer, FastSettings, LookAtCamera, MediumParams, ReferenceRenderer, ReferenceSettings,
    Scene, Solid, SolidShape,
};

fn medium(extinction: f32) -> MediumParams {
    MediumParams {
        extinction,
        albedo: 0.5,
        phase: CloudPhase::Isotropic,
    }
}

fn unit_cube() -> Aabb {
    Aabb {
        min: Vec3::ZERO,
        max: Vec3::ONE,
    }
}

fn one_pixel(position: Vec3) -> LookAtCamera {
    LookAtCamera::look_at(
        position,
        Vec3::splat(0.5),
        Vec3::Z,
        30f32.to_radians(),
        1,
        1,
    )
    .unwrap()
}

fn quick() -> ReferenceSettings {
    ReferenceSettings {
        samples_per_pixel: 1,
        ..ReferenceSettings::default()
    }
}

fn refused_naming<T: std::fmt::Debug>(r: Result<T, VolumeError>, field: &str) -> String {
    match r {
        Err(e @ VolumeError::InvalidParameter { name, .. }) => {
            assert_eq!(name, field, "{e}");
            e.to_string()
        }
        other => panic!("expected a refusal naming `{field}`, got {other:?}"),
    }
}

#[test]
fn the_reference_refuses_a_medium_too_thick_to_cross() {
    let cube = Homogeneous::new(unit_cube(), 1.0).unwrap();
    // 1e9 1/m over a 1.7 m diagonal: 1.7e9 null collisions per crossing,
    // and a mean free path far below f32's resolution of the distances.
    for extinction in [1e9, 1e8, 1e6] {
        let scene = Scene::new(&cube, medium(extinction), Vec3::ONE);
        let msg = refused_naming(ReferenceRenderer::new(&scene, quick()), "extinction");
        assert!(msg.contains("131072"), "{msg}");
    }
    // At the bound the renderer is built, and one pixel's work is bounded by it.
    let ext = MAX_COLLISIONS_PER_RAY / 3f32.sqrt() * 0.999;
    let scene = Scene::new(&cube, medium(ext), Vec3::ONE);
    assert!(ReferenceRenderer::new(&scene, quick()).is_ok());
}

#[test]
fn the_reference_refuses_a_camera_too_far_to_resolve_the_mean_free_path() {
    let cube = Homogeneous::new(unit_cube(), 1.0).unwrap();
    let scene = Scene::new(&cube, medium(50.0), Vec3::ONE);
    let r = ReferenceRenderer::new(&scene, quick()).unwrap();
    assert!(r.render(&one_pixel(Vec3::new(4.0, -3.0, 2.0))).is_ok());
    // 50 1/m seen from 10 km: 5e5 expected collisions along the eye ray.
    let msg = refused_naming(r.render(&one_pixel(Vec3::new(1e4, 0.0, 0.5))), "extinction");
    assert!(msg.contains("camera"), "{msg}");
}

#[test]
fn both_renderers_refuse_a_grid_whose_majorant_overflows() {
    let mut g = Grid3::new(4, 4, 4, 0.1f32).unwrap();
    g[(2, 1, 3)] = 3e38;
    let grid = GridDensity::new(g, Vec3::ZERO, 0.25).unwrap();
    let scene = Scene::new(&grid, medium(1.0), Vec3::ONE);
    let fast = refused_naming(
        FastRenderer::new(&scene, FastSettings::default()),
        "majorant",
    );
    let reference = refused_naming(ReferenceRenderer::new(&scene, quick()), "majorant");
    assert_eq!(fast, reference);
    assert!(fast.contains("3e38") && fast.contains("1e9"), "{fast}");
}

#[test]
fn the_reference_tracks_a_ray_that_starts_far_from_a_dense_box() {
    // A dense medium within the collision bound (86 600 expected collisions
    // along the diagonal), entered by a ray from 10 000 km away, as the sun
    // rays from a distant ground point under a low sun are: tracked from
    // the origin, each free flight (about 2e-5 m) was below f32's
    // resolution of the distance (1 m at 1e7) and the walk never ended.
    // Empty but for one voxel off the ray, so every tentative collision is null.
    let mut g = Grid3::new(4, 4, 4, 0.0f32).unwrap();
    g[(3, 3, 3)] = 1.0;
    let grid = GridDensity::new(g, Vec3::ZERO, 0.25).unwrap();
    let scene = Scene::new(&grid, medium(50_000.0), Vec3::ONE);
    let r = ReferenceRenderer::new(&scene, quick()).unwrap();
    let mut rng = natura_core::Seed(3).rng();
    for origin in [Vec3::new(-1e7, 0.5, 0.5), Vec3::new(0.5, 0.5, -3e6)] {
        let d = (Vec3::splat(0.5) - origin).normalize();
        let l = r.radiance(origin, d, &mut rng);
        assert!(l.is_finite() && l.min_element() >= 0.0, "{l}");
    }
}

/// A field that goes wrong inside one corner of its box: NaN, negative, or
/// above the bound it declares.
struct Faulty(f32);

impl natura_volume::Density for Faulty {
    fn density(&self, p: Vec3) -> f32 {
        if p.x > 0.7 && p.y > 0.7 && p.z > 0.7 {
            self.0
        } else {
            0.5
        }
    }
    fn bounds(&self) -> Aabb {
        unit_cube()
    }
    fn bound_in(&self, _: &Aabb) -> f32 {
        1.0
    }
    fn max_density(&self) -> f32 {
        1.0
    }
}

#[test]
fn both_renderers_refuse_a_density_that_is_nan_negative_or_above_its_bound() {
    for (value, field) in [
        (f32::NAN, "density"),
        (-0.25, "density"),
        (f32::INFINITY, "density"),
        (1.5, "max_density"),
    ] {
        let field_ = Faulty(value);
        let scene = Scene::new(&field_, medium(1.0), Vec3::ONE);
        let fast = refused_naming(FastRenderer::new(&scene, FastSettings::default()), field);
        let reference = refused_naming(ReferenceRenderer::new(&scene, quick()), field);
        assert_eq!(fast, reference);
        assert!(fast.contains(" at ("), "{fast}");
    }
    // The same field within its bound is accepted.
    let fine = Faulty(0.9);
    let scene = Scene::new(&fine, medium(1.0), Vec3::ONE);
    assert!(FastRenderer::new(&scene, FastSettings::default()).is_ok());
}

#[test]
fn a_cylinder_without_height_is_refused() {
    let cube = Homogeneous::new(unit_cube(), 1.0).unwrap();
    for h in [0.0, -0.1, f32::NAN, f32::INFINITY] {
        let scene = Scene {
            solids: vec![Solid {
                centre: Vec3::splat(0.5),
                radius: 0.2,
                albedo: Vec3::splat(0.5),
                sky_irradiance: Vec3::ZERO,
                shape: SolidShape::Cylinder { half_height: h },
            }],
            ..Scene::new(&cube, medium(1.0), Vec3::ONE)
        };
        refused_naming(
            FastRenderer::new(&scene, FastSettings::default()),
            "solid.shape.half_height",
        );
        refused_naming(
            ReferenceRenderer::new(&scene, quick()),
            "solid.shape.half_height",
        );
    }
}

/// A phase function outside its domain (`|g| ≥ 1`, a droplet size outside
/// the cloud phase's fitted table) or an albedo above 1 or NaN is refused by
/// both renderers, naming the key, before any work.
#[test]
fn both_renderers_refuse_a_phase_or_albedo_outside_its_domain() {
    let density = Homogeneous::new(unit_cube(), 1.0).unwrap();
    let with = |albedo: f32, phase: CloudPhase| MediumParams {
        extinction: 1.0,
        albedo,
        phase,
    };
    for (m, field) in [
        (with(0.5, CloudPhase::HenyeyGreenstein(1.0)), "g"),
        (with(0.5, CloudPhase::HenyeyGreenstein(-1.2)), "g"),
        (with(0.5, CloudPhase::HenyeyGreenstein(f32::NAN)), "g"),
        (
            with(0.5, CloudPhase::Cloud { diameter_um: 2.0 }),
            "diameter_um",
        ),
        (
            with(0.5, CloudPhase::Cloud { diameter_um: 80.0 }),
            "diameter_um",
        ),
        (with(1.5, CloudPhase::Isotropic), "albedo"),
        (with(f32::NAN, CloudPhase::Isotropic), "albedo"),
    ] {
        let scene = Scene::new(&density, m, Vec3::ONE);
        let fast = refused_naming(FastRenderer::new(&scene, FastSettings::default()), field);
        let reference = refused_naming(ReferenceRenderer::new(&scene, quick()), field);
        assert_eq!(fast, reference);
    }
}
