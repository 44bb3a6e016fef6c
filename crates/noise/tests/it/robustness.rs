//! Parameters that would make a field's values overflow are refused up front,
//! and non-finite points give NaN in every basis.

use glam::{DVec2, DVec3};
use natura_noise::{
    Checkerboard, Fbm, Field, HeteroTerrain, HeteroTerrainParams, HybridMultifractal, HybridParams,
    MAX_BOUND, Multifractal, MultifractalParams, NoiseError, Perlin, RidgedMultifractal,
    RidgedParams, Simplex, Spectral, Turbulence, Value, Worley,
};

#[test]
fn fbm_with_overflowing_amplitudes_is_refused_naming_h() {
    for h in [-1e300, -200.0, f64::MIN] {
        let e = Fbm::new(Perlin::new(1), Spectral::default().with_h(h)).unwrap_err();
        assert!(
            matches!(e, NoiseError::InvalidParam { name: "h", .. }),
            "h = {h}: {e:?}"
        );
        assert!(Turbulence::new(Perlin::new(1), Spectral::default().with_h(h)).is_err());
    }
    // Rough but bounded: accepted, and finite everywhere.
    let f = Fbm::new(Perlin::new(1), Spectral::default().with_h(-1.0)).unwrap();
    assert!(f.bound() <= MAX_BOUND);
    assert!(f.eval2(DVec2::new(0.3, 0.7)).is_finite());
}

#[test]
fn multifractal_offsets_and_gains_are_bounded() {
    let s = Spectral::default();
    for v in [1e300, -1e300, 1e4, f64::NAN] {
        let r = RidgedParams {
            spectral: s,
            offset: v,
            gain: 2.0,
        };
        assert!(matches!(
            RidgedMultifractal::new(Perlin::new(1), r).unwrap_err(),
            NoiseError::InvalidParam { name: "offset", .. }
        ));
        let r = RidgedParams {
            spectral: s,
            offset: 1.0,
            gain: v,
        };
        assert!(matches!(
            RidgedMultifractal::new(Perlin::new(1), r).unwrap_err(),
            NoiseError::InvalidParam { name: "gain", .. }
        ));
        let h = HybridParams {
            spectral: s,
            offset: v,
        };
        assert!(HybridMultifractal::new(Perlin::new(1), h).is_err());
        let t = HeteroTerrainParams {
            offset: v,
            ..HeteroTerrainParams::default()
        };
        assert!(HeteroTerrain::new(Perlin::new(1), t).is_err());
        let m = MultifractalParams {
            offset: v,
            ..MultifractalParams::default()
        };
        assert!(Multifractal::new(Perlin::new(1), m).is_err());
    }
    // The largest accepted offset still gives finite values and a finite bound.
    let r = RidgedParams {
        spectral: s,
        offset: 1e3,
        gain: 1e3,
    };
    let f = RidgedMultifractal::new(Perlin::new(1), r).unwrap();
    assert!(f.bound().is_finite());
    for k in 0..100 {
        let p = DVec3::new(k as f64 * 0.37, k as f64 * -1.3, 2.0);
        let (v, g) = f.eval_grad3(p);
        assert!(v.is_finite() && g.is_finite(), "{p}: {v} {g}");
    }
}

#[test]
fn every_basis_gives_nan_at_non_finite_points() {
    let bases: Vec<Box<dyn Field>> = vec![
        Box::new(Perlin::new(3)),
        Box::new(Simplex::new(3)),
        Box::new(Value::new(3)),
        Box::new(Worley::new(3, natura_noise::WorleyParams::default()).unwrap()),
        Box::new(Checkerboard),
    ];
    for (k, b) in bases.iter().enumerate() {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(b.eval2(DVec2::new(bad, 0.5)).is_nan(), "basis {k} at {bad}");
            assert!(
                b.eval3(DVec3::new(0.5, 0.25, bad)).is_nan(),
                "basis {k} at {bad}"
            );
        }
    }
}
