//! natura-noise with natura-core: filling grids from any field in parallel
//! rows is deterministic (bit-identical on 1 and 2 threads) and matches
//! point evaluation.

use natura::core::Grid2;
use natura::core::glam::DVec2;
use natura::noise::*;

fn fill(f: &dyn Field, threads: usize) -> Grid2<f32> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let mut g = Grid2::new(257, 131, 0.0f32).unwrap();
    pool.install(|| {
        g.par_rows_mut(|j, row| f.fill_row2(DVec2::new(-3.7, 1.3 + j as f64 * 0.031), 0.029, row));
    });
    g
}

#[test]
fn parallel_row_fills_are_bit_identical_on_1_and_2_threads() {
    let p = Perlin::new(5);
    let s = Spectral::default();
    let fields: Vec<Box<dyn Field>> = vec![
        Box::new(Fbm::new(p, s).unwrap()),
        Box::new(RidgedMultifractal::new(p, RidgedParams::default()).unwrap()),
        Box::new(HybridMultifractal::new(Simplex::new(5), HybridParams::default()).unwrap()),
        Box::new(Worley::new(5, WorleyParams::default()).unwrap()),
        Box::new(DistNoise::dist_noise(p, 1.0).unwrap()),
    ];
    for f in &fields {
        let a = fill(f.as_ref(), 1);
        let b = fill(f.as_ref(), 2);
        assert_eq!(a.as_slice(), b.as_slice());
        for (j, row) in a.rows().enumerate().step_by(17) {
            for (i, &v) in row.iter().enumerate().step_by(13) {
                let e = f.eval2(DVec2::new(-3.7 + i as f64 * 0.029, 1.3 + j as f64 * 0.031));
                assert!(
                    (v as f64 - e).abs() <= 1e-5 * f.bound().max(1.0),
                    "{v} vs {e}"
                );
            }
        }
    }
}

#[test]
fn grid_fill_matches_rows() {
    let f = Fbm::new(Perlin::new(1), Spectral::default().with_frequency(0.01)).unwrap();
    let l = Lattice2::new(DVec2::new(100.0, -50.0), DVec2::new(1.0, 2.0), 64, 32).unwrap();
    let mut a = vec![0.0f32; l.len()];
    f.fill_grid2(&l, &mut a).unwrap();
    let g = Grid2::from_fn(64, 32, |i, j| f.eval2(l.point(i, j)) as f32).unwrap();
    for (x, y) in a.iter().zip(g.as_slice()) {
        assert!((x - y).abs() < 1e-5);
    }
}
