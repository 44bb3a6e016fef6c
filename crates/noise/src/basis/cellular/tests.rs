//! The staged block search against brute force.

use super::*;

/// splitmix64 points in `[-r, r)` (test data only).
struct Points(u64);

impl Points {
    fn next(&mut self, r: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * r
    }
}

/// The four nearest true distances over every cell within Chebyshev
/// distance 3 of the point's cell (far more than any search needs).
fn brute2(w: &Worley, p: DVec2) -> [f64; 4] {
    let (ix, fx) = split(p.x);
    let (iy, fy) = split(p.y);
    let mut d = [0.0f64; 49];
    for (k, d) in d.iter_mut().enumerate() {
        let (dx, dy) = (k as i32 % 7 - 3, k as i32 / 7 - 3);
        let (px, py) = w.point2(ix.wrapping_add(dx as u32), iy.wrapping_add(dy as u32));
        *d = w
            .params
            .metric
            .d2(fx - (f64::from(dx) + px), fy - (f64::from(dy) + py));
    }
    d.sort_unstable_by(f64::total_cmp);
    [d[0], d[1], d[2], d[3]]
}

fn brute3(w: &Worley, p: DVec3) -> [f64; 4] {
    let s = p.to_array().map(split);
    let mut d = [0.0f64; 343];
    for (k, d) in d.iter_mut().enumerate() {
        let o = [k as i32 % 7 - 3, k as i32 / 7 % 7 - 3, k as i32 / 49 - 3];
        let c = w.point3(
            s[0].0.wrapping_add(o[0] as u32),
            s[1].0.wrapping_add(o[1] as u32),
            s[2].0.wrapping_add(o[2] as u32),
        );
        *d = w.params.metric.d3(
            s[0].1 - (f64::from(o[0]) + c[0]),
            s[1].1 - (f64::from(o[1]) + c[1]),
            s[2].1 - (f64::from(o[2]) + c[2]),
        );
    }
    d.sort_unstable_by(f64::total_cmp);
    [d[0], d[1], d[2], d[3]]
}

/// Every feature, metric and a range of jitters: the point values (the
/// staged search, with its fallback to the ring search) equal the brute
/// force, in 2-D and 3-D, near the origin and far from it.
#[test]
fn staged_search_equals_brute_force() {
    use WorleyFeature::*;
    let mut pts = Points(17);
    for metric in [
        Metric::Euclidean,
        Metric::EuclideanSquared,
        Metric::Manhattan,
        Metric::Chebyshev,
    ] {
        for jitter in [0.0, 0.3, 0.8, 1.0] {
            for feature in [F1, F2, F3, F4, F2MinusF1, F3MinusF2, F4MinusF3] {
                let params = WorleyParams {
                    feature,
                    metric,
                    jitter,
                    ..WorleyParams::default()
                };
                let w = Worley::new(11, params).unwrap();
                for k in 0..300 {
                    let r = if k % 3 == 0 { 1.0e7 } else { 40.0 };
                    let p2 = DVec2::new(pts.next(r), pts.next(r));
                    let want = feature.pick(&brute2(&w, p2));
                    let got = w.eval2(p2);
                    assert!(
                        (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                        "{params:?} 2-D {p2}: {got} vs {want}"
                    );
                    if k % 3 == 0 {
                        let p3 = DVec3::new(pts.next(r), pts.next(r), pts.next(r));
                        let want = feature.pick(&brute3(&w, p3));
                        let got = w.eval3(p3);
                        assert!(
                            (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                            "{params:?} 3-D {p3}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }
}
