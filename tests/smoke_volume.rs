//! natura-fluid's smoke rendered by natura-volume: the two crates meet only
//! here and in the smoke3d example, through plain grids
//! (`SmokeVolume::from_solver`), so neither depends on the other.

use natura::core::Grid3;
use natura::core::glam::Vec3;
use natura::fluid::grid::Dims;
use natura::fluid::smoke::{Smoke, SmokeParams};
use natura::volume::grid::SmokeVolume;
use natura::volume::{Density, VolumeError};

#[test]
fn a_solver_s_smoke_becomes_a_volume() {
    let mut s = Smoke::new(Dims::new(12, 12, 16).unwrap(), 0.1, SmokeParams::default()).unwrap();
    s.density_mut()[(6, 6, 2)] = 1.0;
    // An advection undershoot: a tiny negative density reads as empty.
    s.density_mut()[(2, 2, 2)] = -1e-4;
    s.temperature_mut()[(6, 6, 2)] = 400.0;
    let v = SmokeVolume::from_solver(
        s.density(),
        s.temperature().clone(),
        s.h(),
        s.params().ambient_temperature,
    )
    .unwrap();
    let c = Vec3::new(6.5, 6.5, 2.5) * 0.1;
    assert!((v.density.density(c) - 1.0).abs() < 1e-6);
    assert!(v.temperature.density(c) > v.ambient);
    assert_eq!(v.density.density(Vec3::new(2.5, 2.5, 2.5) * 0.1), 0.0);
    assert_eq!(v.ambient, s.params().ambient_temperature);

    // A NaN voxel is refused, and so is a plain negative density given
    // directly (not through a solver).
    let mut nan = s.density().clone();
    nan[(0, 0, 0)] = f32::NAN;
    assert!(SmokeVolume::from_solver(&nan, s.temperature().clone(), 0.1, 293.0).is_err());
    let mut bad = Grid3::new(12, 12, 16, 0.0f32).unwrap();
    bad[(0, 0, 0)] = -1.0;
    assert!(matches!(
        SmokeVolume::from_grids(bad, None, Vec3::ZERO, 0.1, 293.0),
        Err(VolumeError::BadVoxel { .. })
    ));
}
