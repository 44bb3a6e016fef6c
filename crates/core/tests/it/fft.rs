//! The planned transforms against a direct sum of the discrete Fourier
//! transform, for lengths that take each of rustfft's paths (powers of two,
//! mixed radix, primes through Rader's and Bluestein's algorithms), and the
//! real transforms against the complex ones.

use std::sync::Arc;

use natura_core::fft::{self, Complex, FftDirection};
use proptest::prelude::*;

/// `Σ_j x_j e^{∓2πi jk/n}`, summed directly in f64.
fn dft(x: &[Complex<f64>], direction: FftDirection) -> Vec<Complex<f64>> {
    let n = x.len();
    let sign = match direction {
        FftDirection::Forward => -1.0,
        FftDirection::Inverse => 1.0,
    };
    (0..n)
        .map(|k| {
            x.iter()
                .enumerate()
                .fold(Complex::new(0.0, 0.0), |acc, (j, v)| {
                    let a = sign * std::f64::consts::TAU * ((j * k) % n) as f64 / n as f64;
                    acc + v * Complex::new(a.cos(), a.sin())
                })
        })
        .collect()
}

fn signal(n: usize, seed: u64) -> Vec<Complex<f64>> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    (0..n).map(|_| Complex::new(next(), next())).collect()
}

const LENGTHS: [usize; 10] = [1, 2, 8, 12, 31, 64, 97, 100, 127, 210];

#[test]
fn complex_plans_equal_the_direct_sum() {
    for n in LENGTHS {
        for direction in [FftDirection::Forward, FftDirection::Inverse] {
            let x = signal(n, n as u64);
            let want = dft(&x, direction);
            let mut got = x.clone();
            let plan = fft::plan_f64(n, direction);
            assert_eq!((plan.len(), plan.fft_direction()), (n, direction));
            plan.process(&mut got);
            for (g, w) in got.iter().zip(&want) {
                assert!((g - w).norm() <= 1e-12 * n as f64, "n {n}: {g} vs {w}");
            }
            let mut single: Vec<Complex<f32>> = x
                .iter()
                .map(|c| Complex::new(c.re as f32, c.im as f32))
                .collect();
            fft::plan_f32(n, direction).process(&mut single);
            for (g, w) in single.iter().zip(&want) {
                let g = Complex::new(f64::from(g.re), f64::from(g.im));
                assert!((g - w).norm() <= 2e-6 * n as f64, "f32, n {n}: {g} vs {w}");
            }
        }
    }
}

#[test]
fn real_plans_equal_the_complex_ones_and_invert() {
    for n in LENGTHS {
        let x: Vec<f64> = signal(n, 7 + n as u64).iter().map(|c| c.re).collect();
        let mut full: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
        fft::plan_f64(n, FftDirection::Forward).process(&mut full);

        let r2c = fft::plan_real_forward_f64(n);
        let mut input = x.clone();
        let mut half = r2c.make_output_vec();
        assert_eq!(half.len(), n / 2 + 1);
        r2c.process(&mut input, &mut half).unwrap();
        for (h, f) in half.iter().zip(&full) {
            assert!((h - f).norm() <= 1e-12 * n as f64, "n {n}: {h} vs {f}");
        }

        let r2c32 = fft::plan_real_forward_f32(n);
        let mut input32: Vec<f32> = x.iter().map(|&v| v as f32).collect();
        let mut half32 = r2c32.make_output_vec();
        r2c32.process(&mut input32, &mut half32).unwrap();
        for (h, f) in half32.iter().zip(&full) {
            let h = Complex::new(f64::from(h.re), f64::from(h.im));
            assert!((h - f).norm() <= 2e-6 * n as f64, "f32, n {n}: {h} vs {f}");
        }

        let c2r32 = fft::plan_real_inverse_f32(n);
        let mut back32 = c2r32.make_output_vec();
        c2r32.process(&mut half32, &mut back32).unwrap();
        for (b, v) in back32.iter().zip(&x) {
            assert!(
                (f64::from(*b) / n as f64 - v).abs() <= 1e-5,
                "f32, n {n}: {b} vs {v}"
            );
        }

        let c2r = fft::plan_real_inverse_f64(n);
        let mut back = c2r.make_output_vec();
        c2r.process(&mut half, &mut back).unwrap();
        for (b, v) in back.iter().zip(&x) {
            assert!((b / n as f64 - v).abs() <= 1e-12, "n {n}: {b} vs {v}");
        }
    }
}

#[test]
fn a_length_asked_for_again_gets_the_same_plan() {
    let a = fft::plan_f64(48, FftDirection::Forward);
    let b = fft::plan_f64(48, FftDirection::Forward);
    assert!(Arc::ptr_eq(&a, &b));
    let c = fft::plan_f32(48, FftDirection::Inverse);
    assert!(Arc::ptr_eq(&c, &fft::plan_f32(48, FftDirection::Inverse)));
    let r = fft::plan_real_forward_f64(48);
    assert!(Arc::ptr_eq(&r, &fft::plan_real_forward_f64(48)));
    // A different length or direction is a different plan.
    assert!(!Arc::ptr_eq(&a, &fft::plan_f64(48, FftDirection::Inverse)));
    assert!(!Arc::ptr_eq(&a, &fft::plan_f64(49, FftDirection::Forward)));
}

#[test]
fn a_length_of_zero_plans_a_transform_that_does_nothing() {
    let mut empty: Vec<Complex<f64>> = Vec::new();
    fft::plan_f64(0, FftDirection::Forward).process(&mut empty);
    let mut empty32: Vec<Complex<f32>> = Vec::new();
    fft::plan_f32(0, FftDirection::Inverse).process(&mut empty32);
    assert!(empty.is_empty() && empty32.is_empty());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Forward then inverse returns the input times its length, for any
    /// length up to 600.
    #[test]
    fn forward_then_inverse_scales_by_the_length(n in 1usize..600, seed in any::<u64>()) {
        let x = signal(n, seed);
        let mut y = x.clone();
        fft::plan_f64(n, FftDirection::Forward).process(&mut y);
        fft::plan_f64(n, FftDirection::Inverse).process(&mut y);
        for (a, b) in y.iter().zip(&x) {
            prop_assert!((a / n as f64 - b).norm() <= 1e-12);
        }
    }
}
