//! Worley's feature-point distributions (Musgrave 2001, "The Seed Tables"):
//! the default's values pinned, the exact search against brute force for
//! every distribution, batch against point, and the statistics each
//! distribution promises.

use crate::common::{Rng, check_gradient, check_lipschitz};

use glam::{DVec2, DVec3};
use natura_noise::basis::cellular::{MAX_DENSITY, MIN_DENSITY};
use natura_noise::{
    FeaturePoints, Field, Metric, NoiseError, Simd, Worley, WorleyFeature, WorleyParams,
};
use proptest::prelude::*;

const METRICS: [Metric; 4] = [
    Metric::Euclidean,
    Metric::EuclideanSquared,
    Metric::Manhattan,
    Metric::Chebyshev,
];

const FEATURES: [WorleyFeature; 7] = [
    WorleyFeature::F1,
    WorleyFeature::F2,
    WorleyFeature::F3,
    WorleyFeature::F4,
    WorleyFeature::F2MinusF1,
    WorleyFeature::F3MinusF2,
    WorleyFeature::F4MinusF3,
];

/// FNV-1a over 64-bit words.
fn fnv(h: &mut u64, bits: u64) {
    for b in bits.to_le_bytes() {
        *h ^= u64::from(b);
        *h = h.wrapping_mul(0x0100_0000_01B3);
    }
}

/// The default distribution (one jittered point per cell) gives the values
/// it gave before the distributions were added, bit for bit: every metric,
/// feature and a few jitters, point values (2-D and 3-D) and batch rows
/// (span and per-lane kernels) at the portable level and the best one.
#[test]
fn default_distribution_values_are_pinned() {
    let mut h = 0xCBF2_9CE4_8422_2325u64;
    let mut rng = Rng(2001);
    for metric in METRICS {
        for feature in FEATURES {
            for jitter in [1.0, 0.6] {
                let w = Worley::new(
                    7,
                    WorleyParams {
                        feature,
                        metric,
                        jitter,
                        ..WorleyParams::default()
                    },
                )
                .unwrap();
                for _ in 0..64 {
                    fnv(&mut h, w.eval2(rng.p2(300.0)).to_bits());
                    fnv(&mut h, w.eval3(rng.p3(300.0)).to_bits());
                }
                for step in [0.013, 1.7] {
                    for simd in [Simd::baseline(), Simd::best()] {
                        let mut row = [0.0f32; 97];
                        w.fill_row2_with(simd, DVec2::new(-3.1, 5.7), step, &mut row);
                        row.iter().for_each(|v| fnv(&mut h, u64::from(v.to_bits())));
                        w.fill_row3_with(simd, DVec3::new(-3.1, 5.7, 0.4), step, &mut row);
                        row.iter().for_each(|v| fnv(&mut h, u64::from(v.to_bits())));
                    }
                }
            }
        }
    }
    assert_eq!(h, 0x3408_1707_5184_7a87, "hash {h:#018x}");
}

fn tables() -> [FeaturePoints; 4] {
    [
        FeaturePoints::Poisson { density: 1.0 },
        FeaturePoints::Poisson { density: 4.0 },
        FeaturePoints::Variable { density: 4.0 },
        FeaturePoints::Gaussian { density: 4.0 },
    ]
}

fn table_field(seed: u64, points: FeaturePoints, feature: WorleyFeature, metric: Metric) -> Worley {
    Worley::new(
        seed,
        WorleyParams {
            feature,
            metric,
            points,
            ..WorleyParams::default()
        },
    )
    .unwrap()
}

/// With a seed table, batch rows (every SIMD level, steps on both sides of
/// the span kernel's limit, planet-scale origins too) are the point values
/// rounded to f32, bit for bit.
#[test]
fn table_batch_rows_are_the_point_values() {
    let mut rng = Rng(24);
    for points in tables() {
        for metric in METRICS {
            for feature in [WorleyFeature::F1, WorleyFeature::F3MinusF2] {
                let w = table_field(3, points, feature, metric);
                for (step, far) in [(0.011, 0.0), (0.4, 0.0), (2.3, 0.0), (0.05, 3.0e6)] {
                    let o2 = rng.p2(40.0) + DVec2::splat(far);
                    let o3 = rng.p3(40.0) + DVec3::splat(far);
                    for simd in Simd::supported() {
                        let mut row = [0.0f32; 131];
                        w.fill_row2_with(simd, o2, step, &mut row);
                        for (i, v) in row.iter().enumerate() {
                            let e = w.eval2(DVec2::new(o2.x + i as f64 * step, o2.y)) as f32;
                            assert_eq!(v.to_bits(), e.to_bits(), "{points:?} 2-D {simd:?} {i}");
                        }
                        w.fill_row3_with(simd, o3, step, &mut row);
                        for (i, v) in row.iter().enumerate() {
                            let p = DVec3::new(o3.x + i as f64 * step, o3.y, o3.z);
                            let e = w.eval3(p) as f32;
                            assert_eq!(v.to_bits(), e.to_bits(), "{points:?} 3-D {simd:?} {i}");
                        }
                    }
                }
            }
        }
    }
}

/// The same seed and table give the same values; another seed, another
/// table kind or another density give different ones; non-finite points
/// give NaN.
#[test]
fn tables_are_deterministic_and_distinct() {
    let mut rng = Rng(25);
    let pts: Vec<DVec3> = (0..200).map(|_| rng.p3(100.0)).collect();
    let values = |w: &Worley| -> Vec<u64> {
        pts.iter()
            .flat_map(|&p| [w.eval3(p).to_bits(), w.eval2(p.truncate()).to_bits()])
            .collect()
    };
    let f1 = WorleyFeature::F1;
    let e = Metric::Euclidean;
    let mut seen = Vec::new();
    for points in tables() {
        let a = values(&table_field(8, points, f1, e));
        assert_eq!(a, values(&table_field(8, points, f1, e)), "{points:?}");
        assert_ne!(a, values(&table_field(9, points, f1, e)), "{points:?}");
        assert!(!seen.contains(&a), "{points:?} repeats another table");
        seen.push(a);
        let w = table_field(8, points, f1, e);
        assert!(w.eval2(DVec2::new(f64::NAN, 1.0)).is_nan());
        assert!(w.eval3(DVec3::new(1.0, f64::INFINITY, 1.0)).is_nan());
        assert!(w.eval_grad3(DVec3::new(f64::NAN, 1.0, 1.0)).0.is_nan());
    }
}

/// A seed table's gradients match central differences, its slopes stay
/// within the Lipschitz constants, its values within the bound, and the
/// features are ordered `F1 ≤ F2 ≤ F3 ≤ F4`.
#[test]
fn table_gradients_bounds_and_order() {
    let mut rng = Rng(26);
    for points in tables() {
        let w = table_field(4, points, WorleyFeature::F1, Metric::Euclidean);
        check_gradient(&w, 1e-5, 27, 300);
        for metric in METRICS {
            let ws = [
                WorleyFeature::F1,
                WorleyFeature::F2,
                WorleyFeature::F3,
                WorleyFeature::F4,
                WorleyFeature::F4MinusF3,
            ]
            .map(|f| table_field(4, points, f, metric));
            check_lipschitz(&ws[4], 28, 5_000, 0.05);
            for _ in 0..500 {
                let p = rng.p3(80.0);
                let f = ws.each_ref().map(|w| w.eval3(p));
                assert!(f[..4].windows(2).all(|a| a[0] <= a[1]), "{f:?}");
                assert!(f.iter().zip(&ws).all(|(v, w)| *v >= 0.0 && *v <= w.bound()));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// A table's density is accepted exactly when it lies in `[0.5, 16]`;
    /// otherwise (NaN, infinite, zero, negative, too small or too large) the
    /// error names `points.density`, and nothing panics.
    #[test]
    fn table_density_is_validated(
        density in prop_oneof![
            Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(0.0), Just(-0.0),
            Just(MIN_DENSITY), Just(MAX_DENSITY), Just(16.000_001), Just(0.499_999),
            -1.0e3f64..1.0e3, 0.0f64..20.0,
        ],
        kind in 0usize..3,
    ) {
        let points = [
            FeaturePoints::Poisson { density },
            FeaturePoints::Variable { density },
            FeaturePoints::Gaussian { density },
        ][kind];
        let params = WorleyParams { points, ..WorleyParams::default() };
        let ok = (MIN_DENSITY..=MAX_DENSITY).contains(&density);
        match Worley::new(1, params) {
            Ok(w) => {
                prop_assert!(ok, "{density} accepted");
                prop_assert!(w.eval2(DVec2::new(0.3, 0.7)).is_finite());
            }
            Err(NoiseError::InvalidParam { name, value, .. }) => {
                prop_assert!(!ok, "{density} refused");
                prop_assert_eq!(name, "points.density");
                prop_assert!(value.to_bits() == density.to_bits());
            }
            Err(e) => prop_assert!(false, "unexpected error {e:?}"),
        }
    }
}
