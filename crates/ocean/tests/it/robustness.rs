//! Hostile parameters give a typed error naming the parameter, and an `Ok`
//! ocean's frames are finite.

use natura_ocean::glam::DVec2;
use natura_ocean::{
    Directional, FrequencySpectrum, G, Jonswap, Ocean, OceanError, OceanParams, Phillips,
    PiersonMoskowitz, Seed, Spectrum, Spreading, Tma,
};
use proptest::prelude::*;

fn params() -> OceanParams {
    OceanParams {
        nx: 32,
        ny: 32,
        lx: 100.0,
        ly: 100.0,
        choppiness: 1.0,
        ..OceanParams::default()
    }
}

fn refused_naming(p: &OceanParams, s: &Phillips, name: &str) {
    match Ocean::new(p, s, Seed(1)) {
        Err(e @ OceanError::InvalidParameter { .. }) => {
            assert!(e.to_string().contains(name), "{e}");
        }
        Err(e) => panic!("wrong error for {name}: {e}"),
        Ok(_) => panic!("{name} accepted"),
    }
}

#[test]
fn absurd_lengths_and_choppiness_are_refused_by_name() {
    let s = Phillips::default();
    for lx in [1e-300, 0.0, -1.0, 1e300, f64::NAN] {
        refused_naming(&OceanParams { lx, ..params() }, &s, "lx");
        refused_naming(&OceanParams { ly: lx, ..params() }, &s, "ly");
    }
    for choppiness in [1e300, 101.0, -0.5, f64::INFINITY] {
        refused_naming(
            &OceanParams {
                choppiness,
                ..params()
            },
            &s,
            "choppiness",
        );
    }
}

#[test]
fn an_overflowing_spectrum_is_refused() {
    for amplitude in [1e300, 1e80] {
        let s = Phillips {
            amplitude,
            ..Phillips::default()
        };
        refused_naming(&params(), &s, "spectrum");
    }
}

#[test]
fn accepted_extremes_give_finite_frames() {
    // The largest accepted choppiness, the smallest and largest patches.
    let cases = [
        OceanParams {
            choppiness: 100.0,
            ..params()
        },
        OceanParams {
            lx: 1e-3,
            ly: 1e-3,
            ..params()
        },
        OceanParams {
            lx: 1e7,
            ly: 1e7,
            ..params()
        },
    ];
    for p in cases {
        let s = Phillips::default();
        let ocean = Ocean::new(&p, &s, Seed(2)).unwrap();
        let f = ocean.evaluate(1.5).unwrap();
        for g in [
            f.height(),
            f.slope_x(),
            f.disp_x(),
            f.jxx(),
            f.jxy(),
            &f.jacobian_grid(),
        ] {
            assert!(g.as_slice().iter().all(|v| v.is_finite()), "{p:?}");
        }
    }
}

/// `10^e` for exponents across f64's whole range, subnormals included.
fn magnitude() -> impl Strategy<Value = f64> {
    (-323.0f64..308.0).prop_map(|e| 10f64.powf(e))
}

/// The spectra whose validation passed.
fn accepted(u: f64, fetch: f64, depth: f64, spreading: Spreading) -> Vec<Box<dyn Spectrum>> {
    let pm = PiersonMoskowitz {
        wind_speed: u,
        ..PiersonMoskowitz::default()
    };
    let jonswap = Jonswap {
        wind_speed: u,
        fetch,
        ..Jonswap::default()
    };
    let tma = Tma { jonswap, depth };
    let phillips = Phillips {
        wind_speed: u,
        ..Phillips::default()
    };
    let mut out: Vec<Box<dyn Spectrum>> = Vec::new();
    let mut push = |s: Box<dyn Spectrum>| {
        if s.validate().is_ok() {
            out.push(s);
        }
    };
    let mut p = Directional::new(pm, 0.4);
    p.spreading = spreading;
    push(Box::new(p));
    let mut j = Directional::new(jonswap, 0.4);
    j.spreading = spreading;
    push(Box::new(j));
    let mut t = Directional::new(tma, 0.4);
    t.spreading = spreading;
    t.dispersion = natura_ocean::Dispersion::FiniteDepth { g: G, depth };
    push(Box::new(t));
    let mut c = Directional::new(pm, 0.4);
    c.dispersion = natura_ocean::Dispersion::Capillary {
        g: G,
        capillary_length: depth,
    };
    push(Box::new(c));
    push(Box::new(phillips));
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// The spectra's contract: a spectrum whose parameters validate gives a
    /// finite density ≥ 0 at every wave vector, at any scale of wind, fetch,
    /// depth and wavenumber f64 holds. (The smallest subnormal wind speed
    /// once validated and gave NaN.)
    #[test]
    fn validated_spectra_are_finite_everywhere(
        u in magnitude(),
        fetch in magnitude(),
        depth in magnitude(),
        k in magnitude(),
        angle in -3.2f64..3.2,
        hasselmann in any::<bool>(),
    ) {
        let spreading = if hasselmann { Spreading::Hasselmann } else { Spreading::Cos2s { s: 8.0 } };
        let kv = DVec2::new(angle.cos(), angle.sin()) * k;
        for s in accepted(u, fetch, depth, spreading) {
            let p = s.density(kv);
            prop_assert!(p.is_finite() && p >= 0.0, "{s:?} at k = {kv}: {p}");
        }
    }
}

#[test]
fn practical_winds_are_accepted_and_vanishing_ones_named() {
    for u in [0.1, 1.0, 10.0, 60.0] {
        assert_eq!(
            accepted(u, 1e4, 20.0, Spreading::Hasselmann).len(),
            5,
            "{u}"
        );
    }
    let tiny = Jonswap {
        wind_speed: 5e-324,
        ..Jonswap::default()
    };
    let e = tiny.validate().unwrap_err().to_string();
    assert!(e.contains("wind_speed"), "{e}");
}
