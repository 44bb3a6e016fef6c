use super::*;
use crate::Turtle;

/// Living leaf clusters of each tree (top-level branch of the axiom), split by
/// side: `(towards +x, towards −x)` relative to the tree's base.
fn leaves_by_side(run: &Run, bases: &[f64]) -> Vec<(usize, usize)> {
    let l = run.lsystem.symbol("L").unwrap();
    let open = run.lsystem.symbol("[").unwrap();
    let close = run.lsystem.symbol("]").unwrap();
    let s = &run.string;
    let mut depth = 0i32;
    let mut tree = vec![0usize; s.len()];
    let mut k = 0usize;
    for (i, t) in tree.iter_mut().enumerate() {
        let sym = s.symbol(i);
        if sym == open {
            depth += 1;
        } else if sym == close {
            depth -= 1;
            if depth == 0 {
                k += 1;
            }
        }
        *t = k.min(bases.len() - 1);
    }
    let mut out = vec![(0, 0); bases.len()];
    let t = Turtle::new(&run.lsystem, run.turtle.clone()).unwrap();
    t.visit(s, |i, st| {
        if s.symbol(i) == l && s.params(i).first().is_some_and(|&v| v > 0.0) {
            let b = tree[i];
            if st.frame.p.x > bases[b] {
                out[b].0 += 1;
            } else {
                out[b].1 += 1;
            }
        }
    })
    .unwrap();
    out
}

#[test]
fn lens_area_limits() {
    use std::f64::consts::PI;
    assert_eq!(lens_area(1.0, 1.0, 2.0), 0.0);
    assert!((lens_area(1.0, 0.5, 0.2) - PI * 0.25).abs() < 1e-12);
    // Two unit discs one radius apart: 2π/3 − √3/2.
    let e = 2.0 * PI / 3.0 - 3f64.sqrt() / 2.0;
    assert!((lens_area(1.0, 1.0, 1.0) - e).abs() < 1e-12);
}

#[test]
fn voxel_grid_matches_every_pair() {
    let mut clusters = Vec::new();
    for i in 0..300u32 {
        let h = |k: u32| natura_core::Seed(9).uniform2(i64::from(i), i64::from(k));
        clusters.push((
            DVec3::new(h(0) * 6.0, h(1) * 6.0, h(2) * 8.0),
            0.2 + 0.4 * h(3),
        ));
    }
    let grid = SkyLight::overcast(0.25);
    let brute = SkyLight {
        use_grid: false,
        ..SkyLight::overcast(0.25)
    };
    let (a, b) = (grid.flux(&clusters), brute.flux(&clusters));
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-12, "{x} {y}");
    }
    assert!(a.iter().all(|&f| (0.0..=1.0 + 1e-12).contains(&f)));
    assert!(a.iter().any(|&f| f < 0.9));
    // The highest cluster is unshaded from the zenith at least.
    let single = grid.flux(&clusters[..1]);
    assert!((single[0] - 1.0).abs() < 1e-12);
}

#[test]
fn steps_per_year_and_environment_sees_only_leaves() {
    let p = CrownParams {
        years: 2,
        ..CrownParams::default()
    };
    assert_eq!(p.steps_per_year(), 31);
    let l = LSystem::parse(&p.lsystem_text()).unwrap();
    let t = Turtle::new(&l, TurtleParams::for_lsystem(&l)).unwrap();
    let mut inner = SkyLight::overcast(0.25);
    let mut env = crate::models::testenv::Recorder {
        inner: &mut inner,
        seen: Vec::new(),
    };
    let mut d = crate::Derivation::new(&l, 0).unwrap();
    let a = l.symbol("A").unwrap();
    for _ in 0..2 * 31 {
        d.step_open(&t, &mut env).unwrap();
    }
    // Messages arrive only in the step before each year's end (step 30, 61), from ?E before an apex
    // (only apices' leaves are live in the first years) or a plain leaf.
    for (k, m) in env.seen.iter().enumerate() {
        if (k + 1) % 31 == 30 {
            assert!(!m.is_empty(), "step {}", k + 1);
        } else {
            assert!(m.is_empty(), "step {} has {} messages", k + 1, m.len());
        }
    }
    assert_eq!(env.seen[29].len(), 1);
    assert_eq!(env.seen[29][0].next_symbol, Some(a));
    assert!((env.seen[29][0].values[0] - 0.5).abs() < 1e-12);
}

#[test]
fn neighbours_shape_the_crowns() {
    // Crowns shaped by neighbours: each tree of a pair keeps a smaller share of its
    // leaf clusters on the side facing the other tree than a lone tree has on that side
    // (the lone crown is itself lopsided, as the phyllotaxis makes it).
    let bases = [-1.0, 1.0];
    let years = 8;
    let run = crowns(&CrownParams {
        years,
        trees_x: bases.to_vec(),
        ..CrownParams::default()
    })
    .unwrap();
    let sides = leaves_by_side(&run, &bases);
    let lone = crowns(&CrownParams {
        years,
        ..CrownParams::default()
    })
    .unwrap();
    let l = leaves_by_side(&lone, &[0.0])[0];
    let share = |a: usize, b: usize| a as f64 / (a + b) as f64;
    let (left, right) = (sides[0], sides[1]);
    // Left tree: its +x side faces the neighbour; right tree: its −x side.
    assert!(
        share(left.0, left.1) < share(l.0, l.1) - 0.05,
        "{left:?} vs lone {l:?}"
    );
    assert!(
        share(right.1, right.0) < share(l.1, l.0) - 0.05,
        "{right:?} vs lone {l:?}"
    );
    // And each tree of the pair has fewer leaves than the lone tree.
    assert!(left.0 + left.1 < l.0 + l.1 && right.0 + right.1 < l.0 + l.1);
}

#[test]
fn counts_for_table_1() {
    // Our counts for one tree of the listing's model (see the module docs):
    // segments, leaf modules and live leaves (radius > 0) after 6 and 8 years.
    for (years, f, l, live) in [(6, 127, 127, 126), (8, 463, 465, 409)] {
        let run = crowns(&CrownParams {
            years,
            ..CrownParams::default()
        })
        .unwrap();
        let id = run.lsystem.symbol("L").unwrap();
        let s = &run.string;
        let alive = (0..s.len())
            .filter(|&i| s.symbol(i) == id && s.params(i).first().is_some_and(|&v| v > 0.0))
            .count();
        assert_eq!(
            (run.count("F"), run.count("L"), alive),
            (f, l, live),
            "{years} years"
        );
    }
}

/// The angles of each fork's daughters, `(s1, s2, lateral +, main −)`,
/// read from the module `C(s1, s2)` the extension writes before a fork.
fn forks(run: &Run) -> Vec<(f64, f64, f64, f64)> {
    let sym = |n: &str| run.lsystem.symbol(n).unwrap();
    let (c, open, close) = (sym("C"), sym("["), sym("]"));
    let s = &run.string;
    let mut out = Vec::new();
    for i in 0..s.len() {
        if s.symbol(i) != c {
            continue;
        }
        assert_eq!(s.symbol(i + 1), open);
        let lateral = s.params(i + 2)[0];
        let mut depth = 0;
        let mut j = i + 1;
        loop {
            if s.symbol(j) == open {
                depth += 1;
            } else if s.symbol(j) == close {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            j += 1;
        }
        let q = s.params(i);
        out.push((q[0], q[1], lateral, s.params(j + 1)[0]));
    }
    out
}

#[test]
fn the_extension_without_straightening_is_the_listing() {
    // The extension's rules with a vanishing straightening grow the
    // listing's tree: the same segments and living clusters after 8 years.
    let p = CrownParams {
        years: 8,
        straightening: 1e-12,
        ..CrownParams::default()
    };
    let listing = CrownParams {
        straightening: 0.0,
        ..p.clone()
    };
    let counts = |p: &CrownParams| {
        let run = crowns(p).unwrap();
        let live = living_clusters(&run, p.leaf_years).unwrap().len();
        (run.count("F"), run.count("L"), live, run.count("C"))
    };
    let (ext, lst) = (counts(&p), counts(&listing));
    assert_eq!((ext.0, ext.1, ext.2), (lst.0, lst.1, lst.2));
    assert_eq!(lst, (463, 465, 405, 0));
    assert!(ext.3 > 100, "{ext:?}");
}

#[test]
fn a_branch_whose_sister_was_shed_turns_to_lead() {
    // Fig. 12's extension: once a fork's lateral is shed its main axis
    // turns back towards the mother's direction, and the other way round;
    // a fork with both daughters keeps the listing's angles.
    let p = CrownParams {
        years: 12,
        straightening: 0.5,
        ..CrownParams::default()
    };
    let run = crowns(&p).unwrap();
    let f = forks(&run);
    let (a1, a2) = (p.alpha1_deg, p.alpha2_deg);
    let lateral_shed = f.iter().filter(|x| x.0 == 1.0).count();
    let main_shed = f.iter().filter(|x| x.1 == 1.0).count();
    assert!(
        lateral_shed > 10 && main_shed > 10,
        "{lateral_shed} {main_shed}"
    );
    for &(s1, s2, lat, main) in &f {
        assert_eq!(main < a1, s1 == 1.0, "{s1} {s2} {lat} {main}");
        assert_eq!(lat < a2, s2 == 1.0, "{s1} {s2} {lat} {main}");
        assert!(main > 0.0 && lat > 0.0 && main <= a1 && lat <= a2);
    }
    // A year after the shedding the angle has lost half: some have turned
    // most of the way.
    assert!(f.iter().any(|x| x.0 == 1.0 && x.3 < 0.3 * a1));
}

#[test]
fn counts_for_table_1_extended() {
    // Fig. 12's tree: 24 years of the extension (one tree, half the angle a
    // year): segments and living clusters, against the source's 22 462 and
    // 19 195 (its rules and parameters are not printed).
    let p = CrownParams {
        years: 24,
        straightening: 0.5,
        ..CrownParams::default()
    };
    let run = crowns(&p).unwrap();
    let live = living_clusters(&run, p.leaf_years).unwrap().len();
    assert_eq!((run.count("F"), live), (11839, 9356));
}

#[test]
fn a_bad_straightening_is_named() {
    for v in [f64::NAN, -0.1, 1.5] {
        let p = CrownParams {
            straightening: v,
            ..CrownParams::default()
        };
        let e = crowns(&p).unwrap_err().to_string();
        assert!(e.contains("CrownParams::straightening"), "{v}: {e}");
    }
}
