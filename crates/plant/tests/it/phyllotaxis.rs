//! Collision-based phyllotaxis (Fowler et al. 1992): the collision
//! condition on every receptacle, the divergence angle, the decreasing-size
//! fix, Fibonacci parastichies on a flat head, organ placement (§3.1), the
//! two-level recursion of the cauliflower (Fig. 10) and bad input.

use glam::DVec3;
use natura_plant::PlantError;
use natura_plant::models::phyllotaxis::{
    PhyllotaxisParams, Primordium, Receptacle, organ_frames, phyllotaxis,
};

const GOLDEN: f64 = 137.507_764_050_037_85;

/// A dome: a quarter circle from the rim (ρ = 1, h = 0) to the top (ρ = 0, h = 1)
/// as one cubic Bézier.
fn dome() -> Receptacle {
    let k = 0.552_284_749_8;
    Receptacle::Bezier {
        segments: vec![[[1.0, 0.0], [1.0, k], [k, 1.0], [0.0, 1.0]]],
    }
}

fn params(receptacle: Receptacle, r_base: f64, r_tip: f64) -> PhyllotaxisParams {
    PhyllotaxisParams {
        receptacle,
        r_base,
        r_tip,
        ..PhyllotaxisParams::default()
    }
}

fn assert_no_overlap(v: &[Primordium], eps: f64) {
    for (n, a) in v.iter().enumerate() {
        for (i, b) in v[..n].iter().enumerate() {
            let d = a.centre.distance(b.centre);
            assert!(
                d >= a.radius + b.radius - eps,
                "primordia {i} and {n}: {d} < {} + {}",
                b.radius,
                a.radius
            );
        }
    }
}

#[test]
fn every_pair_is_separated_and_phi_n_is_n_times_137_5_on_every_receptacle() {
    for (name, p) in [
        ("cone", PhyllotaxisParams::default()),
        ("disc", params(Receptacle::Disc { radius: 1.0 }, 0.04, 0.04)),
        (
            "sphere",
            params(Receptacle::Sphere { radius: 1.0 }, 0.08, 0.08),
        ),
        ("dome", params(dome(), 0.06, 0.03)),
    ] {
        let v = phyllotaxis(&p).unwrap();
        assert!(v.len() > 100, "{name}: {}", v.len());
        assert_no_overlap(&v, 1e-9);
        for (n, a) in v.iter().enumerate() {
            let d = (a.phi.to_degrees() - n as f64 * GOLDEN).abs();
            assert!(d < 1e-6, "{name}: φ_{n} off by {d}°");
            assert!(a.t >= p.t_min && a.t <= p.t_max, "{name}: t_{n} = {}", a.t);
            let c = p.receptacle.point(a.phi, a.t);
            assert!(
                c.distance(a.centre) < 1e-12,
                "{name}: centre off the receptacle"
            );
        }
        // The receptacle is full: placement stopped before max_count.
        assert!(v.len() < p.max_count, "{name}");
    }
}

#[test]
fn with_delta_t_falls_back_at_most_by_the_new_radius() {
    // t'_min = max(t_min, t_n − δ), δ the radius in t units; on the cone
    // |dC/dt| = √(R² + H²).
    let p = PhyllotaxisParams::default();
    let v = phyllotaxis(&p).unwrap();
    let speed = 2f64.sqrt();
    for (n, w) in v.windows(2).enumerate() {
        let delta = p.radius(w[0].t) / speed;
        assert!(
            w[1].t >= w[0].t - delta - 1e-9,
            "t_{} = {} < t_{n} − δ",
            n + 1,
            w[1].t
        );
    }
}

#[test]
fn the_decreasing_size_fix_keeps_small_primordia_out_of_gaps_at_the_base() {
    // §2.4: consecutive primordia shrinking (r₀ > r₁ > …). Without δ some
    // late small primordium drops far back down into a gap between the
    // large ones at the base; with t'_min = max(t_min, t_n − δ) none does.
    let base = PhyllotaxisParams {
        r_base: 0.12,
        r_tip: 0.12,
        order_decay: 0.006,
        ..PhyllotaxisParams::default()
    };
    let drop = |use_delta: bool| {
        let v = phyllotaxis(&PhyllotaxisParams {
            use_delta,
            ..base.clone()
        })
        .unwrap();
        assert_no_overlap(&v, 1e-9);
        // The largest fall of t below the highest t reached so far.
        let mut top = 0.0f64;
        let mut worst = 0.0f64;
        for q in &v {
            worst = worst.max(top - q.t);
            top = top.max(q.t);
        }
        (worst, v.len())
    };
    let (with, without) = (drop(true), drop(false));
    println!("fall with δ {with:?}, without {without:?}");
    assert!(
        without.0 > 0.3,
        "without δ the worst fall is only {without:?}"
    );
    assert!(with.0 < 0.1, "with δ a primordium still falls {with:?}");
}

fn is_fibonacci(n: usize) -> bool {
    let (mut a, mut b) = (1, 2);
    while a < n {
        (a, b) = (b, a + b);
    }
    a == n
}

#[test]
fn parastichies_on_a_flat_head_are_consecutive_fibonacci_numbers() {
    // Equal primordia on a disc. Neighbours in a parastichy differ in index
    // by the parastichy count; the two index differences most common among
    // each primordium's two nearest earlier neighbours are the counts of
    // the two families of spirals.
    let p = params(Receptacle::Disc { radius: 1.0 }, 0.03, 0.03);
    let v = phyllotaxis(&p).unwrap();
    assert!(v.len() > 300, "{}", v.len());
    let mut tally = std::collections::BTreeMap::<usize, usize>::new();
    // The outer part of the head (the first half of the primordia, placed
    // from the rim inwards).
    for n in 50..v.len() / 2 {
        let mut near: Vec<(f64, usize)> = (0..n)
            .map(|i| (v[i].centre.distance(v[n].centre), n - i))
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        for &(_, d) in &near[..2] {
            *tally.entry(d).or_default() += 1;
        }
    }
    let mut counts: Vec<(usize, usize)> = tally.into_iter().map(|(d, c)| (c, d)).collect();
    counts.sort_unstable_by(|a, b| b.cmp(a));
    let (a, b) = (counts[0].1.min(counts[1].1), counts[0].1.max(counts[1].1));
    println!("parastichies: {a}, {b} ({counts:?})");
    assert!(is_fibonacci(a) && is_fibonacci(b), "{counts:?}");
    // Consecutive: b is the Fibonacci number after a.
    let (mut x, mut y) = (1, 2);
    while x < a {
        (x, y) = (y, x + y);
    }
    assert_eq!(y, b, "{a}, {b} are not consecutive Fibonacci numbers");
    // A head of this size shows the 55/89 pair.
    assert!(a >= 21, "{a}, {b}");
}

/// The receptacle's outward normal at `(φ, t)` by finite differences:
/// `∂P/∂φ × ∂P/∂t`.
fn numeric_normal(r: &Receptacle, phi: f64, t: f64) -> DVec3 {
    let h = 1e-6;
    let (t0, t1) = ((t - h).max(0.0), (t + h).min(1.0));
    let dt = r.point(phi, t1) - r.point(phi, t0);
    let dphi = r.point(phi + h, t) - r.point(phi - h, t);
    dphi.cross(dt).normalize()
}

#[test]
fn organ_frames_are_orthonormal_follow_the_receptacle_and_scale_with_the_primordium() {
    for (name, p) in [
        ("cone", PhyllotaxisParams::default()),
        (
            "sphere",
            params(Receptacle::Sphere { radius: 1.0 }, 0.1, 0.1),
        ),
        ("dome", params(dome(), 0.08, 0.04)),
    ] {
        let v = phyllotaxis(&p).unwrap();
        let f = organ_frames(&p.receptacle, &v).unwrap();
        assert_eq!(f.len(), v.len());
        for (q, o) in v.iter().zip(&f) {
            for (a, b) in [
                (o.normal, o.tangent),
                (o.normal, o.side),
                (o.tangent, o.side),
            ] {
                assert!(a.dot(b).abs() < 1e-9, "{name}: not orthogonal");
            }
            for a in [o.normal, o.tangent, o.side] {
                assert!((a.length() - 1.0).abs() < 1e-9, "{name}: not unit");
            }
            assert!(
                (o.tangent.cross(o.side).dot(o.normal) - 1.0).abs() < 1e-9,
                "{name}"
            );
            // The contact point goes to the centre; local +z is the normal.
            assert!(o.to_world(DVec3::ZERO).distance(q.centre) < 1e-12);
            if q.t > 1e-3 && q.t < 1.0 - 1e-3 {
                let n = numeric_normal(&p.receptacle, q.phi, q.t);
                assert!(n.dot(o.normal) > 1.0 - 1e-6, "{name}: {n} vs {}", o.normal);
            }
            // The tangent points up the curve, towards the tip.
            let ahead = p.receptacle.point(q.phi, (q.t + 1e-4).min(1.0));
            let behind = p.receptacle.point(q.phi, (q.t - 1e-4).max(0.0));
            assert!((ahead - behind).dot(o.tangent) > 0.0, "{name}");
            // The organ's size is the primordium's radius.
            assert_eq!(o.scale, q.radius);
            let tip = o.to_world(DVec3::Z);
            assert!((tip.distance(q.centre) - q.radius).abs() < 1e-12);
        }
        // Outward: on the sphere the normal points away from the centre.
        if name == "sphere" {
            assert!(f.iter().all(|o| o.normal.dot(o.origin) > 0.0));
        }
    }
}

#[test]
fn cauliflower_heads_carry_heads_that_satisfy_the_collision_condition() {
    // Fig. 10: the receptacle carries florets that are phyllotactic heads
    // themselves. Level 1 places the heads on a dome; level 2 places each
    // head's own primordia on a small dome in the head's frame.
    let outer = params(dome(), 0.2, 0.12);
    let heads = phyllotaxis(&outer).unwrap();
    let frames = organ_frames(&outer.receptacle, &heads).unwrap();
    let inner = params(dome(), 0.12, 0.08);
    let own = phyllotaxis(&inner).unwrap();
    assert!(
        heads.len() > 10 && own.len() > 20,
        "{} {}",
        heads.len(),
        own.len()
    );
    for f in &frames {
        let placed: Vec<Primordium> = own
            .iter()
            .map(|q| Primordium {
                centre: f.to_world(q.centre),
                radius: q.radius * f.scale,
                ..*q
            })
            .collect();
        assert_no_overlap(&placed, 1e-9);
        // The head stands on its primordium, inside its sphere's reach.
        for q in &placed {
            assert!(q.centre.distance(f.origin) <= 1.001 * f.scale);
        }
    }
}

fn name_of(e: &PlantError) -> &'static str {
    match e {
        PlantError::InvalidParameter { name, .. } => name,
        other => panic!("not a parameter error: {other}"),
    }
}

#[test]
fn bad_input_is_an_error_naming_the_parameter() {
    let d = PhyllotaxisParams::default();
    let cases: Vec<(PhyllotaxisParams, &str)> = vec![
        (
            PhyllotaxisParams {
                r_base: f64::NAN,
                ..d.clone()
            },
            "r_base",
        ),
        (
            PhyllotaxisParams {
                r_tip: -0.1,
                ..d.clone()
            },
            "r_tip",
        ),
        (
            PhyllotaxisParams {
                t_min: 0.8,
                t_max: 0.2,
                ..d.clone()
            },
            "t_min",
        ),
        (
            PhyllotaxisParams {
                t_max: f64::NAN,
                ..d.clone()
            },
            "t_max",
        ),
        (
            PhyllotaxisParams {
                divergence_deg: f64::INFINITY,
                ..d.clone()
            },
            "divergence_deg",
        ),
        (
            PhyllotaxisParams {
                receptacle: Receptacle::Bezier { segments: vec![] },
                ..d.clone()
            },
            "segments",
        ),
        (
            PhyllotaxisParams {
                receptacle: Receptacle::Bezier {
                    segments: vec![[[1.0, 0.0], [f64::NAN, 0.5], [0.5, 1.0], [0.0, 1.0]]],
                },
                ..d.clone()
            },
            "segments",
        ),
        (
            PhyllotaxisParams {
                receptacle: Receptacle::Sphere { radius: -1.0 },
                ..d.clone()
            },
            "receptacle.radius",
        ),
        (
            PhyllotaxisParams {
                order_decay: 1.0,
                ..d.clone()
            },
            "order_decay",
        ),
        (
            PhyllotaxisParams {
                order_decay: -0.1,
                ..d.clone()
            },
            "order_decay",
        ),
    ];
    for (p, want) in cases {
        let e = phyllotaxis(&p).unwrap_err();
        assert!(name_of(&e).contains(want), "{want}: {e}");
        assert!(e.to_string().contains(want), "{e}");
    }
    // Organ placement refuses primordia it cannot place.
    let v = phyllotaxis(&d).unwrap();
    let mut bad = v[..3].to_vec();
    bad[1].radius = f64::NAN;
    let e = organ_frames(&d.receptacle, &bad).unwrap_err();
    assert!(name_of(&e).contains("primordia"), "{e}");
    bad[1].radius = -1.0;
    assert!(organ_frames(&d.receptacle, &bad).is_err());
    let e = organ_frames(&Receptacle::Bezier { segments: vec![] }, &v).unwrap_err();
    assert!(name_of(&e).contains("segments"), "{e}");
    // A curve that is a single point has no direction anywhere.
    let point = Receptacle::Bezier {
        segments: vec![[[1.0, 1.0]; 4]],
    };
    let q = Primordium {
        centre: DVec3::new(1.0, 0.0, 1.0),
        radius: 0.1,
        phi: 0.0,
        t: 0.5,
    };
    assert!(organ_frames(&point, &[q]).is_err());
}
