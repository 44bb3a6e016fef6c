use natura_core::{HeightField, NoProgress, Seed};

use super::*;
use crate::PlantError;

/// One species that never survives domination and is never re-seeded: the
/// self-thinning experiment of Deussen et al. 1998, §4.3, Fig. 4–5.
fn thinning_params(initial_per_ha: f64) -> EcoParams {
    let sp = Species {
        name: "lychnis".into(),
        seeds_per_ha: 0.0,
        initial_per_ha,
        r0_min: 0.02,
        r0_max: 0.1,
        max_radius: 3.0,
        growth: 0.05,
        survive_domination: 0.0,
        wet_tolerance: 10.0,
        light_tolerance: 10.0,
        vigor_spread: 0.0,
        ..Species::default()
    };
    EcoParams {
        species: vec![sp],
        steps: 30,
        seed: Seed(4),
        ..EcoParams::default()
    }
}

fn brute_intersections(p: &[Plant]) -> usize {
    let mut n = 0;
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let (dx, dy) = (p[i].x - p[j].x, p[i].y - p[j].y);
            let r = p[i].radius + p[j].radius;
            n += usize::from(dx * dx + dy * dy < r * r);
        }
    }
    n
}

#[test]
fn self_thinning_leaves_no_intersecting_circles_and_follows_slope_minus_one() {
    let hf = HeightField::flat(41, 41, 1.0, 0.0).unwrap();
    // 62,500 plants per hectare: the source's starting density (62,500 on its field).
    let mut eco = Ecosystem::new(&hf, thinning_params(62_500.0)).unwrap();
    let n0 = eco.plants().len();
    assert!((9000..11000).contains(&n0), "{n0}");
    let mut pts = Vec::new();
    for _ in 0..30 {
        let s = eco.step().unwrap();
        assert_eq!(s.seeded, 0);
        assert_eq!(s.survived, 0);
        assert_eq!(brute_intersections(eco.plants()), 0, "step {}", eco.steps());
        let n = eco.plants().len() as f64;
        let area: f64 = eco
            .plants()
            .iter()
            .map(|p| std::f64::consts::PI * f64::from(p.radius).powi(2))
            .sum::<f64>()
            / n;
        pts.push((n.ln(), area.ln()));
    }
    // On the thinning line the circles cover a constant fraction of the field, so
    // log(mean area) against log(density) has slope −1 (the source's Fig. 5).
    let tail = &pts[10..];
    let m = tail.len() as f64;
    let (sx, sy) = tail.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (mx, my) = (sx / m, sy / m);
    let (num, den) = tail.iter().fold((0.0, 0.0), |a, p| {
        (a.0 + (p.0 - mx) * (p.1 - my), a.1 + (p.0 - mx).powi(2))
    });
    let slope = num / den;
    assert!((slope + 1.0).abs() < 0.2, "slope {slope}");
}

fn valley() -> HeightField {
    // A V-shaped valley with a steep wall on one side and a gentle one on the other.
    HeightField::from_fn(65, 65, 4.0, |i, j| {
        let x = i as f32 - 20.0;
        let wall = if x < 0.0 { -x * 6.0 } else { x * 0.8 };
        wall + j as f32 * 0.5
    })
    .unwrap()
}

#[test]
fn species_respect_their_limits_and_preferences() {
    let hf = valley();
    let p = EcoParams {
        steps: 8,
        ..EcoParams::default()
    };
    let mut eco = Ecosystem::new(&hf, p).unwrap();
    eco.run(&NoProgress).unwrap();
    let site = eco.site();
    let species = &eco.params().species;
    let mut wet = vec![(0.0f64, 0usize); species.len()];
    for pl in eco.plants() {
        let sp = &species[pl.species as usize];
        let (i, j) = site.nearest(pl.x, pl.y);
        assert!(
            f64::from(site.slope[(i, j)]) <= sp.max_slope,
            "{} on a cliff",
            sp.name
        );
        let a = f64::from(site.altitude[(i, j)]);
        assert!(a >= sp.altitude_min && a <= sp.altitude_max);
        wet[pl.species as usize].0 += f64::from(site.wetness[(i, j)]);
        wet[pl.species as usize].1 += 1;
    }
    assert!(wet.iter().all(|w| w.1 > 0), "{wet:?}");
    let mean = |k: usize| wet[k].0 / wet[k].1 as f64;
    // The wet shrub (index 2) lives on wetter ground than the tree (index 0).
    assert!(mean(2) > mean(0) + 0.05, "{} vs {}", mean(2), mean(0));
    // The steep wall is too steep for every species: nobody grows there.
    assert!(
        eco.plants()
            .iter()
            .all(|p| p.x > 18.0 * 4.0 - 8.0 || site.slope[site.nearest(p.x, p.y)] < 1.0)
    );
}

#[test]
fn one_and_two_threads_are_bit_identical() {
    let hf = valley();
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut eco = Ecosystem::new(
                &hf,
                EcoParams {
                    steps: 6,
                    ..EcoParams::default()
                },
            )
            .unwrap();
            eco.run(&NoProgress).unwrap();
            let inst = Instancing::new(&eco, 4).unwrap();
            (eco.plants().to_vec(), inst.instances)
        })
    };
    let (a, ia) = run(1);
    let (b, ib) = run(2);
    assert!(a.len() > 1000, "{}", a.len());
    assert_eq!(a.len(), b.len());
    for (p, q) in a.iter().zip(&b) {
        assert_eq!(p.id, q.id);
        assert_eq!(p.radius.to_bits(), q.radius.to_bits());
        assert_eq!(p.x.to_bits(), q.x.to_bits());
    }
    assert_eq!(ia, ib);
}

#[test]
fn instancing_uses_few_prototypes_for_many_plants() {
    let hf = valley();
    let mut eco = Ecosystem::new(
        &hf,
        EcoParams {
            steps: 5,
            ..EcoParams::default()
        },
    )
    .unwrap();
    eco.run(&NoProgress).unwrap();
    let inst = Instancing::new(&eco, 7).unwrap();
    assert!(inst.prototypes.len() <= 4 * 7);
    assert!(inst.reduction() > 50.0, "{}", inst.reduction());
    for (i, p) in inst.instances.iter().zip(eco.plants()) {
        let proto = &inst.prototypes[i.prototype as usize];
        assert_eq!(proto.species, i.species);
        assert!(proto.geometry.segment_count() > 0);
        // The scaled crown matches the plant's circle of influence.
        assert!((proto.geometry_radius * i.scale - p.radius).abs() < 1e-3 * p.radius.max(1.0));
    }
    assert!(matches!(
        Instancing::new(&eco, 0),
        Err(PlantError::InvalidParameter {
            name: "per_species",
            ..
        })
    ));
}

#[test]
fn bad_input_gives_typed_errors() {
    let hf = valley();
    let bad = |p: EcoParams| {
        matches!(
            Ecosystem::new(&hf, p),
            Err(PlantError::InvalidParameter { .. })
        )
    };
    assert!(bad(EcoParams {
        species: vec![],
        ..EcoParams::default()
    }));
    let mut p = EcoParams::default();
    p.species[0].growth = f64::NAN;
    assert!(bad(p));
    let mut p = EcoParams::default();
    p.species[1].survive_domination = 1.5;
    assert!(bad(p));
    let mut p = EcoParams::default();
    p.species[2].r0_max = 100.0;
    assert!(bad(p));
    assert!(bad(EcoParams {
        sun: glam::Vec3::ZERO,
        ..EcoParams::default()
    }));
    assert!(bad(EcoParams {
        max_plants: 10,
        ..EcoParams::default()
    }));
    let tiny = HeightField::flat(2, 2, 1.0, 0.0).unwrap();
    assert!(Ecosystem::new(&tiny, EcoParams::default()).is_err());
    let mut nan = valley();
    nan.heights_mut()[(3, 3)] = f32::NAN;
    assert!(matches!(
        Ecosystem::new(&nan, EcoParams::default()),
        Err(PlantError::Core(_))
    ));
}

#[test]
fn a_resumed_ecosystem_steps_on_as_the_original() {
    let hf = valley();
    let params = EcoParams {
        steps: 8,
        ..EcoParams::default()
    };
    let mut whole = Ecosystem::new(&hf, params.clone()).unwrap();
    for _ in 0..3 {
        whole.step().unwrap();
    }
    let saved = whole.plants().to_vec();
    whole.run(&NoProgress).unwrap();
    let mut resumed = Ecosystem::resume(&hf, params.clone(), saved.clone(), 3).unwrap();
    assert_eq!(
        resumed.plants(),
        &saved[..],
        "resuming keeps the saved order"
    );
    resumed.run(&NoProgress).unwrap();
    assert_eq!(resumed.steps(), 8);
    assert!(whole.plants().len() > 1000);
    assert_eq!(resumed.plants(), whole.plants());
    assert_eq!(
        Instancing::new(&resumed, 4).unwrap(),
        Instancing::new(&whole, 4).unwrap()
    );

    let refused = |plants: Vec<Plant>, step: u32| {
        matches!(
            Ecosystem::resume(&hf, params.clone(), plants, step),
            Err(PlantError::InvalidParameter {
                name: "Ecosystem::resume",
                ..
            })
        )
    };
    assert!(refused(saved.clone(), 9), "a step past the simulation");
    let (ex, _) = Site::new(&hf, params.sun).unwrap().extent();
    for damage in [
        |p: &mut Plant, _: f32| p.radius = f32::NAN,
        |p: &mut Plant, _: f32| p.radius = 0.0,
        |p: &mut Plant, ex: f32| p.x = ex + 1.0,
        |p: &mut Plant, _: f32| p.vigor = 2.0,
        |p: &mut Plant, _: f32| p.species = u16::MAX,
    ] {
        let mut bad = saved.clone();
        damage(&mut bad[7], ex);
        assert!(refused(bad, 3));
    }
}

/// The name and message of an `InvalidParameter`, or a panic naming what came instead.
fn refusal(r: Result<Ecosystem, PlantError>) -> (&'static str, String) {
    match r {
        Err(e @ PlantError::InvalidParameter { name, .. }) => (name, e.to_string()),
        Err(e) => panic!("expected InvalidParameter, got {e}"),
        Ok(eco) => panic!("expected an error, got {} plants", eco.plants().len()),
    }
}

/// A 32 km × 32 km terrain of 33² samples: about 10⁵ hectares.
fn wide() -> HeightField {
    HeightField::from_fn(33, 33, 1000.0, |i, j| ((i * 7 + j * 3) % 5) as f32).unwrap()
}

#[test]
fn sowing_is_checked_against_max_plants_before_anything_is_allocated() {
    let hf = wide();
    // Densities beyond one plant per square centimetre are refused outright.
    for (field, v) in [("initial_per_ha", 1e300), ("seeds_per_ha", 1e300)] {
        let mut p = EcoParams::default();
        if field == "initial_per_ha" {
            p.species[3].initial_per_ha = v;
        } else {
            p.species[3].seeds_per_ha = v;
        }
        let (name, msg) = refusal(Ecosystem::new(&hf, p));
        assert_eq!(name, format!("Species::{field}"), "{msg}");
        assert!(msg.contains("[0, 1e8]"), "{msg}");
    }
    let grass = |initial_per_ha, seeds_per_ha| EcoParams {
        species: vec![Species {
            initial_per_ha,
            seeds_per_ha,
            max_radius: 5.0,
            ..Species::grass()
        }],
        ..EcoParams::default()
    };
    // A density within range whose count over this terrain (10¹³ seeds)
    // exceeds max_plants: refused, naming the density, before allocating.
    let (name, msg) = refusal(Ecosystem::new(&hf, grass(1e8, 0.0)));
    assert_eq!(name, "Species::initial_per_ha", "{msg}");
    assert!(msg.contains("grass") && msg.contains("max_plants"), "{msg}");
    // The same for the seeds of a step.
    let mut eco = Ecosystem::new(&hf, grass(0.0, 1e8)).unwrap();
    match eco.step() {
        Err(e @ PlantError::InvalidParameter { name, .. }) => {
            assert_eq!(name, "Species::seeds_per_ha", "{e}");
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
    // All species together against a small max_plants.
    let p = EcoParams {
        max_plants: 1000,
        ..EcoParams::default()
    };
    let (name, msg) = refusal(Ecosystem::new(&hf, p));
    assert_eq!(name, "Species::initial_per_ha", "{msg}");
    assert!(msg.contains("max_plants = 1000"), "{msg}");
}

#[test]
fn species_parameters_are_held_to_physical_ranges() {
    let hf = valley();
    type Edit = fn(&mut Species);
    let cases: [(&str, Edit); 5] = [
        ("Species::max_radius", |s| s.max_radius = 1e300),
        ("Species::r0_min", |s| s.r0_min = 1e-300),
        ("Species::r0_max", |s| s.r0_max = 5e3),
        ("Species::growth", |s| s.growth = 1e300),
        ("Species::seeds_per_ha", |s| s.seeds_per_ha = 1e9),
    ];
    for (field, set) in cases {
        let mut p = EcoParams::default();
        set(&mut p.species[0]);
        let (name, msg) = refusal(Ecosystem::new(&hf, p));
        assert_eq!(name, field, "{msg}");
    }
}

#[test]
fn a_neighbour_grid_too_fine_for_the_terrain_is_refused_before_it_is_built() {
    let sp = Species {
        r0_min: 1e-3,
        r0_max: 1e-3,
        max_radius: 2e-3,
        initial_per_ha: 0.0,
        seeds_per_ha: 0.0,
        ..Species::default()
    };
    let p = EcoParams {
        species: vec![sp],
        ..EcoParams::default()
    };
    let (name, msg) = refusal(Ecosystem::new(&wide(), p.clone()));
    assert_eq!(name, "Species::max_radius", "{msg}");
    assert!(msg.contains("0.002"), "{msg}");
    let resumed = Ecosystem::resume(&wide(), p, Vec::new(), 0);
    assert!(matches!(
        resumed,
        Err(PlantError::InvalidParameter {
            name: "Species::max_radius",
            ..
        })
    ));
}
