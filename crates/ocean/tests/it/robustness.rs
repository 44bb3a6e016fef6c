//! Hostile parameters give a typed error naming the parameter, and an `Ok`
//! ocean's frames are finite.

use natura_ocean::{Ocean, OceanError, OceanParams, Phillips, Seed};

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
