use super::*;
use glam::DVec3;

fn grow(years: u32, trees_x: Vec<f64>) -> (ConiferParams, Run) {
    let p = ConiferParams {
        years,
        trees_x,
        ..ConiferParams::default()
    };
    let run = conifers(&p).unwrap();
    (p, run)
}

/// Horizontal distance from the vertical axis at `x0`.
fn reach(c: DVec3, x0: f64) -> f64 {
    (c.x - x0).hypot(c.y)
}

#[test]
fn the_first_year_is_one_flat_whorl() {
    let p = ConiferParams::default();
    assert_eq!(p.steps_per_year(), 13);
    let (p, run) = grow(1, vec![0.0]);
    // The first year's trunk, the stem's growth and the whorl's five laterals.
    assert_eq!(run.count("F"), 7);
    let c = living_clusters(&run, p.leaf_years).unwrap();
    assert_eq!(c.len(), 5);
    // The whorl is one tier: its clusters at one height, one distance from
    // the stem, spread round it.
    let z = c[0].centre.z;
    let r = reach(c[0].centre, 0.0);
    for &LeafCluster {
        centre: q, radius, ..
    } in &c
    {
        assert!(
            (q.z - z).abs() < 1e-9 && (reach(q, 0.0) - r).abs() < 1e-9,
            "{q}"
        );
        assert!((radius - 0.5 * p.lateral_ratio * p.stem_growth * p.stem_decrement).abs() < 1e-12);
    }
    let mean = c.iter().map(|q| q.centre).sum::<DVec3>() / 5.0;
    assert!(mean.truncate().length() < 1e-9, "{mean}");
}

#[test]
fn lower_tiers_spread_wider() {
    // The phase effect: the tiers made first have grown longest, so the
    // crown is widest at the bottom.
    let (p, run) = grow(10, vec![0.0]);
    let c = living_clusters(&run, p.leaf_years).unwrap();
    let (lo, hi) = c
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| {
            (a.min(q.centre.z), b.max(q.centre.z))
        });
    let third = (hi - lo) / 3.0;
    let widest = |z0: f64, z1: f64| {
        c.iter()
            .filter(|q| q.centre.z >= z0 && q.centre.z < z1)
            .map(|q| reach(q.centre, 0.0))
            .fold(0.0, f64::max)
    };
    let (bottom, top) = (widest(lo, lo + third), widest(hi - third, hi + 1.0));
    assert!(bottom > 1.8 * top, "bottom {bottom}, top {top}");
}

/// Living clusters of the tree at `x0` on the side towards `toward` (an x
/// position) and away from it.
fn sides(c: &[LeafCluster], x0: f64, toward: f64) -> (usize, usize) {
    let x = |q: &LeafCluster| q.centre.x;
    let mine: Vec<_> = c
        .iter()
        .filter(|q| (x(q) - x0).abs() < (x(q) - toward).abs())
        .collect();
    let facing = mine
        .iter()
        .filter(|q| (x(q) - x0) * (toward - x0) > 0.0)
        .count();
    (facing, mine.len() - facing)
}

#[test]
fn neighbours_keep_out_of_each_others_crowns() {
    // Two conifers 2.5 m apart: each keeps fewer of its clusters on the side
    // facing the other than on the side away from it, which a lone tree
    // (round by construction) does not.
    let (p, pair) = grow(10, vec![-1.25, 1.25]);
    let c = living_clusters(&pair, p.leaf_years).unwrap();
    for (x0, other) in [(-1.25, 1.25), (1.25, -1.25)] {
        let (facing, away) = sides(&c, x0, other);
        assert!(
            (facing as f64) < 0.8 * away as f64,
            "tree at {x0}: {facing} facing, {away} away"
        );
    }
    let (_, lone) = grow(10, vec![0.0]);
    let c = living_clusters(&lone, p.leaf_years).unwrap();
    let (facing, away) = sides(&c, 0.0, 10.0);
    let share = facing as f64 / (facing + away) as f64;
    assert!((share - 0.5).abs() < 0.05, "lone tree: {facing} / {away}");
}

#[test]
fn bare_branches_are_kept() {
    // Nothing is shed: from year 6 to year 14 the pair's lowest tier keeps
    // every branch within 1.2 m of its stem (a few forks are added), while the clusters on them die
    // (shaded by the tiers above and the neighbour, or past their years)
    // until those branches are bare.
    assert!(!ConiferParams::default().lsystem_text().contains('%'));
    let tier = |years: u32| {
        let (p, run) = grow(years, vec![-1.25, 1.25]);
        let g = run.geometry().unwrap();
        // The first whorl stands on the trunk and the first year's stem.
        let z = p.stem_growth * (1.0 + p.stem_decrement);
        let band = 0.5 * p.stem_growth * p.stem_decrement.powi(2);
        let near = |q: DVec3| (q.z - z).abs() < band && reach(q, -1.25) < 1.2;
        let segments = g.start.iter().filter(|s| near(s.as_dvec3())).count();
        let live = living_clusters(&run, p.leaf_years)
            .unwrap()
            .iter()
            .filter(|q| near(q.centre))
            .count();
        (segments, live)
    };
    let (s6, l6) = tier(6);
    let (s14, l14) = tier(14);
    assert!(s6 > 50 && s14 >= s6, "segments {s6} → {s14}");
    assert!(l6 > 20 && l14 == 0, "living clusters {l6} → {l14}");
}

#[test]
fn counts_for_table_1() {
    // Our counts for one tree after the source's 15 years (see the module
    // docs; the source's rules are not printed): segments, leaf modules and
    // living clusters.
    let (p, run) = grow(15, vec![0.0]);
    let live = living_clusters(&run, p.leaf_years).unwrap().len();
    assert_eq!((run.count("F"), run.count("L"), live), (12251, 12235, 6526));
}

#[test]
fn bad_parameters_are_named() {
    for (name, p) in [
        (
            "ConiferParams::tier_deg",
            ConiferParams {
                tier_deg: f64::NAN,
                ..ConiferParams::default()
            },
        ),
        (
            "ConiferParams::whorl",
            ConiferParams {
                whorl: 0,
                ..ConiferParams::default()
            },
        ),
        (
            "ConiferParams::stem_decrement",
            ConiferParams {
                stem_decrement: 1.5,
                ..ConiferParams::default()
            },
        ),
        (
            "ConiferParams::trees_x",
            ConiferParams {
                trees_x: vec![],
                ..ConiferParams::default()
            },
        ),
        (
            "ConiferParams::stem_growth",
            ConiferParams {
                stem_growth: -1.0,
                ..ConiferParams::default()
            },
        ),
    ] {
        let e = conifers(&p).unwrap_err().to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
}
