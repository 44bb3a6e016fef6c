use super::*;
use natura_core::{NoProgress, Seed};

fn tilted(n: usize) -> HeightField {
    let s = Seed(8);
    HeightField::from_fn(n, n, 1.0, |i, j| {
        50.0 + 0.3 * i as f32 + 0.1 * j as f32 + 2.0 * s.gaussian2(i as i64, j as i64) as f32
    })
    .unwrap()
}

fn totals(m: &MusgraveHydraulic, hf: &HeightField) -> (f64, f64) {
    (hf.heights().sum() + m.sediment().sum(), m.water().sum())
}

/// Erratum 1: over capacity, the excess settles at `v`, the cell the
/// water leaves (Musgrave 1993, §2.4.1), not at the receiving `u` as
/// Musgrave et al. 1989, §4.1 prints. A 3 × 3 field, flat but for a
/// raised centre holding water and more sediment than the water can
/// carry: after one step the centre has risen by exactly
/// `K_d (s − C_s)` and the eight receivers have not moved (the printed
/// rule would raise them and leave the centre as it was).
#[test]
fn deposition_over_capacity_lands_where_the_water_leaves() {
    let mut hf =
        HeightField::from_fn(3, 3, 1.0, |i, j| if (i, j) == (1, 1) { 0.1 } else { 0.0 }).unwrap();
    let p = MusgraveParams {
        rain_period: 0,
        ..Default::default()
    };
    let mut m = MusgraveHydraulic::new(p.clone(), &hf).unwrap();
    let mut w = Grid2::new(3, 3, 0.0f32).unwrap();
    w[(1, 1)] = 0.05;
    m.set_water(w).unwrap();
    let s_v = 1.0f32;
    m.sediment[(1, 1)] = s_v;
    m.run(&mut hf, 1, &NoProgress).unwrap();
    // All 0.05 m of water leaves (half the 0.15 m drop would be more),
    // carrying C_s = K_c·ΔW; K_d of the excess settles at the centre.
    let c_s = p.k_c as f32 * 0.05;
    let settled = p.k_d as f32 * (s_v - c_s);
    let h = hf.heights();
    assert!(
        (h[(1, 1)] - (0.1 + settled)).abs() < 1e-6,
        "centre {}",
        h[(1, 1)]
    );
    for (i, j) in (0..3).flat_map(|i| (0..3).map(move |j| (i, j))) {
        if (i, j) != (1, 1) {
            assert_eq!(h[(i, j)], 0.0, "receiver ({i}, {j})");
        }
    }
    // Nothing is lost: the bed, the suspended load and what was carried
    // add up to the centre's 0.1 m and its 1 m of sediment.
    let total = h.sum() + m.sediment().sum();
    assert!((total - 1.1).abs() < 1e-5, "{total}");
}

#[test]
fn conserves_material_and_water_closed() {
    let mut hf = tilted(32);
    let mut m = MusgraveHydraulic::new(
        MusgraveParams {
            rain_period: 20,
            ..Default::default()
        },
        &hf,
    )
    .unwrap();
    let (mat0, _) = totals(&m, &hf);
    m.run(&mut hf, 500, &NoProgress).unwrap();
    let (mat, water) = totals(&m, &hf);
    let l = m.ledger();
    assert!((mat - mat0).abs() <= 1e-4 * mat0, "material {mat0} → {mat}");
    assert!(
        (water - l.rain).abs() <= 1e-4 * l.rain,
        "water {water} vs rain {}",
        l.rain
    );
    assert!(m.water().min() >= 0.0 && m.sediment().min() >= 0.0);
}

#[test]
fn conserves_with_open_edges_and_evaporation() {
    let mut hf = tilted(24);
    let p = MusgraveParams {
        edges: Edges::Open,
        evaporation: 0.01,
        rain_period: 10,
        ..Default::default()
    };
    let mut m = MusgraveHydraulic::new(p, &hf).unwrap();
    let (mat0, _) = totals(&m, &hf);
    m.run(&mut hf, 500, &NoProgress).unwrap();
    let (mat, water) = totals(&m, &hf);
    let l = m.ledger();
    assert!(l.outflow_water > 0.0 && l.evaporated > 0.0);
    assert!((mat + l.outflow_sediment - mat0).abs() <= 1e-4 * mat0);
    let budget = l.rain - l.evaporated - l.outflow_water;
    assert!(
        (water - budget).abs() <= 1e-4 * l.rain,
        "{water} vs {budget}"
    );
}

#[test]
fn fixed_points() {
    // Dry terrain is unchanged; a flat lake is unchanged.
    let mut hf = tilted(12);
    let before = hf.clone();
    let mut m = MusgraveHydraulic::new(
        MusgraveParams {
            rain_period: 0,
            ..Default::default()
        },
        &hf,
    )
    .unwrap();
    m.run(&mut hf, 5, &NoProgress).unwrap();
    assert_eq!(hf, before);
    let mut flat = HeightField::flat(8, 8, 1.0, 10.0).unwrap();
    let mut m = MusgraveHydraulic::new(
        MusgraveParams {
            rain_period: 0,
            ..Default::default()
        },
        &flat,
    )
    .unwrap();
    m.set_water(Grid2::new(8, 8, 0.5).unwrap()).unwrap();
    m.run(&mut flat, 5, &NoProgress).unwrap();
    assert!(m.water().as_slice().iter().all(|&w| w == 0.5));
    assert!(flat.heights().as_slice().iter().all(|&a| a == 10.0));
}

#[test]
fn equalising_transfer_never_inverts_levels() {
    let mut hf = HeightField::from_fn(3, 3, 1.0, |_, _| 0.0).unwrap();
    let mut m = MusgraveHydraulic::new(
        MusgraveParams {
            rain_period: 0,
            k_c: 0.0,
            neighbourhood: Neighbourhood::Four,
            ..Default::default()
        },
        &hf,
    )
    .unwrap();
    let mut w = Grid2::new(3, 3, 0.0f32).unwrap();
    w[(0, 0)] = 4.0;
    m.set_water(w).unwrap();
    let mut prev = 4.0f32;
    for _ in 0..20 {
        m.step(&mut hf).unwrap();
        let corner = m.water()[(0, 0)];
        assert!(corner <= prev + 1e-6 && corner >= 0.0);
        prev = corner;
    }
}

#[test]
fn refuses_bad_params() {
    let hf = tilted(8);
    for p in [
        MusgraveParams {
            k_d: 1.5,
            ..Default::default()
        },
        MusgraveParams {
            k_s: -0.1,
            ..Default::default()
        },
        MusgraveParams {
            k_c: f64::NAN,
            ..Default::default()
        },
        MusgraveParams {
            transfer: 0.0,
            ..Default::default()
        },
        MusgraveParams {
            rain: RainLaw::Uniform { depth_m: -1.0 },
            ..Default::default()
        },
        MusgraveParams {
            rain: RainLaw::AltitudeLinear {
                k: 1e9,
                base_m: 0.0,
            },
            ..Default::default()
        },
    ] {
        assert!(MusgraveHydraulic::new(p, &hf).is_err());
    }
}

/// The source's constants (Musgrave et al. 1989, §4.1 and Plate 9):
/// `K_c = 5`, `K_d = 0.1`, `K_s = 0.3`, rain of `0.001·a` every 65 steps.
/// The rain schedule is checked by what it does: on a closed field
/// without evaporation the water total rises on steps 0, 65 and 130 (by
/// `0.001·a` summed over the cells, `a` the altitude) and at no other step.
#[test]
fn the_source_constants_and_rain_every_65_steps() {
    let p = MusgraveParams::default();
    assert_eq!((p.k_c, p.k_d, p.k_s), (5.0, 0.1, 0.3));
    assert_eq!(
        p.rain,
        RainLaw::AltitudeLinear {
            k: 0.001,
            base_m: 0.0
        }
    );
    assert_eq!(p.rain_period, 65);
    assert_eq!(p.evaporation, 0.0);
    let mut hf = tilted(12);
    let mut m = MusgraveHydraulic::new(p, &hf).unwrap();
    let mut rained = Vec::new();
    for step in 0..140u32 {
        let before = m.water().sum();
        // The rain of this step, from the bed as it is before the step.
        let due: f64 = hf
            .heights()
            .as_slice()
            .iter()
            .map(|&a| 0.001 * f64::from(a))
            .sum();
        m.run(&mut hf, 1, &NoProgress).unwrap();
        let added = m.water().sum() - before;
        if added.abs() > 1e-4 {
            assert!(
                (added - due).abs() < 1e-3 * due,
                "step {step}: {added} m³ of rain, the law gives {due}"
            );
            rained.push(step);
        }
    }
    assert_eq!(rained, [0, 65, 130]);
}
