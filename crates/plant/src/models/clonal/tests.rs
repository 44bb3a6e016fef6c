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
            frame: TurtleFrame::default(),
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

/// First parameters of the modules named `name` in the run's final string.
fn first_params(run: &Run, name: &str) -> Vec<f64> {
    let id = run.lsystem.symbol(name).unwrap();
    let s = &run.string;
    (0..s.len())
        .filter(|&i| s.symbol(i) == id)
        .map(|i| s.params(i)[0])
        .collect()
}

fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, var.sqrt())
}

#[test]
fn fig7_spacers_and_angles_follow_their_normal_distributions() {
    let p = ClonalParams {
        steps: 120,
        ..ClonalParams::fig7()
    };
    let (run, _) = clonal(&p).unwrap();
    // Live spacers `F(len, age)` and dead ones `f(len)` keep their drawn length.
    let mut len = first_params(&run, "F");
    len.extend(first_params(&run, "f"));
    assert!(len.len() > 100, "{}", len.len());
    let (m, sd) = mean_sd(&len);
    let se = p.spacer_sd / (len.len() as f64).sqrt();
    assert!((m - p.spacer).abs() < 4.0 * se, "mean {m}");
    assert!((sd / p.spacer_sd - 1.0).abs() < 0.2, "sd {sd}");
    assert!(len.iter().all(|&l| l >= 0.1 * p.spacer));
    // Branches turn by ±α with α drawn per branch.
    let turns: Vec<f64> = first_params(&run, "+").iter().map(|a| a.abs()).collect();
    assert!(turns.len() > 20, "{}", turns.len());
    let (m, sd) = mean_sd(&turns);
    let se = p.alpha_sd_deg / (turns.len() as f64).sqrt();
    assert!((m - p.alpha_deg).abs() < 4.0 * se, "mean {m}");
    assert!((sd / p.alpha_sd_deg - 1.0).abs() < 0.3, "sd {sd}");
    // Without deviations every spacer is `Len` and every turn α.
    let (run, _) = clonal(&ClonalParams {
        steps: 120,
        ..ClonalParams::default()
    })
    .unwrap();
    assert!(first_params(&run, "F").iter().all(|&l| l == 2.0));
    assert!(first_params(&run, "+").iter().all(|&a| a.abs() == 45.0));
    // Deviations out of range are typed errors.
    for bad in [
        ClonalParams {
            spacer_sd: -0.1,
            ..ClonalParams::default()
        },
        ClonalParams {
            alpha_sd_deg: f64::NAN,
            ..ClonalParams::default()
        },
    ] {
        assert!(matches!(
            clonal(&bad),
            Err(PlantError::InvalidParameter { .. })
        ));
    }
}

#[test]
fn trifoliate_leaves_change_the_picture_not_the_clone() {
    let disc = ClonalParams {
        steps: 60,
        ..strip(5)
    };
    let tri = ClonalParams {
        trifoliate: true,
        ..disc.clone()
    };
    let (run_d, env_d) = clonal(&disc).unwrap();
    let (run_t, env_t) = clonal(&tri).unwrap();
    assert_eq!(env_d.born, env_t.born);
    assert_eq!(env_d.live, env_t.live);
    assert_eq!(run_d.string.symbols().len(), run_t.string.symbols().len());
    let ramets = run_d.count("@o");
    assert!(ramets > 3, "{ramets}");
    let (gd, gt) = (run_d.geometry().unwrap(), run_t.geometry().unwrap());
    let count = |g: &crate::Geometry, c: char| g.surfaces.iter().filter(|s| s.name == c).count();
    assert_eq!(count(&gd, 'o'), ramets);
    assert_eq!(count(&gt, 'o'), 0);
    assert_eq!(count(&gt, 'L'), 3 * ramets);
    // Each leaflet lies flat (heading horizontal), as long as its ramet's radius.
    for s in gt.surfaces.iter().filter(|s| s.name == 'L') {
        assert!(s.frame.h.z.abs() < 1e-9, "{:?}", s.frame.h);
        assert!(
            env_t
                .live
                .iter()
                .any(|&(_, r)| (r - s.length).abs() < 1e-12)
        );
    }
    assert_eq!(gd.start, gt.start, "the spacers are the same");
}

/// The leaf radius is printed `sqrt(15-x*5)π` (Měch & Prusinkiewicz 1996,
/// Fig. 6's listing); read here as the radius of a disc of area `15 − 5x`,
/// `sqrt((15 − 5x)/π)`. Every ramet's disc has an area in `[10, 15]` (light
/// `x` in `[0, 1]`): radii 1.78 to 2.19, where the printed form would give
/// 9.9 to 12.2 — five times wider than the spacers are long.
#[test]
fn ramet_leaves_are_discs_of_area_fifteen_minus_five_x() {
    let p = ClonalParams {
        steps: 60,
        background: 0.6,
        ..strip(7)
    };
    assert_eq!(p.leaf_area, [15.0, 5.0]);
    let (run, _) = clonal(&p).unwrap();
    let radii = first_params(&run, "@o");
    assert!(radii.len() > 5, "{}", radii.len());
    for r in &radii {
        let area = std::f64::consts::PI * r * r;
        assert!(
            (10.0 - 1e-9..=15.0 + 1e-9).contains(&area),
            "radius {r}, area {area}"
        );
    }
    // Ramets in the half light (0.6, area 12) and in full light (area 10)
    // both occur.
    let (lo, hi) = radii
        .iter()
        .fold((f64::MAX, f64::MIN), |a, &r| (a.0.min(r), a.1.max(r)));
    assert!(hi - lo > 0.1, "{lo} {hi}");
}

/// Our counts for the source's Fig. 7 (Table 1: 786 segments, 229 leaf
/// clusters after 182 steps; see the module docs).
#[test]
fn counts_for_table_1() {
    let p = ClonalParams::fig7();
    assert_eq!(p.steps, 182);
    let (run, _) = clonal(&p).unwrap();
    assert_eq!((run.count("F"), run.count("@o")), (1460, 348));
}
