use super::*;
use model::Corners;
use natura_core::NoProgress;

fn cone(n: usize) -> HeightField {
    let s = Seed(6);
    HeightField::from_fn(n, n, 1.0, |i, j| {
        let (x, y) = (i as f32 - n as f32 / 2.0, j as f32 - n as f32 / 2.0);
        60.0 - (x * x + y * y).sqrt() + 0.5 * s.gaussian2(i as i64, j as i64) as f32
    })
    .unwrap()
}

#[test]
fn conserves_mass_and_changes_terrain() {
    let mut hf = cone(64);
    let m0 = hf.heights().sum();
    let mut d = DropletErosion::new(DropletParams::default(), &hf, Seed(1)).unwrap();
    d.run(&mut hf, 5000, &NoProgress).unwrap();
    let m1 = hf.heights().sum() + d.outflow();
    assert!((m1 - m0).abs() < 1e-4 * m0, "{m0} → {m1}");
    assert!(
        d.deposition()
            .unwrap()
            .as_slice()
            .iter()
            .any(|&v| v < -0.01)
    );
    assert!(hf.check_finite().is_ok());
}

#[test]
fn refuses_bad_params() {
    let hf = cone(16);
    for p in [
        DropletParams {
            inertia: 1.0,
            ..Default::default()
        },
        DropletParams {
            radius: 0,
            ..Default::default()
        },
        DropletParams {
            erode: -0.1,
            ..Default::default()
        },
        DropletParams {
            lifetime: 0,
            ..Default::default()
        },
        DropletParams {
            capacity: f64::NAN,
            ..Default::default()
        },
    ] {
        assert!(DropletErosion::new(p, &hf, Seed(1)).is_err());
    }
}

/// A rough random field (fractal sum of lattice Gaussians) for the stability tests.
fn rough(nx: usize, ny: usize, cell: f32, seed: u64) -> HeightField {
    let s = Seed(seed);
    HeightField::from_fn(nx, ny, cell, |i, j| {
        let mut v = 0.0;
        let (mut a, mut f) = (50.0f32, 4usize);
        while f <= 2 * nx.max(ny) {
            let (fi, fj) = ((i * f / nx) as i64, (j * f / ny) as i64);
            v += a * s.gaussian2(fi, fj + 1000 * f as i64) as f32;
            a *= 0.5;
            f *= 2;
        }
        v
    })
    .unwrap()
}

/// The brush's shortcut away from the edges (its weight sum taken as
/// the whole brush's, no sample tested) changes nothing: droplets run
/// with the shortcut and with every sample tested leave the same field
/// and deposition, bit for bit.
#[test]
fn the_interior_brush_shortcut_changes_nothing() {
    let hf = rough(96, 80, 10.0, 7);
    let d = DropletErosion::new(DropletParams::default(), &hf, Seed(3)).unwrap();
    let run = |reach: i32| {
        let model = DropletModel {
            p: &d.p,
            nx: 96,
            ny: 80,
            seed: d.seed,
            brush: &d.brush,
            brush_reach: reach,
            brush_total: d.brush.iter().map(|b| b.2).sum(),
            erodibility: None,
            cell: d.cell,
        };
        let mut h = hf.heights().as_slice().to_vec();
        let mut dep = vec![0.0f32; h.len()];
        let mut g = Ground {
            h: &mut h,
            deposition: &mut dep,
            offset: 0,
            cell: d.cell,
        };
        let out: f64 = (0..3000).map(|id| model.simulate(&mut g, id)).sum();
        (h, dep, out)
    };
    // A reach no cell satisfies sends every step through the tested path.
    let (fast, slow) = (run(reach(&d.brush)), run(i32::MAX / 4));
    assert_eq!(reach(&d.brush), 2);
    assert!(
        fast.0
            .iter()
            .zip(hf.heights().as_slice())
            .any(|(a, b)| a != b)
    );
    assert!(
        fast.0
            .iter()
            .zip(&slow.0)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    );
    assert!(
        fast.1
            .iter()
            .zip(&slow.1)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    );
    assert_eq!(fast.2.to_bits(), slow.2.to_bits());
}

/// A droplet whose start rounds onto the field's far edge (x = nx − 1 in
/// f32) interpolates inside the last cell instead of reading past the row.
#[test]
fn a_start_on_the_far_edge_stays_inside_the_field() {
    let corners = Corners::at(255.0, 255.0, 256, 256);
    assert!(corners.cells.iter().all(|&i| i < 256 * 256));
    assert_eq!(corners.weights, [0.0, 0.0, 0.0, 1.0]);
    let corners = Corners::at(255.0, 3.5, 256, 256);
    assert_eq!(corners.cells[1] % 256, 255, "same row, not the next one");
    // Find a droplet index whose start rounds to x = 255 exactly, and run it.
    let hf = rough(256, 256, 30.0, 4);
    let mut d = DropletErosion::new(DropletParams::default(), &hf, Seed(37)).unwrap();
    let model = DropletModel {
        p: &d.p,
        nx: 256,
        ny: 256,
        seed: d.seed,
        brush: &d.brush,
        brush_reach: reach(&d.brush),
        brush_total: d.brush.iter().map(|b| b.2).sum(),
        erodibility: None,
        cell: d.cell,
    };
    let id = (0..400_000_000u64)
        .find(|&id| {
            let (x, y) = model.start(id);
            x == 255.0 || y == 255.0
        })
        .expect("an edge start within 4e8 droplets");
    let mut hf2 = hf.clone();
    d.next_droplet = id;
    d.run(&mut hf2, 1, &NoProgress).unwrap();
    assert!(hf2.check_finite().is_ok());
}

/// Millions of droplet steps with Beyer's defaults leave every height
/// inside the range the terrain started with (the field grows no pit and
/// no spike): the unbounded version reached ±1e21 m here.
#[test]
fn default_params_stay_in_range_over_many_droplets() {
    let mut hf = rough(96, 96, 1.0, 11);
    let (lo, hi) = hf.min_max();
    let mut d = DropletErosion::new(DropletParams::default(), &hf, Seed(2)).unwrap();
    d.run(&mut hf, 150_000, &NoProgress).unwrap();
    let (a, b) = hf.min_max();
    assert!(
        a >= lo && b <= hi + 0.05 * (hi - lo),
        "{lo}..{hi} → {a}..{b}"
    );
}

/// Bands of droplets running at once give the same field on 1 and 2
/// threads, and conserve mass like the sequential run.
#[test]
fn banded_rounds_are_thread_independent_and_conserve_mass() {
    let p = DropletParams {
        batch: 512,
        ..DropletParams::default()
    };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut hf = rough(80, 300, 2.0, 5);
            let mut d = DropletErosion::new(p.clone(), &hf, Seed(9)).unwrap();
            d.run(&mut hf, 20_000, &NoProgress).unwrap();
            (hf, d.outflow())
        })
    };
    let (a, out_a) = run(1);
    let (b, out_b) = run(2);
    assert_eq!(a.heights().as_slice(), b.heights().as_slice());
    assert_eq!(out_a.to_bits(), out_b.to_bits());
    let m0 = rough(80, 300, 2.0, 5).heights().sum();
    let m1 = a.heights().sum() + out_a;
    assert!((m1 - m0).abs() < 1e-3 * m0.abs().max(1.0), "{m0} → {m1}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
    /// Any accepted parameter set on any grid size keeps heights finite
    /// and inside the starting range, plus at most what the last deposits
    /// of dying droplets add.
    #[test]
    fn any_accepted_params_stay_in_range(
        nx in 3usize..48, ny in 3usize..48, cell in 0.1f32..500.0,
        inertia in 0.0f64..0.99, capacity in 0.0f64..50.0, min_slope in 0.0f64..1.0,
        erode in 0.0f64..=1.0, deposit in 0.0f64..=1.0, evaporate in 0.0f64..0.99,
        gravity in 0.0f64..100.0, radius in 1u32..=16, lifetime in 1u32..200,
        water in 0.01f64..10.0, speed in 0.0f64..10.0, batch in 1u32..300,
        seed in 0u64..1000,
    ) {
        let p = DropletParams {
            inertia, capacity, min_slope, erode, deposit, evaporate, gravity, radius,
            lifetime, initial_water: water, initial_speed: speed, batch,
        };
        let mut hf = rough(nx, ny, cell, seed);
        let (lo, hi) = hf.min_max();
        let mut d = DropletErosion::new(p, &hf, Seed(seed)).unwrap();
        d.run(&mut hf, 3000, &NoProgress).unwrap();
        proptest::prop_assert!(hf.check_finite().is_ok());
        let (a, b) = hf.min_max();
        proptest::prop_assert!(a >= lo, "{} < {}", a, lo);
        proptest::prop_assert!(b <= hi + (hi - lo), "{} > {} + range", b, hi);
    }
}
