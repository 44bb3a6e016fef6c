//! The footprint-limited fBm: its analytic gradient against central
//! differences, its value, slope and footprint bounds on random points, its
//! offsets keeping the octaves alive at the lattice points, frequency ranges
//! beyond 2³² of the first octave, and its errors.

use natura_noise::glam::DVec2;
use natura_noise::{
    Fbm, Field, FootprintFbm, FootprintParams, NoiseError, Perlin, Spectral, visible_octaves,
};
use proptest::prelude::*;

fn fbm(h: f64, lacunarity: f64, octaves: u32, seed: u64) -> FootprintFbm<Perlin> {
    FootprintFbm::new(
        Perlin::new(seed),
        &FootprintParams {
            amplitude: 2.0,
            h,
            lacunarity,
            octaves,
            wavelength: 10.0,
        },
    )
    .unwrap()
}

/// `visible_whole` is `(⌈v⌉, ⌊v⌋)` of `visible` or `None`, never another
/// pair: the one property the detail tracer's march relies on to skip
/// the logarithm.
fn whole_agrees(d: &FootprintFbm<Perlin>, w: f64) -> Result<bool, TestCaseError> {
    let v = d.visible(w);
    match d.visible_whole(w) {
        Some((c, f)) => {
            prop_assert_eq!(
                (c, f),
                (v.ceil() as usize, v.floor() as usize),
                "w {:e}, v {}",
                w,
                v
            );
            prop_assert_eq!(
                d.footprint_bound_whole(w, (c, f)).to_bits(),
                d.footprint_bound_visible(w, v).to_bits(),
                "w {:e}",
                w
            );
            Ok(true)
        }
        None => Ok(false),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// At random footprints, lacunarities and octave counts (and
    /// wavelengths across many decades) the whole part agrees, and it is
    /// known without the logarithm almost everywhere.
    #[test]
    fn the_whole_octave_count_is_the_logarithms(
        lac in 1.0001f64..64.0, octaves in 0u32..25, lw in -12.0f64..6.0, l0 in -3.0f64..4.0,
    ) {
        let d = FootprintFbm::new(Perlin::new(1), &FootprintParams {
            amplitude: 1.0, h: 0.5, lacunarity: lac, octaves, wavelength: 10f64.powf(l0),
        }).unwrap();
        let w = 10f64.powf(lw);
        prop_assert!(whole_agrees(&d, w)?, "w {:e}: left to the logarithm", w);
    }

    /// The analytic gradient is the central difference of the value (at a
    /// step a thousandth of the finest wavelength summed), and the value it
    /// comes with is `eval2`'s (to the rounding of the basis's own value and
    /// gradient path).
    #[test]
    fn gradient_matches_central_differences(
        x in -500.0f64..500.0, y in -500.0f64..500.0,
        h in 0.0f64..2.0, lac in 1.5f64..4.0, octaves in 1u32..10,
        lw in -3.0f64..1.0, seed in 0u64..1000,
    ) {
        let d = fbm(h, lac, octaves, seed);
        let (p, w) = (DVec2::new(x, y), 10f64.powf(lw));
        let (v, g) = d.eval_grad2(p, w);
        prop_assert!((v - d.eval2(p, w)).abs() <= 1e-13 * (1.0 + d.amplitude_bound(w)));
        let n = d.visible(w).ceil().max(1.0);
        let e = 1e-3 * 10.0 / lac.powf(n - 1.0);
        let gx = (d.eval2(p + DVec2::X * e, w) - d.eval2(p - DVec2::X * e, w)) / (2.0 * e);
        let gy = (d.eval2(p + DVec2::Y * e, w) - d.eval2(p - DVec2::Y * e, w)) / (2.0 * e);
        let err = (g - DVec2::new(gx, gy)).length();
        prop_assert!(err <= 1e-3 * (1.0 + d.lipschitz_bound(w)), "{g} vs ({gx}, {gy})");
    }

    /// `|D| ≤ A(w)`, `|∇D| ≤ L(w)`, and both hold at every larger
    /// footprint; `|D(w') − D(w)| ≤ F(w)·(w' − w)` for `w' ≥ w`.
    #[test]
    fn bounds_hold(
        x in -500.0f64..500.0, y in -500.0f64..500.0,
        h in 0.0f64..2.0, lac in 1.5f64..4.0, octaves in 0u32..12,
        lw in -4.0f64..1.0, grow in 0.0f64..0.05, later in 1.0f64..100.0,
    ) {
        let d = fbm(h, lac, octaves, 3);
        let (p, w) = (DVec2::new(x, y), 10f64.powf(lw));
        for w2 in [w, w * later] {
            let (v, g) = d.eval_grad2(p, w2);
            prop_assert!(v.abs() <= d.amplitude_bound(w) + 1e-12);
            prop_assert!(g.length() <= d.lipschitz_bound(w) * (1.0 + 1e-12) + 1e-12);
        }
        let w2 = w * (1.0 + grow);
        let dv = (d.eval2(p, w2) - d.eval2(p, w)).abs();
        prop_assert!(dv <= d.footprint_bound(w) * (w2 - w) + 1e-9);
        // The ranges of octaves bound their sums.
        let n = d.visible(w);
        let top = n.ceil() as usize;
        let mut part = 0.0;
        for k in 0..top {
            part += d.octave_term(k, n, p);
            prop_assert!((d.eval2(p, w) - part).abs() <= d.amplitude_between(k + 1, top) + 1e-12);
        }
        prop_assert_eq!(part.to_bits(), d.eval2(p, w).to_bits());
    }
}

/// With lacunarity 2 and the first wavelength on the lattice of samples,
/// every octave of an unshifted sum vanishes at the samples; the offsets keep
/// each octave, and the sum, alive there.
#[test]
fn offsets_keep_octaves_alive_at_lattice_points() {
    let d = fbm(0.8, 2.0, 8, 5);
    let plain = Fbm::new(
        Perlin::new(5),
        Spectral::default()
            .with_lacunarity(2.0)
            .with_octaves(8.0)
            .with_frequency(0.1),
    )
    .unwrap();
    let n = d.visible(0.0);
    let mut rms = [0.0f64; 8];
    let mut sum_rms = 0.0;
    for j in 0..32 {
        for i in 0..32 {
            let p = DVec2::new(10.0 * f64::from(i), 10.0 * f64::from(j));
            assert_eq!(plain.eval2(p), 0.0, "the unshifted sum at {p}");
            for (k, r) in rms.iter_mut().enumerate() {
                *r += (d.octave_term(k, n, p) / d.amplitude(k)).powi(2);
            }
            sum_rms += d.eval2(p, 0.0).powi(2);
        }
    }
    for (k, r) in rms.iter().enumerate() {
        let r = (r / 1024.0).sqrt();
        assert!(r > 0.05, "octave {k} has rms {r} at the lattice points");
    }
    assert!((sum_rms / 1024.0).sqrt() > 0.1);
}

/// natura-render allows 24 octaves with lacunarity 4 (a top frequency 2⁴⁶
/// times the first), beyond `Spectral`'s limit of 2³²: they are summed, stay
/// finite and within the bounds, and appear only below their footprints.
#[test]
fn frequencies_beyond_two_to_the_32_are_summed_finite_and_bounded() {
    for lac in [4.0, 16.0] {
        let d = fbm(0.0, lac, 24, 9);
        assert!(d.frequency(23) / d.frequency(0) > 4_294_967_296.0);
        for i in 0..200 {
            let p = DVec2::new(37.1 * f64::from(i), -13.7 * f64::from(i) + 0.3);
            let (v, g) = d.eval_grad2(p, 0.0);
            assert!(v.is_finite() && g.is_finite(), "{v} {g} at {p}");
            assert!(v.abs() <= d.amplitude_bound(0.0));
            assert!(g.length() <= d.lipschitz_bound(0.0));
        }
        // The finest octave only below its Nyquist footprint λ₂₃/2, whole
        // below λ₂₃/2r.
        assert!(d.visible(5.0 / lac.powi(23) * 1.001) < 23.0);
        assert_eq!(d.visible(5.0 / lac.powi(24) * 0.999), 24.0);
        assert_eq!(d.finest_footprint(), 5.0 / lac.powi(24));
    }
}

#[test]
fn visible_octaves_is_the_crate_rule_capped_at_the_count() {
    let d = fbm(0.8, 2.2, 6, 1);
    for w in [1e-6, 0.01, 0.3, 1.0, 4.9, 5.0, 100.0] {
        assert_eq!(d.visible(w), visible_octaves(w, 0.1, 2.2).min(6.0));
    }
    assert_eq!(d.visible(0.0), 6.0);
    assert_eq!(d.visible(-1.0), 6.0);
    assert_eq!(d.eval2(DVec2::new(3.3, 4.4), d.far_footprint()), 0.0);
    // (Octave `k` counts as present up to a relative 1e-9 past `λ_k/2`.)
    assert_eq!(d.amplitude_bound(d.far_footprint() * 1.01), 0.0);
}

#[test]
fn bad_parameters_name_themselves() {
    let ok = FootprintParams {
        amplitude: 1.0,
        h: 0.8,
        lacunarity: 2.0,
        octaves: 4,
        wavelength: 10.0,
    };
    for (p, name) in [
        (
            FootprintParams {
                amplitude: -1.0,
                ..ok
            },
            "amplitude",
        ),
        (FootprintParams { h: f64::NAN, ..ok }, "h"),
        (
            FootprintParams {
                lacunarity: 1.0,
                ..ok
            },
            "lacunarity",
        ),
        (FootprintParams { octaves: 65, ..ok }, "octaves"),
        (
            FootprintParams {
                wavelength: f64::INFINITY,
                ..ok
            },
            "wavelength",
        ),
    ] {
        match FootprintFbm::new(Perlin::new(1), &p) {
            Err(NoiseError::InvalidParam { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
    }
    let huge = FootprintParams {
        amplitude: 1e30,
        octaves: 64,
        ..ok
    };
    assert!(matches!(
        FootprintFbm::new(Perlin::new(1), &huge),
        Err(NoiseError::Unbounded { .. })
    ));
    let none = FootprintFbm::new(
        Perlin::new(1),
        &FootprintParams {
            amplitude: 0.0,
            ..ok
        },
    )
    .unwrap();
    assert_eq!(none.octave_count(), 0);
    assert_eq!(none.eval2(DVec2::new(1.0, 2.0), 0.0), 0.0);
}

/// Footprints at and around every whole octave count, a few units in the
/// last place apart and at the relative margin on both sides: where the
/// rounding of `v` could decide, `visible_whole` defers to the logarithm;
/// everywhere it answers, it answers as the logarithm does. Lacunarities
/// near 1, 2 and huge, and the degenerate footprints.
#[test]
fn the_whole_octave_count_holds_at_every_threshold() {
    let mut answered = 0;
    let mut deferred = 0;
    for (lac, octaves, wavelength) in [
        (2.0, 9, 10.0),
        (2.0, 24, 1.0),
        (1.000_001, 12, 3.0),
        (std::f64::consts::E, 7, 0.1),
        (1.9, 64, 10.0),
        (1e100, 3, 1.0),
        (1e300, 2, 1e-300),
    ] {
        let d = FootprintFbm::new(
            Perlin::new(2),
            &FootprintParams {
                amplitude: 1.0,
                h: 0.9,
                lacunarity: lac,
                octaves,
                wavelength,
            },
        )
        .unwrap();
        for k in 0..=octaves {
            let at = 0.5 * wavelength / lac.powi(k as i32);
            if !at.is_normal() {
                continue;
            }
            for rel in [
                0.0, 1e-15, -1e-15, 5e-10, -5e-10, 2e-9, -2e-9, 1e-6, -1e-6, 0.3, -0.3,
            ] {
                let mut w = at * (1.0 + rel);
                for _ in 0..9 {
                    if whole_agrees(&d, w).unwrap() {
                        answered += 1;
                    } else {
                        deferred += 1;
                    }
                    w = f64::from_bits(w.to_bits() + 1);
                }
            }
        }
        for w in [
            0.0,
            -1.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::INFINITY,
        ] {
            whole_agrees(&d, w).unwrap();
        }
        assert_eq!(d.visible_whole(f64::NAN), None);
    }
    // Both branches were taken: the margin defers, the rest answers.
    assert!(
        answered > 1000 && deferred > 100,
        "{answered} answered, {deferred} deferred"
    );
}
