//! Mirage tests: Gladstone–Dale values, straight rays in uniform air, the
//! inferior and superior mirages, reversibility, total internal reflection.

use super::*;
use crate::Dir3;
use glam::DVec3;

fn road() -> StratifiedAir {
    StratifiedAir::new(TemperatureProfile::hot_road(), 101_325.0).unwrap()
}

#[test]
fn gladstone_dale_sea_level() {
    // n − 1 ≈ 2.77e-4 at 15 °C, 1 atm; hotter air is thinner.
    let n = StratifiedAir::index_of(288.15, 101_325.0);
    assert!((n - 1.0 - 2.77e-4).abs() < 3e-6, "{}", n - 1.0);
    assert!(StratifiedAir::index_of(333.15, 101_325.0) < n);
    // The slope is the derivative of n(z).
    let air = road();
    for z in [0.01, 0.2, 1.0, 30.0] {
        let h = 1e-5;
        let fd = (air.n_and_slope(z + h).0 - air.n_and_slope(z - h).0) / (2.0 * h);
        assert!(
            (fd - air.n_and_slope(z).1).abs() < 1e-6 * fd.abs() + 1e-11,
            "{z}"
        );
    }
}

#[test]
fn uniform_medium_gives_straight_rays() {
    let t = GrinTracer {
        max_length_m: 500.0,
        ..GrinTracer::default()
    };
    let d = Dir3::new(DVec3::new(1.0, 0.3, 0.05)).unwrap();
    let o = DVec3::new(0.0, 0.0, 2.0);
    let p = t.trace(&UniformIndex(1.0003), o, d).unwrap();
    for q in &p.points {
        let along = (*q - o).dot(d.get());
        assert!(((*q - o) - d.get() * along).length() < 1e-9);
    }
    assert!((p.final_direction() - d.get()).length() < 1e-12);
}

#[test]
fn inferior_mirage_ray_turns_up_above_the_hot_layer() {
    let air = road();
    let t = GrinTracer {
        max_length_m: 2000.0,
        top_z: 50.0,
        ..GrinTracer::default()
    };
    // From 1.5 m, 0.12° below the horizontal: the ray bends back up before the road.
    let d = Dir3::from_angles(-0.12f64.to_radians(), 0.0).unwrap();
    let p = t.trace(&air, DVec3::new(0.0, 0.0, 1.5), d).unwrap();
    assert!(p.min_z() > 0.0, "min z {}", p.min_z());
    assert!(p.final_direction().z > 0.0, "{:?}", p.end);
    assert!(
        invariant_drift(&p, &air) < 1e-9,
        "{}",
        invariant_drift(&p, &air)
    );
    // Steeper rays reach the road.
    let steep = t
        .trace(
            &air,
            DVec3::new(0.0, 0.0, 1.5),
            Dir3::from_angles(-1f64.to_radians(), 0.0).unwrap(),
        )
        .unwrap();
    assert!(matches!(steep.end, PathEnd::Ground { .. }));
}

#[test]
fn superior_mirage_ray_bends_down_under_the_inversion() {
    let air = StratifiedAir::new(TemperatureProfile::cold_sea_inversion(), 101_325.0).unwrap();
    let t = GrinTracer {
        max_length_m: 30_000.0,
        top_z: 200.0,
        ..GrinTracer::default()
    };
    let d = Dir3::from_angles(0.05f64.to_radians(), 0.0).unwrap();
    let p = t.trace(&air, DVec3::new(0.0, 0.0, 5.0), d).unwrap();
    let zmax = p.points.iter().map(|q| q.z).fold(f64::MIN, f64::max);
    assert!(zmax < 30.0, "trapped below the inversion top: {zmax}");
    assert!(p.final_direction().z < 0.0 || matches!(p.end, PathEnd::Ground { .. }));
}

#[test]
fn paths_are_reversible() {
    let air = road();
    let t = GrinTracer {
        max_length_m: 600.0,
        top_z: 50.0,
        tolerance_m: 1e-11,
        ..GrinTracer::default()
    };
    let o = DVec3::new(0.0, 0.0, 1.5);
    let fwd = t
        .trace(
            &air,
            o,
            Dir3::from_angles(-0.1f64.to_radians(), 0.3).unwrap(),
        )
        .unwrap();
    let end = *fwd.points.last().unwrap();
    let back_dir = Dir3::new(-fwd.final_direction()).unwrap();
    let back = GrinTracer {
        max_length_m: fwd.length_m,
        ..t
    }
    .trace(&air, end, back_dir)
    .unwrap();
    let home = *back.points.last().unwrap();
    assert!((home - o).length() < 1e-5, "returned to {home}");
}

#[test]
fn total_internal_reflection_exactly_beyond_the_critical_angle() {
    let m = PlanarMirage::from_temperatures(0.5, 293.15, 333.15, 101_325.0).unwrap();
    let crit = m.critical_grazing_angle().unwrap();
    // About 0.46° for 60 °C ground air under 20 °C air.
    assert!(
        (crit.to_degrees() - 0.46).abs() < 0.03,
        "{}",
        crit.to_degrees()
    );
    let o = DVec3::new(0.0, 0.0, 2.0);
    let below = m
        .interact(o, Dir3::from_angles(-(crit * 0.999), 0.0).unwrap(), None)
        .unwrap();
    assert!(below.refracted.is_none() && below.reflectance == 1.0);
    assert!(below.reflected.get().z > 0.0);
    let above = m
        .interact(o, Dir3::from_angles(-(crit * 1.001), 0.0).unwrap(), None)
        .unwrap();
    assert!(above.refracted.is_some() && above.reflectance < 1.0);
    // Going up from the thin layer never reflects totally.
    let up = m
        .interact(
            DVec3::new(0.0, 0.0, 0.1),
            Dir3::from_angles(0.001, 0.0).unwrap(),
            None,
        )
        .unwrap();
    assert!(up.refracted.is_some());
    // A bumped normal changes the reflection but never yields NaN.
    let bump = Dir3::new(DVec3::new(0.01, 0.0, 1.0)).unwrap();
    let b = m
        .interact(o, Dir3::from_angles(-0.002, 0.0).unwrap(), Some(bump))
        .unwrap();
    assert!(b.reflected.get().is_finite());
    assert!(m.interact(o, Dir3::UP, None).is_none());
}

#[test]
fn bad_input_is_refused() {
    let t = GrinTracer::default();
    assert!(
        t.trace(&road(), DVec3::new(0.0, 0.0, -1.0), Dir3::X)
            .is_err()
    );
    assert!(
        GrinTracer {
            tolerance_m: 0.0,
            ..t
        }
        .trace(&road(), DVec3::new(0.0, 0.0, 1.0), Dir3::X)
        .is_err()
    );
    assert!(StratifiedAir::new(TemperatureProfile::hot_road(), -1.0).is_err());
    let bad = TemperatureProfile::HotSurface {
        air_k: f64::NAN,
        excess_k: 1.0,
        decay_m: 1.0,
        lapse_k_per_m: 0.0,
    };
    assert!(StratifiedAir::new(bad, 101_325.0).is_err());
    assert!(PlanarMirage::new(0.0, -1.0, 1.0).is_err());
    assert!(PlanarMirage::from_temperatures(0.0, 0.0, 300.0, 1e5).is_err());
}
