//! Property tests: conservation, non-negativity and level-of-detail invariants
//! hold for arbitrary small fields, seeds and parameters.

use natura_core::{HeightField, NoProgress, Seed};
use natura_terrain::erosion::{
    Diffusion, DiffusionParams, Edges, MusgraveHydraulic, MusgraveParams, Neighbourhood, PipeModel,
    PipeParams, Thermal, ThermalParams,
};
use natura_terrain::synth::{MidpointParams, SubdivisionParams, SubdivisionScheme, subdivide};
use proptest::prelude::*;

fn field(nx: usize, ny: usize, seed: u64, relief: f32) -> HeightField {
    let s = Seed(seed);
    HeightField::from_fn(nx, ny, 1.0, |i, j| {
        100.0 + relief * s.gaussian2(i as i64, j as i64) as f32
    })
    .unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(1.0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn thermal_and_diffusion_conserve(nx in 3usize..20, ny in 3usize..20, seed in any::<u64>(), relief in 0.0f32..30.0,
                                      rate in 0.01f64..0.125, periodic in any::<bool>(), eight in any::<bool>()) {
        let mut hf = field(nx, ny, seed, relief);
        let m0 = hf.heights().sum();
        let edges = if periodic { Edges::Periodic } else { Edges::Closed };
        let neighbourhood = if eight { Neighbourhood::Eight } else { Neighbourhood::Four };
        Thermal::new(ThermalParams { talus_rate: rate, edges, neighbourhood, ..Default::default() }, &hf).unwrap().run(&mut hf, 30, &NoProgress).unwrap();
        Diffusion::new(DiffusionParams { rate, edges, neighbourhood }, &hf).unwrap().run(&mut hf, 30, &NoProgress).unwrap();
        prop_assert!(rel(m0, hf.heights().sum()) < 1e-5);
        prop_assert!(hf.check_finite().is_ok());
    }

    #[test]
    fn musgrave_conserves_and_stays_non_negative(n in 3usize..16, seed in any::<u64>(), relief in 0.0f32..20.0,
                                                 k_d in 0.0f64..=1.0, k_s in 0.0f64..=1.0, k_c in 0.0f64..20.0,
                                                 transfer in 0.05f64..=1.0, guard in any::<bool>()) {
        let mut hf = field(n, n, seed, relief);
        let p = MusgraveParams { k_d, k_s, k_c, transfer, erosion_guard: guard, rain_period: 7, ..Default::default() };
        let mut m = MusgraveHydraulic::new(p, &hf).unwrap();
        let m0 = hf.heights().sum();
        m.run(&mut hf, 60, &NoProgress).unwrap();
        prop_assert!(rel(m0, hf.heights().sum() + m.sediment().sum()) < 1e-5);
        prop_assert!((m.water().sum() - m.ledger().rain).abs() <= 1e-4 * m.ledger().rain.max(1e-6));
        prop_assert!(m.water().min() >= 0.0 && m.sediment().min() >= 0.0);
    }

    #[test]
    fn pipe_model_conserves(n in 3usize..16, seed in any::<u64>(), relief in 0.0f32..20.0, dt in 0.001f64..2.0,
                            k_s in 0.0f64..=1.0, k_d in 0.0f64..=1.0, open in any::<bool>()) {
        let mut hf = field(n, n, seed, relief);
        let edges = if open { Edges::Open } else { Edges::Closed };
        let p = PipeParams { dt, k_s, k_d, k_e: 0.0, edges, ..Default::default() };
        let mut m = PipeModel::new(p, &hf).unwrap();
        let m0 = hf.heights().sum();
        m.run(&mut hf, 60, &NoProgress).unwrap();
        let l = m.ledger();
        prop_assert!(rel(m0, hf.heights().sum() + m.total_sediment() + l.outflow_sediment) < 1e-5);
        prop_assert!((m.total_water() - (l.rain - l.outflow_water - l.evaporated)).abs() <= 1e-3 * l.rain.max(1e-6));
    }

    #[test]
    fn subdivision_lod_consistency(seed in any::<u64>(), h in 0.05f64..=1.0, k in 1u32..3, nx in 2usize..40, ny in 2usize..40,
                                   scheme in prop_oneof![Just(SubdivisionScheme::Triangle), Just(SubdivisionScheme::Quad), Just(SubdivisionScheme::DiamondSquare)]) {
        let levels = 6;
        let mut p = SubdivisionParams { midpoint: MidpointParams { h, ..Default::default() }, scheme, levels: Some(levels) };
        let fine = subdivide(nx, ny, 1.0, &p, Seed(seed)).unwrap();
        p.levels = Some(levels - k);
        let f = 1usize << k;
        let (cx, cy) = ((nx - 1) / f + 1, (ny - 1) / f + 1);
        let coarse = subdivide(cx, cy, f as f32, &p, Seed(seed)).unwrap();
        for j in 0..cy {
            for i in 0..cx {
                prop_assert_eq!(coarse.heights()[(i, j)].to_bits(), fine.heights()[(i * f, j * f)].to_bits());
            }
        }
    }
}
