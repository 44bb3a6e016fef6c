//! The 3-D evaluation of the footprint-limited fBm: its value is the sum of
//! its octaves' terms with the 3-D offsets, its gradient the central
//! difference of its value, its values within the 2-D bounds, its octaves
//! gone at the far footprint, and the 2-D evaluation untouched by it.

use natura_noise::fractal::footprint::{octave_offset, octave_offset3};
use natura_noise::glam::{DVec2, DVec3};
use natura_noise::{Field, FootprintFbm, FootprintParams, Perlin};
use proptest::prelude::*;

fn fbm(h: f64, lacunarity: f64, octaves: u32, seed: u64) -> FootprintFbm<Perlin> {
    FootprintFbm::new(
        Perlin::new(seed),
        &FootprintParams {
            amplitude: 2.0,
            h,
            lacunarity,
            octaves,
            wavelength: 10.0,
        },
    )
    .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// `eval3` is the sum, in order, of `c_k·a_k·N(f_k·p + o_k)` with the 3-D
    /// offsets, bit for bit; its gradient matches central differences; both
    /// lie within the bounds.
    #[test]
    fn eval3_is_its_octave_sum_and_its_gradient_matches(
        x in -500.0f64..500.0, y in -500.0f64..500.0, z in -500.0f64..500.0,
        h in 0.0f64..2.0, lac in 1.5f64..4.0, octaves in 1u32..10,
        lw in -3.0f64..1.0, seed in 0u64..1000,
    ) {
        let d = fbm(h, lac, octaves, seed);
        let (p, w) = (DVec3::new(x, y, z), 10f64.powf(lw));
        let n = d.visible(w);
        let mut sum = 0.0;
        for k in 0..n.ceil() as usize {
            let q = p * d.frequency(k) + octave_offset3(k);
            sum += (n - k as f64).min(1.0) * d.amplitude(k) * d.basis().eval3(q);
        }
        let v = d.eval3(p, w);
        prop_assert_eq!(v.to_bits(), sum.to_bits());
        prop_assert!(v.abs() <= d.amplitude_bound(w));
        let (gv, g) = d.eval_grad3(p, w);
        prop_assert!((gv - v).abs() <= 1e-9 * d.amplitude_bound(0.0).max(1.0));
        prop_assert!(g.length() <= d.lipschitz_bound3(w) * (1.0 + 1e-9));
        let top = (n.ceil() as usize).max(1) - 1;
        let e = 1e-4 / d.frequency(top);
        for (axis, gk) in [(DVec3::X, g.x), (DVec3::Y, g.y), (DVec3::Z, g.z)] {
            let fd = (d.eval3(p + axis * e, w) - d.eval3(p - axis * e, w)) / (2.0 * e);
            let tol = 1e-4 * d.lipschitz_bound3(w).max(1e-6);
            prop_assert!((fd - gk).abs() <= tol, "{fd} vs {gk}");
        }
    }
}

/// The 3-D offsets extend the 2-D ones, and the 2-D evaluation is still the
/// sum of the 2-D octave terms with the 2-D offsets (the 3-D path adds
/// nothing to it).
#[test]
fn the_2d_path_keeps_its_offsets_and_sum() {
    for k in 0..64 {
        let (a, b) = (octave_offset(k), octave_offset3(k));
        assert_eq!(a.x.to_bits(), b.x.to_bits());
        assert_eq!(a.y.to_bits(), b.y.to_bits());
        assert!((b.z - 0.732_051 * (k + 1) as f64).abs() < 1e-12);
    }
    assert_eq!(octave_offset(0), DVec2::new(0.618_034, 0.414_214));
    let d = fbm(0.7, 2.0, 8, 3);
    for i in 0..200 {
        let p = DVec2::new(i as f64 * 1.37 - 80.0, i as f64 * 0.71 + 5.0);
        let w = 0.01 * (1 + i % 50) as f64;
        let n = d.visible(w);
        let mut sum = 0.0;
        for k in 0..n.ceil() as usize {
            let q = p * d.frequency(k) + octave_offset(k);
            sum += (n - k as f64).min(1.0) * d.amplitude(k) * d.basis().eval2(q);
        }
        assert_eq!(d.eval2(p, w).to_bits(), sum.to_bits());
    }
}

/// Nothing is left from the far footprint on; every octave is present at a
/// zero footprint.
#[test]
fn far_footprint_is_zero_and_point_samples_have_every_octave() {
    let d = fbm(0.5, 2.0, 6, 9);
    let p = DVec3::new(3.3, -7.1, 12.9);
    assert_eq!(d.eval3(p, d.far_footprint()), 0.0);
    assert_eq!(d.eval3(p, 1e6), 0.0);
    let mut sum = 0.0;
    for k in 0..6 {
        sum += d.octave_term3(k, d.visible(0.0), p);
    }
    assert_eq!(d.eval3(p, 0.0).to_bits(), sum.to_bits());
    assert!(d.eval3(p, 0.0) != 0.0);
}

/// The lane evaluation gives each point the same bits alone or in any
/// batch, and stays within 2e-5 of the amplitudes' sum of the `f64` path.
#[test]
fn lane_points_are_batch_independent_and_close_to_eval3() {
    let d = fbm(1.0, 2.0, 10, 4);
    let n = 300;
    let (mut x, mut y, mut z, mut w) = (vec![], vec![], vec![], vec![]);
    for i in 0..n {
        let t = i as f64;
        x.push(t * 3.7 - 500.0);
        y.push((t * 0.37).sin() * 300.0);
        z.push(t * 1.3 + 0.5);
        w.push(if i % 7 == 0 {
            10.0
        } else {
            1e-3 * (1 + i % 97) as f64
        });
    }
    let mut all = vec![0.0f32; n];
    d.fill_points3(&x, &y, &z, &w, &mut all).unwrap();
    let tol = 2e-5 * d.amplitude_between(0, d.octave_count());
    for i in 0..n {
        let mut one = [0.0f32];
        d.fill_points3(&x[i..=i], &y[i..=i], &z[i..=i], &w[i..=i], &mut one)
            .unwrap();
        assert_eq!(one[0].to_bits(), all[i].to_bits(), "point {i}");
        let exact = d.eval3(DVec3::new(x[i], y[i], z[i]), w[i]);
        assert!(
            (f64::from(all[i]) - exact).abs() <= tol,
            "{} vs {exact}",
            all[i]
        );
    }
    assert!(d.fill_points3(&x, &y, &z, &w[1..], &mut all).is_err());
}
