use super::*;
use crate::models::testenv::Recorder;
use crate::{Derivation, Turtle};

/// Half poor, a favourable strip on the right covering `share` of the field.
fn strip(seed: u64) -> ClonalParams {
    ClonalParams {
        size: [100.0, 60.0],
        background: 0.15,
        patches: vec![Patch {
            min: [60.0, 0.0],
            max: [100.0, 60.0],
            value: 1.0,
        }],
        start: [30.0, 30.0],
        steps: 120,
        seed,
        ..ClonalParams::default()
    }
}

#[test]
fn environment_sees_exactly_the_e_modules() {
    let p = ClonalParams {
        steps: 60,
        ..strip(3)
    };
    let l = LSystem::parse(&p.lsystem_text()).unwrap();
    let t = Turtle::new(&l, turtle(&p, &l)).unwrap();
    let mut inner = p.ground().unwrap();
    let mut env = Recorder {
        inner: &mut inner,
        seen: Vec::new(),
    };
    let e = l.symbol("?E").unwrap();
    let mut d = Derivation::new(&l, p.seed).unwrap();
    let addresses = |d: &Derivation<'_>| -> Vec<usize> {
        let s = d.string();
        (0..s.len()).filter(|&i| s.symbol(i) == e).collect()
    };
    d.communicate(&t, &mut env).unwrap();
    let mut expected = vec![addresses(&d)];
    let mut kinds = [0usize; 3];
    for _ in 0..p.steps {
        d.step_open(&t, &mut env).unwrap();
        expected.push(addresses(&d));
    }
    assert_eq!(env.seen.len(), expected.len());
    for (msgs, want) in env.seen.iter().zip(&expected) {
        let got: Vec<usize> = msgs.iter().map(|m| m.address).collect();
        assert_eq!(&got, want);
        for m in msgs {
            kinds[m.values[0] as usize] += 1;
        }
    }
    // Samples, births and deaths all occurred; every death matched a birth.
    assert!(kinds.iter().all(|&k| k > 0), "{kinds:?}");
    assert_eq!(inner.born.len(), kinds[1]);
    assert_eq!(inner.live.len(), kinds[1] - kinds[2]);
    // Live ramets are exactly the discs of the final string.
    let g = Turtle::new(&l, turtle(&p, &l))
        .unwrap()
        .interpret(d.string())
        .unwrap();
    assert_eq!(g.surfaces.len(), inner.live.len());
}

#[test]
fn clone_forages_in_the_favourable_patch() {
    let share = 0.4;
    for seed in [1, 2, 3] {
        let (run, ground) = clonal(&strip(seed)).unwrap();
        let n = ground.born.len();
        let good = ground.born.iter().filter(|(c, _)| c.x >= 60.0).count();
        let frac = good as f64 / n as f64;
        assert!(n > 50, "seed {seed}: only {n} ramets");
        assert!(
            frac > 1.5 * share,
            "seed {seed}: {good} of {n} ramets in the favourable patch"
        );
        // Leaves are smaller where the light is better.
        let mean = |good: bool| {
            let v: Vec<f64> = ground
                .born
                .iter()
                .filter(|(c, _)| (c.x >= 60.0) == good)
                .map(|&(_, r)| r)
                .collect();
            v.iter().sum::<f64>() / v.len().max(1) as f64
        };
        assert!(mean(true) < mean(false));
        assert!(run.count("F") + run.count("f") > 0);
    }
}

#[test]
fn same_seed_same_clone() {
    let a = clonal(&strip(7)).unwrap();
    let b = clonal(&strip(7)).unwrap();
    assert_eq!(a.0.string, b.0.string);
    assert_eq!(a.1.born, b.1.born);
}

#[test]
fn bad_params() {
    for p in [
        ClonalParams {
            prob_branch: [0.5, 0.6],
            ..ClonalParams::default()
        },
        ClonalParams {
            cell: 0.0,
            ..ClonalParams::default()
        },
        ClonalParams {
            leaf_area: [5.0, 5.0],
            ..ClonalParams::default()
        },
        ClonalParams {
            min_light: f64::NAN,
            ..ClonalParams::default()
        },
        ClonalParams {
            patches: vec![Patch {
                min: [1.0, 0.0],
                max: [0.0, 1.0],
                value: 0.5,
            }],
            ..ClonalParams::default()
        },
    ] {
        assert!(matches!(
            clonal(&p),
            Err(PlantError::InvalidParameter { .. })
        ));
    }
}

#[test]
fn unknown_message_kind_is_an_error() {
    let mut g = ClonalParams::default().ground().unwrap();
    let msg = Message {
        address: 0,
        values: vec![5.0, 0.0],
        state: crate::TurtleState {
            frame: Frame::default(),
            width: 1.0,
            colour: 0,
            distance: 0.0,
            last_seg: u32::MAX,
            taper_from: 1.0,
        },
        next_symbol: None,
    };
    assert!(g.respond(0, &[msg], &mut Vec::new()).is_err());
}

#[cfg(feature = "serde")]
#[test]
fn params_fill_left_out_keys_and_refuse_unknown_ones() {
    let p: ClonalParams = serde_json::from_str(r#"{"steps": 5}"#).unwrap();
    assert_eq!(
        p,
        ClonalParams {
            steps: 5,
            ..ClonalParams::default()
        }
    );
    assert!(serde_json::from_str::<ClonalParams>(r#"{"stepz": 5}"#).is_err());
}
