//! The seed tables' search against brute force, and the statistics each
//! table promises (mean density, regional variation, clustering).

use super::*;
use crate::basis::cellular::{WorleyFeature, WorleyParams};
use alloc::vec;
use alloc::vec::Vec;

/// splitmix64 uniforms (test data only).
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        (mix64({
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            self.0
        }) >> 11) as f64
            / (1u64 << 53) as f64
    }
    fn range(&mut self, r: f64) -> f64 {
        (self.unit() * 2.0 - 1.0) * r
    }
}

const METRICS: [Metric; 4] = [
    Metric::Euclidean,
    Metric::EuclideanSquared,
    Metric::Manhattan,
    Metric::Chebyshev,
];

fn field(points: FeaturePoints, feature: WorleyFeature, metric: Metric) -> Worley {
    Worley::new(
        23,
        WorleyParams {
            feature,
            metric,
            points,
            ..WorleyParams::default()
        },
    )
    .unwrap()
}

/// The feature points of integer cell `c` (lattice coordinates; `c[2]`
/// ignored in 2-D), absolute.
fn cell_points(w: &Worley, c: [i64; 3], dims: usize) -> Vec<[f64; 3]> {
    let t = w.table.as_ref().unwrap();
    let u = c.map(|v| v as u32);
    let h = if dims == 2 {
        corner(u[0], row2(u[1], w.s))
    } else {
        corner(u[0], row3(u[1], u[2], w.s))
    };
    let origin = c.map(|v| v as f64);
    let mut out = Vec::new();
    t.for_points(h, origin, dims, |q| {
        out.push(core::array::from_fn(|a| origin[a] + q[a]));
    });
    if dims == 2 {
        for q in &mut out {
            q[2] = 0.0;
        }
    }
    out
}

/// The four nearest distances from `p` to every point of the cells within
/// Chebyshev distance `reach` of its cell, capped as the field caps them.
/// Panics if the block may have missed a nearer point (so a pass means the
/// oracle saw enough).
fn brute(w: &Worley, p: [f64; 3], dims: usize, reach: i64) -> [f64; 4] {
    let m = w.params.metric;
    let t = w.table.as_ref().unwrap();
    let c = p.map(|v| libm::floor(v) as i64);
    let mut d = Vec::new();
    let zr = if dims == 3 { reach } else { 0 };
    for dz in -zr..=zr {
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                let cell = [c[0] + dx, c[1] + dy, c[2] + dz];
                for q in cell_points(w, cell, dims) {
                    let o: [f64; 3] = core::array::from_fn(|a| p[a] - q[a]);
                    d.push(if dims == 2 {
                        m.d2(o[0], o[1])
                    } else {
                        m.d3(o[0], o[1], o[2])
                    });
                }
            }
        }
    }
    d.sort_unstable_by(f64::total_cmp);
    let cap = cap_value(m);
    let edge = (0..dims)
        .map(|a| p[a] - libm::floor(p[a]))
        .fold(f64::INFINITY, |e, f| e.min(f.min(1.0 - f)));
    let unseen = m.metric_of_axis_bound(reach as f64 + edge - t.spill);
    let k4 = d.get(3).copied().unwrap_or(f64::INFINITY);
    assert!(
        k4.min(cap) <= unseen,
        "oracle block too small at {p:?}: F4 {k4}, unseen {unseen}"
    );
    core::array::from_fn(|i| d.get(i).copied().unwrap_or(f64::INFINITY).min(cap))
}

fn tables() -> [FeaturePoints; 7] {
    [
        FeaturePoints::Poisson { density: 1.0 },
        FeaturePoints::Poisson { density: 4.0 },
        FeaturePoints::Poisson {
            density: MIN_DENSITY,
        },
        FeaturePoints::Variable { density: 4.0 },
        FeaturePoints::Variable {
            density: MIN_DENSITY,
        },
        FeaturePoints::Gaussian { density: 4.0 },
        FeaturePoints::Gaussian {
            density: MIN_DENSITY,
        },
    ]
}

/// Test points: random ones, and ones inside empty cells (found by
/// scanning), where the nearest points lie in other cells.
fn test_points(w: &Worley, dims: usize, n: usize, rng: &mut Rng) -> (Vec<[f64; 3]>, usize) {
    let mut pts = Vec::new();
    let mut empty = 0;
    while pts.len() < n {
        let p: [f64; 3] = core::array::from_fn(|a| if a < dims { rng.range(60.0) } else { 0.0 });
        let c = p.map(|v| libm::floor(v) as i64);
        if pts.len() % 2 == 0 || cell_points(w, c, dims).is_empty() {
            empty += usize::from(cell_points(w, c, dims).is_empty());
            pts.push(p);
        }
    }
    (pts, empty)
}

/// F1…F4 and F2 − F1, every metric and every table, 2-D and 3-D: the ring
/// search equals the sorted distances to all points of a large block of
/// cells, at random points and at points inside empty cells.
#[test]
fn table_search_equals_brute_force() {
    use WorleyFeature::*;
    let mut rng = Rng(5);
    let mut empties = 0;
    for points in tables() {
        for metric in METRICS {
            let ws = [F1, F2, F3, F4, F2MinusF1].map(|f| field(points, f, metric));
            for dims in [2, 3] {
                let (n, reach) = if dims == 2 { (60, 9) } else { (12, 5) };
                let (pts, empty) = test_points(&ws[0], dims, n, &mut rng);
                empties += empty;
                for p in pts {
                    let want = brute(&ws[0], p, dims, reach);
                    for w in &ws {
                        let got = if dims == 2 {
                            w.eval2(DVec2::new(p[0], p[1]))
                        } else {
                            w.eval3(DVec3::from_array(p))
                        };
                        let want = w.params.feature.pick(&want);
                        assert!(
                            (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                            "{points:?} {metric:?} {:?} {dims}-D {p:?}: {got} vs {want}",
                            w.params.feature
                        );
                    }
                }
            }
        }
    }
    assert!(empties > 200, "only {empties} points in empty cells");
}

/// Counts of points per cell over a `side`ⁿ block of cells from `start`.
fn counts(w: &Worley, dims: usize, side: i64, start: i64) -> Vec<f64> {
    let mut out = Vec::new();
    let zs = if dims == 3 { side } else { 1 };
    for k in 0..zs {
        for j in 0..side {
            for i in 0..side {
                let c = [start + i, start + j, start + k];
                out.push(cell_points(w, c, dims).len() as f64);
            }
        }
    }
    out
}

fn mean_var(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    (
        m,
        v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0),
    )
}

/// Over about 10⁵ cells the mean count per cell is the density, and the
/// plain table's counts have the Poisson variance (= mean, within 3 %).
/// Tolerances: five or more standard errors at the worst case, density 1 in
/// 3-D (≈ 10⁵ cells): 2 % for the plain table (variance `n`), 4 % for the
/// clustered one (compound Poisson, variance `5n`) and for the variable one
/// (its regional swings, a few hundred periods of the modulation).
#[test]
fn mean_points_per_cell_is_the_density() {
    for (dims, side) in [(2, 320), (3, 46)] {
        for density in [1.0, 4.0, 10.0] {
            for (points, tol) in [
                (FeaturePoints::Poisson { density }, 0.02),
                (FeaturePoints::Variable { density }, 0.04),
                (FeaturePoints::Gaussian { density }, 0.04),
            ] {
                let w = field(points, WorleyFeature::F1, Metric::Euclidean);
                let (mean, var) = mean_var(&counts(&w, dims, side, -side / 2));
                assert!(
                    (mean / density - 1.0).abs() < tol,
                    "{points:?} {dims}-D: mean {mean}"
                );
                if let FeaturePoints::Poisson { .. } = points {
                    assert!((var / mean - 1.0).abs() < 0.03, "{points:?}: var {var}");
                }
            }
        }
    }
}

/// The variable table is denser in some regions than in others: the counts
/// of 8×8-cell regions vary at least 4 times as much (relative to their
/// mean) as the plain table's, whose regions differ only by chance.
#[test]
fn variable_table_varies_between_regions() {
    let region = |points| {
        let w = field(points, WorleyFeature::F1, Metric::Euclidean);
        let c = counts(&w, 2, 256, -128);
        let mut sums = vec![0.0; 32 * 32];
        for (i, n) in c.iter().enumerate() {
            let (x, y) = (i % 256, i / 256);
            sums[(y / 8) * 32 + x / 8] += n;
        }
        let (m, v) = mean_var(&sums);
        v / m
    };
    let plain = region(FeaturePoints::Poisson { density: 4.0 });
    let variable = region(FeaturePoints::Variable { density: 4.0 });
    assert!((plain - 1.0).abs() < 0.2, "plain dispersion {plain}");
    assert!(variable > 4.0 * plain, "{variable} vs {plain}");
}

/// The Clark–Evans ratio (mean nearest-neighbour distance over its value
/// `1/(2√ρ)` for a Poisson pattern of density ρ): about 1 for the plain
/// table, well below for the clustered one. The nearest neighbour of a
/// feature point is its F2 (its F1 is itself).
#[test]
fn gaussian_table_clusters() {
    let ratio = |points, density: f64| {
        let w = field(points, WorleyFeature::F2, Metric::Euclidean);
        let mut sum = 0.0;
        let mut n = 0;
        for j in 0..60 {
            for i in 0..60 {
                for q in cell_points(&w, [i, j, 0], 2) {
                    sum += w.eval2(DVec2::new(q[0], q[1]));
                    n += 1;
                }
            }
        }
        sum / f64::from(n) * 2.0 * libm::sqrt(density)
    };
    for density in [1.0, 4.0] {
        let plain = ratio(FeaturePoints::Poisson { density }, density);
        let clustered = ratio(FeaturePoints::Gaussian { density }, density);
        assert!((plain - 1.0).abs() < 0.05, "plain ratio {plain}");
        assert!(clustered < 0.7 * plain, "{clustered} vs {plain}");
    }
}

/// The clusters' spreads differ (the heterogeneity is itself
/// heterogeneous): the nearest-neighbour distances of the clustered table
/// vary more, relative to their mean, than the plain table's.
#[test]
fn gaussian_table_spreads_vary() {
    let cv = |points| {
        let w = field(points, WorleyFeature::F2, Metric::Euclidean);
        let mut d = Vec::new();
        for j in 0..60 {
            for i in 0..60 {
                for q in cell_points(&w, [i, j, 0], 2) {
                    d.push(w.eval2(DVec2::new(q[0], q[1])));
                }
            }
        }
        let (m, v) = mean_var(&d);
        libm::sqrt(v) / m
    };
    let plain = cv(FeaturePoints::Poisson { density: 4.0 });
    let clustered = cv(FeaturePoints::Gaussian { density: 4.0 });
    assert!(clustered > 1.3 * plain, "{clustered} vs {plain}");
}

/// Values never exceed the bound, and reach the cap only where the points
/// are genuinely far: never at the allowed densities in a sample.
#[test]
fn values_stay_below_the_cap() {
    let mut rng = Rng(9);
    for points in tables() {
        for metric in METRICS {
            let w = field(points, WorleyFeature::F4, metric);
            for _ in 0..2000 {
                let p = DVec2::new(rng.range(1e4), rng.range(1e4));
                let v = w.eval2(p);
                assert!(v >= 0.0 && v < w.bound(), "{points:?} {metric:?} {p}: {v}");
            }
        }
    }
}
