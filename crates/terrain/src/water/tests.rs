use natura_core::{Grid2, HeightField, Seed};

use super::*;
use crate::TerrainError;

/// A bowl: a rim of height 10 around a closed basin of depth 4 below a spill
/// notch at 8 on one side, on a 20 × 20 field.
fn basin() -> HeightField {
    HeightField::from_fn(20, 20, 5.0, |i, j| {
        let edge = i == 0 || j == 0 || i == 19 || j == 19;
        let rim = i == 2 || j == 2 || i == 17 || j == 17;
        if edge {
            0.0
        } else if rim && i == 2 && j == 10 {
            8.0
        } else if rim {
            10.0
        } else if (3..17).contains(&i) && (3..17).contains(&j) {
            4.0
        } else {
            1.0
        }
    })
    .unwrap()
}

#[test]
fn a_closed_basin_fills_to_its_spill_height() {
    let hf = basin();
    let s = water_surface(&hf, -5.0, &LakeParams::default()).unwrap();
    // Priority-Flood+ε: the lake lies level at the notch, a few ulps above it.
    for j in 3..17 {
        for i in 3..17 {
            let w = s.heights()[(i, j)];
            assert!((8.0..8.001).contains(&w), "({i}, {j}): {w}");
        }
    }
    // Dry land stays, the rim included.
    assert_eq!(s.heights()[(5, 2)], 10.0);
    assert_eq!(s.heights()[(0, 0)], 0.0);
}

#[test]
fn shallow_or_small_lakes_stay_dry_and_the_sea_covers_the_low_land() {
    let hf = basin();
    let deep = LakeParams {
        min_depth_m: 5.0,
        ..LakeParams::default()
    };
    let s = water_surface(&hf, 0.5, &deep).unwrap();
    assert_eq!(s.heights()[(10, 10)], 4.0);
    assert_eq!(s.heights()[(0, 0)], 0.5);
    let few = LakeParams {
        min_cells: 14 * 14 + 1,
        ..LakeParams::default()
    };
    let s = water_surface(&hf, -5.0, &few).unwrap();
    assert_eq!(s.heights()[(10, 10)], 4.0);
    // Never below the terrain.
    let s = water_surface(&hf, 3.0, &LakeParams::default()).unwrap();
    for (w, h) in s.heights().as_slice().iter().zip(hf.heights().as_slice()) {
        assert!(w >= h);
    }
}

#[test]
fn water_surface_refuses_a_nan_level_or_depth() {
    let hf = basin();
    assert!(matches!(
        water_surface(&hf, f32::NAN, &LakeParams::default()),
        Err(TerrainError::InvalidParameter { name: "sea", .. })
    ));
    let bad = LakeParams {
        min_depth_m: f32::NAN,
        ..LakeParams::default()
    };
    assert!(matches!(
        water_surface(&hf, 0.0, &bad),
        Err(TerrainError::InvalidParameter {
            name: "min_depth_m",
            ..
        })
    ));
}

#[test]
fn components_below_the_minimum_size_are_dropped() {
    // A 3-cell bar, a diagonal pair (two 1-cell components) and a 2 × 2 block.
    let on = [
        (0, 0),
        (1, 0),
        (2, 0),
        (5, 5),
        (6, 6),
        (3, 3),
        (4, 3),
        (3, 4),
        (4, 4),
    ];
    let mask = Grid2::from_fn(8, 8, |i, j| on.contains(&(i, j))).unwrap();
    let k = large_components(&mask, 3).unwrap();
    for j in 0..8 {
        for i in 0..8 {
            let big = on.contains(&(i, j)) && (i, j) != (5, 5) && (i, j) != (6, 6);
            assert_eq!(k[(i, j)], big, "({i}, {j})");
        }
    }
    assert_eq!(large_components(&mask, 0).unwrap(), mask);
    assert!(
        large_components(&mask, 5)
            .unwrap()
            .as_slice()
            .iter()
            .all(|&b| !b)
    );
}

#[test]
fn the_level_is_a_quantile_of_the_interior() {
    // Heights 0..100 by column; a border of 10 % leaves columns 10..=89.
    let hf = HeightField::from_fn(100, 50, 1.0, |i, _| i as f32).unwrap();
    assert_eq!(water_level(&hf, 0.1, 0.0).unwrap(), 10.0);
    assert_eq!(water_level(&hf, 0.1, 1.0).unwrap(), 89.0);
    assert_eq!(water_level(&hf, 0.0, 0.5).unwrap(), 50.0);
    // The border never swallows the whole field.
    assert_eq!(water_level(&hf, 0.5, 0.0).unwrap(), 49.0);
    for (f, q) in [(f64::NAN, 0.5), (0.6, 0.5), (0.1, f64::NAN), (0.1, 1.5)] {
        assert!(matches!(
            water_level(&hf, f, q),
            Err(TerrainError::InvalidParameter { .. })
        ));
    }
}

#[test]
fn the_coast_sinks_monotonically() {
    let hf = HeightField::from_fn(64, 48, 10.0, |i, j| 50.0 + (i * j) as f32 * 0.1).unwrap();
    let sunk = |depth_m: f32| {
        let mut h = hf.clone();
        let p = CoastParams {
            depth_m,
            ..CoastParams::default()
        };
        sink_coast(&mut h, &p, Seed(7)).unwrap();
        h
    };
    let (shallow, deep) = (sunk(100.0), sunk(300.0));
    for ((a, b), h) in shallow
        .heights()
        .as_slice()
        .iter()
        .zip(deep.heights().as_slice())
        .zip(hf.heights().as_slice())
    {
        // Up to rounding where the coast leaves a sample as it is.
        assert!(*a <= h + 1e-4 && *b <= a + 1e-4, "{h} -> {a}, {b}");
    }
    // The edge lies under the datum; the middle is untouched.
    for j in 0..48 {
        assert!(deep.heights()[(0, j)] < 0.0 && deep.heights()[(63, j)] < 0.0);
    }
    assert!((deep.heights()[(32, 24)] - hf.heights()[(32, 24)]).abs() < 1e-4);
    // Same seed, same coast; no coast, no change.
    assert_eq!(sunk(300.0), deep);
    let mut same = hf.clone();
    let none = CoastParams {
        fraction: 0.0,
        ..CoastParams::default()
    };
    sink_coast(&mut same, &none, Seed(7)).unwrap();
    assert_eq!(same, hf);
}

#[test]
fn sink_coast_refuses_bad_input() {
    let mut hf = HeightField::from_fn(8, 8, 1.0, |_, _| 1.0).unwrap();
    for p in [
        CoastParams {
            fraction: f32::NAN,
            ..CoastParams::default()
        },
        CoastParams {
            depth_m: -1.0,
            ..CoastParams::default()
        },
        CoastParams {
            wander_octaves: f64::NAN,
            ..CoastParams::default()
        },
    ] {
        assert!(sink_coast(&mut hf, &p, Seed(1)).is_err(), "{p:?}");
    }
    let mut line = HeightField::from_fn(1, 8, 1.0, |_, _| 1.0).unwrap();
    assert!(matches!(
        sink_coast(&mut line, &CoastParams::default(), Seed(1)),
        Err(TerrainError::BadSize { .. })
    ));
}
