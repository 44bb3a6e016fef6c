//! Simplex, Worley and value bases: batch vs point, gradients, Lipschitz bounds, ranges.

use crate::common;

use common::{Rng, check_batch, check_gradient, check_lipschitz, check_rows_bitwise};
use glam::{DVec2, DVec3};
use natura_noise::{Field, Metric, Simplex, Worley, WorleyFeature, WorleyParams};

#[test]
fn simplex_batch_gradient_lipschitz_range() {
    let s = Simplex::new(3);
    check_batch(&s, 1e-5, 1);
    check_gradient(&s, 1e-6, 2, 2000);
    let (r2, r3) = check_lipschitz(&s, 3, 100_000, 0.05);
    assert!(r2 > 0.7 && r3 > 0.6, "observed/L {r2} {r3}");
    let mut rng = Rng(4);
    let (mut m2, mut m3) = (0.0f64, 0.0f64);
    for _ in 0..3000 {
        let mut p = rng.p2(300.0);
        let mut q = rng.p3(300.0);
        for _ in 0..60 {
            let (v, g) = s.eval_grad2(p);
            p += g * v.signum() * 0.005;
            let (v, g) = s.eval_grad3(q);
            q += g * v.signum() * 0.005;
        }
        m2 = m2.max(s.eval2(p).abs());
        m3 = m3.max(s.eval3(q).abs());
        assert!(m2 <= 1.0 + 1e-9 && m3 <= 1.0 + 1e-9, "{m2} {m3}");
    }
    assert!(m2 > 0.98 && m3 > 0.9, "bound calibration {m2} {m3}");
    // Zero at the simplex lattice's vertices (the unskewed integer points).
    let g2 = (3.0 - 3f64.sqrt()) / 6.0;
    let v2 = DVec2::new(4.0, -7.0) - DVec2::splat(-3.0 * g2);
    assert!(s.eval2(v2).abs() < 1e-9);
    let v3 = DVec3::new(4.0, -7.0, 2.0) - DVec3::splat(-1.0 / 6.0);
    assert!(s.eval3(v3).abs() < 1e-9);
}

fn worleys() -> Vec<Worley> {
    let mut v = Vec::new();
    for metric in [
        Metric::Euclidean,
        Metric::EuclideanSquared,
        Metric::Manhattan,
        Metric::Chebyshev,
    ] {
        for feature in [
            WorleyFeature::F1,
            WorleyFeature::F2,
            WorleyFeature::F3,
            WorleyFeature::F4,
            WorleyFeature::F2MinusF1,
            WorleyFeature::F3MinusF2,
            WorleyFeature::F4MinusF3,
        ] {
            v.push(
                Worley::new(
                    5,
                    WorleyParams {
                        feature,
                        metric,
                        jitter: 1.0,
                        ..WorleyParams::default()
                    },
                )
                .unwrap(),
            );
        }
    }
    v
}

#[test]
fn worley_batch_matches_exact_point_search() {
    for w in worleys() {
        check_batch(&w, 2e-6, 6);
    }
    for jitter in [0.0, 0.5] {
        check_batch(
            &Worley::new(
                1,
                WorleyParams {
                    jitter,
                    ..Default::default()
                },
            )
            .unwrap(),
            2e-6,
            7,
        );
    }
}

/// Brute force over a wide block of cells against the ring search.
#[test]
fn worley_search_is_exact_and_ordered() {
    let mut rng = Rng(8);
    let feats = |metric| {
        [
            WorleyFeature::F1,
            WorleyFeature::F2,
            WorleyFeature::F3,
            WorleyFeature::F4,
        ]
        .map(|feature| {
            Worley::new(
                9,
                WorleyParams {
                    feature,
                    metric,
                    jitter: 1.0,
                    ..WorleyParams::default()
                },
            )
            .unwrap()
        })
    };
    for metric in [Metric::Euclidean, Metric::Manhattan, Metric::Chebyshev] {
        let ws = feats(metric);
        for _ in 0..3000 {
            let p = rng.p2(100.0);
            let f: Vec<f64> = ws.iter().map(|w| w.eval2(p)).collect();
            assert!(f.windows(2).all(|a| a[0] <= a[1]), "{f:?}");
            assert!(f[0] >= 0.0);
            let q = rng.p3(100.0);
            let g: Vec<f64> = ws.iter().map(|w| w.eval3(q)).collect();
            assert!(g.windows(2).all(|a| a[0] <= a[1]), "{g:?}");
        }
    }
    // F1 vanishes at a feature point: find one by descending the gradient.
    let w = Worley::new(2, WorleyParams::default()).unwrap();
    let mut p = DVec2::new(10.3, 4.7);
    for _ in 0..50 {
        let (v, g) = w.eval_grad2(p);
        p -= g * v;
    }
    assert!(w.eval2(p) < 1e-9);
}

#[test]
fn worley_gradient_and_lipschitz() {
    for w in worleys() {
        check_lipschitz(&w, 10, 20_000, 0.05);
    }
    let w = Worley::new(3, WorleyParams::default()).unwrap();
    check_gradient(&w, 1e-5, 11, 500);
    let mut rng = Rng(12);
    for w in worleys() {
        for _ in 0..2000 {
            let v = w.eval3(rng.p3(50.0));
            assert!(v >= 0.0 && v <= w.bound(), "{v} > {}", w.bound());
        }
    }
}

#[test]
fn worley_rejects_bad_jitter_and_propagates_nan() {
    assert!(
        Worley::new(
            1,
            WorleyParams {
                jitter: 1.5,
                ..Default::default()
            }
        )
        .is_err()
    );
    assert!(
        Worley::new(
            1,
            WorleyParams {
                jitter: f64::NAN,
                ..Default::default()
            }
        )
        .is_err()
    );
    let w = Worley::new(1, WorleyParams::default()).unwrap();
    assert!(w.eval2(DVec2::new(f64::NAN, 1.0)).is_nan());
    assert!(w.eval3(DVec3::new(1.0, f64::INFINITY, 1.0)).is_nan());
}

/// The batch rows split each block's first point in f64 and run the lanes in
/// f32 from that local origin: far from the origin (planet-scale coordinates)
/// they must still match the f64 point path within 1e-5 at every SIMD level,
/// for steps on both sides of the span path's limit and long rows (many blocks).
#[test]
fn rebased_rows_match_point_path_far_from_origin() {
    use natura_noise::{Fade, Perlin, Simd};
    let fields: [&dyn Field; 3] = [
        &Perlin::new(5),
        &Perlin::with_fade(6, Fade::Cubic),
        &Simplex::new(7),
    ];
    let n = 300;
    for f in fields {
        for (a, &o) in [1.0e6 + 0.37, -3.3e8 - 0.61, 4.0e9 + 0.125, -6.0e9 + 0.3]
            .iter()
            .enumerate()
        {
            for &step in &[0.013, 0.07, 0.9, 3.7] {
                let o2 = DVec2::new(o, 0.5 * o + 0.21);
                let o3 = DVec3::new(o, -0.25 * o + 0.4, 0.125 * o - 0.7);
                for simd in Simd::supported() {
                    let mut row = vec![0.0f32; n];
                    f.fill_row2_with(simd, o2, step, &mut row);
                    for (i, &v) in row.iter().enumerate() {
                        let e = f.eval2(DVec2::new(o2.x + i as f64 * step, o2.y));
                        assert!(
                            (f64::from(v) - e).abs() <= 1e-5,
                            "2-D {simd:?} origin #{a} step {step} i {i}: {v} vs {e}"
                        );
                    }
                    f.fill_row3_with(simd, o3, step, &mut row);
                    for (i, &v) in row.iter().enumerate() {
                        let e = f.eval3(DVec3::new(o3.x + i as f64 * step, o3.y, o3.z));
                        assert!(
                            (f64::from(v) - e).abs() <= 1e-5,
                            "3-D {simd:?} origin #{a} step {step} i {i}: {v} vs {e}"
                        );
                    }
                }
            }
        }
    }
}

/// Value noise's rows between 1/32 and 1 cell a point go window by window
/// (each 16-point group looks its cells' column values up by permutes):
/// at the range's ends, across the 256-point chunks, far from the origin,
/// for every interpolation, 2-D and 3-D, equal at every SIMD level.
#[test]
fn value_window_rows_match_point_path() {
    use natura_noise::{Value, ValueInterp};
    let steps = [1.0 / 32.0 + 1e-9, 0.1, 0.5, 0.999_999_9, 1.0];
    let origins = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(-3.999_999_99, 0.5, 2.0),
        DVec3::new(2.0e6 + 0.3, -4.0e5, 17.25),
    ];
    for interp in [
        ValueInterp::Linear,
        ValueInterp::Cubic,
        ValueInterp::Quintic,
    ] {
        let n = Value::with_interp(8, interp);
        for &step in &steps {
            for &o in &origins {
                check_rows_bitwise(&n, step, o.truncate(), o, 700, 1e-5);
            }
        }
    }
}
